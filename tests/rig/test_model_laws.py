"""The creep law inside the twin's right-hand side (issue 19, point 2).

The FASTSIM family enters the twin through a table of F/(μN) against ε = G a b C11 ξ/(μN)
(:mod:`rollerrig.contact.table`). Here: the table does not depend on a/b (FASTSIM), the twin's
force equals the contact package's :func:`rollerrig.contact.creep_force` at the same state, the
analytic dF/dN of the arm's Newton loop is the force's derivative, and the choice is validated.
"""

import numpy as np
import pytest

from rollerrig._validation import ParameterError
from rollerrig.contact import creep_force
from rollerrig.contact.creep import POLACH_DRY, _friction_kernel
from rollerrig.contact.hertz import hertz_contact
from rollerrig.contact.kalker import kalker_coefficients
from rollerrig.contact.laws import CREEP_LAWS, EUROSPRINTER_MODIFIED_FASTSIM, FastsimParameters
from rollerrig.contact.table import TABLE_NODES, creep_table, table_ratio
from rollerrig.experiment import load_protocol
from rollerrig.rig import model as m
from rollerrig.rig.assemble import assemble
from rollerrig.rig.parameters import default_rig

TABLE_TOLERANCE = 2e-5
"""|F_twin − F_creep_force| / (μN) [-]: the Hermite table against the discrete FASTSIM (30×30
strips) it is made from; measured 8e-6 (FASTSIM), 7e-6 (modified), 3e-7 (FaStrip)."""


@pytest.fixture(scope="module")
def rig():
    return default_rig()


@pytest.fixture(scope="module")
def protocol():
    return load_protocol("release-test")


def _params(rig, protocol, law, friction_sets=None):
    inputs = assemble(rig, protocol, m.DriveConfig(law=law), friction_sets)
    p = inputs.segments[0].params.copy()
    p[m.P_ARM_RATIO] = 0.0  # the load is the one given: compare the law alone
    return p


def test_the_twin_knows_every_law_of_the_contact_package():
    assert tuple(m.LAW_CODES) == CREEP_LAWS
    assert m.N_TAB == TABLE_NODES


def test_fastsims_table_is_one_function_of_eps_whatever_the_ellipse():
    # F/(μN) of FASTSIM depends on ε = G a b C11 ξ/(μN) alone (normalised grid).
    eps = np.linspace(0.0, 4.0, 81)
    g, nu, load, mu = 8.08e10, 0.3, 4300.0, POLACH_DRY.static_friction  # μ at w = 0
    ratios = []
    for a, b in ((3.4e-3, 2.7e-3), (2e-3, 6e-3), (8e-3, 2e-3)):
        c11 = float(kalker_coefficients(a / b, nu).c11)
        xi = eps * mu * load / (g * a * b * c11)
        fx = creep_force("fastsim", xi, 0.0, load, a, b, g, nu, POLACH_DRY).fx
        ratios.append(fx / (mu * load))
    np.testing.assert_allclose(ratios[1], ratios[0], rtol=0, atol=1e-14)
    np.testing.assert_allclose(ratios[2], ratios[0], rtol=0, atol=1e-14)
    table = creep_table("fastsim")
    assert np.max(np.abs(table_ratio(table, eps) - ratios[0])) < TABLE_TOLERANCE
    # Initial slope: Kalker's linear theory (F = G a b C11 ξ, i.e. f = ε).
    assert table.slopes[0] == pytest.approx(1.0, rel=1e-3)


@pytest.mark.parametrize("law", ["fastsim", "modified-fastsim", "fastrip"])
@pytest.mark.parametrize("load", [2000.0, 4300.0, 9000.0])
def test_the_twins_force_is_creep_force_of_the_contact_package(rig, protocol, law, load):
    sets = {"dry": EUROSPRINTER_MODIFIED_FASTSIM} if law == "modified-fastsim" else None
    p = _params(rig, protocol, law, sets)
    g, mat = rig.geometry, rig.material
    contact = hertz_contact(
        load,
        g.wheel_radius_x,
        g.wheel_radius_y,
        g.roller_radius_x,
        g.roller_radius_y,
        youngs_modulus=mat.youngs_modulus,
        poisson=mat.poisson,
    )
    a, b = float(contact.semi_axis_x), float(contact.semi_axis_y)
    shear = mat.youngs_modulus / (2.0 * (1.0 + mat.poisson))
    xi = np.concatenate([np.linspace(-0.03, 0.03, 121), [1e-7, -2e-5, 0.2]])
    w = 8.3 * xi  # slip velocity at 30 km/h [m/s]
    params = EUROSPRINTER_MODIFIED_FASTSIM if law == "modified-fastsim" else POLACH_DRY
    ref = creep_force(law, xi, w, load, a, b, shear, mat.poisson, params).fx
    mu = _friction_kernel(w, p[m.P_MU0], p[m.P_A], p[m.P_B])
    twin = np.array(
        [m._contact_load_and_force(load, x, f, p)[1] for x, f in zip(xi, mu, strict=True)]
    )
    assert np.max(np.abs(twin - ref) / (mu * load)) < TABLE_TOLERANCE


