"""ETDRK4 (issue 20): the φ-functions, the step's stability, accuracy against Radau at rtol
1e-10 (max |ΔT56| on the 250 Hz grid) for the default twin, the flexible frame, the dq drive and
the hard case, the fallback near standstill, the step-error guard (macro-slip at low speed), and
the truth channels at 4 kHz."""

import numpy as np
import pytest
import scipy.linalg
from hypothesis import given, settings
from hypothesis import strategies as st

from rollerrig.experiment import (
    Hold,
    Protocol,
    RampTorque,
    ReleaseTorque,
    SetRollerSpeed,
    load_protocol,
    protocol_from_toml_string,
)
from rollerrig.rig.assemble import assemble
from rollerrig.rig.model import DriveConfig
from rollerrig.rig.parameters import default_rig
from rollerrig.solve import etdrk4
from rollerrig.solve.etdrk4 import eigenvalues_of_coupled_part, phi_functions, rk4_stable_step
from rollerrig.solve.fast import (
    CURRENT_BLOCKS,
    FAST_DEFAULTS,
    IDEAL_SPEED_EXP_STEP,
    SWEEP_EXP_STEP,
    _exp_settings,
    integrate_batch,
    integrate_experiment,
    sweep_settings,
)
from rollerrig.solve.reference import integrate_reference
from rollerrig.solve.simulation import Simulation, output_times


def _t56(inputs, x):
    k56 = inputs.rig.stiffness.roller_shaft
    b56 = inputs.rig.damping.roller_shaft
    return k56 * (x[:, 4] - x[:, 5]) + b56 * (x[:, 11] - x[:, 12])


@pytest.mark.parametrize("n", [1, 2, 3])
@pytest.mark.parametrize("scale", [1e-6, 0.3, 3.0, 40.0])
def test_phi_functions_are_the_blocks_of_the_augmented_exponential(n, scale):
    """exp([[Z, I, 0, 0], [0, 0, I, 0], [0, 0, 0, I], [0, 0, 0, 0]]) holds e^Z, φ1, φ2, φ3 in
    its first block row (Saad 1992); the same of Z/2 gives e^{Z/2}, φ1(Z/2)."""
    rng = np.random.default_rng(n * 100 + int(scale * 10))
    z = rng.normal(size=(n, n)) * scale
    out = [np.empty((n, n)) for _ in range(6)]
    phi_functions(z, n, *out)

    def first_row(zz):
        a = np.zeros((4 * n, 4 * n))
        a[:n, :n] = zz
        for k in range(3):
            a[k * n : (k + 1) * n, (k + 1) * n : (k + 2) * n] = np.eye(n)
        e = scipy.linalg.expm(a)
        return [e[:n, k * n : (k + 1) * n] for k in range(4)]

    expected = first_row(z) + first_row(z / 2)[:2]
    for got, want in zip(out, expected, strict=True):
        np.testing.assert_allclose(got, want, rtol=1e-11, atol=1e-13 * max(1.0, np.abs(want).max()))


@given(
    st.lists(st.floats(-1e3, 1e3, allow_subnormal=False), min_size=4, max_size=4),
    st.floats(-9.0, 2.5),
)
@settings(max_examples=300, deadline=None)
def test_the_2x2_phi_functions_are_the_general_code_s_numbers(entries, log_scale):
    """The scalar 2 x 2 path takes the loops' operations in their order: the same numbers, at
    every scaling from tiny to large, up to rounding. As Python the two give the same bits;
    compiled, LLVM rounds the loops' sums differently at times, and the doublings carry that
    on, about 2^s ulp after s doublings (1 ulp of φ2 at the entries [0, 0, 1, 3]/1e3, 7 ulp at
    [1, 1, 31, 0]/10, 2e-13 relative at [0, 1.5, 423.5, 578]·10^-0.5 with s = 10, found by
    Hypothesis on 2026-12-01: the test had compared bits, and failed there on every commit
    since the 2 x 2 path). A wrong term or order of the doublings moves them by far more."""
    z = np.zeros((3, 3))
    z[:2, :2] = np.reshape(entries, (2, 2)) / 1e3 * 10.0**log_scale
    fast_out = [np.zeros((3, 3)) for _ in range(6)]
    loop_out = [np.zeros((3, 3)) for _ in range(6)]
    etdrk4._phi_2x2(z, *fast_out)
    etdrk4._phi_general(z, 2, *loop_out, np.empty((2, 3, 3)))
    for got, want in zip(fast_out, loop_out, strict=True):
        scale = max(1.0, float(np.abs(want).max()))
        np.testing.assert_allclose(got, want, rtol=1e-11, atol=1e-13 * scale)


def test_eigenvalues_of_a_matrix_with_a_non_finite_entry_raise():
    jac = np.array([[-1.0, 2.0], [3.0, np.nan]])
    with pytest.raises(np.linalg.LinAlgError, match="non-finite"):
        eigenvalues_of_coupled_part(jac)


