"""Sweeps of rig variants on one experiment, run in parallel on the compiled backend.

The measure is the seed's: after a sudden release of the wheel torque, how far the force the
rig derives from the torque sensor (T56 / r_r) overshoots below zero, relative to its value just
before the release (Kayaalp Figs. 42-43: "relative values of amplitudes"). The true contact
force's overshoot is reported beside it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from rollerrig.experiment import Hold, Protocol, RampTorque, ReleaseTorque
from rollerrig.rig.assemble import assemble
from rollerrig.rig.model import DriveConfig
from rollerrig.rig.parameters import RigParameters

__all__ = ["RELEASE_TEST", "STUDIES", "StudyResult", "release_overshoots", "run_study"]

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
    """Outcome of a study: one row per variant."""

    name: str
    parameter: str
    unit: str
    values: tuple
    labels: tuple[str, ...]
    measured_overshoot: np.ndarray  # [-]
    true_overshoot: np.ndarray  # [-]

    def rows(self) -> list[dict]:
        return [
            {
                "variant": label,
                self.parameter + (f" [{self.unit}]" if self.unit else ""): value,
                "overshoot of T56/r_r [-]": float(m),
                "overshoot of F_x [-]": float(t),
            }
            for label, value, m, t in zip(
                self.labels, self.values, self.measured_overshoot, self.true_overshoot, strict=True
            )
        ]


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


def run_study(
    name: str, rig: RigParameters, protocol: Protocol | None = None, output_rate: float = 1000.0
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
    """
    from rollerrig._validation import ParameterError
    from rollerrig.solve.fast import integrate_batch
    from rollerrig.solve.results import build_dataset

    if name not in STUDIES:
        raise ParameterError(f"unknown study {name!r}; choose one of {sorted(STUDIES)}")
    protocol = protocol or RELEASE_TEST
    parameter, unit, values, labels, variants = STUDIES[name](rig)
    inputs = [assemble(r, protocol, d) for r, d in variants]
    t = np.arange(int(np.floor(protocol.duration * output_rate)) + 1) / output_rate
    x, status = integrate_batch(inputs, t)
    if np.any(status != 0):
        bad = [labels[i] for i in np.flatnonzero(status)]
        raise RuntimeError(f"the fast backend failed on {bad}")
    measured, true = [], []
    for inp, xi in zip(inputs, x, strict=True):
        rows = release_overshoots(build_dataset(inp, t, xi, {}), protocol)
        measured.append(max(r["measured_overshoot [-]"] for r in rows))
        true.append(max(r["true_overshoot [-]"] for r in rows))
    return StudyResult(name, parameter, unit, values, labels, np.array(measured), np.array(true))
