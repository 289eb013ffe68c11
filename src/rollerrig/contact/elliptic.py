"""Carlson's symmetric elliptic integrals R_F and R_D, for the Hertz ellipse.

The contact's Hertz solution (:mod:`rollerrig.contact.hertz`) needs the complete elliptic
integrals K and E and their ratio; written with Carlson's integrals (DLMF 19.25.1) they are
free of the cancellation of ``K − E`` near the circle. They are computed here by Carlson's
duplication algorithm (Carlson 1995; DLMF 19.36(i)) in plain numpy rather than imported from
``scipy.special``: every command that builds a rig evaluates them, and ``import
scipy.special`` (0.2 s, most of it scipy's array-API layer) was a tenth of ``rollerrig
simulate`` (issue 20). The tests check both against ``scipy.special.elliprf``/``elliprd``
(the same algorithm in Carlson's and Boost's implementation) to a few ulp.

The duplication step ``λ = √x√y + √y√z + √z√x``, ``(x, y, z) ← (x + λ, y + λ, z + λ)/4``
leaves the integral unchanged (up to R_D's accumulated sum) and shrinks the spread of the
arguments fourfold; once the spread is below ``(3 r)^(1/6)`` (R_F) or ``(r/4)^(1/6)`` (R_D)
of their mean, Carlson's fifth-order series (DLMF 19.36.1, 19.36.2) is within a relative
``r`` of the integral. Every element takes the slowest element's number of steps (further
steps only shrink the spread more), so the arrays are processed whole.

References
----------
- B. C. Carlson, "Numerical computation of real or complex elliptic integrals", Numer.
  Algorithms 10 (1995) 13-26 (the algorithms and their error bounds).
- NIST Digital Library of Mathematical Functions, §19.25(i) (K and E as Carlson integrals),
  §19.36(i) (the series of R_F and R_D).
"""

from __future__ import annotations

import numpy as np

__all__ = ["carlson_rd", "carlson_rf", "complete_elliptic_integrals"]

# Carlson's tolerance r: the series' truncation error is below r relative (Carlson 1995, eqs.
# 2.2 and 2.19); a quarter of the spacing of doubles leaves round-off as the error.
_TOLERANCE = 0.25 * np.finfo(float).eps
_MAX_STEPS = 200  # each step shrinks the spread fourfold: 4^-200 is below any double's range


def _converged(threshold, mean):
    """Whether the series may be applied to every element: ``4^-m Q <= |A_m|`` (Carlson 1995,
    eq. 2.2), with ``threshold = 4^-m Q``; an element that is NaN or infinite counts as done
    (its result is NaN or follows from the infinity)."""
    return bool(np.all(~(threshold > np.abs(mean))))


def _duplication(x, y, z, mean, threshold, r_d_sum=False):
    """Carlson's duplication steps until the series applies to every element (Carlson 1995,
    eqs. 2.2-2.5): ``λ = √x√y + √y√z + √z√x``, ``(x, y, z, A) ← (x + λ, y + λ, z + λ, A + λ)/4``.

    Returns ``(A_m, m, S)``: the last mean, the number of steps and, with ``r_d_sum``, R_D's
    sum ``S = Σ_k 4^-k / (√z_k (z_k + λ_k))`` (zeros otherwise); ``threshold`` is ``Q``, the
    initial spread scaled by the method's tolerance factor.
    """
    total = np.zeros_like(mean)
    weight = 1.0
    steps = 0
    while steps < _MAX_STEPS and not _converged(threshold, mean):
        steps += 1
        threshold = 0.25 * threshold
        sx, sy, sz = np.sqrt(x), np.sqrt(y), np.sqrt(z)
        lam = sx * (sy + sz) + sy * sz
        if r_d_sum:
            total = total + weight / (sz * (z + lam))
            weight *= 0.25
        x, y, z, mean = 0.25 * (x + lam), 0.25 * (y + lam), 0.25 * (z + lam), 0.25 * (mean + lam)
    return mean, steps, total


@np.errstate(all="ignore")  # NaN and inf are results here (documented), not accidents
def carlson_rf(x, y, z):
    """Carlson's symmetric integral of the first kind, R_F(x, y, z) (DLMF 19.16.1).

    ``R_F = ½ ∫₀^∞ dt / √((t + x)(t + y)(t + z))``, for x, y, z >= 0 with at most one zero.

    Parameters
    ----------
    x, y, z : float or array_like
        Arguments [-], broadcast together; non-negative, at most one of them zero.

    Returns
    -------
    float or ndarray
        R_F [-]; NaN where an argument is negative or NaN, inf where two are zero. The
        arguments' magnitudes should lie within about 1e±150 (the duplication multiplies
        them); outside, the result may be NaN or inf.

    Examples
    --------
    >>> round(float(carlson_rf(0.0, 1.0, 1.0)), 12)  # π/2, DLMF 19.20.1
    1.570796326795
    """
    x, y, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, y, z)))
    x0, y0, z0 = x, y, z
    mean = (x + y + z) / 3.0
    spread = np.maximum(np.maximum(np.abs(mean - x), np.abs(mean - y)), np.abs(mean - z))
    mean0 = mean.copy()
    threshold = (3.0 * _TOLERANCE) ** (-1.0 / 6.0) * spread
    mean, steps, _ = _duplication(x, y, z, mean, threshold)
    scale = 4.0**steps * mean
    dx = (mean0 - x0) / scale
    dy = (mean0 - y0) / scale
    dz = -(dx + dy)
    e2 = dx * dy - dz * dz
    e3 = dx * dy * dz
    # DLMF 19.36.1
    series = 1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0
    out = series / np.sqrt(mean)
    zeros = (x0 == 0).astype(int) + (y0 == 0) + (z0 == 0)
    out = np.where(zeros >= 2, np.inf, out)
    out = np.where((x0 < 0) | (y0 < 0) | (z0 < 0), np.nan, out)
    return out[()] if out.ndim == 0 else out


