"""`Simulation`: binds a rig, an experiment protocol, the drive models and a solver."""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Mapping
from pathlib import Path

import numpy as np

from rollerrig._validation import (
    ParameterError,
    did_you_mean,
    numbers_apart,
    require_in_range,
    require_positive,
)
from rollerrig.contact.creep import PolachParameters
from rollerrig.contact.laws import FastsimParameters
from rollerrig.experiment.protocol import Protocol, load_protocol
from rollerrig.rig.assemble import ModelInputs, assemble
from rollerrig.rig.model import DriveConfig
from rollerrig.rig.parameters import RigParameters, default_rig, load_rig

__all__ = ["SOLVERS", "Simulation", "SolverError", "output_times"]

SOLVERS = ("fast", "reference")


class SolverError(ParameterError):
    """A solver could not integrate an experiment: the message says which solver, on which
    experiment and rig, at which simulated time, why, and what to try.

    Attributes
    ----------
    solver : str
        ``"fast"`` or ``"reference"``.
    t_stop : float
        Simulated time the solver reached [s].
    reason : str
        What failed and what to try.
    """

    def __init__(self, message: str, *, solver: str, t_stop: float, reason: str) -> None:
        super().__init__(message)
        self.solver = solver
        self.t_stop = t_stop
        self.reason = reason


def output_times(duration: float, rate: float) -> np.ndarray:
    """Sample instants [s] from 0 to ``duration`` [s] at ``rate`` [Hz], never beyond the end.

    A duration summed from step durations can fall an ulp short of a sample instant
    (1 + 2 × (1.5 + 0.02 + 1) = 6.039999999999999 s at 250 Hz): the last sample is then the
    end itself, not an instant after it, where no input is defined.

    Examples
    --------
    >>> float(output_times(6.039999999999999, 250.0)[-1])
    6.039999999999999
    """
    duration = require_positive("duration", duration, "s", single=True)
    rate = require_positive("rate", rate, "Hz", single=True)
    samples = np.floor(duration * rate + 1e-9) + 1.0  # inf past 1.8e308: int() had overflowed
    limit = _memory_limit()
    if not samples * 8.0 <= limit:  # numpy's MemoryError (or OverflowError) otherwise
        raise ParameterError(
            f"duration × rate must give at most {limit / 8.0:.3g} samples (this machine's "
            f"memory), got {duration:g} s × {rate:g} Hz = {samples:.3g} samples; shorten the "
            "duration or lower the rate"
        )
    n = int(samples) - 1
    t = np.arange(n + 1) / rate
    t[-1] = min(t[-1], duration)
    return t


_RESULT_CHANNELS = 80
"""About how many float64 series a run holds per output sample (the states, the truth channels,
what the rig measures, the solver's copies): for the size check of :func:`_check_result_size`."""


def _memory_limit() -> float:
    """Bytes of results a run may hold: half the machine's physical memory where the system
    says it, else 16 GiB."""
    try:
        return 0.5 * os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):  # no sysconf (Windows)
        return 16.0 * 2**30


def _require_callable(name: str, value) -> None:
    if value is not None and not callable(value):
        raise ParameterError(
            f"{name} must be a callable or None, got a {type(value).__name__} ({value!r})"
        )


def _check_result_size(protocol, rate: float) -> None:
    """Refuse, before anything is allocated, an experiment whose results would not fit in
    memory: half the machine's physical memory where the system says it, else 16 GiB. A
    protocol step of a million seconds otherwise ended in numpy's MemoryError."""
    samples = np.floor(protocol.duration * rate) + 1.0
    need = samples * _RESULT_CHANNELS * 8.0
    limit = _memory_limit()
    if need > limit:
        raise ParameterError(
            f"experiment {protocol.name!r} lasts {protocol.duration:g} s: at {rate:g} Hz that "
            f"is {samples:.3g} output samples, about {need / 2**30:.3g} GiB of results, more "
            f"than this machine can hold ({limit / 2**30:.3g} GiB allowed); shorten the "
            "protocol's steps or lower the output rate"
        )