@given(st.integers(1, 9), st.integers(0, 2**31 - 1), st.floats(0.0, 0.9))
@settings(max_examples=200, deadline=None)
def test_the_uncoupled_states_split_off_leave_the_eigenvalues_as_they_were(n, seed, sparsity):
    """Taking out the states with nothing off the diagonal in their row or column (their
    diagonal entry is an eigenvalue), again and again as each leaves, gives the spectrum
    numpy finds for the whole matrix (simple eigenvalues here, so that both are accurate)."""
    rng = np.random.default_rng(seed)
    jac = rng.normal(size=(n, n)) * 1e3 * (rng.random((n, n)) >= sparsity)
    np.fill_diagonal(jac, rng.uniform(-2e3, 2e3, n))
    for i in rng.choice(n, size=rng.integers(0, n + 1), replace=False):
        off = np.arange(n) != i
        if rng.random() < 0.5:
            jac[i, off] = 0.0
        else:
            jac[off, i] = 0.0
    got = list(eigenvalues_of_coupled_part(jac))
    want = np.linalg.eigvals(jac).astype(complex)
    assert len(got) == n
    for w in want:  # as multisets: each matched to the nearest one left
        k = int(np.argmin([abs(v - w) for v in got]))
        assert abs(got.pop(k) - w) <= 1e-6 * 2e3 * n


def test_the_stable_step_keeps_rk4_inside_its_region_with_a_margin():
    # RK4 is stable on the negative real axis up to h|λ| = 2.785, on the imaginary to 2.828.
    h = rk4_stable_step(np.array([-1000.0 + 0j]), 1.0)
    assert 2.785 / 1000 / 1.25 * 0.9 < h <= 2.785 / 1000 / 1.25
    h = rk4_stable_step(np.array([-1.0 + 2000.0j, -1.0 - 2000.0j]), 1.0)
    assert 2.828 / 2000 / 1.25 * 0.9 < h <= 2.828 / 2000 / 1.25
    # Growth of the physics (and rigid-body modes) is no limit; a step below that is kept.
    assert rk4_stable_step(np.array([0.0 + 0j, 5.0 + 1.0j]), 1e-3) == 1e-3


@pytest.fixture(scope="module")
def seed():
    sim = Simulation(experiment="seed-30kmh-dry")
    ref, stats = integrate_reference(sim.inputs, sim.times, rtol=1e-10)
    assert stats["status"] == 0
    return sim, ref


@pytest.mark.slow
def test_the_default_twin_is_within_0_05_nm_of_radau_1e_10(seed):
    """The issue's target: max |ΔT56| <= 0.05 N.m on the 250 Hz grid of the 30 s dry test
    (0.027 N.m measured, in 18 750 steps of 1.6 ms, no segment left to the fallback)."""
    sim, ref = seed
    x, stats = integrate_experiment(sim.inputs, sim.times)
    assert stats["status"] == 0 and stats["method"] == "etdrk4"
    assert stats["fallback_segments"] == 0
    assert np.max(np.abs(_t56(sim.inputs, x) - _t56(sim.inputs, ref))) <= 0.05
    # Speeds within 0.1 % (as test_simulation.py asks of the fast backend).
    np.testing.assert_allclose(x[:, 7:14], ref[:, 7:14], rtol=1e-3, atol=2e-2)
    # Fourth order: a step 1.6x shorter is about 1.6^4 = 6.5x more accurate.
    x_fine, _ = integrate_experiment(sim.inputs, sim.times, exp_step=1e-3)
    assert np.max(np.abs(_t56(sim.inputs, x_fine) - _t56(sim.inputs, ref))) <= 0.01


def _pulse(load, speed_kmh, torque):
    return Protocol.from_steps(
        "pulse",
        [Hold(0.3), RampTorque(torque, 0.6), Hold(0.3), ReleaseTorque(), Hold(1.5)],
        normal_load=load,
        roller_speed=speed_kmh / 3.6,
    )


