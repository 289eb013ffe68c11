"""The PMSM's steady voltage demand against its own current ODE and closed forms."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rollerrig._validation import ParameterError
from rollerrig.drives.pmsm import max_phase_voltage, pmsm_current_derivatives, pmsm_torque
from rollerrig.drives.pmsm_envelope import pmsm_steady_voltage, pmsm_voltage_share
from rollerrig.rig.parameters import default_rig, load_rig

P, FLUX, R, LD, LQ, IMAX = 22, 0.2, 0.04, 5e-4, 6e-4, 400.0


@settings(max_examples=60, deadline=None)
@given(st.floats(-2000.0, 2000.0), st.floats(-100.0, 100.0))
def test_the_voltage_holds_the_current_loops_still(torque, omega):
    """At the returned (v_d, v_q) the dq current ODE (seed eqs. 4.23-4.24, corrected) is at
    rest with i_d = 0 and the clipped i_q: the demand is the steady state of the model, not a
    formula of its own."""
    i_q = np.clip(torque / (1.5 * P * FLUX), -IMAX, IMAX)
    omega_e = P * omega
    v_d, v_q = -omega_e * LQ * i_q, R * i_q + omega_e * FLUX
    did, diq = pmsm_current_derivatives(0.0, i_q, v_d, v_q, omega, P, R, LD, LQ, FLUX)
    assert abs(did) <= 1e-9 * (1 + abs(v_d) / LD) and abs(diq) <= 1e-9 * (1 + abs(v_q) / LQ)
    got = pmsm_steady_voltage(torque, omega, P, FLUX, R, LQ, IMAX)
    assert got == pytest.approx(np.hypot(v_d, v_q), rel=1e-12, abs=1e-12)
    # The torque at that current is the request, up to the current limit.
    assert pmsm_torque(0.0, i_q, P, FLUX, LD, LQ) == pytest.approx(
        np.clip(torque, -1.5 * P * FLUX * IMAX, 1.5 * P * FLUX * IMAX), rel=1e-12, abs=1e-9
    )


def test_closed_forms_back_emf_and_standstill():
    assert pmsm_steady_voltage(0.0, 50.0, P, FLUX, R, LQ, IMAX) == pytest.approx(P * 50.0 * FLUX)
    # At standstill only the resistance: R i_q.
    assert pmsm_steady_voltage(264.0, 0.0, P, FLUX, R, LQ, IMAX) == pytest.approx(R * 40.0)


def test_the_bundled_rigs_share_at_30_kmh():
    """The Pardubice wheel (r 0.348 m) at 30 km/h turns at 23.9 rad/s: 30 % of its inverter's
    voltage at no torque; the quarter-scale rig's wheel (r 0.1143 m) at 72.9 rad/s: 98 %, the
    case whose torque collapsed on the twin (pmsm_envelope's docstring)."""
    pard, vt = default_rig(), load_rig("vt-fra-quarter-scale")
    for rig, expected in ((pard, 0.304), (vt, 0.983)):
        omega = 30 / 3.6 / rig.geometry.wheel_radius_x
        back_emf = rig.pmsm.pole_pairs * omega * rig.pmsm.flux_linkage
        vmax = float(max_phase_voltage(rig.pmsm.dc_link_voltage))
        share = float(pmsm_voltage_share(0.0, omega, rig.pmsm))
        assert share == pytest.approx(back_emf / vmax, rel=1e-12)
        assert share == pytest.approx(expected, abs=1e-3)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((np.nan, 1.0), "torque must be finite"),
        ((1.0, "fast"), "omega_mech must be a number"),
    ],
)
def test_bad_inputs_are_named(args, message):
    with pytest.raises(ParameterError, match=message):
        pmsm_steady_voltage(*args, P, FLUX, R, LQ, IMAX)
