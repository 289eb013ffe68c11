"""Tests for rollerrig.contact.kalker: Kalker's table, interpolation rule and asymptotes."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rollerrig._validation import ParameterError
from rollerrig.contact.kalker import KALKER_TABLE, kalker_coefficients

NUS = (0.0, 0.25, 0.5)


# --- Published table ------------------------------------------------------------------------


def test_table_nodes_reproduced_exactly():
    # Source: Kalker (1990) Table E.3; the interpolation must return the 19 x 3 nodes exactly.
    for j, nu in enumerate(NUS):
        c = kalker_coefficients(KALKER_TABLE.a_over_b, nu)
        np.testing.assert_allclose(c.c11, KALKER_TABLE.c11[:, j], rtol=1e-13)
        np.testing.assert_allclose(c.c22, KALKER_TABLE.c22[:, j], rtol=1e-13)
        np.testing.assert_allclose(c.c23, KALKER_TABLE.c23[:, j], rtol=1e-13)
        np.testing.assert_allclose(c.c33, KALKER_TABLE.c33[:, j], rtol=1e-13)


@pytest.mark.parametrize(
    ("a_over_b", "nu", "expected"),
    [
        # Source: Kalker (1990) Table E.3, as in CONTACT's linrol (m_hertz.f90), g = a/b = 1:
        (1.0, 0.0, (3.40, 3.40, 1.33, 1.21)),
        (1.0, 0.25, (4.12, 3.67, 1.47, 1.19)),
        (1.0, 0.5, (5.20, 3.98, 1.63, 1.16)),
        # g = a/b = 0.1 (first row) and 0.8 (C23 = 1.25 at nu = 0.25, monotone row)
        (0.1, 0.25, (3.31, 2.52, 0.473, 8.28)),
        (0.8, 0.25, (3.91, 3.41, 1.25, 1.37)),
        # g = b/a = 0.1, i.e. a/b = 10 (last row)
        (10.0, 0.0, (10.7, 10.7, 12.2, 0.795)),
        (10.0, 0.5, (12.9, 16.0, 18.0, 0.228)),
    ],
)
def test_published_values(a_over_b, nu, expected):
    assert tuple(kalker_coefficients(a_over_b, nu)) == pytest.approx(expected, rel=1e-12)


def test_c33_columns_match_public_nu_0_3_table():
    # Cross-check: a public wheel-rail code tabulates C33 at nu = 0.3 as 0.8·C(0.25) + 0.2·C(0.5)
    # of Table E.3: 8.964 at a/b = 0.1, 1.184 at a/b = 1, 0.4664 at b/a = 0.1.
    c33 = KALKER_TABLE.c33
    blend = 0.8 * c33[:, 1] + 0.2 * c33[:, 2]
    assert blend[0] == pytest.approx(8.964, abs=5e-4)
    assert blend[9] == pytest.approx(1.184, abs=5e-4)
    assert blend[-1] == pytest.approx(0.4664, abs=5e-5)


def test_c11_equals_c22_at_nu_zero():
    # Table property (Kalker 1990): for nu = 0 the longitudinal and lateral problems coincide.
    np.testing.assert_array_equal(KALKER_TABLE.c11[:, 0], KALKER_TABLE.c22[:, 0])
    x = np.geomspace(1e-3, 1e3, 101)
    c = kalker_coefficients(x, 0.0)
    np.testing.assert_allclose(c.c11, c.c22, rtol=1e-12)


def test_table_is_read_only():
    with pytest.raises(ValueError):
        KALKER_TABLE.c11[0, 0] = 1.0


# --- Interpolation rule ---------------------------------------------------------------------


@pytest.mark.parametrize("nu", [0.0, 0.1, 0.28, 0.5])
@pytest.mark.parametrize("point", [0.1, 1.0, 10.0])
def test_continuous_at_circle_and_table_edges(point, nu):
    eps = 1e-9
    lo = np.array(kalker_coefficients(point * (1 - eps), nu))
    hi = np.array(kalker_coefficients(point * (1 + eps), nu))
    np.testing.assert_allclose(lo, hi, rtol=1e-6)


def test_nu_interpolation_matches_contact_linrol_rule_at_nodes():
    # CONTACT's linrol: 1/C interpolated quadratically through nu = 0, 0.25, 0.5. At a table
    # node our rule is the same, so it must agree exactly.
    nu = 0.28
    w = np.array([(nu - 0.25) * (nu - 0.5) * 8, -(nu - 0.5) * nu * 16, nu * (nu - 0.25) * 8])
    for i in range(19):
        expected = 1.0 / np.sum(w / KALKER_TABLE.c11[i])
        assert kalker_coefficients(KALKER_TABLE.a_over_b[i], nu).c11 == pytest.approx(expected)


def test_close_to_contact_linear_interpolation_between_nodes():
    # Peer cross-check: CONTACT interpolates linearly in g; ours is a monotone cubic in ln(a/b).
    # Where the curves are flat (C11, C22, C23 for a < b; C33 for a > b) the two rules agree to
    # 0.2 %. Toward the slender end the coefficients follow their asymptotic laws (1/g,
    # 1/(g ln g), g^-1.5), the chord of the linear rule lies above the convex curve, and the
    # rules differ by up to 5 % for g >= 0.2 and 13 % for 0.1 < g < 0.2 (C23, a > b); there ours
    # must stay between the two node values (no overshoot).
    g = np.linspace(0.1, 1.0, 181)
    first = g < 0.2
    for table_rows, ratio in ((slice(0, 10), g), (slice(9, 19), 1.0 / g)):
        nodes_g = KALKER_TABLE.g[table_rows]
        order = np.argsort(nodes_g)
        for name in ("c11", "c22", "c23", "c33"):
            column = getattr(KALKER_TABLE, name)[table_rows, 1][order]
            linear = np.interp(g, nodes_g[order], column)
            ours = getattr(kalker_coefficients(ratio, 0.25), name)
            np.testing.assert_allclose(ours[~first], linear[~first], rtol=0.05)
            np.testing.assert_allclose(ours[first], linear[first], rtol=0.13)
            low, high = sorted(column[:2])
            assert np.all((ours[first] >= low - 1e-12) & (ours[first] <= high + 1e-12))


def test_monotone_cubic_is_scipys_pchip():
    # Reference: scipy.interpolate.PchipInterpolator (Fritsch & Butland slopes, three-point
    # ends). The module writes the same rule itself (no scipy.interpolate import on the path
    # of every rig): on the table's nodes and on random data with flat and sign-changing
    # stretches, the two agree to round-off.
    from scipy.interpolate import PchipInterpolator

    from rollerrig.contact import kalker

    x = np.linspace(kalker._LOG_NODES[0], kalker._LOG_NODES[-1], 2001)
    ref = PchipInterpolator(kalker._LOG_NODES, kalker._NODE_VALUES, axis=0)(x)
    np.testing.assert_allclose(kalker._table_at(x), ref, rtol=1e-14)
    rng = np.random.default_rng(20)
    for _ in range(200):
        nodes = np.sort(rng.uniform(-3.0, 3.0, rng.integers(3, 12)))
        if np.min(np.diff(nodes)) < 1e-3:
            continue
        values = rng.normal(size=(nodes.size, 2, 3))
        values[rng.uniform(size=nodes.size) < 0.3, 0, 0] = 0.0  # flat stretches, zero slopes
        at = np.linspace(nodes[0], nodes[-1], 301)
        ours = kalker._pchip(nodes, values, kalker._pchip_slopes(nodes, values), at)
        theirs = PchipInterpolator(nodes, values, axis=0)(at)
        np.testing.assert_allclose(ours, theirs, rtol=0.0, atol=1e-12)


def test_monotone_in_poisson_for_c11():
    nu = np.linspace(0.0, 0.5, 11)
    for ratio in (0.1, 0.5, 1.0, 3.0, 10.0):
        assert np.all(np.diff(kalker_coefficients(ratio, nu).c11) > 0)


# --- Asymptotes -----------------------------------------------------------------------------


@pytest.mark.parametrize("nu", NUS)
def test_asymptote_narrow_in_rolling_direction(nu):
    # Kalker (1990) App. E (as in CONTACT's linrol), g = a/b -> 0:
    # C11 -> π²/(4(1-nu)), C22 -> π²/4, C23 -> π√g/(3(1-nu))·(1 + nu(ln(16/g) - 5)).
    g = 1e-6
    c = kalker_coefficients(g, nu)
    assert c.c11 == pytest.approx(np.pi**2 / (4 * (1 - nu)), rel=1e-4)
    assert c.c22 == pytest.approx(np.pi**2 / 4, rel=1e-4)
    c23 = np.pi * np.sqrt(g) / (3 * (1 - nu)) * (1 + nu * (np.log(16 / g) - 5))
    assert c.c23 == pytest.approx(c23, rel=1e-4)
    assert c.c33 == pytest.approx(np.pi**2 / (16 * (1 - nu) * g), rel=1e-4)


@pytest.mark.parametrize("nu", NUS)
def test_asymptote_long_in_rolling_direction(nu):
    # Kalker (1990) App. E (as in CONTACT's linrol), g = b/a -> 0, Λ = ln(16/g²).
    g = 1e-6
    lam = np.log(16 / g**2)
    c = kalker_coefficients(1 / g, nu)
    c11 = 2 * np.pi / ((lam - 2 * nu) * g) * (1 + (3 - np.log(4)) / (lam - 2 * nu))
    d2 = (1 - nu) * lam + 2 * nu
    c22 = 2 * np.pi / g * (1 + (1 - nu) * (3 - np.log(4)) / d2) / d2
    c23 = 2 * np.pi / (3 * g**1.5 * ((1 - nu) * lam - 2 + 4 * nu))
    assert c.c11 == pytest.approx(c11, rel=1e-4)
    assert c.c22 == pytest.approx(c22, rel=1e-4)
    assert c.c23 == pytest.approx(c23, rel=1e-4)
    # C33: no verified asymptote; documented clamp at its a/b = 10 value
    assert c.c33 == pytest.approx(kalker_coefficients(10.0, nu).c33, rel=1e-12)


@pytest.mark.parametrize("nu", NUS)
def test_asymptotes_close_to_table_edges(nu):
    # Sanity of the asymptotes: at the table edge they are within 7 % of the table (C33 for
    # b/a -> 0 excluded), so the blending correction is small.
    from rollerrig.contact.kalker import _asymptote_a_gt_b, _asymptote_a_le_b

    j = NUS.index(nu)
    lo = _asymptote_a_le_b(np.float64(0.1), nu)
    hi = _asymptote_a_gt_b(np.float64(0.1), nu)
    for k, name in enumerate(("c11", "c22", "c23", "c33")):
        assert lo[k] == pytest.approx(getattr(KALKER_TABLE, name)[0, j], rel=0.07)
    for k, name in enumerate(("c11", "c22", "c23")):
        assert hi[k] == pytest.approx(getattr(KALKER_TABLE, name)[-1, j], rel=0.07)


@settings(max_examples=80, deadline=None)
@given(log_ratio=st.floats(-12.0, 12.0), nu=st.floats(0.0, 0.5))
def test_positive_and_finite_everywhere(log_ratio, nu):
    c = np.array(kalker_coefficients(np.exp(log_ratio), nu))
    assert np.all(np.isfinite(c)) and np.all(c > 0)


def test_vectorised_broadcast():
    c = kalker_coefficients(np.array([[0.05], [1.0], [20.0]]), np.array([0.0, 0.3]))
    assert np.shape(c.c11) == (3, 2)
    assert c.c11[1, 1] == pytest.approx(float(kalker_coefficients(1.0, 0.3).c11))


# --- Validation -----------------------------------------------------------------------------


@pytest.mark.parametrize("bad", [0.0, -1.0, np.nan, np.inf, 1e300, 1e-300])
def test_bad_ratio_names_parameter(bad):
    """Beyond 1e8 either way the asymptotes had given C11 = 0 and C23 = NaN (at 1e300)."""
    with pytest.raises(ParameterError, match=r"a_over_b must (be finite|lie in \[1e-08, 1e\+08\])"):
        kalker_coefficients(bad, 0.3)


@pytest.mark.parametrize("bad", [-0.01, 0.51])
def test_bad_poisson_names_parameter(bad):
    with pytest.raises(ParameterError, match=r"poisson must lie in \[0, 0.5\]"):
        kalker_coefficients(1.0, bad)


def test_mismatched_shapes_name_both_parameters():
    # numpy's own error ("operands could not be broadcast together") had named neither.
    with pytest.raises(
        ParameterError,
        match=r"a_over_b \(shape \(3,\)\) and poisson \(shape \(2,\)\) must have the same "
        r"shape, or one of them be a single number",
    ):
        kalker_coefficients([1.0, 2.0, 3.0], [0.1, 0.2])


def _contact_rule(a_over_b, nu):
    """CONTACT's ``linrol`` inside the table (Vollebregt, m_hertz.f90): linear in
    g = min(a/b, b/a) between the rows of the side a <= b or a > b, then the quadratic in ν of
    1/C; written here from its description, for C11, C22, C23."""
    from rollerrig.contact.kalker import KALKER_TABLE as T

    g = a_over_b if a_over_b <= 1.0 else 1.0 / a_over_b
    side = T.a_over_b <= 1.0 + 1e-12 if a_over_b <= 1.0 else T.a_over_b >= 1.0 - 1e-12
    order = np.argsort(T.g[side])
    out = []
    for table in (T.c11, T.c22, T.c23):
        c = [np.interp(g, T.g[side][order], table[side][order][:, j]) for j in range(3)]
        inv = (
            (nu - 0.25) * (nu - 0.5) * 8.0 / c[0]
            - (nu - 0.5) * nu * 16.0 / c[1]
            + nu * (nu - 0.25) * 8.0 / c[2]
        )
        out.append(1.0 / inv)
    return np.array(out)


def test_between_the_nodes_contact_s_chord_differs_as_the_guide_states():
    # docs/guide/contact.rst (ν = 0.28): within 0.8 % for 0.1 <= a/b <= 2 (0.03 % at the
    # rig's 0.85); for slender ellipses along the rolling direction, where C grows like 1/g,
    # CONTACT's chord in g lies above ours: ours lower by up to 6.3 % (C11, C22) and 12.7 %
    # (C23) of CONTACT's for a/b = 5-10.
    nu = 0.28
    inside = np.exp(np.linspace(np.log(0.1), np.log(2.0), 301))
    ours = np.array([kalker_coefficients(r, nu)[:3] for r in inside], dtype=float)
    theirs = np.array([_contact_rule(r, nu) for r in inside])
    assert np.max(np.abs(ours / theirs - 1.0)) < 0.008
    rig = np.array(kalker_coefficients(0.85, nu)[:3], dtype=float)
    assert np.max(np.abs(rig / _contact_rule(0.85, nu) - 1.0)) < 3e-4
    slender = np.exp(np.linspace(np.log(5.0), np.log(10.0), 201))[1:-1]
    ours = np.array([kalker_coefficients(r, nu)[:3] for r in slender], dtype=float)
    theirs = np.array([_contact_rule(r, nu) for r in slender])
    ratio = ours / theirs - 1.0
    assert np.all(ratio <= 1e-9)  # the chord lies above
    assert -0.065 < ratio[:, :2].min() < -0.055 and -0.13 < ratio[:, 2].min() < -0.12
