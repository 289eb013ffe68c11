"""Synthetic recordings for the calibration tests: the twin with parameters the calibration is
not told, through the disturbance model of :mod:`rollerrig.recordings.synthetic` (noise, the motor
and order lines, quantised encoders, the air-spring pressure's noise).

The data come from :class:`~rollerrig.solve.simulation.Simulation` as a user makes them (the
fast backend's own settings, which the calibration's replay shares; see
:class:`rollerrig.calibrate.model.ReplayModel`).
"""

import dataclasses

import numpy as np
import pytest

from rollerrig.contact.creep import POLACH_DRY
from rollerrig.experiment import Hold, Protocol, RampTorque, ReleaseTorque
from rollerrig.recordings.synthetic import synthetic_recording
from rollerrig.rig.parameters import default_rig
from rollerrig.solve.simulation import Simulation

TRUTH = {
    "stiffness.roller_shaft": 43500.0 * 1.1,
    "bearing.friction_coefficient": 0.007 * 1.3,
    "induction_motor.response_lag_clp": 2.75 * 0.8,
    "inertia.roller": 45.0 * 1.05,
}
"""Rig values of the synthetic tests (the bundled rig's start: 43.5 kN.m/rad, 0.007, 2.75 1/s,
45 kg.m^2)."""

TRUE_FRICTION = dataclasses.replace(POLACH_DRY, static_friction=0.52)
"""The recording's friction law (the calibration starts from the dry set, mu0 = 0.55)."""


def short_test() -> Protocol:
    """One adhesion cycle at 30 km/h, 4.3 kN: 1 s free rolling, ramp to 720 N.m in 3 s (past
    the adhesion peak), hold 0.5 s, sudden release, 3 s rest: 7.52 s."""
    return Protocol.from_steps(
        "calibration-test",
        [Hold(1.0), RampTorque(720.0, 3.0), Hold(0.5), ReleaseTorque(), Hold(3.0)],
        normal_load=4300.0,
        roller_speed=30 / 3.6,
    )


def make_recording(truth=None, seed=0, friction=None, protocol=None, law="polach"):
    """(recording, truth dataset) of the twin with ``truth`` overrides, ``friction`` and the
    creep law ``law``."""
    from rollerrig.rig.model import DriveConfig

    rig = default_rig().with_overrides(TRUTH if truth is None else truth)
    sets = None if friction is None else {"dry": friction}
    sim = Simulation(
        rig,
        short_test() if protocol is None else protocol,
        drives=DriveConfig(law=law),
        friction_sets=sets,
    )
    return synthetic_recording(sim.run(), seed=seed)


@pytest.fixture(scope="session")
def recording_maker():
    return make_recording


@pytest.fixture(scope="session")
def altered_recording():
    """One short synthetic test with :data:`TRUTH` and :data:`TRUE_FRICTION` (seed 4)."""
    return make_recording(seed=4, friction=TRUE_FRICTION)


@pytest.fixture(scope="session")
def truth_values():
    return dict(TRUTH) | {"polach.static_friction": TRUE_FRICTION.static_friction}


def random_truth(rng: np.random.Generator, spread: float = 0.03) -> dict:
    """:data:`TRUTH` with each value scaled by exp(U(-spread, spread))."""
    return {k: v * float(np.exp(rng.uniform(-spread, spread))) for k, v in TRUTH.items()}


@pytest.fixture(scope="session")
def truth_drawer():
    return random_truth


# --------------------------------------------------------------------------------------------
# calibration.json as rollerrig calibrate writes it (no fit): tests of calibfile and binding
# --------------------------------------------------------------------------------------------

CALIBRATED = {
    "stiffness.roller_shaft": (47850.0, 1.7, 43500.0),
    "inertia.roller": (45.2, 0.01, 45.0),
}


def _entry(value, se, initial, unit):
    return {
        "value": value,
        "standard_error": se,
        "unit": unit,
        "initial": initial,
        "identified": True,
        "relative_standard_error": se / value,
        "at_upper_bound": False,
    }


def _calibration_doc(rig=None) -> dict:
    """A calibration.json as ``rollerrig calibrate`` writes it, made on ``rig`` (default: the
    bundled rig) with two identified keys and one that is not."""
    from rollerrig.calibrate.binding import rig_binding
    from rollerrig.output import rig_sha256

    rig = default_rig() if rig is None else rig
    units = {"stiffness.roller_shaft": "N.m/rad", "inertia.roller": "kg.m^2"}
    params = {k: _entry(v, se, i, units[k]) for k, (v, se, i) in CALIBRATED.items()}
    params["damping.wheel_shaft"] = {
        "value": None,
        "standard_error": None,
        "unit": "N.m.s/rad",
        "initial": 10.0,
        "identified": False,
        "why_null": "relative standard error 3.2 > 0.5",
    }
    keys = [*CALIBRATED, "experiment.roller_speed"]
    return {
        "parameters": params,
        "values": {k: v for k, (v, _, _) in CALIBRATED.items()},
        "correlation": {
            "keys": keys,
            "matrix": [[1.0, 0.1, 0.0], [0.1, 1.0, -0.2], [0.0, -0.2, 1.0]],
        },
        "warnings": ["damping.wheel_shaft: relative standard error 3.2 > 0.5"],
        "recording": {"source": "test.tdms"},
        "rig": rig_binding(rig, CALIBRATED),
        "provenance": {"software": "rollerrig", "inputs": {}, "rig": {"sha256": rig_sha256(rig)}},
    }


@pytest.fixture(scope="session")
def calibration_doc():
    """``calibration_doc(rig=None)``: a calibration.json as ``rollerrig calibrate`` writes it,
    made on ``rig`` (default: the bundled rig), with :data:`CALIBRATED` identified and
    ``damping.wheel_shaft`` not."""
    return _calibration_doc
