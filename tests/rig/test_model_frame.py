"""The frame's degree of freedom at the contact (issue 12): rigid by default, quasi-static
compliance and its own mode when flexible."""

import numpy as np
import pytest

from rollerrig.experiment import load_protocol
from rollerrig.rig import model as m
from rollerrig.rig.assemble import assemble
from rollerrig.rig.linear import coupled_modes, linearise_twin
from rollerrig.rig.model import DriveConfig
from rollerrig.rig.parameters import default_rig
from rollerrig.solve.simulation import Simulation


@pytest.fixture(scope="module")
def rig():
    return default_rig()


@pytest.fixture(scope="module")
def runs(rig):
    protocol = load_protocol("release-test")
    return {
        frame: Simulation(rig, protocol, DriveConfig(frame=frame), output_rate=1000.0).run()
        for frame in ("rigid", "flexible")
    }


def test_a_rigid_frame_is_not_a_degree_of_freedom(rig, runs):
    assert "frame_displacement" not in runs["rigid"]
    lin = linearise_twin(rig, 30 / 3.6, 4300.0)
    assert "frame_displacement" not in lin.state_names and len(lin.state_names) == 19


def test_the_initial_state_is_an_equilibrium_with_the_frame_carrying_the_contact_force(rig):
    inputs = assemble(rig, load_protocol("release-test"), DriveConfig(frame="flexible"))
    x0, seg = inputs.initial_state, inputs.segments[0]
    dx = np.empty(m.N_STATES)
    m.rig_rhs(0.0, x0, seg.params, inputs.tables, dx)
    force = m.rig_terms(0.0, x0, seg.params, inputs.tables)[m.TERM_NAMES.index("contact_force")]
    assert x0[m.X_FRAME_X] == pytest.approx(force / rig.frame.longitudinal_stiffness, rel=1e-12)
    assert dx[m.X_FRAME_V] == pytest.approx(0.0, abs=1e-9)


def test_the_frame_follows_the_contact_force_quasi_statically_during_the_ramp(rig, runs):
    # A 48 Hz oscillator driven by a 2 s ramp: the dynamic amplification 1/(1 - (f/f_n)^2)
    # is 1 to within 1e-4, so x_f = F_x / k_f (the FE's static compliance) during the ramp.
    ds = runs["flexible"]
    ramp = (ds.time > 1.5) & (ds.time < 3.4)
    static = ds.contact_force.values / rig.frame.longitudinal_stiffness
    x = ds.frame_displacement.values
    err = np.max(np.abs(x[ramp] - static[ramp])) / np.max(np.abs(static[ramp]))
    assert err < 0.01
    # At the ramp's top the wheel torque 600 N.m over the wheel radius is the traction force
    # (less the wheel's inertia and bearing loss): 1724 N, 17 µm on a frame of 1.006e8 N/m.
    top = 600.0 / rig.geometry.wheel_radius_x / rig.frame.longitudinal_stiffness
    assert np.max(static[ramp]) == pytest.approx(top, rel=0.05)


def test_the_flexible_frame_has_its_own_mode_near_sqrt_k_over_m(rig):
    result = coupled_modes(rig, 30 / 3.6, 4300.0, drives=DriveConfig(frame="flexible"))
    frame_modes = [
        mode for mode in result.modes
        if mode.frequency and max(mode.participation, key=mode.participation.get) == "frame"
    ]  # fmt: skip
    assert len(frame_modes) == 1
    mode = frame_modes[0]
    # Closed form of the frame alone, f = sqrt(k/m)/2π = 48.1 Hz; the contact couples the
    # roller and wheel inertias through the creep damping and lowers it (46.8 Hz measured).
    assert mode.frequency == pytest.approx(rig.frame.frequency, rel=0.05)
    assert mode.damping_ratio > rig.frame.damping_ratio  # the contact's creep damping adds


def test_the_default_frame_changes_the_release_by_less_than_a_percent(runs):
    from rollerrig.studies.metrics import release_overshoots

    protocol = load_protocol("release-test")
    rigid = release_overshoots(runs["rigid"], protocol)[0]["measured_overshoot [-]"]
    flexible = release_overshoots(runs["flexible"], protocol)[0]["measured_overshoot [-]"]
    assert flexible == pytest.approx(rigid, rel=0.01)


def test_the_linearised_twin_refuses_the_dq_drive_and_names_where_it_is(rig):
    from rollerrig._validation import ParameterError

    with pytest.raises(ParameterError, match="twin_modes"):
        linearise_twin(rig, 30 / 3.6, 4300.0, drives=DriveConfig(roller="induction_dq"))
