"""Sweeps of rig variants on one experiment, run in parallel on the compiled backend.

The measure is the seed's: after a sudden release of the wheel torque, how far the force the
rig derives from the torque sensor (T56 / r_r) overshoots below zero, relative to its value just
before the release (Kayaalp Figs. 42-43: "relative values of amplitudes"). The true contact
force's overshoot is reported beside it.

Every point of a sweep has a status: a variant the solver cannot integrate (or one without a
release to measure) is reported with its reason and NaN overshoots, and the other points still
complete.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.experiment import Hold, Protocol, RampTorque, ReleaseTorque
from rollerrig.rig.assemble import assemble
from rollerrig.rig.model import DriveConfig
from rollerrig.rig.parameters import RigParameters
from rollerrig.solve.simulation import output_times

__all__ = [
    "POINT_FAILED",
    "POINT_NO_RELEASE",
    "POINT_OK",
    "RELEASE_TEST",
    "STUDIES",
    "StudyResult",
    "release_overshoots",
    "run_study",
    "run_sweep",
]

POINT_OK = "ok"
"""Status of a sweep point that was simulated and measured."""
POINT_FAILED = "solver failed"
"""Status of a sweep point the solver could not integrate (its reason says where and why)."""
POINT_NO_RELEASE = "no release"
"""Status of a sweep point without a torque release from a positive force to measure."""

RELEASE_TEST = Protocol.from_steps(
    "release-test",
    [Hold(1.0), RampTorque(600.0, 2.0), Hold(0.5), ReleaseTorque(), Hold(3.0)],
    normal_load=4300.0,
    roller_speed=30 / 3.6,
    friction="dry",
    description="One ramp-hold-sudden release at 30 km/h, dry, 4.3 kN, for the parametric studies.",
    source="Kayaalp 4.5.1.7-4.5.1.8 (pattern as seed-30kmh-dry, one cycle)",
)
"""The default experiment of the studies: one release from 600 N.m (below the adhesion limit,
so that the release, not macro-slip, is what the studies compare)."""


def release_overshoots(ds, protocol: Protocol, window: float = 3.0) -> list[dict]:
    """Overshoot below zero after each sudden torque release.

    Parameters
    ----------
    ds : xarray.Dataset
        Simulation results (:func:`rollerrig.solve.results.build_dataset`).
    protocol : Protocol
        The experiment (its ``release_torque`` events).
    window : float
        Time after each release searched for the minimum [s].

    Returns
    -------
    list of dict
        Per release: time [s], force from T56 before it [N], its minimum after [N], the relative
        overshoot [-], and the true contact force's minimum and relative overshoot.
    """
    rows = []
    for event in protocol.events:
        if event.action != "release_torque":
            continue
        before = float(ds.measured_force.sel(time=event.start, method="nearest"))
        if before <= 0:
            continue
        span = (ds.time > event.start) & (ds.time <= event.start + window)
        measured = float(ds.measured_force.where(span).min())
        true = float(ds.contact_force.where(span).min())
        rows.append(
            {
                "time [s]": event.start,
                "force_before [N]": before,
                "measured_min [N]": measured,
                "measured_overshoot [-]": -measured / before,
                "true_min [N]": true,
                "true_overshoot [-]": -true / before,
            }
        )
    return rows


@dataclass(frozen=True)
class StudyResult:
    """Outcome of a study: one row per variant.

    ``measured_overshoot`` and ``true_overshoot`` are NaN where ``status`` is not
    :data:`POINT_OK`; ``reasons`` then says why (empty for the points that succeeded).
    """

    name: str
    parameter: str
    unit: str
    values: tuple
    labels: tuple[str, ...]
    measured_overshoot: np.ndarray  # [-]
    true_overshoot: np.ndarray  # [-]
    status: tuple[str, ...] = ()
    reasons: tuple[str, ...] = ()

    @property
    def failed(self) -> tuple[str, ...]:
        """Labels of the points that did not succeed."""
        return tuple(
            label for label, s in zip(self.labels, self.status, strict=True) if s != POINT_OK
        )

    def rows(self) -> list[dict]:
        """One dict per variant; a point that did not succeed has None overshoots, its status
        and its reason."""
        rows = []
        for i, (label, value) in enumerate(zip(self.labels, self.values, strict=True)):
            status = self.status[i] if self.status else POINT_OK
            ok = status == POINT_OK
            rows.append(
                {
                    "variant": label,
                    self.parameter + (f" [{self.unit}]" if self.unit else ""): value,
                    "overshoot of T56/r_r [-]": float(self.measured_overshoot[i]) if ok else None,
                    "overshoot of F_x [-]": float(self.true_overshoot[i]) if ok else None,
                    "status": status,
                    "reason": self.reasons[i] if self.reasons else "",
                }
            )
        return rows


def _stiffness(rig: RigParameters):
    values = tuple(43.5e3 + 20e3 * np.arange(6))
    variants = [(rig.with_overrides({"stiffness.roller_shaft": k}), DriveConfig()) for k in values]
    labels = tuple(f"k56 = {k / 1e3:.1f} kN·m/rad" for k in values)
    return "roller-shaft stiffness k56", "N.m/rad", values, labels, variants


def _lag(rig: RigParameters):
    values = (0.0, 0.05, 0.1, 0.2, 0.3635, 0.5)
    variants = [(rig, DriveConfig(roller_lag=tau)) for tau in values]
    labels = tuple(f"τ = {tau:g} s" for tau in values)
    return "AM response lag τ", "s", values, labels, variants


def _drives(rig: RigParameters):
    stiff = rig.with_overrides({"stiffness.roller_shaft": 143.5e3})
    servo_fast = rig.with_overrides({"servo_roller_drive.speed_bandwidth": 2 * np.pi * 20.0})
    variants = [
        (rig, DriveConfig()),
        (rig, DriveConfig(roller_lag=0.0)),
        (stiff, DriveConfig(roller_lag=0.0)),
        (rig, DriveConfig(roller="servo")),
        (servo_fast, DriveConfig(roller="servo")),
        (rig, DriveConfig(roller="ideal_speed")),
    ]
    labels = (
        "AM V/f with lag (rig today)",
        "AM V/f, no lag",
        "AM V/f, no lag, k56 = 143.5 kN·m/rad",
        "speed servo, 5 Hz bandwidth",
        "speed servo, 20 Hz bandwidth",
        "ideal speed source",
    )
    return "roller drive", "", tuple(range(len(labels))), labels, variants


STUDIES: dict[str, Callable] = {"stiffness": _stiffness, "lag": _lag, "drives": _drives}
"""Built-in studies: roller-shaft stiffness (Kayaalp Fig. 43), motor lag (Fig. 47), roller
drives including the seed's proposed fixes (Figs. 48-49)."""