class Simulation:
    """A simulated adhesion experiment on a rig.

    Parameters
    ----------
    rig : RigParameters, path or None
        Rig parameters, a rig TOML file, or ``None`` for the bundled default rig.
    experiment : Protocol, str or path
        A compiled protocol, the name of a bundled one (e.g. ``"seed-30kmh-dry"``), or a file.
    drives : DriveConfig, optional
        Drive models (default: PMSM wheel drive, induction-motor roller drive with lag).
    friction_sets : mapping, optional
        Polach parameters by friction-condition name (default: Polach 2005 dry and wet).
    solver : {"fast", "reference"}
        The compiled fast backend (ETDRK4 with the ROS34PW2 W-method as its fallback,
        :mod:`rollerrig.solve.fast`), or scipy's Radau on the compiled model. ETDRK4's step
        is fixed; where its own error estimate says it is not enough (macro-slip at low
        speed) a segment goes to ROS34PW2 (:data:`~rollerrig.solve.fast.FAST_DEFAULTS`).
    output_rate : float, optional
        Sampling rate of the results [Hz]; default the rig's DAQ rate. At least two samples
        over the experiment.
    rtol : float, optional
        Relative tolerance of the solver [-], in [1e-13, 0.1] (below about 100 machine
        epsilons scipy's Radau raises it itself).

    Examples
    --------
    A bundled protocol on the bundled rig:

    >>> Simulation(experiment="seed-30kmh-dry")
    Simulation(rig='pardubice-tram-roller-rig', experiment='seed-30kmh-dry' (30 s), \
drives=pmsm/induction, solver='fast', output_rate=250 Hz)

    A protocol built from steps (a notebook): one torque pulse at 30 km/h, dry, 4.3 kN.

    >>> from rollerrig.experiment import Hold, Protocol, RampTorque, ReleaseTorque
    >>> pulse = Protocol.from_steps(
    ...     "pulse",
    ...     [Hold(0.2), RampTorque(300.0, 0.3), ReleaseTorque(), Hold(0.48)],
    ...     normal_load=4300.0,
    ...     roller_speed=30 / 3.6,
    ... )
    >>> sim = Simulation(experiment=pulse, solver="reference", output_rate=250.0)
    >>> sim.times.size
    251
    >>> ds = sim.run()  # doctest: +SKIP
    >>> round(float(ds.t56.max()))  # roller-shaft torque [N.m]  # doctest: +SKIP
    220
    """

    def __init__(
        self,
        rig: RigParameters | str | os.PathLike | None = None,
        experiment: Protocol | str | os.PathLike = "seed-30kmh-dry",
        drives: DriveConfig | None = None,
        friction_sets: Mapping[str, PolachParameters] | None = None,
        solver: str = "fast",
        output_rate: float | None = None,
        rtol: float | None = None,
    ) -> None:
        if not isinstance(solver, str) or solver not in SOLVERS:
            hint = did_you_mean(solver, SOLVERS) if isinstance(solver, str) else ""
            raise ParameterError(f"solver must be one of {SOLVERS}, got {solver!r}{hint}")
        if friction_sets is not None:
            if not isinstance(friction_sets, Mapping):
                raise ParameterError(
                    "friction_sets must be a mapping of friction-condition name -> "
                    f"PolachParameters, got a {type(friction_sets).__name__}"
                )
            if not friction_sets:  # assemble() had taken the defaults in its place
                raise ParameterError(
                    "friction_sets must name at least one friction condition, got an empty "
                    "mapping; pass None for the defaults (Polach 2005 dry and wet)"
                )
            for key, value in friction_sets.items():
                if not isinstance(value, PolachParameters | FastsimParameters):
                    raise ParameterError(
                        f"friction_sets[{key!r}] must be PolachParameters or "
                        f"FastsimParameters, got a {type(value).__name__} ({value!r})"
                    )
        if rig is None:
            rig = default_rig()
        elif not isinstance(rig, RigParameters):
            if not isinstance(rig, str | os.PathLike):  # Simulation(protocol): a common slip
                raise ParameterError(
                    f"rig must be RigParameters, a rig TOML file or None, got a "
                    f"{type(rig).__name__}; pass the experiment as experiment=..."
                )
            rig = load_rig(Path(rig))
        if not isinstance(experiment, Protocol | str | os.PathLike):
            raise ParameterError(
                "experiment must be a Protocol, the name of a bundled protocol or a protocol "
                f"TOML file, got a {type(experiment).__name__}"
            )
        protocol = experiment if isinstance(experiment, Protocol) else load_protocol(experiment)
        if output_rate is None:
            rate = rig.sensors.daq_rate
        else:
            rate = require_positive("output_rate", output_rate, "Hz", single=True)
        if rate * protocol.duration < 1.0:  # a run of one sample had come back
            lowest, got = numbers_apart(1.0 / protocol.duration, rate)
            raise ParameterError(
                f"output_rate must give at least two samples over the experiment's "
                f"{protocol.duration:g} s, so >= {lowest} [Hz], got {got}"
            )
        if rtol is not None:
            # The solvers' relative tolerance: below 1e-13 round-off, above 0.1 no solution.
            rtol = require_in_range(
                "rtol", rtol, 1e-13, 0.1, "1", low_inclusive=True, high_inclusive=True, single=True
            )
        _check_result_size(protocol, rate)
        self.rig = rig
        self.protocol = protocol
        self.solver = solver
        self.output_rate = rate
        self.rtol = rtol
        self.inputs: ModelInputs = assemble(rig, protocol, drives, friction_sets)

    def __repr__(self) -> str:
        drives = self.inputs.drives
        return (
            f"Simulation(rig={self.rig.meta.name!r}, experiment={self.protocol.name!r} "
            f"({self.protocol.duration:g} s), drives={drives.wheel}/{drives.roller}, "
            f"solver={self.solver!r}, output_rate={self.output_rate:g} Hz)"
        )

    @property
    def times(self) -> np.ndarray:
        """Sample times of the results [s], never beyond the protocol's end
        (:func:`output_times`)."""
        return output_times(self.protocol.duration, self.output_rate)

    def run(
        self,
        progress: Callable[[float, float], None] | None = None,
        notify: Callable[[str], None] | None = None,
    ):
        """Run the experiment and return the labelled dataset
        (:func:`~rollerrig.solve.results.build_dataset`, an :class:`xarray.Dataset`);
        ``progress`` and ``notify`` as in :meth:`solve`.

        Raises
        ------
        SolverError
            The solver failed: the message names the time it reached and what to try.
        """
        return self.solve(progress, notify).to_xarray()

    def solve(
        self,
        progress: Callable[[float, float], None] | None = None,
        notify: Callable[[str], None] | None = None,
    ):
        """Run the experiment and return the labelled results without importing xarray
        (:func:`~rollerrig.solve.results.build_results`, a
        :class:`~rollerrig.output.labelled.LabelledData`): the content of :meth:`run`'s
        Dataset, for a caller that only writes, draws or summarises it (``rollerrig
        simulate``); its ``to_xarray()`` gives the Dataset.

        ``progress(t_reached, t_end)`` [s] is called as the solve goes on; with the fast
        solver ``notify(message)`` is told when the run is about to compile the solver's
        fallback (:func:`rollerrig.solve.fast.integrate_experiment`).

        Raises
        ------
        SolverError
            The solver failed: the message names the time it reached and what to try.
        """
        from rollerrig.solve.results import build_results

        _require_callable("progress", progress)
        _require_callable("notify", notify)
        t = self.times
        start = time.perf_counter()
        loading: list[float] = []
        if self.solver == "fast":
            from numba.core import event

            from rollerrig.solve.fast import FAST_DEFAULTS, default_exp_step, integrate_experiment

            # numba's compiler-lock events time the driver's loading from the cache (or its
            # first compilation: both hold the lock) apart from the solve: in a fresh process
            # numba's own start and the load are about 0.45 s, the default solve 0.02 s.
            with event.install_timer("numba:compiler_lock", loading.append):
                x, stats = integrate_experiment(
                    self.inputs, t, rtol=self.rtol, progress=progress, notify=notify
                )
            settings = dict(FAST_DEFAULTS) | ({"rtol": self.rtol} if self.rtol else {})
            settings["exp_step"] = default_exp_step(self.inputs)
            if stats.get("method") == "etdrk4":
                name = "ETDRK4 exponential integrator (numba), ROS34PW2 W-method fallback"
            else:
                name = "ROS34PW2 W-method (numba)"
        else:
            from rollerrig.solve.reference import integrate_reference

            rtol = 1e-9 if self.rtol is None else self.rtol
            x, stats = integrate_reference(self.inputs, t, rtol=rtol, progress=progress)
            settings = {"rtol": rtol, "method": "Radau"}
            name = "scipy solve_ivp Radau"
        wall = time.perf_counter() - start
        if stats["status"] != 0 or not np.all(np.isfinite(x)):
            self._fail(name, stats, x, t)
        solver = {
            "name": name,
            "settings": settings,
            "stats": stats,
            "wall_time_s": wall,
            "load_time_s": float(sum(loading)),
        }
        return build_results(self.inputs, t, x, solver)

    def _fail(self, name: str, stats: dict, x: np.ndarray, t: np.ndarray):
        """Raise the :class:`SolverError` of a failed run."""
        t_stop = stats.get("t_stop")
        if t_stop is None or stats["status"] == 0:  # finite status, non-finite samples
            bad = np.flatnonzero(~np.all(np.isfinite(x), axis=1))
            t_stop = float(t[bad[0]]) if bad.size else float("nan")
        reason = stats.get("reason") or (
            f"at t = {t_stop:.6g} s the results became NaN or infinite; check the rig "
            "parameters (an inertia, radius or load near zero, a very large stiffness, damping "
            "or controller gain)"
            + ("" if self.solver == "reference" else " or try solver='reference'")
        )
        raise SolverError(
            f"the {self.solver} solver ({name}) failed on experiment {self.protocol.name!r} "
            f"({self.protocol.duration:g} s) on rig {self.rig.meta.name!r}: {reason}",
            solver=self.solver,
            t_stop=float(t_stop),
            reason=reason,
        )
