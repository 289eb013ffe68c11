"""Assembling the solver inputs: the domain of the drives and of the steady free-rolling start.

References and the numbers pinned below:
- The bundled rig's PMSM (Kayaalp Table 1: 852 N.m rated, φ = 0.2 Wb, 44 poles) with the
  assumed inverter limit max_current = 244 A: the air-gap torque at the current limit with
  i_d = 0 is 1.5 p φ I_max = 1.5 · 22 · 0.2 · 244 = 1610.4 N.m (Kayaalp eq. 4.25).
- Steady free rolling: the roller drive supplies the bearing losses
  f_g r_b,r (W_r + N) + f_g r_b,w N r_r / r_w (bearing friction f_g = 0.007, radii 65 and
  60 mm, W_r = 5 kN, Kayaalp eqs. 4.13-4.14 times the bearing radius), about 1.0e4 N.m at
  N = 1e7 N, against the induction motor's largest torque at 30 km/h under V/f (Chapman 2012,
  eq. 6-54, with V and X scaled by f); the contact must carry the wheel's bearing loss
  f_g r_b,w N / r_w, 12.07 N at N = 10 kN, against Polach's saturation Q μ (Polach 2005).
  The ranges the errors state are checked by assembling just inside and just outside them.
"""

from __future__ import annotations

import dataclasses
import itertools
import re
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rollerrig._validation import ParameterError
from rollerrig._warnings import DomainWarning
from rollerrig.contact.creep import POLACH_DRY
from rollerrig.experiment import protocol_from_toml_string
from rollerrig.rig import model as m
from rollerrig.rig.assemble import assemble
from rollerrig.rig.model import DriveConfig
from rollerrig.rig.parameters import default_rig


def _protocol(load_kn=10.0, torque_nm=500.0, speed_kmh=30.0):
    return protocol_from_toml_string(
        f"""
[experiment]
name = "domain"
normal_load_kN = {load_kn}
roller_speed_kmh = {speed_kmh}
[[step]]
action = "ramp_torque"
to_Nm = {torque_nm}
duration_s = 1.0
"""
    )


@pytest.fixture(scope="module")
def rig():
    return default_rig()


def _dry_with(static_friction):
    return {"dry": dataclasses.replace(POLACH_DRY, static_friction=static_friction)}


# --- torque request against the wheel drive ---------------------------------------------------


def test_torque_request_of_1e5_Nm_warns_against_the_852_Nm_pmsm(rig):
    with pytest.warns(DomainWarning) as record:
        assemble(rig, _protocol(torque_nm=1e5))
    assert len(record) == 1
    message = str(record[0].message)
    assert "torque request 1e+05 N.m (protocol 'domain', t = 1 s)" in message
    assert "at most 1610 N.m at its current limit max_current = 244 A" in message
    assert "rated torque 852 N.m" in message and "saturates" in message


def test_ideal_torque_source_warns_that_the_rig_could_not(rig):
    with pytest.warns(DomainWarning, match="ideal torque source delivers it"):
        assemble(rig, _protocol(torque_nm=-2000.0), DriveConfig(wheel="ideal_torque"))


def test_requests_within_the_current_limit_do_not_warn(rig):
    # 1600 N.m is above the rated 852 N.m but below 1610.4 N.m: the inverter delivers it.
    with warnings.catch_warnings():
        warnings.simplefilter("error", DomainWarning)
        assemble(rig, _protocol(torque_nm=1600.0))
        assemble(rig, _protocol(torque_nm=720.0), DriveConfig(roller="servo"))


def test_a_wheel_beyond_its_pmsms_voltage_warns_where_the_torque_would_collapse():
    """The quarter-scale rig's wheel (r 0.1143 m) at 30 km/h turns at 72.9 rad/s, its back-EMF
    98 % of the inverter's 346 V: on the twin its torque collapsed at 45 N.m of a 912 N.m
    request (drives/pmsm_envelope.py). The Pardubice wheel at the same speed needs 30-34 %."""
    from rollerrig.experiment import load_protocol
    from rollerrig.rig.parameters import load_rig

    protocol = load_protocol("seed-30kmh-dry")
    with pytest.warns(DomainWarning, match="voltage its inverter has") as record:
        assemble(load_rig("vt-fra-quarter-scale"), protocol)
    message = next(str(r.message) for r in record if "inverter" in str(r.message))
    assert "(V_dc/√3 = 346.4 V)" in message and "the wheel at 72.91 rad/s" in message
    assert "95 % or more from t = 0 s" in message and "no field weakening" in message
    with warnings.catch_warnings():
        warnings.simplefilter("error", DomainWarning)
        assemble(default_rig(), protocol)
        # An ideal torque source has no voltage limit.
        assemble(load_rig("vt-fra-quarter-scale"), protocol, DriveConfig(wheel="ideal_torque"))


# --- a shaft so stiff that its torque is round-off ----------------------------------------------