@pytest.mark.slow
@pytest.mark.parametrize(
    ("drives", "load", "speed", "torque", "limit"),
    [
        (DriveConfig(frame="flexible"), 4300.0, 30.0, 700.0, 0.05),
        (DriveConfig(roller="induction_dq"), 4300.0, 30.0, 700.0, 0.05),
        (DriveConfig(wheel="ideal_torque", roller="servo"), 4300.0, 30.0, 700.0, 0.05),
        # The hard case: the contact's pole at -12 000 1/s, only the re-linearised contact block
        # keeps RK4 stable at 1.6 ms (measured 0.085 N.m on a 4 s pulse).
        (DriveConfig(), 20000.0, 10.0, 1400.0, 0.2),
        # The ideal speed source: the ringing after the release hardly damped, RK4's phase
        # error in it adds up unseen by the guard; 0.4 ms by default (IDEAL_SPEED_EXP_STEP).
        (DriveConfig(roller="ideal_speed"), 20000.0, 10.0, 1400.0, 0.1),
    ],
    ids=["flexible-frame", "dq-drive", "servo-ideal-wheel", "20kN-10kmh-1400Nm", "ideal-speed"],
)
def test_drives_frames_and_the_hard_case_against_radau(drives, load, speed, torque, limit):
    """Against Radau at rtol 1e-9: within 2e-5 N.m of rtol 1e-10 on each of these pulses
    (measured: flexible frame 1.8e-7, dq 1.2e-6, servo 5.9e-7, hard case 1.5e-5, ideal speed
    3.6e-5), a reference over 2 000 times closer than the limits, at a third of its cost (the
    flexible frame 16 -> 5.6 s). The default twin's test above keeps rtol 1e-10, the issue's
    target. The ideal speed source's case measured 0.068 N.m at its 0.4 ms (at the default
    drives' 1.6 ms: 0.99, with the step-error guard silent)."""
    inputs = assemble(default_rig(), _pulse(load, speed, torque), drives)
    t = output_times(inputs.protocol.duration, 250.0)
    ref, _ = integrate_reference(inputs, t, rtol=1e-9)
    x, stats = integrate_experiment(inputs, t)
    assert stats["status"] == 0 and stats["fallback_segments"] == 0
    assert np.max(np.abs(_t56(inputs, x) - _t56(inputs, ref))) <= limit


@pytest.mark.slow
def test_a_sweep_s_settings_hold_a_sweep_s_accuracy_in_fewer_steps(seed):
    """Issue 20's sweeps: 0.1 N.m of T56 (a single run's 0.05), for at least 1.15 times fewer
    steps (measured on the 30 s dry test 2026-12-03: 0.06 N.m in 15 000 steps against 0.0275
    in 18 753), and the batch of the sweeps' settings gives the single runs' states."""
    sim, ref = seed
    x, stats = integrate_experiment(sim.inputs, sim.times, sweep=True)
    default_steps = integrate_experiment(sim.inputs, sim.times)[1]["accepted_steps"]
    assert stats["status"] == 0 and stats["fallback_segments"] == 0
    assert np.max(np.abs(_t56(sim.inputs, x) - _t56(sim.inputs, ref))) <= 0.1
    assert stats["accepted_steps"] * 1.15 <= default_steps
    xb, _ = integrate_batch([sim.inputs, sim.inputs], sim.times, **sweep_settings())
    np.testing.assert_array_equal(xb[1], x)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("drives", "load", "speed", "torque", "limit"),
    [
        (DriveConfig(frame="flexible"), 4300.0, 30.0, 700.0, 0.1),
        (DriveConfig(roller="servo"), 4300.0, 30.0, 700.0, 0.1),
        # The hard case is beyond a sweep's 0.1 N.m (measured 0.233 N.m; default 0.079).
        (DriveConfig(), 20000.0, 10.0, 1400.0, 0.3),
        # The PMSM at its voltage limit: the wheel spinning up past the adhesion at 60 km/h
        # (18 of 681 samples at the limit), at it throughout at 120 km/h.
        (DriveConfig(), 4300.0, 60.0, 1400.0, 0.1),
        (DriveConfig(), 4300.0, 120.0, 1400.0, 0.1),
    ],
    ids=["flexible-frame", "servo", "20kN-10kmh-1400Nm", "voltage-limit-60kmh", "limit-120kmh"],
)
def test_a_sweep_s_settings_against_radau(drives, load, speed, torque, limit):
    """Measured 2026-12-03 against Radau at rtol 1e-9: the flexible frame 0.094 N.m, the
    servo 0.092, the hard case 0.233 (the default settings 0.023, 0.022 and 0.079). At the
    PMSM's voltage limit the currents' loops are not the linear loops the sweep takes exactly
    (the frozen diagonal -1 337 1/s against -490 to -740 there, and d-q cross terms): taken
    exactly anyway, 1.84 and 0.76 N.m with the step-error guard silent; a segment that meets
    the limit, and the one after it, is integrated as a single run integrates it: 0.043 and
    0.065, and at 120 km/h, at the limit throughout, in the single run's steps (an attempt
    first in every segment had taken 3 161 against 1 718)."""
    inputs = assemble(default_rig(), _pulse(load, speed, torque), drives)
    t = output_times(inputs.protocol.duration, 250.0)
    ref, _ = integrate_reference(inputs, t, rtol=1e-9)
    x, stats = integrate_experiment(inputs, t, sweep=True)
    assert stats["status"] == 0
    assert np.max(np.abs(_t56(inputs, x) - _t56(inputs, ref))) <= limit
    if speed >= 120.0:
        single = integrate_experiment(inputs, t)[1]
        assert stats["accepted_steps"] <= single["accepted_steps"]


