"""The twin with a creep law of the FASTSIM family: both backends agree (issue 19, point 2).

A torque pulse past the dry adhesion limit at 4.3 kN (about 700 N.m at the wheel): the contact
runs up the creep curve, over its peak into macro-slip and back after the release, so the table
is used on both branches.
"""

import json

import numpy as np
import pytest

from rollerrig.experiment import Hold, Protocol, RampTorque, ReleaseTorque
from rollerrig.rig.model import DriveConfig
from rollerrig.solve.simulation import Simulation

BACKEND_T56_TOLERANCE = 1.0
"""max |ΔT56| [N.m] between the fast backend and the reference (Radau, rtol 1e-9): the issue's
accuracy target for the twin (tests/solve/test_simulation.py)."""


@pytest.fixture(scope="module")
def pulse():
    return Protocol.from_steps(
        "pulse-past-adhesion",
        [Hold(0.2), RampTorque(900.0, 0.6), ReleaseTorque(), Hold(0.5)],
        normal_load=4300.0,
        roller_speed=30 / 3.6,
    )


def _run(pulse, law, solver):
    return Simulation(
        experiment=pulse, drives=DriveConfig(law=law), solver=solver, output_rate=500.0
    ).run()


@pytest.mark.parametrize("law", ["fastsim", "modified-fastsim"])
def test_fast_and_reference_backends_agree_with_a_tabulated_law(pulse, law):
    fast = _run(pulse, law, "fast")
    ref = _run(pulse, law, "reference")
    assert np.max(np.abs(fast.t56.values - ref.t56.values)) < BACKEND_T56_TOLERANCE
    # The contact force itself within 10 N (measured 5.9 N, 0.8 %, in macro-slip past the
    # peak, where the contact's mode on the falling branch is least damped; 5.4 N on the 30 s
    # seed-30kmh-dry).
    np.testing.assert_allclose(
        fast.contact_force.values, ref.contact_force.values, rtol=0, atol=10.0
    )
    assert json.loads(fast.attrs["provenance"])["drives"]["law"] == law


def test_the_law_changes_the_run_and_fastsim_saturates_at_mu_n(pulse):
    polach = _run(pulse, "polach", "fast")
    fastsim = _run(pulse, "fastsim", "fast")
    # Different laws, different creep (FASTSIM lies above Polach before saturation).
    assert np.max(np.abs(fastsim.creep.values - polach.creep.values)) > 1e-4
    # The contact force never exceeds μN (the table's saturated value is 1.0006 μN on the
    # discrete 30×30 grid).
    coa = np.abs(fastsim.contact_force.values) / (
        fastsim.normal_load.values * fastsim.friction_coefficient.values
    )
    assert coa.max() <= 1.0007
