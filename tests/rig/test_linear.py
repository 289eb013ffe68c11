"""The coupled twin linearised at steady free rolling, checked against independent references.

References:
* :func:`rollerrig.rig.chain.modal_analysis` (the free chain, first-order form of
  M θ'' + C θ' + K θ = 0): the linearised twin with the contact and the drives removed must have
  exactly its poles; with the contact in and the induction motor without lag, the chain plus
  the contact damper (:func:`contact_damping_matrix`) and the motor's slip damper
  (:func:`damper_matrix`) with slopes from closed forms.
* Polach (2005): at vanishing creep the creep force is ``(kA + kS)/2 · G a b c11 · s`` (the linear
  limit of eq. 4.20 of the seed), so ``dF/dw = (kA + kS) G a b c11 / (2 √(v² + v_ε²))``.
* The two-inertia closed form of the roller-shaft pair: ``μ s² + b56 s + k56 = 0`` with
  ``μ = J5 J6 / (J5 + J6)``.
"""

from __future__ import annotations

import numpy as np
import pytest
from typer.testing import CliRunner

from rollerrig._validation import ParameterError
from rollerrig._warnings import DomainWarning
from rollerrig.cli import app
from rollerrig.contact.creep import POLACH_DRY
from rollerrig.rig import model as m
from rollerrig.rig.assemble import assemble
from rollerrig.rig.chain import (
    chain_matrices,
    contact_damping_matrix,
    damper_matrix,
    modal_analysis,
)
from rollerrig.rig.linear import (
    _active,
    _operating_point_protocol,
    coupled_modes,
    format_coupled_modes,
    linearise_rhs,
    linearise_twin,
    modes_of,
)
from rollerrig.rig.model import DriveConfig
from rollerrig.rig.parameters import default_rig

SPEED = 30 / 3.6  # [m/s], the seed's 30 km/h test
LOAD = 4.3e3  # [N]


@pytest.fixture(scope="module")
def rig():
    return default_rig()


def _inputs(rig, drives, speed=SPEED, load=LOAD):
    inputs = assemble(rig, _operating_point_protocol(speed, load, "dry"), drives)
    return inputs, inputs.segments[0].params.copy()


def _eigenvalues(params, inputs, state):
    jac = linearise_rhs(params, inputs.tables, state)
    active = _active(jac)
    return np.linalg.eigvals(jac[np.ix_(active, active)]), [m.STATE_NAMES[k] for k in active]


def _sorted(values):
    values = np.asarray(values)
    return values[np.lexsort((values.imag, values.real.round(9)))]


def _idealised(rig, *, contact: bool, am_slope: float):
    """Ideal wheel torque source, no bearing loss, AM with a linear slope and no lag."""
    inputs, p = _inputs(rig, DriveConfig(wheel="ideal_torque", roller="induction_linear"))
    p[m.P_BEAR_W] = p[m.P_BEAR_R] = 0.0
    p[m.P_AM_SLOPE] = am_slope
    p[m.P_LAG_TAU] = 0.0
    p[m.P_RIPPLE_AMP] = 0.0
    if not contact:
        p[m.P_CREEP_STIFF_REF] = 0.0
    # Free rolling without losses: no slip, every shaft untwisted, both at the set speed.
    x0 = np.zeros(m.N_STATES)
    x0[m.X_OMEGA + 1 : m.X_OMEGA + 4] = SPEED / p[m.P_RW]
    x0[m.X_OMEGA + 4 : m.X_OMEGA + 6] = SPEED / p[m.P_RR]
    return inputs, p, x0


def test_without_contact_and_drives_the_poles_are_the_free_chains(rig):
    inputs, p, x0 = _idealised(rig, contact=False, am_slope=0.0)
    lam, names = _eigenvalues(p, inputs, x0)
    assert names == list(m.STATE_NAMES[:14])  # the drives' states drop out
    M, K, C = chain_matrices(rig)
    reference = modal_analysis(M, K, C).poles
    scale = np.max(np.abs(reference))
    np.testing.assert_allclose(_sorted(lam), _sorted(reference), rtol=0, atol=1e-6 * scale)