def test_a_state_of_its_own_goes_to_the_diagonal_not_the_rows():
    """1 x 1 blocks (the currents in a sweep) are applied as scalars, not as rows padded to
    three columns; the others' rows are as before (the result is the same to the bit: a padded
    row adds only exact zeros)."""
    blocks = np.array([[0, 7, -1], [14, -1, -1], [10, 11, -1], [15, -1, -1]], dtype=np.int64)
    sizes = etdrk4._block_sizes(blocks)
    cols, rows, first, local, diag, slot = etdrk4._block_rows(blocks, sizes)
    assert rows.tolist() == [0, 7, 10, 11] and diag.tolist() == [14, 15]
    assert slot.tolist() == [-1, 0, -1, 1] and first.tolist() == [0, 2, 2, 4, 4]
    assert cols[2].tolist() == [10, 11, 10] and local[2].tolist() == [2, 3, 2]


@pytest.mark.parametrize(
    ("drives", "current_blocks", "step"),
    [
        (DriveConfig(), True, SWEEP_EXP_STEP),
        (DriveConfig(wheel="ideal_torque"), False, SWEEP_EXP_STEP),  # no currents to take
        # its ringing: 0.4 ms, below the current loops' limit, so no blocks that buy nothing
        (DriveConfig(roller="ideal_speed"), False, IDEAL_SPEED_EXP_STEP),
    ],
)
def test_a_sweep_takes_the_currents_exactly_and_a_longer_step(drives, current_blocks, step):
    inputs = assemble(default_rig(), _pulse(4300.0, 30.0, 700.0), drives)
    _, h, _, static, _, _, _ = _exp_settings(inputs, None, None, None, None, sweep=True)
    assert h == step
    has = any((row == CURRENT_BLOCKS[0]).all() for row in static)
    assert has == current_blocks and static.shape[0] == 2 + 2 * current_blocks
    # A single run keeps the mounts only and the default step; a cap caps the sweep's step.
    single = _exp_settings(inputs, None, None, None, None)
    assert single[3].shape[0] == 2 and single[1] == min(step, FAST_DEFAULTS["exp_step"])
    assert _exp_settings(inputs, None, None, None, 1e-3, sweep=True)[1] == min(step, 1e-3)


LOAD_DROP = """
[experiment]
name = "load-drop-under-torque"
normal_load_kN = 4.3
friction = "dry"
roller_speed_kmh = 10
[[step]]
action = "hold"
duration_s = 0.2
[[step]]
action = "set_normal_load"
to_kN = 20
duration_s = 0.3
[[step]]
action = "ramp_torque"
to_Nm = 1400
duration_s = 0.5
[[step]]
action = "set_normal_load"
to_kN = 4.3
duration_s = 0.01
[[step]]
action = "hold"
duration_s = 0.5
"""


@pytest.mark.slow
def test_a_fast_input_transition_re_linearises_the_contact_every_step():
    """The load dropped from 20 to 4.3 kN in 10 ms under 1 400 N.m at 10 km/h (macro-slip at
    once): with the contact linearised once for that 6-step segment the run was off by
    2.5 N.m against Radau, the step-error guard silent (it sees only RK4's states); a segment
    shorter than two re-linearisation intervals re-linearises every step (0.076 N.m on a
    longer version of this test, 2026-11-30)."""
    inputs = assemble(default_rig(), protocol_from_toml_string(LOAD_DROP))
    t = output_times(inputs.protocol.duration, 250.0)
    ref, _ = integrate_reference(inputs, t, rtol=1e-9)
    x, stats = integrate_experiment(inputs, t)
    assert stats["status"] == 0
    assert np.max(np.abs(_t56(inputs, x) - _t56(inputs, ref))) <= 0.2


@pytest.mark.parametrize("step", [0.5e-3, 1.6e-3])
def test_an_ideal_speed_source_holds_the_rotor_on_its_ramp_through_the_ramps_end(step):
    """The ideal speed source gives the rotor exactly the set point's acceleration, so the
    rotor's speed is the set point to round-off at any step. At a segment's last step the
    last stage must see the segment's own acceleration: taken at ``t + h``, which rounds past
    the end of the ramp [2.5, 3.5] s at a 0.5 ms step, it saw the hold's 0, and with the
    acceleration of a two-node table 0 at its end at every step; the rotor lost up to a third
    of a step's speed change (5e-4 rad/s; 0.9 N.m of T56 in the ringing after it,
    2026-11-30)."""
    from rollerrig.experiment import SetRollerSpeed
    from rollerrig.rig import model as m

    protocol = Protocol.from_steps(
        "ramp-end",
        [Hold(2.5), SetRollerSpeed(20 / 3.6, 1.0), Hold(0.05)],
        normal_load=20e3,
        roller_speed=10 / 3.6,
    )
    inputs = assemble(default_rig(), protocol, drives=DriveConfig(roller="ideal_speed"))
    t = np.array([0.0, 3.0, 3.4995, 3.5, 3.55])
    x, stats = integrate_experiment(inputs, t, exp_step=step)
    assert stats["status"] == 0 and stats["fallback_segments"] == 0
    set_point = np.interp(t, inputs.tables[m.TAB_SPEED_T], inputs.tables[m.TAB_SPEED])
    r_r = inputs.segments[0].params[m.P_RR]
    np.testing.assert_allclose(x[:, m.X_OMEGA + 5], set_point / r_r, rtol=0, atol=1e-9)