@np.errstate(all="ignore")
def carlson_rd(x, y, z):
    """Carlson's symmetric integral of the second kind, R_D(x, y, z) (DLMF 19.16.5).

    ``R_D = (3/2) ∫₀^∞ dt / ((t + z) √((t + x)(t + y)(t + z)))``, for x, y >= 0 with at most
    one zero and z > 0.

    Parameters
    ----------
    x, y, z : float or array_like
        Arguments [-], broadcast together.

    Returns
    -------
    float or ndarray
        R_D [-]; NaN where an argument is negative or NaN or z is zero, inf where x and y
        are both zero. Magnitudes within about 1e±150, as for :func:`carlson_rf`.

    Examples
    --------
    >>> round(float(carlson_rd(0.0, 2.0, 1.0)), 12)  # 1.7972103521034, Carlson (1995) §3
    1.797210352103
    """
    x, y, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, y, z)))
    x0, y0, z0 = x, y, z
    mean = (x + y + 3.0 * z) / 5.0
    mean0 = mean.copy()
    spread = np.maximum(np.maximum(np.abs(mean - x), np.abs(mean - y)), np.abs(mean - z))
    threshold = (0.25 * _TOLERANCE) ** (-1.0 / 6.0) * spread
    mean, steps, total = _duplication(x, y, z, mean, threshold, r_d_sum=True)
    weight = 0.25**steps
    scale = 4.0**steps * mean
    dx = (mean0 - x0) / scale
    dy = (mean0 - y0) / scale
    dz = -(dx + dy) / 3.0
    xy = dx * dy
    z2 = dz * dz
    e2 = xy - 6.0 * z2
    e3 = (3.0 * xy - 8.0 * z2) * dz
    e4 = 3.0 * (xy - z2) * z2
    e5 = xy * z2 * dz
    # DLMF 19.36.2
    series = (
        1.0
        - 3.0 * e2 / 14.0
        + e3 / 6.0
        + 9.0 * e2 * e2 / 88.0
        - 3.0 * e4 / 22.0
        - 9.0 * e2 * e3 / 52.0
        + 3.0 * e5 / 26.0
    )
    out = weight * series / (mean * np.sqrt(mean)) + 3.0 * total
    out = np.where((x0 == 0) & (y0 == 0), np.inf, out)
    out = np.where((x0 < 0) | (y0 < 0) | (z0 <= 0), np.nan, out)
    return out[()] if out.ndim == 0 else out


def complete_elliptic_integrals(complementary_parameter):
    """K(m) and E(m), the complete elliptic integrals of parameter m = 1 − p.

    With p = 1 − m given directly (as ``scipy.special.ellipkm1`` takes it), so that slender
    ellipses (p → 0) keep their digits: ``K = R_F(0, p, 1)`` and ``E = (p/3)(R_D(0, p, 1) +
    R_D(0, 1, p))`` (DLMF 19.25.1, the form without cancellation).

    Parameters
    ----------
    complementary_parameter : float or array_like
        p = 1 − m ∈ [0, 1] [-] (for an ellipse of axis ratio g, p = g²).

    Returns
    -------
    K, E : float or ndarray
        [-]. At p = 1 (m = 0, the circle) K = E = π/2; at p = 0 (m = 1, the ellipse
        degenerate to a line) K = inf and E = 1, their limits (DLMF 19.6.1), where the product
        ``(p/3) R_D(0, 1, p)`` is 0 · inf.

    Examples
    --------
    >>> k, e = complete_elliptic_integrals(1.0)  # the circle: K = E = π/2
    >>> round(float(k), 12), round(float(e), 12)
    (1.570796326795, 1.570796326795)
    >>> k, e = complete_elliptic_integrals(0.0)  # m = 1: K = inf, E = 1
    >>> float(k), float(e)
    (inf, 1.0)
    """
    p = np.asarray(complementary_parameter, dtype=float)
    k = carlson_rf(0.0, p, 1.0)
    with np.errstate(invalid="ignore"):  # 0 · inf at p = 0, replaced below
        e = (p / 3.0) * (carlson_rd(0.0, p, 1.0) + carlson_rd(0.0, 1.0, p))
    e = np.where(p == 0.0, 1.0, e)  # E(m = 1) = 1 (DLMF 19.6.1)
    return k, (e[()] if e.ndim == 0 else e)