def test_contact_and_am_slip_are_the_chain_with_their_dampers(rig):
    # Contact in (Polach's linear limit at zero creep) and the induction motor's slope without
    # lag: the chain with two extra dampers, from closed forms.
    slope_am = 800.0  # [N.m.s/rad]
    inputs, p, x0 = _idealised(rig, contact=True, am_slope=slope_am)
    lam, _ = _eigenvalues(p, inputs, x0)
    v_eps = p[m.P_VREG]
    dfdw = (
        (POLACH_DRY.k_adhesion + POLACH_DRY.k_slip)
        * p[m.P_CREEP_STIFF_REF]
        / (2.0 * np.sqrt(SPEED**2 + v_eps**2))
    )
    M, K, C = chain_matrices(rig)
    extra = contact_damping_matrix(dfdw, p[m.P_RW], p[m.P_RR]) + damper_matrix(7, 6, 7, slope_am)
    reference = modal_analysis(M, K, C, extra).poles
    scale = np.max(np.abs(reference))
    np.testing.assert_allclose(_sorted(lam), _sorted(reference), rtol=0, atol=1e-6 * scale)


def test_roller_shaft_pair_against_the_two_inertia_closed_form(rig):
    inputs, p, x0 = _idealised(rig, contact=False, am_slope=0.0)
    lam, _ = _eigenvalues(p, inputs, x0)
    j5, j6 = rig.inertia.roller, rig.inertia.am_rotor
    k, b = rig.stiffness.roller_shaft, rig.damping.roller_shaft
    mu = j5 * j6 / (j5 + j6)
    closed = (-b + np.sqrt(complex(b * b - 4.0 * mu * k))) / (2.0 * mu)
    nearest = lam[np.argmin(np.abs(lam - closed))]
    assert nearest == pytest.approx(closed, rel=1e-9)
    assert closed.imag / (2 * np.pi) == pytest.approx(13.84, abs=0.005)  # the chain's table


def test_finite_difference_jacobian_does_not_depend_on_the_step(rig):
    lin = linearise_twin(rig, SPEED, LOAD)
    assert lin.step_difference < 1e-5
    inputs, p = _inputs(rig, DriveConfig())
    p[m.P_RIPPLE_AMP] = 0.0
    a = linearise_rhs(p, inputs.tables, inputs.initial_state, step=1e-7)
    b = linearise_rhs(p, inputs.tables, inputs.initial_state, step=3e-7)
    scale = np.maximum(np.max(np.abs(a), axis=0), 1e-300)
    assert np.max(np.abs(a - b) / scale) < 1e-5
    # the full twin: PMSM currents and PI integrals, the AM lag state; no servo integral
    assert "roller_drive_torque_state" in lin.state_names and "i_q" in lin.state_names
    assert "speed_error_integral" not in lin.state_names


def test_coupled_modes_at_the_seeds_operating_point(rig):
    cm = coupled_modes(rig, SPEED, LOAD, load_source="test")
    ring = {round(md.frequency): md for md in cm.ringing}
    # The roller-shaft mode rings (ζ ~ 0.004) just below the free chain's 13.84 Hz.
    shaft = ring[14]
    assert 13.6 < shaft.frequency < 13.84 and shaft.damping_ratio < 0.01
    assert shaft.element == "roller_shaft" and "am_rotor" in shaft.what_moves
    # The chain's overdamped mounts (ζ 12 and 41) are real poles here: they never ring.
    real = [md for md in cm.modes if md.kind == "real"]
    assert any(md.element == "am_mount" for md in real)
    assert any(md.element == "pmsm_mount" for md in real)
    assert all(md.frequency == 0.0 and not md.can_ring for md in real)
    # The wheel-rubber mode (47.86 Hz undamped, 44.42 Hz damped in the free chain) moves down
    # to about 38.5 Hz with the contact in, too damped to ring (ζ > 0.3).
    rubber = next(md for md in cm.modes if md.element == "wheel_rubber" and md.kind != "real")
    assert 38.0 < rubber.frequency < 39.5 and not rubber.can_ring
    # Rigid rotations of the two free subchains.
    assert sum(md.kind == "rigid" for md in cm.modes) == 2
    rows = cm.as_dict()["modes"]
    assert all(r["frequency [Hz]"] is not None for r in rows)
    assert {r["kind"] for r in rows} == {"oscillatory", "real", "rigid"}