STANDSTILL = """
[experiment]
name = "from-standstill"
normal_load_kN = 4.3
friction = "dry"
roller_speed_kmh = 0
[[step]]
action = "hold"
duration_s = 0.3
[[step]]
action = "set_roller_speed"
to_kmh = 5
duration_s = 1.0
[[step]]
action = "hold"
duration_s = 0.5
"""


def test_from_standstill_the_ramp_goes_to_the_fallback_and_stays_accurate():
    """Through standstill (the bearings' friction regularised, the creep's too) the hold keeps
    ETDRK4's stable step; the ramp up from standstill goes to the fallback (the V/f drive's
    zero frequency: :data:`rollerrig.solve.fast.STOP_SPEED`). Measured 0.011 N.m against
    Radau 1e-9 (ETDRK4 on the ramp as well: 0.015)."""
    inputs = assemble(default_rig(), protocol_from_toml_string(STANDSTILL))
    t = output_times(inputs.protocol.duration, 250.0)
    x, stats = integrate_experiment(inputs, t)
    assert stats["status"] == 0 and stats["fallback_segments"] == 1
    ref, _ = integrate_reference(inputs, t, rtol=1e-9)
    assert np.max(np.abs(_t56(inputs, x) - _t56(inputs, ref))) < 0.05


@pytest.mark.parametrize("compiles", [True, False])
def test_the_caller_is_told_before_the_fallback_compiles(monkeypatch, compiles):
    """Which segments go to ROS34PW2 is known only by running them; where its driver is not
    compiled yet (its first use on an installation, 10-20 s) ``notify`` is told so, naming
    the segment, before it compiles, so that a progress bar's stall is explained."""
    from rollerrig.solve import fast

    monkeypatch.setattr(fast, "_will_compile", lambda dispatcher: compiles)
    inputs = assemble(default_rig(), protocol_from_toml_string(STANDSTILL))
    t = output_times(inputs.protocol.duration, 250.0)
    told = []
    x, stats = integrate_experiment(inputs, t, notify=told.append)
    assert stats["fallback_segments"] == 1
    if compiles:
        assert len(told) == 1
        assert "t = 0.3 s" in told[0] and "ROS34PW2" in told[0] and "compiles now" in told[0]
    else:
        assert told == []
    np.testing.assert_array_equal(x, integrate_experiment(inputs, t)[0])


def _ramp_through_standstill(direction):
    """The roller ramped under 200 N.m from 3 km/h to standstill (``"stop"``), or from
    standstill to 5 km/h (``"start"``: the V/f supply is off at standstill, so the wheel's
    torque has turned the roller ahead of its set point when the ramp begins); held, released.
    """
    if direction == "stop":
        steps = [Hold(0.3), RampTorque(200.0, 0.5), SetRollerSpeed(0.0, 2.0), Hold(0.5)]
        start_speed = 3 / 3.6
    else:
        steps = [Hold(0.3), RampTorque(200.0, 0.3), SetRollerSpeed(5 / 3.6, 1.5), Hold(0.5)]
        start_speed = 0.0
    protocol = Protocol.from_steps(
        direction,
        [*steps, ReleaseTorque(), Hold(0.7)],
        normal_load=4300.0,
        roller_speed=start_speed,
    )
    return assemble(default_rig(), protocol)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("direction", "exp_step"), [("stop", None), ("start", None), ("start", 0.8e-3)]
)
def test_a_ramp_to_or_from_standstill_goes_to_the_fallback(direction, exp_step):
    """As the V/f drive's frequency goes to 0 its torque's gradient grows without bound, past
    what the stability estimate at the ramp's start saw. With the guard silent ETDRK4 was off
    by 5.4 N.m on the stop and by 10.3 N.m on the start at a step of 0.8 ms (at 1.6 ms the
    guard caught the start). Both ramps go to the fallback, whose tolerance is no looser than
    ``fallback_rtol``: measured against Radau 1e-11, 0.0048 N.m on the stop and 0.10 on the
    start (at ROS34PW2's own default 1e-5: 0.11 and 0.46)."""
    inputs = _ramp_through_standstill(direction)
    t = output_times(inputs.protocol.duration, 250.0)
    ref, _ = integrate_reference(inputs, t, rtol=1e-10)
    x, stats = integrate_experiment(inputs, t, exp_step=exp_step)
    assert stats["status"] == 0 and stats["fallback_segments"] == 1
    assert np.max(np.abs(_t56(inputs, x) - _t56(inputs, ref))) <= 0.2