def test_a_roller_shaft_of_1e20_nm_per_rad_warns_that_t56_is_round_off(rig):
    """The twist of a 1e20 N.m/rad shaft is below the angles' round-off: the warning names the
    resolution, and a run shows it (T56 hundreds of times the contact's torque, which the
    default shaft's T56 follows)."""
    from rollerrig.solve.fast import integrate_experiment
    from rollerrig.solve.simulation import output_times

    stiff = rig.with_overrides({"stiffness.roller_shaft": 1e20})
    with pytest.warns(DomainWarning) as record:
        inputs = assemble(stiff, _protocol())
    (message,) = [str(r.message) for r in record if "stiffness.roller_shaft" in str(r.message)]
    resolution = float(re.search(r"torque only to ([\d.e+-]+) N\.m", message).group(1))
    # 30 km/h for 1 s: the angles reach 24 rad, whose spacing is 3.6e-15 rad
    assert resolution == pytest.approx(1e20 * np.spacing(30 / 3.6 / 0.348), rel=2e-3)
    assert "a stiffness below 2.81e+13 N.m/rad keeps them within 0.1 N.m" in message
    t = output_times(inputs.protocol.duration, 250.0)
    x, _ = integrate_experiment(inputs, t)
    t56 = 1e20 * (x[:, m.X_THETA + 4] - x[:, m.X_THETA + 5])
    assert np.max(np.abs(t56)) > 100 * 500.0  # the request is 500 N.m


def test_the_rig_s_shafts_and_a_1e12_nm_per_rad_roller_shaft_do_not_warn(rig):
    with warnings.catch_warnings():
        warnings.simplefilter("error", DomainWarning)
        assemble(rig, _protocol(torque_nm=720.0))
        assemble(rig.with_overrides({"stiffness.roller_shaft": 1e12}), _protocol(torque_nm=720.0))


# --- no steady free rolling: a clear error with the range of a solution ------------------------


def test_normal_load_of_1e7_N_names_the_load_range_instead_of_a_root_finder_error(rig):
    # The Hertz contact at 1e7 N is just outside its domain too (a/R'x = 0.11): expected.
    with pytest.warns(DomainWarning, match="Hertz contact outside its domain"):
        with pytest.raises(ParameterError) as info:
            assemble(rig, _protocol(load_kn=1e4))
    message = str(info.value)
    assert "different signs" not in message
    assert "no steady free rolling at 30 km/h and normal load 1e+07 N" in message
    assert "roller drive (induction) must supply the bearing losses, 1.001e+04 N.m" in message
    limit = float(re.search(r"normal loads below about ([\d.e+]+) N", message).group(1))
    # 1.94 MN: the AM's breakdown torque with R_s = 0.085 ohm per delta phase (2.07 MN at the
    # former 0.045 ohm); the statement below checks the range itself
    assert limit == pytest.approx(1.94e6, rel=0.01)
    # the stated range is true: just inside it the rig starts, just outside it does not
    assemble(rig, _protocol(load_kn=0.99 * limit / 1e3))
    with pytest.raises(ParameterError, match="no steady free rolling"):
        assemble(rig, _protocol(load_kn=1.01 * limit / 1e3))


def test_servo_roller_drive_names_its_torque_limit(rig):
    with pytest.raises(ParameterError, match=r"roller drive \(servo\).*servo torque_limit"):
        assemble(rig, _protocol(load_kn=2e3), DriveConfig(roller="servo"))


def test_static_friction_of_1e_6_names_the_friction_range(rig):
    with pytest.raises(ParameterError) as info:
        assemble(rig, _protocol(), friction_sets=_dry_with(1e-6))
    message = str(info.value)
    assert "different signs" not in message
    # 12.06 N: the drag F_x < 0 lowers the contact's load through the arm (N = S + 0.497 F_x)
    assert "wheel's bearing loss, F_x = 12.06 N" in message
    assert "friction set 'dry' (static_friction mu0 = 1e-06)" in message
    low = float(re.search(r"static_friction above about ([\d.e+-]+)", message).group(1))
    assert low == pytest.approx(1.21e-3, rel=0.01)
    assemble(rig, _protocol(), friction_sets=_dry_with(1.05 * low))
    with pytest.raises(ParameterError, match="static_friction above about"):
        assemble(rig, _protocol(), friction_sets=_dry_with(0.95 * low))