def test_modes_follow_the_drives(rig):
    # Without the AM's lag the slow speed mode of roller and lag disappears.
    no_lag = coupled_modes(rig, SPEED, LOAD, drives=DriveConfig(roller_lag=0.0))
    assert all(md.frequency > 5.0 for md in no_lag.ringing)
    assert not any("am_torque_lag" in md.participation for md in no_lag.modes)
    lagged = coupled_modes(rig, SPEED, LOAD)
    slow = [md for md in lagged.ringing if md.frequency < 5.0]
    assert slow and slow[0].participation.get("am_torque_lag", 0.0) > 0.1


def test_modes_of_needs_no_drives_for_a_pure_chain(rig):
    M, K, C = chain_matrices(rig)
    n = M.shape[0]
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    names = [f"theta{i}" for i in range(1, 8)] + [f"omega{i}" for i in range(1, 8)]
    modes = modes_of(a, names, rig)
    shaft = next(md for md in modes if md.element == "roller_shaft")
    assert shaft.frequency == pytest.approx(13.84, abs=0.01)
    assert set(shaft.participation) <= {
        "pmsm_stator",
        "pmsm_rotor",
        "wheel_disc",
        "wheel_tyre",
        "roller",
        "am_rotor",
        "am_stator",
    }


def test_validation(rig):
    with pytest.raises(ValueError, match="speed"):
        linearise_twin(rig, 0.0, LOAD)
    with pytest.raises(ValueError, match="normal_load"):
        linearise_twin(rig, SPEED, -1.0)
    with pytest.raises(ValueError, match="friction"):
        linearise_twin(rig, SPEED, LOAD, friction="ice")
    # 1e7 N: beyond the roller drive (tests/rig/test_assemble.py) and, intended here, just
    # outside the Hertz domain (a/R'x = 0.114).
    with pytest.warns(DomainWarning), pytest.raises(ParameterError, match="no steady free rolling"):
        linearise_twin(rig, SPEED, 1e7)
    with pytest.raises(ValueError, match="damping_threshold"):
        coupled_modes(rig, SPEED, LOAD, damping_threshold=1.5)


def test_cli_modes_prints_both_tables_with_units():
    runner = CliRunner()
    plain = runner.invoke(app, ["modes"])
    assert plain.exit_code == 0, plain.output
    assert "f [Hz]" in plain.output and "13.84" in plain.output
    assert "Coupled twin" not in plain.output
    r = runner.invoke(app, ["modes", "--speed-kmh", "30", "--load-kn", "4.3"])
    assert r.exit_code == 0, r.output
    assert "f_d [Hz]" in r.output and "tau [s]" in r.output  # units survive (no markup)
    assert "13.84" in r.output and "13.78" in r.output and "real pole" in r.output
    assert "roller_shaft: am_rotor" in r.output
    assert runner.invoke(app, ["modes", "--load-kn", "4"]).exit_code == 2
    bad = runner.invoke(app, ["modes", "--speed-kmh", "-3"])
    assert bad.exit_code == 2 and "--speed-kmh" in bad.output


def test_format_is_plain_text(rig):
    text = format_coupled_modes(coupled_modes(rig, SPEED, LOAD))
    assert "can ring" in text and "4.3 kN" in text


