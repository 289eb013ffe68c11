"""Polach creep law and friction law against closed forms and the linear theory.

References used for pinned numbers:
- Polach (2005), Wear 258, 992-1000: the model (eq. 12), its friction law (eq. 8), its limits
  (linear theory for small creep with k_A = k_S = 1, saturation at Q·μ), Table 2 parameter sets.
- Kalker (1990): linear theory F = G a b C11 s.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rollerrig._validation import ParameterError
from rollerrig.contact.creep import (
    POLACH_DRY,
    POLACH_PARAMETER_SETS,
    POLACH_WET,
    PolachParameters,
    adhesion_gradient,
    friction_coefficient,
    kalker_linear_force,
    polach_creep_force,
)

# A representative wheel-roller contact (values of the order of the default rig at 4.3 kN).
A_X, B_Y, C11, G = 3.4e-3, 2.7e-3, 3.9, 8.077e10
Q = 4300.0


def _force(s, w, params):
    return polach_creep_force(s, w, Q, A_X, B_Y, C11, G, params)


def test_parameter_sets_match_polach_2005_table_2():
    # Polach (2005), Table 2: dry mu0=0.55 A=0.40 B=0.60 s/m kA=1.00 kS=0.40;
    #                         wet mu0=0.30 A=0.40 B=0.20 s/m kA=0.30 kS=0.10.
    assert POLACH_DRY.as_tuple() == (0.55, 0.40, 0.60, 1.00, 0.40)
    assert POLACH_WET.as_tuple() == (0.30, 0.40, 0.20, 0.30, 0.10)
    assert set(POLACH_PARAMETER_SETS) == {"dry", "wet"}
    assert all("Polach (2005)" in p.source for p in POLACH_PARAMETER_SETS.values())


def test_friction_law_closed_form():
    # Polach (2005) eq. 8: mu(0) = mu0, mu(1/B) = mu0[(1-A)/e + A], mu(inf) = A mu0.
    p = POLACH_DRY
    assert friction_coefficient(0.0, p) == pytest.approx(0.55, rel=1e-15)
    expected = 0.55 * ((1 - 0.4) * np.exp(-1.0) + 0.4)
    assert friction_coefficient(1 / 0.6, p) == pytest.approx(expected, rel=1e-14)
    assert friction_coefficient(1e4, p) == pytest.approx(0.4 * 0.55, rel=1e-12)
    assert friction_coefficient(-2.0, p) == friction_coefficient(2.0, p)


def test_linear_limit_is_kalker_linear_theory():
    # kA = kS = 1, small creep: Polach -> Kalker linear theory F = G a b C11 s (Polach 2005).
    p = PolachParameters(0.5, 1.0, 0.0, 1.0, 1.0)
    s = np.array([1e-8, 1e-7, -1e-7])
    linear = kalker_linear_force(s, A_X, B_Y, C11, G)
    np.testing.assert_allclose(_force(s, 0.0, p), linear, rtol=1e-6)


def test_initial_slope_scales_with_reduction_factors():
    # dF/ds at s = 0 is (kA + kS)/2 times Kalker's slope (expand both terms to first order).
    p = POLACH_DRY
    s = 1e-9
    slope = _force(s, 0.0, p) / s
    kalker = G * A_X * B_Y * C11
    assert slope == pytest.approx(0.5 * (p.k_adhesion + p.k_slip) * kalker, rel=1e-6)


def test_saturation_at_coulomb_limit():
    # eps -> inf: kA eps/(1+(kA eps)^2) -> 0, arctan -> pi/2, so F -> Q mu(w).
    w = 3.0
    f = _force(1e6, w, POLACH_DRY)
    assert f == pytest.approx(Q * friction_coefficient(w, POLACH_DRY), rel=1e-5)


def test_gradient_uses_shear_modulus_not_contact_stiffness():
    # Kayaalp eq. 4.16 with Polach's C = 3 G C11 / (8 a) equals the corrected eq. 4.17.
    s, mu = 2e-3, 0.4
    c_stiff = 3 * G * C11 / (8 * A_X)
    eq_4_16 = (2 / 3) * c_stiff * np.pi * A_X**2 * B_Y * s / (Q * mu)
    assert adhesion_gradient(s, Q, mu, A_X, B_Y, C11, G) == pytest.approx(eq_4_16, rel=1e-14)


def test_wet_curve_peaks_below_dry_curve():
    s = np.linspace(0, 0.05, 501)
    v = 30 / 3.6
    dry = _force(s, s * v, POLACH_DRY) / Q
    wet = _force(s, s * v, POLACH_WET) / Q
    assert dry.max() > 1.5 * wet.max()
    # The dry curve has a maximum inside the range and then falls (slip-velocity friction).
    assert 0 < np.argmax(dry) < len(s) - 1


@settings(max_examples=200, deadline=None)
@given(
    s=st.floats(-0.5, 0.5, allow_nan=False),
    v=st.floats(0.5, 20.0),
    name=st.sampled_from(["dry", "wet"]),
)
def test_force_is_odd_and_bounded(s, v, name):
    p = POLACH_PARAMETER_SETS[name]
    f = _force(s, s * v, p)
    assert _force(-s, -s * v, p) == pytest.approx(-f, abs=1e-9)
    mu = friction_coefficient(s * v, p)
    # |kA eps/(1+(kA eps)^2)| <= 1/2 and |arctan| < pi/2  =>  |F| < Q mu (1 + 1/pi).
    assert abs(f) <= Q * mu * (1 + 1 / np.pi) + 1e-9
    assert np.sign(f) == np.sign(s) or s == 0


@settings(max_examples=200, deadline=None)
@given(
    k=st.floats(0.05, 1.0),
    s1=st.floats(0.0, 0.3),
    ds=st.floats(1e-6, 0.3),
)
def test_monotone_in_creep_for_equal_factors_and_constant_friction(k, s1, ds):
    # With kA = kS = k and B = 0: dF/d(k eps) = 2/(1+(k eps)^2)^2 > 0.
    p = PolachParameters(0.5, 0.4, 0.0, k, k)
    assert _force(s1 + ds, 0.0, p) > _force(s1, 0.0, p)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"k_adhesion": 0.3, "k_slip": 0.5}, "kS <= kA"),
        ({"k_adhesion": 1.2, "k_slip": 0.5}, "k_adhesion"),
        ({"static_friction": -0.1}, "static_friction"),
        ({"limit_ratio": 1.5}, "limit_ratio"),
        ({"friction_decay": float("nan")}, "friction_decay"),
    ],
)
def test_invalid_parameters_name_the_parameter(kwargs, message):
    base = {
        "static_friction": 0.5,
        "limit_ratio": 0.4,
        "friction_decay": 0.6,
        "k_adhesion": 1.0,
        "k_slip": 0.4,
    }
    with pytest.raises(ParameterError, match=message):
        PolachParameters(**(base | kwargs))


def test_nonphysical_inputs_raise():
    with pytest.raises(ParameterError, match="normal_load"):
        polach_creep_force(0.01, 0.1, -5.0, A_X, B_Y, C11, G)
    with pytest.raises(ParameterError, match="creep"):
        polach_creep_force(np.nan, 0.1, Q, A_X, B_Y, C11, G)


@pytest.mark.parametrize("eps", [0.0, 1e-3, 0.3, 1.0, 2.7, -4.0, 40.0, 1e200])
@pytest.mark.parametrize(("k_a", "k_s"), [(1.0, 1.0), (0.45, 0.15), (0.09, 0.33)])
def test_polach_shape_derivatives_match_complex_step_differences(eps, k_a, k_s):
    """h' and h'' (the arm loop's Halley steps use h'') against complex-step derivatives of
    h (Squire & Trapp 1998: f'(x) = Im f(x + i δ)/δ, exact to round-off with no cancellation),
    h'' as the complex step of the closed-form h'; and no overflow at huge ε."""
    from rollerrig.contact.creep import polach_shape_derivatives, polach_shape_kernel

    def shape(e):
        return k_a * e / (1.0 + (k_a * e) ** 2) + np.arctan(k_s * e)

    def slope(e):
        a, b = k_a * e, k_s * e
        return k_a * (1.0 - a * a) / (1.0 + a * a) ** 2 + k_s / (1.0 + b * b)

    h, dh, d2h = polach_shape_derivatives(eps, k_a, k_s)
    assert (h, dh) == polach_shape_kernel(eps, k_a, k_s)
    assert np.isfinite(d2h)
    if abs(eps) > 1e3:  # the complex step of (k_a ε)² overflows; h'' → 0 as ε^-3
        assert abs(d2h) < 1e-300
        return
    step = 1e-30
    assert dh == pytest.approx(shape(complex(eps, step)).imag / step, rel=1e-13, abs=1e-15)
    assert d2h == pytest.approx(slope(complex(eps, step)).imag / step, rel=1e-12, abs=1e-15)


def test_huge_creep_saturates_without_overflow_warnings():
    # Beyond |k_A eps| = 1.3e154, (k_A eps)^2 overflowed with a RuntimeWarning although the
    # force was right: the saturation (2/pi) Q mu (pi/2) = Q mu(w) (Polach 2005, eq. 12 with
    # k_A eps/(1 + (k_A eps)^2) -> 0 and arctan -> pi/2).
    import warnings

    s = np.array([1e160, -1e200, 1e300])
    w = 0.0833
    mu = float(friction_coefficient(w))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        f = _force(s, w, POLACH_DRY)
    np.testing.assert_allclose(f, np.sign(s) * Q * mu, rtol=1e-14)


def test_mismatched_array_lengths_name_the_parameters():
    with pytest.raises(
        ParameterError,
        match=r"creep \(shape \(3,\)\) and slip_velocity \(shape \(2,\)\) must have the same "
        r"shape, or one of them be a single number",
    ):
        polach_creep_force([0.01, 0.02, 0.03], [0.1, 0.2], Q, A_X, B_Y, C11, G)
    with pytest.raises(ParameterError, match=r"creep \(shape \(3,\)\) and semi_axis_x"):
        polach_creep_force([0.01, 0.02, 0.03], 0.1, Q, [A_X, 2 * A_X], B_Y, C11, G)
    with pytest.raises(ParameterError, match=r"normal_load \(shape \(2,\)\)"):
        adhesion_gradient([1e-3, 2e-3, 3e-3], [Q, Q], 0.5, A_X, B_Y, C11, G)
    with pytest.raises(ParameterError, match=r"creep \(shape \(3,\)\) and c11 \(shape \(2,\)\)"):
        kalker_linear_force([1e-3, 2e-3, 3e-3], A_X, B_Y, [C11, C11], G)


def test_scalars_give_scalars_and_arrays_broadcast():
    f = polach_creep_force(0.01, 0.0833, Q, A_X, B_Y, C11, G)
    assert np.ndim(f) == 0
    f = polach_creep_force(np.array([[0.01], [0.02]]), 0.0833, Q, [A_X, B_Y], B_Y, C11, G)
    assert f.shape == (2, 2)