@pytest.fixture(scope="module")
def macro_slip_at_5_kmh():
    """A torque ramp from -900 to +900 N.m at 4.3 kN and 5 km/h, past the adhesion limit in
    braking and in traction (slip reversal through macro-slip), then released; Radau 1e-9."""
    pulse = Protocol.from_steps(
        "reversal",
        [Hold(0.3), RampTorque(-900.0, 1.0), RampTorque(900.0, 1.5), ReleaseTorque(), Hold(1.0)],
        normal_load=4300.0,
        roller_speed=5 / 3.6,
    )
    inputs = assemble(default_rig(), pulse)
    t = output_times(inputs.protocol.duration, 250.0)
    ref, stats = integrate_reference(inputs, t, rtol=1e-9)
    assert stats["status"] == 0
    return inputs, t, ref


def test_the_error_guard_sends_macro_slip_at_low_speed_to_ros34pw2(macro_slip_at_5_kmh):
    """ETDRK4's fixed step alone is off by 5.5 N.m here (measured); each step's error estimate
    of T56 sends the segments past the adhesion limit to a shorter step and, where that is not
    enough, to ROS34PW2 (measured 0.042 N.m, ROS34PW2 alone 0.098), while the validated cases
    above keep every segment (fallback 0)."""
    inputs, t, ref = macro_slip_at_5_kmh
    x, stats = integrate_experiment(inputs, t)
    assert stats["status"] == 0 and stats["method"] == "etdrk4"
    assert 1 <= stats["fallback_segments"] < len(inputs.segments)
    assert np.max(np.abs(_t56(inputs, x) - _t56(inputs, ref))) <= 0.2
    unguarded, stats = integrate_experiment(inputs, t, exp_error=0.0)
    assert stats["fallback_segments"] == 0
    assert np.max(np.abs(_t56(inputs, unguarded) - _t56(inputs, ref))) > 1.0


def test_a_batch_through_fallbacks_equals_the_single_runs(macro_slip_at_5_kmh):
    """integrate_batch runs each variant's driver in a thread; a segment left to the fallback
    returns to Python there (ROS34PW2's driver, then ETDRK4's resumes): each variant equals
    its single run to the bit, counts included."""
    inputs, t, _ = macro_slip_at_5_kmh
    variants = [inputs, inputs, inputs]
    x, stats = integrate_batch(variants, t)
    single, single_stats = integrate_experiment(inputs, t)
    assert single_stats["fallback_segments"] >= 1
    for xb, sb in zip(x, stats, strict=True):
        np.testing.assert_array_equal(xb, single)
        assert sb == single_stats


def _pulse_on_a_shaft(stiffness):
    """A 300 N.m pulse at 30 km/h and 4.3 kN on a roller shaft of ``stiffness`` [N.m/rad]:
    the inputs and the 250 Hz output times."""
    rig = default_rig().with_overrides({"stiffness.roller_shaft": stiffness})
    pulse = Protocol.from_steps(
        "pulse",
        [Hold(0.2), RampTorque(300.0, 0.3), ReleaseTorque(), Hold(0.5)],
        normal_load=4300.0,
        roller_speed=30 / 3.6,
    )
    inputs = assemble(rig, pulse)
    t = output_times(inputs.protocol.duration, 250.0)
    return inputs, t


def test_a_fallback_resumes_where_it_left_and_matches_ros34pw2_to_the_bit():
    """A shaft 10 000 times stiffer sends every segment to ROS34PW2 (the stable step is below
    0.2 of the largest): ETDRK4's driver hands each segment back to Python, which runs
    ROS34PW2's driver on it and resumes at the next. The states at every output row and the
    step counts are then exactly those of ``method="ros34pw2"`` (the same driver on the same
    segments, at the fallback's tolerance), so no output row is skipped, doubled or shifted at a
    resume."""
    inputs, t = _pulse_on_a_shaft(8.35e8)
    x_exp, s_exp = integrate_experiment(inputs, t, exp_error=0.0)
    rtol = FAST_DEFAULTS["fallback_rtol"]  # as ETDRK4's fallback, no looser than this
    x_ros, s_ros = integrate_experiment(inputs, t, method="ros34pw2", rtol=rtol)
    assert s_exp["fallback_segments"] == len(inputs.segments) > 1
    np.testing.assert_array_equal(x_exp, x_ros)
    for key in ("accepted_steps", "rejected_steps", "jacobians", "status", "t_stop"):
        assert s_exp[key] == s_ros[key]


def test_progress_takes_the_same_steps_through_fallback_and_etdrk4_segments(
    macro_slip_at_5_kmh,
):
    """With a progress callback the driver runs segment by segment; with segments of both
    kinds (ETDRK4's and its fallback's) the result and the counts are the same to the bit as
    one call (the last stability estimate is kept across the calls)."""
    inputs, t, _ = macro_slip_at_5_kmh
    x, stats = integrate_experiment(inputs, t)
    seen = []
    x_p, stats_p = integrate_experiment(inputs, t, progress=lambda now, end: seen.append(now))
    assert 1 <= stats["fallback_segments"] < len(inputs.segments)
    np.testing.assert_array_equal(x_p, x)
    assert stats_p == stats
    assert len(seen) == len(inputs.segments)