def test_one_entry_gives_the_modes_of_every_roller_drive():
    """rig.modes.twin_modes: the lag model through the 22-state linearisation, the dq machine
    through its coupled twin; the wheel shaft's mode (PMSM rotor on the wheel, 110.8 Hz) does
    not depend on the roller drive, the machine's fluxes take part in the dq twin's modes."""
    from rollerrig.rig.modes import twin_modes

    rig = default_rig()
    lag = twin_modes(rig, 30 / 3.6, 4.3e3)
    dq = twin_modes(rig, 30 / 3.6, 4.3e3, drives=m.DriveConfig(roller="induction_dq"))
    assert lag.ringing[-1].frequency == pytest.approx(dq.ringing[-1].frequency, rel=1e-3)
    assert "am_psi" in format_coupled_modes(dq)
    assert "roller_drive_vf" in format_coupled_modes(dq)
    with pytest.raises(ParameterError, match="twin_modes"):
        linearise_twin(rig, 30 / 3.6, 4.3e3, drives=m.DriveConfig(roller="induction_dq"))


def test_modes_takes_the_roller_drive():
    result = CliRunner().invoke(
        app, ["modes", "--speed-kmh", "30", "--roller-drive", "induction_dq"]
    )
    assert result.exit_code == 0, result.output
    assert "roller drive induction_dq" in result.output and "am_psi" in result.output


def test_a_pole_that_hides_the_chain_is_refused_with_what_moves(rig):
    """A PMSM stator of 1e-12 kg.m^2 puts a pole at about −1e17 1/s: the rigid bound (1e-6 of
    the fastest pole) would call every mode rigid. The error names the pole and its states."""
    tiny = rig.with_overrides({"inertia.pmsm_stator": 1e-12})
    with pytest.raises(ParameterError, match=r"pole at .* 1/s .*theta1|pole at .* 1/s .*omega1"):
        coupled_modes(tiny, SPEED, LOAD, load_source="test")


def test_linearise_twin_refuses_a_step_that_gives_a_nan_jacobian():
    import re

    from rollerrig.rig.linear import linearise_twin
    from rollerrig.rig.parameters import default_rig

    for step in (0.0, -1e-7):
        with pytest.raises(ParameterError, match=re.escape("step must lie in (0, 1) [-]")):
            linearise_twin(default_rig(), 30 / 3.6, 4.3e3, step=step)
    for step in (float("nan"), float("inf")):
        with pytest.raises(ParameterError, match=re.escape("step must be finite [-]")):
            linearise_twin(default_rig(), 30 / 3.6, 4.3e3, step=step)


def test_a_misspelt_friction_and_a_threshold_of_text_are_named():
    import re

    from rollerrig.rig.linear import coupled_modes, linearise_twin
    from rollerrig.rig.parameters import default_rig

    with pytest.raises(ParameterError, match=re.escape("(did you mean 'dry'?)")):
        linearise_twin(default_rig(), 30 / 3.6, 4.3e3, friction="dyr")
    with pytest.raises(ParameterError, match=re.escape("damping_threshold must be a number")):
        coupled_modes(default_rig(), 30 / 3.6, 4.3e3, damping_threshold="a")
    with pytest.raises(ParameterError, match=re.escape("damping_threshold must be finite [-]")):
        coupled_modes(default_rig(), 30 / 3.6, 4.3e3, damping_threshold=None)


def test_modes_of_names_a_jacobian_it_cannot_use():
    import re

    from rollerrig.rig.linear import modes_of
    from rollerrig.rig.parameters import default_rig

    rig = default_rig()
    names = ["omega1", "omega2"]
    with pytest.raises(ParameterError, match=re.escape("jacobian must be a square matrix")):
        modes_of(np.zeros((2, 3)), names, rig)
    with pytest.raises(ParameterError, match=re.escape("state_names must name each of the")):
        modes_of(-np.eye(2), ["omega1"], rig)
    with pytest.raises(ParameterError, match=re.escape("jacobian must be finite")):
        modes_of(np.full((2, 2), np.nan), names, rig)
    with pytest.raises(ParameterError, match=re.escape("damping_threshold must be finite [-]")):
        modes_of(-np.eye(2), names, rig, float("nan"))
    with pytest.raises(ParameterError, match=re.escape("damping_threshold must lie in (0, 1)")):
        modes_of(-np.eye(2), names, rig, 1.5)
