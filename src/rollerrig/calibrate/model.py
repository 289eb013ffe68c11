"""The replayed twin as a function of the free parameters, evaluated in parallel batches.

:class:`ReplayModel` turns parameter vectors z (``z_i = ln(p_i − p_low,i)``, see
:mod:`rollerrig.calibrate.problem`) into the channels the recording holds: it builds one rig
variant per vector (:meth:`RigParameters.with_overrides`, the creep law's parameter set of the
recording, the roller speed set point), assembles them on the replayed protocol
(:func:`rollerrig.rig.assemble.assemble`) and integrates every variant that shares a protocol
in one call of the fast backend, :func:`rollerrig.solve.fast.integrate_batch` (parallel threads).
Variants of the speed set point or of the normal load have a protocol of their own (inputs of
the experiment, not rig parameters) and run in batches of their own.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.calibrate.measurement import Measurement
from rollerrig.calibrate.problem import (
    FreeParameter,
    replay_protocol_from_recording,
    split_values,
    with_polach,
)
from rollerrig.contact.creep import PolachParameters
from rollerrig.contact.laws import FastsimParameters
from rollerrig.rig import model as m
from rollerrig.rig.assemble import assemble
from rollerrig.rig.parameters import RigParameters

__all__ = ["Prediction", "ReplayModel"]

_T56 = m.TERM_NAMES.index("t56")
_WHEEL_ANGLE = m.X_THETA + 2  # the wheel encoder sits on the wheel shaft (disc, body 3)
_ROLLER_ANGLE = m.X_THETA + 4  # the roller encoder on the roller shaft (body 5)


@dataclass(frozen=True)
class Prediction:
    """What the twin predicts for one parameter vector, or why it could not.

    Attributes
    ----------
    channels : dict or None
        Channel -> predicted values (:meth:`Measurement.predicted`); None on a failure.
    failure : str
        Why the variant could not be simulated (empty on success).
    """

    channels: dict[str, np.ndarray] | None
    failure: str = ""

    @property
    def ok(self) -> bool:
        """Whether the variant was simulated."""
        return self.channels is not None


class ReplayModel:
    """The twin replaying one recording, as a function of the free parameters.

    Parameters
    ----------
    measurement : Measurement
        The recording's channels, load, time base and torque request.
    rig : RigParameters
        The rig the free keys are applied to.
    friction : PolachParameters or FastsimParameters
        The friction law of the recording the ``polach.*`` (or ``fastsim.*``) keys are
        applied to: of the creep law ``drives.law``
        (:func:`~rollerrig.calibrate.problem.friction_parameters`).
    params : sequence of FreeParameter
        The free parameters, the nuisance ``experiment.*`` ones among them.
    drives : DriveConfig, optional
        Drive models and the creep law (default: PMSM wheel drive, induction-motor roller
        drive with its lag, Polach's law). A law of the FASTSIM family runs from its table
        (:mod:`rollerrig.contact.table`), which none of its parameters enters: a variant
        builds no table, and costs about 1.1-1.2 times a Polach one (its steady free rolling
        is solved in Python from the table): one Levenberg-Marquardt evaluation (9 variants,
        central differences) of a 7.5 s test took 0.70 s against 0.60 s (medians of 7).
    rtol : float, optional
        Relative tolerance of the fast backend (default its own).
    h_max : float, optional
        Largest step of the fast backend [s]; default its own
        (:data:`~rollerrig.solve.fast.FAST_DEFAULTS`): the calibration fits the twin as the
        package runs it everywhere (``simulate``, studies, the synthetic recordings), so a
        recording the twin made is reproduced to its last digit (4e-8 N.m RMS of T56 on the
        bundled 30 s test), and the calibrated rig is the one that reproduces the recording
        in that twin. Its numerical error against the exact solution (0.034 N.m RMS of T56 on
        that test at 0.9 ms, from a run at 0.25 ms) is a thirtieth of the torque sensor's
        noise; a smaller ``h_max`` removes it (third order), at the cost of time.

    Attributes
    ----------
    simulations : int
        Variants simulated so far [-].
    """

    def __init__(
        self,
        measurement: Measurement,
        rig: RigParameters,
        friction: PolachParameters | FastsimParameters,
        params: Sequence[FreeParameter],
        drives: m.DriveConfig | None = None,
        rtol: float | None = None,
        h_max: float | None = None,
    ) -> None:
        self.measurement = measurement
        self.rig = rig
        self.friction = friction
        self.params = tuple(params)
        self.drives = drives or m.DriveConfig()
        self.rtol = rtol
        self.h_max = None if h_max is None else float(h_max)
        self.condition = friction.name or "recording"
        self.simulations = 0
        self._protocols: dict[float, object] = {}

    # -- parameter vectors -----------------------------------------------------------------

    def values(self, z: np.ndarray) -> list[float]:
        """Parameter values [SI] of the vector ``z``."""
        return [p.value(float(zi)) for p, zi in zip(self.params, z, strict=True)]

    def variant(
        self, z: np.ndarray
    ) -> tuple[RigParameters, PolachParameters | FastsimParameters, float, float]:
        """(rig, friction law, roller speed set point [m/s], normal load [N]) of ``z``.

        Raises
        ------
        ParameterError
            A value outside what the rig file or the creep law accepts (e.g. k_S > k_A).
        """
        values = self.values(z)
        rig_values, law_values, experiment = split_values(self.params, values)
        rig = self.rig.with_overrides(rig_values) if rig_values else self.rig
        friction = with_polach(self.friction, law_values)
        speed = experiment.get("roller_speed", self.measurement.roller_speed_start)
        load = experiment.get("normal_load", self.measurement.normal_load)
        return rig, friction, float(speed), float(load)

    def protocol(self, speed: float, load: float):
        """The replayed protocol at the set point ``speed`` [m/s] and the load ``load`` [N]
        (built once per pair)."""
        key = (speed, load)
        if key not in self._protocols:
            self._protocols[key] = replay_protocol_from_recording(
                self.measurement, speed, self.condition, "calibration-replay", load
            )
        return self._protocols[key]

    # -- simulation -------------------------------------------------------------------------

    def simulate(self, zs: Sequence[np.ndarray], *, coarse: bool = False) -> list[Prediction]:
        """Simulate the parameter vectors ``zs``; variants sharing a protocol run in one batch.

        ``coarse``: with ROS34PW2's step cap of sweeps (:data:`~rollerrig.solve.fast.
        SWEEP_H_MAX`; not the sweeps' settings of :func:`~rollerrig.solve.fast.sweep_settings`,
        which a calibration does not take). With ETDRK4, the fast backend's default, that
        changes nothing (its 1.6 ms step is below that cap): a coarse run is a full run. With
        ROS34PW2 it was about twice as fast, accurate enough to compare values far apart.

        Returns
        -------
        list of Prediction
            One per vector, in order; a variant that cannot be built or integrated is a
            :class:`Prediction` with its reason (it never stops the others).
        """
        from rollerrig.solve.fast import SWEEP_H_MAX, integrate_batch

        out: list[Prediction | None] = [None] * len(zs)
        groups: dict[tuple[float, float], list[tuple[int, object]]] = {}
        for i, z in enumerate(zs):
            try:
                rig, friction, speed, load = self.variant(np.asarray(z, dtype=float))
                inputs = assemble(
                    rig, self.protocol(speed, load), self.drives, {self.condition: friction}
                )
            except ParameterError as exc:
                out[i] = Prediction(None, " ".join(str(exc).split()))
                continue
            groups.setdefault((speed, load), []).append((i, inputs))
        t = self.measurement.time
        for members in groups.values():
            h_max = SWEEP_H_MAX if coarse else self.h_max
            x, stats = integrate_batch([inp for _, inp in members], t, rtol=self.rtol, h_max=h_max)
            self.simulations += len(members)
            for k, (i, inputs) in enumerate(members):
                out[i] = self._prediction(inputs, x[k], stats[k])
        return out  # type: ignore[return-value]

    def _prediction(self, inputs, x: np.ndarray, stats: dict) -> Prediction:
        from rollerrig.solve.results import first_segment_terms

        if stats["status"] != 0 or not np.all(np.isfinite(x)):
            reason = stats.get("reason") or "the states became NaN or infinite"
            return Prediction(None, f"the fast solver failed: {reason}")
        t = self.measurement.time
        # T56 does not depend on friction: the first segment's parameters serve every sample.
        terms = first_segment_terms(inputs, t, x)
        load = float(inputs.protocol.normal_load[0])
        channels = self.measurement.predicted(
            terms[:, _T56], x[:, _WHEEL_ANGLE], x[:, _ROLLER_ANGLE], load
        )
        if not all(np.all(np.isfinite(v)) for v in channels.values()):
            return Prediction(None, "the predicted channels are not finite")
        return Prediction(channels)


def finite_difference_vectors(
    z: np.ndarray, upper: np.ndarray, step: float | np.ndarray, central: bool = False
) -> tuple[list[np.ndarray], np.ndarray]:
    """The perturbed vectors of a finite-difference Jacobian in z, and their steps.

    Forward differences step up by ``step`` unless that passes the upper bound (then down);
    central differences step both ways (one-sided next to a bound). ``step``: one step for
    every parameter, or one per parameter.

    Returns
    -------
    vectors : list of ndarray
        ``n`` forward vectors, or ``2n`` (up then down, per parameter) for central ones.
    steps : ndarray, shape (n, 2)
        The (up, down) displacement of each parameter [-]; down is 0 for forward differences.
    """
    n = z.size
    each = np.broadcast_to(np.asarray(step, dtype=float), (n,))
    steps = np.zeros((n, 2))
    vectors = []
    for i in range(n):
        h = float(each[i])
        up = h if z[i] + h <= upper[i] else -h
        down = -h if central else 0.0
        if central and up < 0.0:  # at the bound: one-sided, two points below
            up, down = -h, -2.0 * h
        steps[i] = (up, down)
        zu = z.copy()
        zu[i] += up
        vectors.append(zu)
        if central:
            zd = z.copy()
            zd[i] += down
            vectors.append(zd)
    return vectors, steps


def jacobian_columns(base: np.ndarray, perturbed: Sequence[np.ndarray], steps: np.ndarray):
    """Finite-difference Jacobian from the base residual-space vector and the perturbed ones.

    ``perturbed`` holds n (forward) or 2n (central: up, down per parameter) vectors, in the
    order of :func:`finite_difference_vectors`.
    """
    n = steps.shape[0]
    jac = np.empty((base.size, n))
    central = len(perturbed) == 2 * n
    for i in range(n):
        up, down = steps[i]
        if central:
            jac[:, i] = (perturbed[2 * i] - perturbed[2 * i + 1]) / (up - down)
        else:
            jac[:, i] = (perturbed[i] - base) / up
    return jac
