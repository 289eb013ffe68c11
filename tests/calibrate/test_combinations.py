"""Correlated keys reported as the combination the data determine
(:func:`rollerrig.calibrate.diagnostics.identified_combinations`), on covariances whose
eigen-decomposition is known in closed form."""

import math

import numpy as np
import pytest

from rollerrig.calibrate.diagnostics import identified_combinations


def _covariance(values, rel_se, r):
    """Covariance [SI] of two values with relative standard errors ``rel_se`` and
    correlation ``r``."""
    s = np.asarray(rel_se) * np.asarray(values)
    return np.array([[s[0] ** 2, r * s[0] * s[1]], [r * s[0] * s[1], s[1] ** 2]])


@pytest.mark.parametrize("r", [0.995, 0.9997, -0.999])
def test_equal_relative_errors_give_the_ratio_or_the_product(r):
    # Equal relative errors s: L = s^2 [[1, r], [r, 1]], eigenvectors (1, -1) and (1, 1) with
    # eigenvalues s^2 (1 - r) and s^2 (1 + r). r > 0 fixes the ratio a/b to s sqrt(2 (1 - r));
    # r < 0 the product to s sqrt(2 (1 + r)) (= s sqrt(2 (1 - |r|))).
    s, values = 2e-4, [43500.0, 6.6]
    (c,) = identified_combinations(
        ["k", "J"], values, ["N.m/rad", "kg.m^2"], _covariance(values, [s, s], r), 0.98
    )
    sign = -1.0 if r > 0 else 1.0
    assert c["exponents"] == {"k": 1.0, "J": sign}
    assert c["value"] == pytest.approx(values[0] * values[1] ** sign, rel=1e-12)
    assert c["relative_standard_error"] == pytest.approx(s * math.sqrt(2 * (1 - abs(r))), 1e-9)
    assert c["standard_error"] == pytest.approx(c["value"] * c["relative_standard_error"])
    assert c["undetermined"]["exponents"] == {"k": 1.0, "J": -sign}
    loose = s * math.sqrt(2 * (1 + abs(r)))
    assert c["undetermined"]["relative_standard_error"] == pytest.approx(loose, rel=1e-9)
    assert c["max_abs_correlation"] == pytest.approx(abs(r))
    assert c["unit"] == ("N.m/rad (kg.m^2)^-1" if r > 0 else "N.m/rad kg.m^2")


def test_unequal_errors_follow_the_closed_form_eigenvector():
    # 2x2 symmetric [[a, c], [c, d]]: smallest eigenvalue lam = (a + d)/2 - sqrt(((a - d)/2)^2
    # + c^2), eigenvector (c, lam - a), so the exponent of b per unit exponent of a is
    # (lam - a)/c = -0.3367 here (b's relative error is the larger: b enters weakly).
    values, rel, r = [2.0, 5.0], [1e-3, 3e-3], 0.995
    cov = _covariance(values, rel, r)
    a, d, c_ = rel[0] ** 2, rel[1] ** 2, r * rel[0] * rel[1]
    lam = (a + d) / 2 - math.sqrt(((a - d) / 2) ** 2 + c_**2)
    exponent = (lam - a) / c_
    assert -1.0 < exponent < 0.0
    (c,) = identified_combinations(["a", "b"], values, ["m", "s"], cov, 0.98)
    assert c["exponents"] == {"a": 1.0, "b": float(f"{exponent:.3g}")}
    g = np.array([1.0, c["exponents"]["b"]])
    rel_cov = cov / np.outer(values, values)
    assert c["relative_standard_error"] == pytest.approx(math.sqrt(g @ rel_cov @ g), rel=1e-12)
    assert c["value"] == pytest.approx(2.0 * 5.0 ** c["exponents"]["b"], rel=1e-12)
    # the exponents rounded to three digits cost little against the exact eigenvalue
    exact = math.sqrt(lam) * math.hypot(1.0, exponent)
    assert c["relative_standard_error"] == pytest.approx(exact, rel=0.02)
    assert c["relative_standard_error"] < min(rel)


def test_no_combination_below_the_threshold_or_for_a_non_positive_value():
    values = [1.0, 2.0]
    weak = _covariance(values, [0.01, 0.01], 0.9)
    assert identified_combinations(["a", "b"], values, ["1", "1"], weak, 0.98) == []
    cov = _covariance([1.0, 2.0], [0.01, 0.01], 0.999)
    assert identified_combinations(["a", "b"], [-1.0, 2.0], ["1", "1"], cov, 0.98) == []


def test_a_chain_of_correlated_pairs_is_one_group():
    # a-b and b-c correlated beyond the threshold, a-c by less: one group of three; d apart.
    s = np.array([0.01, 0.01, 0.01, 0.01])
    corr = np.array(
        [[1.0, 0.99, 0.97, 0.0], [0.99, 1.0, 0.99, 0.0], [0.97, 0.99, 1.0, 0.0], [0, 0, 0, 1.0]]
    )
    values = np.array([1.0, 2.0, 3.0, 4.0])
    cov = corr * np.outer(s * values, s * values)
    (c,) = identified_combinations(list("abcd"), values, ["1"] * 4, cov, 0.98)
    assert c["keys"] == ["a", "b", "c"]
    rel = cov[:3, :3] / np.outer(values[:3], values[:3])
    smallest = np.linalg.eigvalsh(rel)[0]
    g = np.array(list(c["exponents"].values()))
    assert c["relative_standard_error"] ** 2 == pytest.approx(g @ rel @ g, rel=1e-12)
    assert c["relative_standard_error"] ** 2 >= smallest * (g @ g) * (1 - 1e-9)  # Rayleigh bound