@pytest.mark.parametrize(("stiffness", "fallback"), [(8.35e7, False), (8.35e8, True)])
def test_a_stiffer_explicit_part_shortens_the_step_or_goes_to_the_fallback(stiffness, fallback):
    """A roller shaft 1 000 times stiffer (a 440 Hz mode) shortens ETDRK4's step to keep RK4
    stable; 10 000 times (1.4 kHz) would need a step below 0.2 of the largest, so every
    segment goes to ROS34PW2. Both stay close to Radau (0.14 and 0.048 N.m measured). The
    step-error guard is off for this (``exp_error=0``): on the 1 000 times stiffer shaft a
    twist error is 1 000 times more torque, and with the guard the ringing past the release is
    integrated at a shorter step (none by ROS34PW2; checked below against Radau)."""
    inputs, t = _pulse_on_a_shaft(stiffness)
    x, stats = integrate_experiment(inputs, t, exp_error=0.0)
    assert stats["status"] == 0
    if fallback:
        assert stats["fallback_segments"] == len(inputs.segments)
    else:
        assert stats["fallback_segments"] == 0
        assert stats["accepted_steps"] > 1.5 * inputs.protocol.duration / 1.6e-3
    ref, _ = integrate_reference(inputs, t, rtol=1e-10)
    assert np.max(np.abs(_t56(inputs, x) - _t56(inputs, ref))) < 0.3
    guarded, stats = integrate_experiment(inputs, t)
    assert stats["status"] == 0
    assert np.max(np.abs(_t56(inputs, guarded) - _t56(inputs, ref))) < 0.3


@pytest.mark.slow
def test_the_guard_shortens_the_step_of_a_stiffer_shaft_s_ringing_before_the_fallback():
    """A roller shaft 3.3 times stiffer (143.5 kN.m/rad, a 25 Hz mode) with a 0.24 s motor lag,
    a pulse to 1 000 N.m at 30 km/h: the ringing after the release trips the step-error guard
    at 1.6 ms, and that segment goes on at a shorter step (1.28 ms, the first of
    GUARD_STEP_DIVISORS) while the shaft rings, not by ROS34PW2 (on the bundled 30 s test with
    this shaft ROS34PW2 was off by 0.31 N.m there). Measured against Radau 1e-10: 0.055 N.m
    (0.014 when the step was halved), unguarded 0.138: the bound tells the two apart, at the
    accuracy the guard gives unshortened segments elsewhere (0.061 N.m on the sweep's
    variants)."""
    rig = default_rig().with_overrides({"stiffness.roller_shaft": 143.5e3})
    pulse = Protocol.from_steps(
        "pulse",
        [Hold(0.2), RampTorque(1000.0, 0.5), ReleaseTorque(), Hold(1.0)],
        normal_load=4300.0,
        roller_speed=30 / 3.6,
    )
    inputs = assemble(rig, pulse, DriveConfig(roller_lag=0.2423))
    t = output_times(inputs.protocol.duration, 250.0)
    ref, _ = integrate_reference(inputs, t, rtol=1e-10)
    x, stats = integrate_experiment(inputs, t)
    assert stats["status"] == 0 and stats["fallback_segments"] == 0
    assert stats["shortened_segments"] >= 1
    assert np.max(np.abs(_t56(inputs, x) - _t56(inputs, ref))) <= 0.08
    unguarded, stats = integrate_experiment(inputs, t, exp_error=0.0)
    assert stats["shortened_segments"] == 0
    assert np.max(np.abs(_t56(inputs, unguarded) - _t56(inputs, ref))) > 0.1


def test_the_methods_agree_and_ros34pw2_stays_selectable(seed):
    sim, _ = seed
    t = sim.times[: 250 * 8]
    x_exp, s_exp = integrate_experiment(sim.inputs, t)
    x_ros, s_ros = integrate_experiment(sim.inputs, t, method="ros34pw2")
    assert s_ros["method"] == "ros34pw2" and "fallback_segments" not in s_ros
    assert s_exp["accepted_steps"] < s_ros["accepted_steps"]
    assert np.max(np.abs(_t56(sim.inputs, x_exp) - _t56(sim.inputs, x_ros))) < 0.2