@pytest.mark.parametrize("law", ["fastsim", "modified-fastsim"])
def test_the_newton_loops_slope_is_the_derivative_of_the_force(rig, protocol, law):
    p = _params(rig, protocol, law)
    for creep in (-0.004, 0.0007, 0.004, 0.02):
        for load in (3000.0, 4300.0):
            slope = m._force_and_slope(creep, load, 0.35, p)[1]
            dn = 1e-4 * load
            up = m._force_and_slope(creep, load + dn, 0.35, p)[0]
            down = m._force_and_slope(creep, load - dn, 0.35, p)[0]
            assert slope == pytest.approx((up - down) / (2 * dn), rel=1e-5, abs=1e-9)


def test_the_arm_loop_converges_with_a_tabulated_law(rig, protocol):
    p = _params(rig, protocol, "fastsim")
    p[m.P_ARM_RATIO] = rig.arm.transfer_ratio
    for creep in (-0.01, 0.002, 0.01):
        load, force = m._contact_load_and_force(4300.0, creep, 0.4, p)
        exact = m._force_and_slope(creep, load, 0.4, p)[0]
        assert load == pytest.approx(4300.0 + p[m.P_ARM_WEIGHT] + p[m.P_ARM_RATIO] * exact)
        assert force == pytest.approx(exact, rel=1e-12)


def test_the_modified_fastsim_takes_k0_alpha_beta_from_its_friction_set(rig, protocol):
    own = FastsimParameters(0.4, 0.5, 0.3, k0=0.7, alpha_inf=0.1, beta=1.5, name="mine")
    p = _params(rig, protocol, "modified-fastsim", {"dry": own})
    assert (p[m.P_K0], p[m.P_ALPHA_INF], p[m.P_BETA]) == (0.7, 0.1, 1.5)
    assert (p[m.P_MU0], p[m.P_A], p[m.P_B]) == (0.4, 0.5, 0.3)
    # With a Polach set: its μ0, A, B and the Eurosprinter set's slope reduction.
    q = _params(rig, protocol, "modified-fastsim")
    e = EUROSPRINTER_MODIFIED_FASTSIM
    assert (q[m.P_K0], q[m.P_ALPHA_INF], q[m.P_BETA]) == (e.k0, e.alpha_inf, e.beta)
    assert q[m.P_MU0] == POLACH_DRY.static_friction
    # Kalker's FASTSIM has no slope reduction.
    f = _params(rig, protocol, "fastsim", {"dry": own})
    assert (f[m.P_K0], f[m.P_ALPHA_INF], f[m.P_BETA]) == (1.0, 1.0, 0.0)


def test_polachs_parameters_are_unchanged_by_the_law_slots(rig, protocol):
    p = _params(rig, protocol, "polach")
    assert p[m.P_LAW] == 0.0
    assert (p[m.P_KA], p[m.P_KS]) == (POLACH_DRY.k_adhesion, POLACH_DRY.k_slip)
    assert not np.any(p[m.P_TAB_F :])  # no table: Polach's closed form


def test_a_misspelt_law_is_refused_with_the_nearest_name():
    with pytest.raises(ParameterError, match="did you mean 'modified-fastsim'"):
        m.DriveConfig(law="modified_fastsim")


def test_polachs_law_with_a_set_that_has_no_ka_ks_is_refused(rig, protocol):
    with pytest.raises(ParameterError, match="needs Polach's k_A, k_S"):
        assemble(rig, protocol, m.DriveConfig(), {"dry": EUROSPRINTER_MODIFIED_FASTSIM})


def test_table_ratio_refuses_what_fastsim_refuses():
    """A NaN gradient and slope parameters outside the modified FASTSIM's ranges had given NaN,
    0 or a ratio as if unreduced; the ranges are fastsim's own."""
    from rollerrig._validation import ParameterError
    from rollerrig.contact.table import creep_table, table_ratio

    t = creep_table("fastsim")
    for args, message in (
        ((float("nan"),), "eps must be finite"),
        ((1e-3, 0.0), r"k0 must lie in \(0, 1\]"),
        ((1e-3, 1.0, -1.0, -1.0), r"alpha_inf must lie in \[0, 1\]"),
        ((1e-3, 1.0, 1.0, -1.0), "beta must be >= 0"),
    ):
        with pytest.raises(ParameterError, match=message):
            table_ratio(t, *args)