def run_sweep(
    variants,
    labels,
    protocol: Protocol | None = None,
    output_rate: float = 1000.0,
    *,
    name: str = "sweep",
    parameter: str = "variant",
    unit: str = "",
    values: tuple | None = None,
    progress: Callable[[int, int, int], None] | None = None,
) -> StudyResult:
    """Run rig variants on one experiment with the parallel fast backend and measure each.

    Parameters
    ----------
    variants : sequence of (RigParameters, DriveConfig)
        The points of the sweep.
    labels : sequence of str
        One label per point.
    protocol : Protocol, optional
        Default :data:`RELEASE_TEST`.
    output_rate : float
        Sampling of the results [Hz]; fine enough to resolve the 13.8 Hz shaft mode.
    name, parameter, unit, values
        Describe the sweep in the result (``values`` default: the point numbers).
    progress : callable, optional
        ``progress(done, total, failed)`` [points], called after each batch of as many points
        as numba has threads (the batches run one after the other, each in parallel).

    Returns
    -------
    StudyResult
        With a status per point: a point the solver cannot integrate does not stop the others.
    """
    from rollerrig.solve.fast import SWEEP_H_MAX, integrate_batch
    from rollerrig.solve.results import build_dataset

    protocol = protocol or RELEASE_TEST
    labels = tuple(labels)
    if len(labels) != len(variants) or not variants:
        raise ParameterError(
            f"a sweep needs one label per variant and at least one variant; got "
            f"{len(variants)} variants and {len(labels)} labels"
        )
    inputs = [assemble(r, protocol, d) for r, d in variants]
    t = output_times(protocol.duration, output_rate)
    n = len(inputs)
    if progress is None:
        x, stats = integrate_batch(inputs, t, h_max=SWEEP_H_MAX)
    else:
        import numba

        size = max(1, numba.get_num_threads())
        parts, stats = [], []
        for start in range(0, n, size):
            x_part, stats_part = integrate_batch(inputs[start : start + size], t, h_max=SWEEP_H_MAX)
            parts.append(x_part)
            stats.extend(stats_part)
            progress(len(stats), n, sum(s["status"] != 0 for s in stats))
        x = np.concatenate(parts)
    measured = np.full(n, np.nan)
    true = np.full(n, np.nan)
    status = [POINT_OK] * n
    reasons = [""] * n
    for i, (inp, xi, st) in enumerate(zip(inputs, x, stats, strict=True)):
        if st["status"] != 0:
            status[i] = POINT_FAILED
            reasons[i] = f"the fast solver failed {st['reason']}"
            continue
        rows = release_overshoots(build_dataset(inp, t, xi, {}), protocol)
        if not rows:
            status[i] = POINT_NO_RELEASE
            reasons[i] = (
                f"the experiment {protocol.name!r} has no torque release from a positive force "
                "to measure"
            )
            continue
        measured[i] = max(r["measured_overshoot [-]"] for r in rows)
        true[i] = max(r["true_overshoot [-]"] for r in rows)
    values = tuple(range(n)) if values is None else tuple(values)
    return StudyResult(
        name, parameter, unit, values, labels, measured, true, tuple(status), tuple(reasons)
    )


def run_study(
    name: str,
    rig: RigParameters,
    protocol: Protocol | None = None,
    output_rate: float = 1000.0,
    progress: Callable[[int, int, int], None] | None = None,
) -> StudyResult:
    """Run a built-in study with the parallel fast backend.

    Parameters
    ----------
    name : {"stiffness", "lag", "drives"}
    rig : RigParameters
        The base rig.
    protocol : Protocol, optional
        Default :data:`RELEASE_TEST`.
    output_rate : float
        Sampling of the results [Hz]; fine enough to resolve the 13.8 Hz shaft mode.
    progress : callable, optional
        ``progress(done, total, failed)`` [points] (see :func:`run_sweep`).

    Returns
    -------
    StudyResult
        A point the solver cannot integrate has status :data:`POINT_FAILED` and a reason; the
        others are measured as usual.
    """
    if name not in STUDIES:
        raise ParameterError(f"unknown study {name!r}; choose one of {sorted(STUDIES)}")
    parameter, unit, values, labels, variants = STUDIES[name](rig)
    return run_sweep(
        variants,
        labels,
        protocol,
        output_rate,
        name=name,
        parameter=parameter,
        unit=unit,
        values=values,
        progress=progress,
    )