def test_the_sensor_relation_holds_on_the_truth_channels_at_4_khz():
    """F_x r_r − T56 − J5 α5 − R05 <= 1e-4 of max |F_x r_r| at every sample of a 4 kHz output:
    α4, α5, α6 and the contact force come from the right-hand side at the output instants (the
    derivative of the dense output's speeds made it 4.37 N.m, issue 20)."""
    sim = Simulation(experiment="seed-30kmh-dry", output_rate=4000.0)
    ds = sim.run()
    rig = sim.rig
    rr = rig.geometry.roller_radius_x
    moment = ds.contact_force.values * rr
    residual = (
        moment
        - ds.t56.values
        - sim.inputs.segments[0].params[4] * ds.roller_acceleration.values
        - ds.bearing_torque_roller.values
    )
    assert np.max(np.abs(residual)) <= 1e-4 * np.max(np.abs(moment))
    # The tyre and the AM rotor too: J4 α4 = T34 − F_x r_w, J6 α6 = T56 + T_a.
    p = sim.inputs.segments[0].params
    rw = rig.geometry.wheel_radius_x
    tyre = p[3] * ds.wheel_acceleration.values - (ds.t34.values - ds.contact_force.values * rw)
    rotor = p[5] * ds.am_rotor_acceleration.values - (ds.t56.values + ds.roller_drive_torque.values)
    assert np.max(np.abs(tyre)) <= 1e-9 * np.max(np.abs(ds.t34.values))
    assert np.max(np.abs(rotor)) <= 1e-9 * np.max(np.abs(ds.t56.values))
    # And α5 is the derivative of the roller speed (differences of the 4 kHz samples).
    diff = np.gradient(ds.roller_speed.values, ds.time.values)
    scale = np.max(np.abs(ds.roller_acceleration.values))
    assert np.median(np.abs(diff - ds.roller_acceleration.values)) < 1e-2 * scale


def test_a_batch_may_mix_rigid_and_flexible_frames():
    """Each variant gets its own contact block ((ω4, ω5), or (ω4, ω5, v_f) with a flexible
    frame), and its states are those of its single run, to the bit."""
    from rollerrig.solve.fast import integrate_batch

    sim = Simulation(experiment="seed-30kmh-dry")
    t = sim.times[: 250 * 6 : 25]
    variants = [sim.inputs, assemble(sim.rig, sim.protocol, DriveConfig(frame="flexible"))]
    x, stats = integrate_batch(variants, t)
    for inputs, xb, sb in zip(variants, x, stats, strict=True):
        xs, ss = integrate_experiment(inputs, t)
        np.testing.assert_array_equal(xb, xs)
        assert sb == ss


def test_an_input_table_at_the_daq_rate_gives_the_plain_protocols_result():
    """A load table sampled at 1 kHz (a replayed recording) makes 30 000 segments of the same
    piecewise-linear input; each reuses the stability estimate of the last 10 ms
    (etdrk4.STABILITY_RECHECK) instead of paying a Jacobian and its eigenvalues. Measured: 0.022
    N·m from the plain protocol's T56 (of 1 182 N·m), within the backend's 0.05 N·m of Radau."""
    import dataclasses

    protocol = load_protocol("seed-30kmh-dry")
    t = np.arange(round(protocol.duration * 1000.0) + 1) / 1000.0
    replay = dataclasses.replace(protocol, load_time=t, normal_load=protocol.normal_load_at(t))
    plain = Simulation(default_rig(), protocol, output_rate=250.0).run()
    table = Simulation(default_rig(), replay, output_rate=250.0).run()
    assert np.max(np.abs(table.t56.values - plain.t56.values)) < 0.05


def test_the_step_loop_is_compiled_without_fast_math():
    """With LLVM's "contract" flag the default solve was 3-5 % faster, but the fused products
    depended on the compile's context: three caches of one install gave three different
    results of the bundled test, bit for bit (2026-12-01). Without any fast-math flag every
    compile gives the same bits."""
    from rollerrig.solve import fast

    for dispatcher in (fast._exp_segment, fast._exp_prepare, fast._exp_workspace):
        assert not dispatcher.targetoptions.get("fastmath"), dispatcher
    from rollerrig.solve._compiled import rig_rhs

    assert not rig_rhs.targetoptions.get("fastmath")


def test_the_guard_s_shorter_step_lasts_only_while_the_shaft_rings(seed):
    """On the bundled 30 s test with the sweep's stiffest shaft (143.5 kN.m/rad, a 25 Hz mode;
    ``benchmarks/run.py``), the ringing trips the guard 9-23 steps after each of the three
    releases. The shorter step then lasts until the estimates say the full step passes again:
    19 540 steps where the whole segment at 1.28 ms took 21 525 and no shortening 18 753
    (max |ΔT56| against Radau 1e-10 0.050 N.m, as with the whole segment shortened; 2026-12-02).
    Step counts, not timings: they are the same on every machine."""
    sim, _ = seed
    rig = sim.inputs.rig.with_overrides({"stiffness.roller_shaft": 143.5e3})
    inputs = assemble(rig, sim.protocol, DriveConfig(roller_lag=0.2423))
    _, stats = integrate_experiment(inputs, sim.times)
    _, plain = integrate_experiment(sim.inputs, sim.times)
    assert stats["status"] == 0 and stats["fallback_segments"] == 0
    assert stats["shortened_segments"] == 3 and stats["rejected_steps"] >= 3
    assert plain["accepted_steps"] < stats["accepted_steps"] < 1.06 * plain["accepted_steps"]