@pytest.mark.parametrize("speed_kmh, load_kn", [(2.0, 350.0), (30.0, 1900.0)])
def test_steady_state_far_down_the_drive_characteristic_is_found(rig, speed_kmh, load_kn):
    # At 2 km/h and 350 kN the V/f motor delivers the losses far below the set speed, and at
    # 30 km/h and 1.9 MN close to its breakdown torque (with R_s = 0.085 ohm per delta phase the
    # limits are 371 kN and 1.94 MN, from the messages of the next tests): both outside the
    # former root bracket [0.5, 1.5] x set speed or at its edge. The state found is steady
    # (every acceleration vanishes, as in tests/rig/test_model.py) and on the stable branch
    # (rotor below the set speed, torque falling with rotor speed).
    inputs = assemble(rig, _protocol(load_kn=load_kn, speed_kmh=speed_kmh, torque_nm=100.0))
    p, x0 = inputs.segments[0].params, inputs.initial_state
    dx = np.empty(m.N_STATES)
    m.rig_rhs(0.0, x0, p, inputs.tables, dx)
    scale = 1.0 + np.abs(x0[m.X_T_ROLLER])
    assert np.max(np.abs(dx[m.X_OMEGA : m.X_OMEGA + 7] * p[m.P_J : m.P_J + 7])) < 1e-6 * scale
    omega_ref = speed_kmh / 3.6 / p[m.P_RR]
    omega = x0[m.X_OMEGA + 5]
    assert 0.0 < omega < omega_ref
    slope = m._open_loop_roller_torque(omega + 1e-6, omega_ref, p) - m._open_loop_roller_torque(
        omega - 1e-6, omega_ref, p
    )
    assert slope < 0.0


@settings(max_examples=80, deadline=None)
@given(
    scale=st.floats(1e-9, 1e3),
    slope=st.floats(1e-3, 1e6),
    level=st.floats(0.01, 0.99),
    xtol=st.sampled_from([1e-15, 1e-13, 1e-9]),
)
def test_bracketed_root_agrees_with_brentq(scale, slope, level, xtol):
    # Reference: scipy.optimize.brentq on the same rising curve (a creep-force-like
    # saturating branch, tanh, over [0, scale]); the rig's assembly no longer imports it.
    from scipy.optimize import brentq

    from rollerrig.rig.assemble import _bracketed_root

    def fun(d):
        return np.tanh(slope * np.asarray(d) / scale)

    needed = level * float(fun(scale))
    ours = _bracketed_root(fun, needed, 0.0, scale, xtol)
    theirs = brentq(lambda d: float(fun(d)) - needed, 0.0, scale, xtol=xtol)
    tolerance = 2 * xtol + 8 * np.finfo(float).eps * scale
    assert abs(ours - theirs) <= tolerance or abs(float(fun(ours)) - needed) <= 4e-16


@pytest.mark.parametrize("roller", ["induction", "ideal_speed"])
def test_a_single_piece_protocols_tables_are_not_read_as_a_segments_line(rig, roller):
    """A protocol that is one speed ramp has every input as one piece (two breakpoints); the
    model reads a two-node table as a segment's line, closed at its end (model.segment_tables),
    so the assembled tables are padded to three nodes: at the ramp's end, the protocol's, the
    whole table's slope is right-continuous, 0, as everywhere else."""
    from rollerrig.experiment import Protocol, SetRollerSpeed

    protocol = Protocol.from_steps(
        "ramp", [SetRollerSpeed(20 / 3.6, 1.0)], normal_load=4300.0, roller_speed=10 / 3.6
    )
    inputs = assemble(rig, protocol, drives=DriveConfig(roller=roller))
    assert inputs.tables.shape[1] >= m.MIN_TABLE_NODES > m.SEGMENT_NODES
    assert m._interp_slope(0.5, inputs.tables, m.TAB_SPEED_T, m.TAB_SPEED) > 0.0
    assert m._interp_slope(1.0, inputs.tables, m.TAB_SPEED_T, m.TAB_SPEED) == 0.0


@pytest.mark.parametrize("where", ["start", "end"])
def test_a_breakpoint_a_rounding_error_from_an_end_leaves_the_segments_covering_the_experiment(
    where,
):
    """A breakpoint 1e-13 s after the start or before the end had its span dropped, so the
    segments began after 0 (the first output instant outside them: refused) or ended before
    the duration (the last output instant past the last segment). It is merged into its
    neighbour's segment; the run covers every output instant."""

    from rollerrig.experiment import load_protocol
    from rollerrig.solve.simulation import Simulation

    protocol = load_protocol("seed-10kmh-wet")
    tiny = 1e-13 if where == "start" else protocol.duration - 1e-13
    times = np.sort(np.append(protocol.torque_time, tiny))
    request = np.interp(times, protocol.torque_time, protocol.torque_request)
    odd = dataclasses.replace(protocol, torque_time=times, torque_request=request)
    inputs = assemble(default_rig(), odd)
    assert inputs.segments[0].start == 0.0
    assert inputs.segments[-1].end == protocol.duration
    assert all(a.end == b.start for a, b in itertools.pairwise(inputs.segments))
    assert all(s.end - s.start > 1e-12 for s in inputs.segments)
    ds = Simulation(experiment=odd).run()
    assert np.all(np.isfinite(ds.t56.values))


def test_assemble_names_a_rig_or_drives_of_another_type():
    from rollerrig.experiment import load_protocol
    from rollerrig.rig.parameters import default_rig

    protocol = load_protocol("release-test")
    with pytest.raises(ParameterError, match=re.escape("drives must be a DriveConfig or None")):
        assemble(default_rig(), protocol, "pmsm")
    with pytest.raises(ParameterError, match=re.escape("rig must be a RigParameters, got")):
        assemble(None, protocol)
