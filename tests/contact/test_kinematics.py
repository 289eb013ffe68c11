"""Creep kinematics: the seed's definition away from standstill, finite and smooth near it."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from rollerrig._validation import ParameterError
from rollerrig.contact.creep import POLACH_DRY, polach_creep_force
from rollerrig.contact.kinematics import MAX_PERIPHERAL_SPEED, creep_and_slip_velocity

RW, RR = 0.348, 0.452


def test_matches_seed_definition_at_test_speeds():
    # Kayaalp eqs. 4.21-4.22: s = (w_w r_w - w_r r_r)/(w_r r_r), w = w_w r_w - w_r r_r.
    v = 30 / 3.6
    ww, wr = 1.02 * v / RW, v / RR
    s, w = creep_and_slip_velocity(ww, wr, RW, RR)
    assert w == pytest.approx(ww * RW - wr * RR, rel=1e-14)
    assert s == pytest.approx((ww * RW - wr * RR) / (wr * RR), rel=2e-5)  # (v_eps/v)^2/2


def test_standstill_and_spin_on_stopped_roller_are_finite():
    s, w = creep_and_slip_velocity(0.0, 0.0, RW, RR)
    assert s == 0.0 and w == 0.0
    s, w = creep_and_slip_velocity(1.0, 0.0, RW, RR, regularisation_speed=0.05)
    assert np.isfinite(s) and s == pytest.approx(RW / 0.05)
    f = polach_creep_force(s, w, 4300.0, 3.4e-3, 2.7e-3, 3.9, 8.08e10, POLACH_DRY)
    assert np.isfinite(f) and 0 < f < 4300.0 * 0.55 * (1 + 1 / np.pi)


def test_slip_reversal_is_smooth_and_sign_correct():
    # Sweep the wheel speed through the roller's: creep and force change sign continuously.
    wr = 5.0 / RR
    ww = np.linspace(0.98, 1.02, 2001) * 5.0 / RW
    s, w = creep_and_slip_velocity(ww, wr, RW, RR)
    f = polach_creep_force(s, w, 4300.0, 3.4e-3, 2.7e-3, 3.9, 8.08e10, POLACH_DRY)
    assert np.all(np.diff(s) > 0)
    assert np.all(np.sign(f) == np.sign(s))
    # Continuity: no jump larger than Kalker's linear slope (an upper bound of Polach's slope
    # for kA, kS <= 1) times the creep increment.
    kalker_slope = 8.08e10 * 3.4e-3 * 2.7e-3 * 3.9
    assert np.max(np.abs(np.diff(f))) <= 1.05 * kalker_slope * np.max(np.diff(s))


@given(st.floats(-50, 50), st.floats(-50, 50))
def test_always_finite_and_antisymmetric(ww, wr):
    s, w = creep_and_slip_velocity(ww, wr, RW, RR)
    assert np.isfinite(s) and np.isfinite(w)
    s2, w2 = creep_and_slip_velocity(-ww, -wr, RW, RR)
    # Running the rig backwards reverses the slip velocity and the creep.
    assert s2 == pytest.approx(-s, abs=1e-12) and w2 == pytest.approx(-w, abs=1e-12)


def test_away_from_standstill_the_creep_is_relative_to_the_roller_speed_magnitude():
    # s = w/sqrt(v_r^2 + v_eps^2) -> w/|v_r|: Kayaalp's w/v_r (eqs. 4.21-4.22) rolling forwards,
    # its negative rolling backwards (a wheel 1 % faster than the roller, both backwards).
    v = 30 / 3.6
    for sign in (1.0, -1.0):
        ww, wr = sign * 1.01 * v / RW, sign * v / RR
        s, w = creep_and_slip_velocity(ww, wr, RW, RR)
        assert s == pytest.approx(w / abs(wr * RR), rel=2e-5)  # (v_eps/v)^2/2
        assert s == pytest.approx(sign * w / (wr * RR), rel=2e-5)
        assert np.sign(s) == np.sign(w) == sign


def test_invalid_radius_is_named():
    with pytest.raises(ParameterError, match="roller_radius"):
        creep_and_slip_velocity(1.0, 1.0, RW, 0.0)


def test_mismatched_array_lengths_name_the_parameters():
    with pytest.raises(
        ParameterError,
        match=r"wheel_speed \(shape \(3,\)\) and roller_speed \(shape \(2,\)\) must have the "
        r"same shape, or one of them be a single number",
    ):
        creep_and_slip_velocity([1.0, 2.0, 3.0], [1.0, 2.0], RW, RR)
    s, w = creep_and_slip_velocity(np.array([[1.0], [2.0]]), [1.0, 2.0, 3.0], RW, RR)
    assert s.shape == w.shape == (2, 3)
    s, w = creep_and_slip_velocity(1.0, 2.0, RW, RR)
    assert np.ndim(s) == np.ndim(w) == 0


@pytest.mark.parametrize(
    ("args", "message"),
    [
        # 1 % creep at 1e155 m/s: the square of the roller's speed overflowed, creep came out 0.
        (
            (1.01e155 / RW, 1e155 / RR, RW, RR),
            r"wheel_speed \* wheel_radius \(the wheel's peripheral speed\) must lie in "
            r"\[-3e\+08, 3e\+08\] \[m/s\], got 1\.01e\+155",
        ),
        (
            (0.0, -1e155 / RR, RW, RR),
            r"roller_speed \* roller_radius \(the roller's peripheral speed\) must lie in "
            r"\[-3e\+08, 3e\+08\] \[m/s\], got -1e\+155",
        ),
        ((1.0, 1e300, RW, 1e10), r"roller_speed \* roller_radius .* must be finite \[m/s\]"),
        ((1.0, 1.0, RW, RR, 1e155), r"regularisation_speed must lie in \(0, 3e\+08\] \[m/s\]"),
    ],
)
def test_speeds_beyond_the_speed_of_light_are_refused(args, message):
    with pytest.raises(ParameterError, match=message):
        creep_and_slip_velocity(*args)


def test_creep_is_right_up_to_the_largest_peripheral_speed():
    v = MAX_PERIPHERAL_SPEED / 1.01
    s, w = creep_and_slip_velocity(1.01 * v / RW, v / RR, RW, RR)
    assert s == pytest.approx(0.01, rel=1e-12) and w == pytest.approx(0.01 * v, rel=1e-12)
