"""Tests for rollerrig.contact.elliptic (Carlson's R_F and R_D) against published values,
closed forms, Legendre's relation and scipy.special (Boost's implementation of Carlson's
algorithms, an independent code)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import special

from rollerrig.contact.elliptic import carlson_rd, carlson_rf, complete_elliptic_integrals

# Carlson (1995), Numer. Algorithms 10, §3, the test values of his algorithms (real cases).
CARLSON_1995 = [
    (carlson_rf, (1.0, 2.0, 0.0), 1.3110287771461),
    (carlson_rf, (2.0, 3.0, 4.0), 0.58408284167715),
    (carlson_rd, (0.0, 2.0, 1.0), 1.7972103521034),
    (carlson_rd, (2.0, 3.0, 4.0), 0.16510527294261),
]


@pytest.mark.parametrize(("fn", "args", "value"), CARLSON_1995)
def test_carlson_s_published_values(fn, args, value):
    # 14 significant digits as printed
    assert float(fn(*args)) == pytest.approx(value, rel=5e-13)


def test_closed_forms():
    # DLMF 19.20.1 and 19.20.18: R_F(x, x, x) = x^-1/2, R_F(0, y, y) = π/(2√y),
    # R_D(x, x, x) = x^-3/2, R_D(0, y, y) = 3π/(4 y^3/2).
    x = np.array([1e-12, 0.3, 1.0, 7.0, 1e9])
    assert np.allclose(carlson_rf(x, x, x), x**-0.5, rtol=1e-15, atol=0)
    assert np.allclose(carlson_rd(x, x, x), x**-1.5, rtol=1e-15, atol=0)
    assert np.allclose(carlson_rf(0.0, x, x), np.pi / (2 * np.sqrt(x)), rtol=1e-15, atol=0)
    assert np.allclose(carlson_rd(0.0, x, x), 3 * np.pi / (4 * x**1.5), rtol=1e-15, atol=0)


def test_legendre_s_relation():
    # E K' + E' K − K K' = π/2 (DLMF 19.7.1): K, E of p and K', E' of 1 − p, computed apart.
    p = np.linspace(1e-6, 1 - 1e-6, 501)
    k, e = complete_elliptic_integrals(p)
    k1, e1 = complete_elliptic_integrals(1.0 - p)
    assert np.allclose(e * k1 + e1 * k - k * k1, np.pi / 2, rtol=0, atol=2e-15 * np.max(k * k1))


def test_complete_integrals_match_scipy_to_a_few_ulp():
    p = np.logspace(-300, 0, 3001)
    k, e = complete_elliptic_integrals(p)
    assert np.max(np.abs(k / special.ellipkm1(p) - 1)) < 4e-15
    assert np.max(np.abs(e / special.ellipe(1.0 - p) - 1)) < 4e-15
    k0, e0 = complete_elliptic_integrals(1.0)  # the circle
    assert float(k0) == pytest.approx(np.pi / 2, rel=1e-15)
    assert float(e0) == pytest.approx(np.pi / 2, rel=1e-15)


positive = st.floats(min_value=1e-100, max_value=1e100)
argument = st.one_of(st.just(0.0), positive)


@settings(max_examples=300, deadline=None)
@given(x=argument, y=positive, z=positive)
def test_rf_and_rd_match_scipy(x, y, z):
    assert float(carlson_rf(x, y, z)) == pytest.approx(float(special.elliprf(x, y, z)), rel=4e-15)
    assert float(carlson_rd(x, y, z)) == pytest.approx(float(special.elliprd(x, y, z)), rel=4e-15)


def test_arrays_broadcast_and_every_element_keeps_its_accuracy():
    # Elements that need many duplication steps beside one that needs none: all take the
    # slowest one's steps, which must not cost the others their digits.
    x = np.array([[0.0], [1.0]])
    y = np.array([1e-30, 1.0, 5.0])
    z = 1.0
    rf, rd = carlson_rf(x, y, z), carlson_rd(x, y, z)
    assert rf.shape == rd.shape == (2, 3)
    for i in range(2):
        for j in range(3):
            assert rf[i, j] == pytest.approx(float(special.elliprf(x[i, 0], y[j], z)), rel=4e-15)
            assert rd[i, j] == pytest.approx(float(special.elliprd(x[i, 0], y[j], z)), rel=4e-15)


def test_outside_the_domain_nan_and_inf_without_warnings():
    with np.errstate(all="raise"):  # a warning would be an error here
        assert np.isnan(carlson_rf(-1.0, 1.0, 1.0))
        assert np.isnan(carlson_rd(1.0, 1.0, 0.0))
        assert np.isnan(carlson_rd(np.nan, 1.0, 1.0))
        assert np.isinf(carlson_rf(0.0, 0.0, 1.0))
        assert np.isinf(carlson_rd(0.0, 0.0, 1.0))


def test_complete_integrals_at_the_ends_of_the_parameter_range():
    # The argument is the complementary parameter p = 1 - m: p = 1 is m = 0 (K = E = π/2),
    # p = 0 is m = 1 (K = inf, E = 1, DLMF 19.6.1), where E was 0 · inf = NaN.
    with np.errstate(all="raise"):  # no warning either
        k, e = complete_elliptic_integrals(0.0)
    assert np.isinf(k) and k == special.ellipk(1.0)
    assert e == 1.0 == special.ellipe(1.0)
    assert np.ndim(k) == np.ndim(e) == 0 and not isinstance(e, np.ndarray)
    p = np.array([0.0, 1e-300, 1e-12, 0.5, 1.0])
    k, e = complete_elliptic_integrals(p)
    assert np.array_equal(np.isinf(k), p == 0.0)
    assert np.allclose(k[1:], special.ellipkm1(p[1:]), rtol=4e-15, atol=0)
    assert np.allclose(e, special.ellipe(1.0 - p), rtol=4e-15, atol=0)
    assert k[-1] == pytest.approx(np.pi / 2, rel=1e-15) and e[-1] == pytest.approx(np.pi / 2)
