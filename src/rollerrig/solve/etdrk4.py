"""Exponential time differencing RK4 (ETDRK4, Cox & Matthews 2002) for the rig's twin.

The twin ``x' = f(t, x)`` is split as ``x' = L x + N(t, x)`` with ``N = f − L x`` and ``L``
block diagonal, made of small blocks (at most 3 states each) on the states where the model is
stiff:

- *static* blocks, linear and constant within a protocol segment: the two stator mounts
  ``(θ1, ω1)`` and ``(θ7, ω7)``, ``[[0, 1], [−k/J, −b/J]]``; their entries are taken once per
  segment by forward differences of the right-hand side (exact up to rounding, since they are
  linear); in a sweep's runs also the PMSM's currents, each a 1 x 1 block, linear only below
  the drive's voltage limit (``rollerrig.solve.fast.CURRENT_BLOCKS``, whose driver integrates
  a segment that met the limit again without them);
- *dynamic* blocks, re-linearised every ``relinearise`` steps from forward differences of the
  right-hand side: the contact's ``(ω4, ω5)`` (with a flexible frame ``(ω4, ω5, v_f)``), whose
  pole, the creep law's slope, changes sign past the adhesion peak and reaches −12 000 1/s at
  20 kN and 10 km/h.

On every other state ``L = 0`` and the method is the classical RK4. One step of length ``h``
(Cox & Matthews 2002, eqs. 26-29; φ-function form of Hochbruck & Ostermann 2010, Sec. 2.3)::

    a = e^{hL/2} u + (h/2) φ1(hL/2) N(t, u)
    b = e^{hL/2} u + (h/2) φ1(hL/2) N(t + h/2, a)
    c = e^{hL/2} a + (h/2) φ1(hL/2) (2 N(t + h/2, b) − N(t, u))
    u_new = e^{hL} u + h [(φ1 − 3φ2 + 4φ3) N_u + 2(φ2 − 2φ3)(N_a + N_b) + (4φ3 − φ2) N_c]

with ``φ_k(hL)``; for ``L = 0`` the weights are 1/6, 1/3, 1/6 (RK4). Four right-hand sides a
step (the one at the new state is the next step's first). The φ-functions of a block are those
of its small matrix, by a Taylor series of φ3 after scaling, the recurrence
``φ_{k−1}(Z) = Z φ_k(Z) + I/(k−1)!`` and the doubling formulas of Skaflestad & Wright (2009),
``φ_k(2Z) = 2^{−k} [e^Z φ_k(Z) + Σ_{j=1..k} φ_j(Z)/(k−j)!]`` (:func:`phi_functions`).

The step is fixed within a protocol segment: the largest step not above ``h_max`` that divides
the segment and keeps the explicit part (the forward-difference Jacobian at the segment's start
without the blocks) inside RK4's stability region with a margin (:func:`rk4_stable_step`). The
output between steps is the cubic Hermite interpolant of the step's ends and derivatives. A
segment on which the stable step would be very short (near standstill, where the bearing
friction's regularisation is stiff), which ends non-finite, or which ramps the roller to or
from standstill (the V/f drive's stiffness at zero frequency, which the estimate at the
segment's start does not see: :data:`rollerrig.solve.fast.STOP_SPEED`), is integrated by the
fallback,
the adaptive ROS34PW2 W-method (:mod:`rollerrig.solve.ros34pw`).

The step is not adapted to the error; instead each step estimates it (classical RK4's
embedded third-order estimate, :func:`_step_error`, weighted to the quantity the results are
judged by). A step whose estimate exceeds ``err_limit`` is rejected and the segment goes on
from the last accepted state at a shorter step (1.25, 2 and 4 times shorter in turn, and only
away from standstill: :data:`rollerrig.solve.fast.GUARD_STEP_DIVISORS`), back to the longer
step once :data:`GROW_AFTER` estimates in a row say it would pass there (:func:`_segment`);
where the shortest step is rejected too, the driver hands the segment to the fallback.
Through macro-slip at low speed the fixed step was off by several N.m (a slip reversal past
the adhesion limit at 5-10 km/h), where ROS34PW2 holds about 0.1 N.m
(:data:`rollerrig.solve.fast.FAST_DEFAULTS` gives the measurements).

Lawson's integrating factor (``e^{hL}`` applied to an RK4 of the transformed equation) was
measured on this model and gets the forced stiff mount modes wrong (issue 20): it is not used.
Which states to treat exactly was measured (issue 20; 2026-11-30, a Python prototype of this
scheme on the compiled right-hand side, which reproduces the shipped 0.0275 N.m; max |ΔT56|
against Radau at rtol 1e-10 on the bundled 30 s test):

- the step is set by RK4's stability on the PMSM's current loops (−1 257 1/s: 1.77 ms with the
  margin) and, just above it, by accuracy: the error is the phase of the lightly damped
  13.8 Hz roller-shaft mode, ringing for seconds after each release (0.040 N.m at 1.77 ms);
- the currents ``i_d``, ``i_q`` as exact 1 x 1 blocks move the stability limit to 3.0 ms (the
  wheel shaft's 112 Hz mode is next) at nearly the same error (0.031 N.m at 1.6 ms), but the
  accuracy limit follows at once: 0.0445 at 1.77 ms, 0.059 at 1.9, 0.074 at 2 ms. On the
  benchmark's sweep (its stiffest shaft, 143.5 kN.m/rad, at four motor lags; 2026-12-02) they
  save fewer steps than the step's length promises, since the guard shortens the step while
  the stiffer shaft rings: 15 300-18 000 steps at 2 ms (0.058-0.076 N.m), 12 800-16 000 at
  2.4 ms (up to 0.109 N.m) against 18 800-19 600 at 1.6 ms (0.014-0.051 N.m), so at most
  1.2 times cheaper at the sweep's 0.1 N.m. That is what a sweep's runs take since
  2026-12-03 (``rollerrig.solve.fast.sweep_settings``: the currents exact, 2.2 ms), the two
  currents applied as scalars (:func:`_block_rows`) at about 3 % of a step's cost; a single
  run keeps the mounts only and 1.6 ms. With their
  PI integrals in the blocks, ``(i_q, I_q)``, the error grows fourfold (0.107 at 1.6 ms):
  that, not the currents, was the fivefold error an earlier note blamed on the current loops;
- the roller shaft (θ5, θ6, ω6) merged with the contact block (5 x 5, re-linearised) halves
  the error (0.012 at 1.6 ms, re-linearised every 32 steps); with the currents exact too,
  2 ms gives 0.032 and 2.2 ms 0.052 N.m: 20 % fewer steps, for a 5 x 5 block's products in
  every step and its φ-functions at each re-linearisation, about 10 % of the step's cost;
- every state exact (the full Jacobian, re-linearised every 16 steps) gives 0.0035 N.m at 2 ms,
  but the φ-functions of a 22 x 22 matrix cost about a hundred steps each;
- splitting a coupled pair across blocks can be unstable although the explicit part's
  eigenvalues say it is not: ω4 alone as the contact block with the shaft (θ5, θ6, ω5, ω6) as
  another gave 4.3 N.m, the wheel side (θ2, θ3, ω2, ω3) as a block without θ4 diverged.

So a cheaper step, rather than a longer one, is what is left of the issue's speed targets.
Measured on 2026-12-03 (the currents exact, max |ΔT56| against Radau at rtol 1e-10 on the
bundled 30 s test) and not kept:

- without the step-error guard the error is 98-99 % in the 10-20 Hz band at every step from
  1.6 to 3 ms (0.031, 0.074, 0.17 and 0.28 N.m at 1.6, 2, 2.5 and 3 ms): the 13.8 Hz mode of
  the roller drive's lagged torque against the rotor (the full Jacobian's eigenvector: the
  lagged torque and ω6, damping ratio 0.004), which lives on the explicit rows;
- RK4's weights fitted to that mode (a stability polynomial ``1 + z + z²/2 + a3 z³ + a4 z⁴``
  equal to ``e^z`` at ``z = hλ``, λ of 13.8 Hz and damping ratio 0.004, only the final
  weights changed): 0.079 N.m at 2.5 ms against 0.075 unfitted, 0.110 against 0.106 at 3 ms;
- the mode's states as a re-linearised block: ``(ω6, T_roller)`` changed nothing (0.076 at
  2.5 ms), ``(θ6, ω6, T_roller)`` made it worse (0.086 at 1.6 ms, 0.199 at 2.5 ms);
- a tighter guard at a longer step: 2 ms with the guard at 0.0035 N.m gives 0.043 N.m in
  16 233 steps (9.7 against 10.6-10.9 ms), about 10 % faster than the default at 0.05 N.m's
  edge; at 2.5 and 3 ms the error stays at 0.073 and 0.106 however tight the guard (down to
  0.001 N.m), since it grows where each step's estimate is small.

References
----------
- S. M. Cox, P. C. Matthews, "Exponential time differencing for stiff systems", J. Comput.
  Phys. 176 (2002) 430-455.
- M. Hochbruck, A. Ostermann, "Exponential integrators", Acta Numerica 19 (2010) 209-286.
- B. Skaflestad, W. M. Wright, "The scaling and modified squaring method for matrix functions
  related to the exponential", Appl. Numer. Math. 59 (2009) 783-799.
"""

from __future__ import annotations

import numpy as np
from numba import types as _nbtypes

from rollerrig.solve import _cache
from rollerrig.solve import _wdriver as _wd

__all__ = ["MAX_BLOCK", "bind", "eigenvalues_of_coupled_part", "phi_functions", "rk4_stable_step"]

MAX_BLOCK = 3
"""Largest block of the linear part [states]."""

_TAYLOR_TERMS = 10  # Taylor terms of φ3 at ‖Z‖ <= 1/2: truncation below 1e-15
_STABILITY_MARGIN = 1.25  # the explicit part's eigenvalues are scaled by this before the check
_MIN_STEP_RATIO = 0.2  # below this share of h_max the segment goes to the fallback
# A segment that starts within this time [s] of the last stability estimate reuses it: a long
# segment keeps the estimate made at its start anyway, and an input table sampled at 1 kHz (a
# replayed recording) would otherwise pay a full Jacobian and its eigenvalues (about 0.3 ms)
# for every millisecond simulated, fifty times the steps' own cost.
STABILITY_RECHECK = 0.01
GROW_AFTER = 64
"""Accepted steps in a row, at a step shortened by the step-error guard, whose error estimates
would pass at the next longer step before the segment goes back to it [-]: 82 ms at 1.28 ms,
more than a period of the roller shaft's mode (13.8 Hz on the default rig, 25 Hz at its
stiffest in the benchmark's sweep), whose ringing after a release is what trips the guard."""
GROW_SAFETY = 8.0
"""Factor on the error estimate scaled to the longer step (by the ratio of the steps to the
fourth power, the estimate's order) before it counts as passing there [-]. On the sweep's
8 variants of its two stiffest shafts (``benchmarks/run.py``; 2026-12-02, against Radau 1e-10)
8 kept max |ΔT56| at 0.051 N.m (the whole segment at the shorter step: 0.050) in 10 % fewer
steps; 2 went back too early, into the ringing: 0.0996 N.m."""
_SQRT_EPS = np.sqrt(np.finfo(float).eps)

# LAPACK's real dgeev as numba's own np.linalg.eigvals calls it (its C helper, bound by name
# like numba's linear algebra, so that compiled callers stay cacheable). numba's real eigvals
# refuses complex eigenvalues ("domain change"), and its complex one (zgeev on the matrix made
# complex) cost twice as much: 41 against 19 us on the coupled part of the default rig's
# explicit part, 13 estimates a run, 2 % of the default solve (2026-11-30).
_F64P = _nbtypes.CPointer(_nbtypes.float64)
_REAL_GEEV = _nbtypes.ExternalFunction(
    "numba_ez_rgeev",  # (kind, jobvl, jobvr, n, a, lda, wr, wi, vl, ldvl, vr, ldvr) -> info
    _nbtypes.intc(
        *(_nbtypes.char,) * 3,
        _nbtypes.intp,
        _F64P,
        _nbtypes.intp,
        _F64P,
        _F64P,
        _F64P,
        _nbtypes.intp,
        _F64P,
        _nbtypes.intp,
    ),
)
_KIND_DOUBLE = ord("d")
_JOB_NONE = ord("N")

# Coefficient slots of a block (see _block_coefficients).
C_L, C_E, C_E2, C_Q, C_F1, C_F2, C_F3 = 0, 1, 2, 3, 4, 5, 6
_N_COEF = 7


@_cache.njit(error_model="numpy")
def _matmul(a, b, n, out):
    for i in range(n):
        for j in range(n):
            s = 0.0
            for k in range(n):
                s += a[i, k] * b[k, j]
            out[i, j] = s


@_cache.njit(error_model="numpy")
def phi_functions(z, n, e, p1, p2, p3, e_half, p1_half):
    """``e^Z``, ``φ1(Z)``, ``φ2(Z)``, ``φ3(Z)``, ``e^{Z/2}`` and ``φ1(Z/2)`` of a small matrix.

    ``φ0(Z) = e^Z``, ``φ_k(Z) = Σ_j Z^j/(j + k)!``. ``Z`` is scaled by ``2^−s`` (``s ≥ 1``) to a
    norm of at most 1/2, ``φ3`` summed by Horner's rule (10 terms), ``φ2, φ1, e^Z`` from the
    recurrence ``φ_{k−1} = Z φ_k + I/(k−1)!``, then doubled ``s`` times (Skaflestad & Wright
    2009, eq. 2.4); the functions of ``Z/2`` are those before the last doubling.

    Parameters
    ----------
    z : ndarray of float64, shape (>= n, >= n)
        ``h L`` [-].
    n : int
        Size of the block, at most :data:`MAX_BLOCK` (the leading ``n × n`` part of every
        array is used).
    e, p1, p2, p3, e_half, p1_half : ndarray of float64, shape (>= n, >= n)
        Outputs [-].

    Examples
    --------
    >>> import numpy as np
    >>> z = np.array([[-2.0]]); out = [np.empty((1, 1)) for _ in range(6)]
    >>> phi_functions(z, 1, *out)
    >>> bool(abs(out[1][0, 0] - (np.exp(-2.0) - 1.0) / -2.0) < 1e-14)
    True
    """
    scratch = np.empty((2, MAX_BLOCK, MAX_BLOCK))
    _phi_into(z, n, e, p1, p2, p3, e_half, p1_half, scratch)


@_cache.njit(error_model="numpy")
def _phi_into(z, n, e, p1, p2, p3, e_half, p1_half, scratch):
    """:func:`phi_functions` with scratch space ``scratch`` (2, 3, 3), allocating nothing."""
    if n == 2:
        _phi_2x2(z, e, p1, p2, p3, e_half, p1_half)
    else:
        _phi_general(z, n, e, p1, p2, p3, e_half, p1_half, scratch)


@_cache.njit(error_model="numpy")
def _mul2(a00, a01, a10, a11, b00, b01, b10, b11):
    """The 2 x 2 product, each entry summed in :func:`_matmul`'s order."""
    return (
        a00 * b00 + a01 * b10,
        a00 * b01 + a01 * b11,
        a10 * b00 + a11 * b10,
        a10 * b01 + a11 * b11,
    )


@_cache.njit(error_model="numpy")
def _phi_2x2(z, e, p1, p2, p3, e_half, p1_half):
    """:func:`_phi_general` for a 2 x 2 block in scalars: the same operations in the same
    order (the same numbers up to the sign of a zero), about four times cheaper than the loops
    over a run-time size, and the contact's block is re-linearised every 16 steps (1 170 times
    on the bundled test: the φ-functions had been 6 % of its solve, 2026-11-30)."""
    norm = max(abs(z[0, 0]) + abs(z[0, 1]), abs(z[1, 0]) + abs(z[1, 1]))
    s = 1
    scale = 0.5
    while norm * scale > 0.5:
        s += 1
        scale *= 0.5
    a00 = z[0, 0] * scale
    a01 = z[0, 1] * scale
    a10 = z[1, 0] * scale
    a11 = z[1, 1] * scale
    fact = 1.0
    for j in range(1, _TAYLOR_TERMS + 4):
        fact *= j
    q00 = 1.0 / fact
    q01 = 0.0
    q10 = 0.0
    q11 = 1.0 / fact
    for j in range(_TAYLOR_TERMS - 1, -1, -1):
        fact /= j + 4
        q00, q01, q10, q11 = _mul2(a00, a01, a10, a11, q00, q01, q10, q11)
        q00 += 1.0 / fact
        q11 += 1.0 / fact
    r00, r01, r10, r11 = _mul2(a00, a01, a10, a11, q00, q01, q10, q11)  # φ2
    r00 += 0.5
    r11 += 0.5
    f00, f01, f10, f11 = _mul2(a00, a01, a10, a11, r00, r01, r10, r11)  # φ1
    f00 += 1.0
    f11 += 1.0
    e00, e01, e10, e11 = _mul2(a00, a01, a10, a11, f00, f01, f10, f11)  # e^A
    e00 += 1.0
    e11 += 1.0
    for k in range(s):
        if k == s - 1:
            e_half[0, 0] = e00
            e_half[0, 1] = e01
            e_half[1, 0] = e10
            e_half[1, 1] = e11
            p1_half[0, 0] = f00
            p1_half[0, 1] = f01
            p1_half[1, 0] = f10
            p1_half[1, 1] = f11
        t00, t01, t10, t11 = _mul2(e00, e01, e10, e11, q00, q01, q10, q11)
        t00 = 0.125 * (t00 + 0.5 * f00 + r00 + q00)
        t01 = 0.125 * (t01 + 0.5 * f01 + r01 + q01)
        t10 = 0.125 * (t10 + 0.5 * f10 + r10 + q10)
        t11 = 0.125 * (t11 + 0.5 * f11 + r11 + q11)
        q00, q01, q10, q11 = t00, t01, t10, t11
        t00, t01, t10, t11 = _mul2(e00, e01, e10, e11, r00, r01, r10, r11)
        r00 = 0.25 * (t00 + f00 + r00)
        r01 = 0.25 * (t01 + f01 + r01)
        r10 = 0.25 * (t10 + f10 + r10)
        r11 = 0.25 * (t11 + f11 + r11)
        t00, t01, t10, t11 = _mul2(e00, e01, e10, e11, f00, f01, f10, f11)
        f00 = 0.5 * (t00 + f00)
        f01 = 0.5 * (t01 + f01)
        f10 = 0.5 * (t10 + f10)
        f11 = 0.5 * (t11 + f11)
        e00, e01, e10, e11 = _mul2(e00, e01, e10, e11, e00, e01, e10, e11)
    for i, (ve, vf, vr, vq) in enumerate(
        ((e00, f00, r00, q00), (e01, f01, r01, q01), (e10, f10, r10, q10), (e11, f11, r11, q11))
    ):
        e[i // 2, i % 2] = ve
        p1[i // 2, i % 2] = vf
        p2[i // 2, i % 2] = vr
        p3[i // 2, i % 2] = vq


@_cache.njit(error_model="numpy")
def _phi_general(z, n, e, p1, p2, p3, e_half, p1_half, scratch):
    """:func:`_phi_into` for any block size up to :data:`MAX_BLOCK`."""
    norm = 0.0
    for i in range(n):
        row = 0.0
        for j in range(n):
            row += abs(z[i, j])
        norm = max(norm, row)
    s = 1
    scale = 0.5
    while norm * scale > 0.5:
        s += 1
        scale *= 0.5
    a = scratch[0]
    tmp = scratch[1]
    for i in range(n):
        for j in range(n):
            a[i, j] = z[i, j] * scale
    # φ3(A) = Σ_{j=0}^{K} A^j / (j + 3)!  (Horner)
    fact = 1.0
    for j in range(1, _TAYLOR_TERMS + 4):
        fact *= j  # (K + 3)!
    for i in range(n):
        for j in range(n):
            p3[i, j] = (1.0 / fact) if i == j else 0.0
    for j in range(_TAYLOR_TERMS - 1, -1, -1):
        fact /= j + 4  # (j + 3)!
        _matmul(a, p3, n, tmp)
        for r in range(n):
            for c in range(n):
                p3[r, c] = tmp[r, c] + ((1.0 / fact) if r == c else 0.0)
    _matmul(a, p3, n, p2)
    for i in range(n):
        p2[i, i] += 0.5
    _matmul(a, p2, n, p1)
    for i in range(n):
        p1[i, i] += 1.0
    _matmul(a, p1, n, e)
    for i in range(n):
        e[i, i] += 1.0
    for k in range(s):
        if k == s - 1:
            for i in range(n):
                for j in range(n):
                    e_half[i, j] = e[i, j]
                    p1_half[i, j] = p1[i, j]
        # φ3(2A) = (e^A φ3 + φ1/2 + φ2 + φ3)/8, φ2(2A) = (e^A φ2 + φ1 + φ2)/4,
        # φ1(2A) = (e^A φ1 + φ1)/2, e^{2A} = e^A e^A (all functions of A commute).
        _matmul(e, p3, n, tmp)
        for i in range(n):
            for j in range(n):
                tmp[i, j] = 0.125 * (tmp[i, j] + 0.5 * p1[i, j] + p2[i, j] + p3[i, j])
        for i in range(n):
            for j in range(n):
                p3[i, j] = tmp[i, j]
        _matmul(e, p2, n, tmp)
        for i in range(n):
            for j in range(n):
                p2[i, j] = 0.25 * (tmp[i, j] + p1[i, j] + p2[i, j])
        _matmul(e, p1, n, tmp)
        for i in range(n):
            for j in range(n):
                p1[i, j] = 0.5 * (tmp[i, j] + p1[i, j])
        _matmul(e, e, n, tmp)
        for i in range(n):
            for j in range(n):
                e[i, j] = tmp[i, j]


@_cache.njit(error_model="numpy")
def _block_coefficients(lin, n, h, coef, scratch):
    """The step's matrices of one block with linear part ``lin`` (n × n) and step ``h`` [s].

    ``coef[C_L] = L``, ``coef[C_E] = e^{hL}``, ``coef[C_E2] = e^{hL/2}``,
    ``coef[C_Q] = (h/2) φ1(hL/2)``, ``coef[C_F1] = h (φ1 − 3φ2 + 4φ3)``,
    ``coef[C_F2] = 2h (φ2 − 2φ3)``, ``coef[C_F3] = h (4φ3 − φ2)``, all of ``hL``; ``scratch``
    is (7, 3, 3) scratch space.
    """
    z = scratch[0]
    p1 = scratch[1]
    p2 = scratch[2]
    p3 = scratch[3]
    p1h = scratch[4]
    for i in range(n):
        for j in range(n):
            z[i, j] = h * lin[i, j]
            coef[C_L, i, j] = lin[i, j]
    _phi_into(z, n, coef[C_E], p1, p2, p3, coef[C_E2], p1h, scratch[5:7])
    for i in range(n):
        for j in range(n):
            coef[C_Q, i, j] = 0.5 * h * p1h[i, j]
            coef[C_F1, i, j] = h * (p1[i, j] - 3.0 * p2[i, j] + 4.0 * p3[i, j])
            coef[C_F2, i, j] = 2.0 * h * (p2[i, j] - 2.0 * p3[i, j])
            coef[C_F3, i, j] = h * (4.0 * p3[i, j] - p2[i, j])


@_cache.njit(error_model="numpy")
def _rk4_stable(z):
    """True when ``|R(z)| <= 1`` for RK4's ``R(z) = 1 + z + z²/2 + z³/6 + z⁴/24``."""
    r = 1.0 + z * (1.0 + z * (0.5 + z * (1.0 / 6.0 + z / 24.0)))
    return abs(r) <= 1.0 + 1e-12


@_cache.njit(error_model="numpy")
def rk4_stable_step(eigenvalues, h_max):
    """Largest step ``h <= h_max`` [s] at which RK4 is stable on every eigenvalue [1/s].

    An eigenvalue ``λ`` counts with a margin (``1.25 λ``); ``h λ`` must lie in RK4's region of
    absolute stability at ``h``, ``3h/4``, ``h/2`` and ``h/4`` (the region along a ray from the
    origin is an interval). Eigenvalues with a non-negative real part (growth of the physics
    itself, and the rigid-body modes at 0) are not a limit. Tried from ``h_max`` down by
    factors of 0.9; 0 when none of 80 tries is stable.

    Examples
    --------
    >>> import numpy as np
    >>> h = rk4_stable_step(np.array([-1000.0 + 0j]), 1.0)
    >>> bool(2.0e-3 < h < 2.785 / 1000 / 1.25)
    True
    """
    h = h_max
    for _ in range(80):
        ok = True
        for lam in eigenvalues:
            if lam.real >= 0.0:
                continue
            z = _STABILITY_MARGIN * h * lam
            if not (
                _rk4_stable(z)
                and _rk4_stable(0.75 * z)
                and _rk4_stable(0.5 * z)
                and _rk4_stable(0.25 * z)
            ):
                ok = False
                break
        if ok:
            return h
        h *= 0.9
    return 0.0


# ---------------------------------------------------------------------------------------------
# Templates: compiled per right-hand side by bind() (globals rhs and fd_jacobian).
# ---------------------------------------------------------------------------------------------
rhs = fd_jacobian = _wd.rhs


def _block_jacobian(t, x, f0, p, tables, idx, n, lin, xp, fp):
    """Forward-difference Jacobian of the block ``idx[:n]`` of the state at ``(t, x)``."""
    for j in range(x.shape[0]):
        xp[j] = x[j]
    for c in range(n):
        j = idx[c]
        xj = x[j]
        xp[j] = xj + _SQRT_EPS * max(abs(xj), 1.0)
        delta = xp[j] - xj
        rhs(t, xp, p, tables, fp)
        xp[j] = xj
        for r in range(n):
            lin[r, c] = (fp[idx[r]] - f0[idx[r]]) / delta


def _block_sizes(blocks):
    sizes = np.zeros(blocks.shape[0], dtype=np.int64)
    for b in range(blocks.shape[0]):
        n = 0
        while n < blocks.shape[1] and blocks[b, n] >= 0:
            n += 1
        sizes[b] = n
    return sizes


@_cache.njit(error_model="numpy")
def eigenvalues_of_coupled_part(jac):
    """Eigenvalues [1/s] of a real square matrix, the states that nothing couples taken out.

    A state whose row, or column, holds nothing off the diagonal (among the states kept) has
    its diagonal entry as an eigenvalue, and the other eigenvalues are those of the matrix
    without it (the determinant expanded along that row or column); this repeats until every
    state left is coupled both ways, whose eigenvalues LAPACK then computes. The rig's unused
    states (a rigid frame's, a controller the drive does not have) so cost nothing in the
    explicit part's stability estimate, whose eigenvalues cost O(n³) (22 -> 19 states on the
    default rig: the estimate about a third cheaper, the default solve 1.5 %).

    Raises numpy.linalg.LinAlgError where an entry of the coupled part is not finite, or
    LAPACK's QR algorithm (real ``dgeev``) does not converge.

    Examples
    --------
    >>> import numpy as np
    >>> jac = np.array([[-1.0, 2.0, 0.0], [0.0, -3.0, 0.0], [5.0, 0.0, 0.0]])
    >>> [float(v) for v in sorted(eigenvalues_of_coupled_part(jac).real)]
    [-3.0, -1.0, 0.0]
    """
    n = jac.shape[0]
    keep = np.ones(n, dtype=np.int64)
    lam = np.empty(n, dtype=np.complex128)
    n_split = 0
    changed = True
    while changed:
        changed = False
        for i in range(n):
            if keep[i] == 0:
                continue
            row = False
            col = False
            for j in range(n):
                if keep[j] == 1 and j != i:
                    row = row or jac[i, j] != 0.0
                    col = col or jac[j, i] != 0.0
            if not (row and col):
                keep[i] = 0
                lam[n - 1 - n_split] = jac[i, i]
                n_split += 1
                changed = True
    m = n - n_split
    if m > 0:
        idx = np.empty(m, dtype=np.int64)
        k = 0
        for i in range(n):
            if keep[i] == 1:
                idx[k] = i
                k += 1
        # Column-major for LAPACK: reduced[b, a] holds the entry (a, b).
        reduced = np.empty((m, m))
        for a in range(m):
            for b in range(m):
                v = jac[idx[a], idx[b]]
                if not np.isfinite(v):  # LAPACK would complain on stderr
                    raise np.linalg.LinAlgError("the matrix has a non-finite entry")
                reduced[b, a] = v
        wr = np.empty(m)
        wi = np.empty(m)
        unused = np.empty(1)
        info = _REAL_GEEV(
            _KIND_DOUBLE, _JOB_NONE, _JOB_NONE, m, reduced.ctypes, m, wr.ctypes, wi.ctypes,
            unused.ctypes, 1, unused.ctypes, 1,
        )  # fmt: skip
        if info != 0:
            raise np.linalg.LinAlgError(
                "LAPACK dgeev failed (its QR algorithm did not converge, or scipy's LAPACK "
                "could not be loaded)"
            )
        for a in range(m):
            lam[a] = complex(wr[a], wi[a])
    return lam


def _stable_step(t, x, f0, p, tables, blocks, sizes, h_max):
    """Largest stable RK4 step [s] of the explicit part (Jacobian without the blocks)."""
    n = x.shape[0]
    jac = np.empty((n, n))
    work = np.empty((2, n))
    fd_jacobian(t, x, p, tables, f0, jac, work)
    for b in range(blocks.shape[0]):
        for r in range(sizes[b]):
            for c in range(sizes[b]):
                jac[blocks[b, r], blocks[b, c]] = 0.0
    for i in range(n):
        for j in range(n):
            if not abs(jac[i, j]) < 1e100:  # non-finite, or beyond what LAPACK balances
                return 0.0
    try:
        lam = eigenvalues_of_coupled_part(jac)
    except Exception:  # the QR algorithm did not converge: leave the segment to the fallback
        return 0.0
    for v in lam:
        if not np.isfinite(v.real) or not np.isfinite(v.imag):
            return 0.0
    return rk4_stable_step(lam, h_max)


def _block_rows(blocks, sizes):
    """The blocks' rows, each with :data:`MAX_BLOCK` columns.

    Returns ``(cols, rows, first, local, diag, slot)``: row ``q`` of the blocks is state
    ``rows[q]``, its
    entries ``L[rows[q], cols[q, c]]`` for ``c < MAX_BLOCK``, and ``local[q, c]`` is the row
    of the blocks that holds state ``cols[q, c]`` (the step keeps ``N = f − L x`` on the
    blocks' rows only); a smaller block's row is padded with its own state and a zero
    coefficient; the rows of block ``b`` are ``first[b]:first[b + 1]``. The step applies the
    blocks' matrices row by row with this fixed width, a loop the compiler unrolls (sparse
    pairs of variable count per row had cost 10-30 % more of the step's own work, measured
    with a trivial right-hand side). Block by block, a 2 x 2 block's states loaded once into
    locals, the blocks' share of a step fell from about 150 to 120 ns (the default solve 3 %
    faster), but a cold compile took 5 s more CPU (23.6 -> 28.7 s, numba's compile events;
    2026-11-30); one padded path for every size was no faster than these rows.

    A 1 x 1 block (a state of its own, the PMSM's currents in a sweep) has no row: its state
    is ``diag[slot[b]]`` (``slot[b]`` is -1 for a block with rows), whose scalar coefficients
    the step applies in a loop of their own. As padded rows the two currents had cost about
    7 % of a step.
    """
    nb = blocks.shape[0]
    first = np.zeros(nb + 1, dtype=np.int64)
    slot = np.full(nb, -1, dtype=np.int64)
    n_diag = 0
    for b in range(nb):
        if sizes[b] == 1:  # a state of its own: on the diagonal, not in the rows
            slot[b] = n_diag
            n_diag += 1
            first[b + 1] = first[b]
        else:
            first[b + 1] = first[b] + sizes[b]
    rows = np.empty(first[nb], dtype=np.int64)
    cols = np.empty((first[nb], MAX_BLOCK), dtype=np.int64)
    local = np.empty((first[nb], MAX_BLOCK), dtype=np.int64)
    diag = np.empty(n_diag, dtype=np.int64)
    for b in range(nb):
        if sizes[b] == 1:
            diag[slot[b]] = blocks[b, 0]
            continue
        for r in range(sizes[b]):
            q = first[b] + r
            rows[q] = blocks[b, r]
            for c in range(MAX_BLOCK):
                cols[q, c] = blocks[b, c] if c < sizes[b] else blocks[b, r]
                local[q, c] = first[b] + c if c < sizes[b] else q
    return cols, rows, first, local, diag, slot


def _store_block(coef, n, first, cf):
    """Copy one block's matrices (``coef``, (7, 3, 3)) into its rows of ``cf`` (7, rows, 3),
    zeros in the padding."""
    for r in range(n):
        for c in range(MAX_BLOCK):
            for slot in range(_N_COEF):
                cf[slot, first + r, c] = coef[slot, r, c] if c < n else 0.0


def _block_nonlinear(f, u, cols, rows, cf, out):
    """``out[q] = (f − L u)[rows[q]]``: the nonlinear part on the blocks' rows (elsewhere it
    is ``f`` itself)."""
    for q in range(rows.shape[0]):
        acc = 0.0
        for c in range(MAX_BLOCK):
            acc += cf[C_L, q, c] * u[cols[q, c]]
        out[q] = f[rows[q]] - acc


def _block_stage(u, v, cols, rows, local, cf, out):
    """``out = e^{hL/2} u + (h/2) φ1(hL/2) v`` on the blocks' rows (``v`` given on those
    rows only)."""
    for q in range(rows.shape[0]):
        acc = 0.0
        for c in range(MAX_BLOCK):
            acc += cf[C_E2, q, c] * u[cols[q, c]] + cf[C_Q, q, c] * v[local[q, c]]
        out[rows[q]] = acc


def _step(t, h, t_new, x, fx, p, tables, cols, rows, local, cf, x_new, a, b_, c_, fa, fb, fc, nl,
          diag, dcf):  # fmt: skip
    """One ETDRK4 step from ``(t, x)`` with ``fx = f(t, x)``; ``x_new`` at ``t_new``, ``t + h``
    up to rounding, passed on its own because the last stage is taken there: at a segment's
    last step ``t + h`` may round past the segment's end, where its inputs are the next
    segment's (an ideal speed source's acceleration lost a third of a step's speed change at
    the end of a ramp, 0.9 N.m of T56 after it, 2026-11-30; ROS34PW2 does the same). The other
    arrays are scratch: ``a``, ``b_``, ``c_`` the stages, ``fa``, ``fb``, ``fc`` their
    right-hand sides (``fc`` is the error estimate's ``f(t_new, c)``), ``nl`` (5, >= rows)
    the nonlinear parts ``N_u, N_a, N_b, N_c`` on the blocks' rows and ``2 N_b − N_u``.

    Every state is first advanced as by RK4 (``N = f`` where ``L = 0``), in one pass per stage
    over the whole state; the blocks' rows are then overwritten with the exponential
    formulas. Where ``L = 0`` the nonlinear part is the right-hand side itself, so it is never
    copied: the step makes 4 passes over the state besides its right-hand sides (it made 9).
    The 1 x 1 blocks' states ``diag`` (their scalar coefficients ``dcf``; their nonlinear
    parts in ``nl`` after the rows') are overwritten likewise, by the same formulas.
    """
    n = x.shape[0]
    nr = rows.shape[0]
    half = 0.5 * h
    nu = nl[0]
    na = nl[1]
    nb = nl[2]
    nc = nl[3]
    mix = nl[4]
    _block_nonlinear(fx, x, cols, rows, cf, nu)
    for i in range(n):
        a[i] = x[i] + half * fx[i]
    _block_stage(x, nu, cols, rows, local, cf, a)
    for d in range(diag.shape[0]):
        j = diag[d]
        nu[nr + d] = fx[j] - dcf[C_L, d] * x[j]
        a[j] = dcf[C_E2, d] * x[j] + dcf[C_Q, d] * nu[nr + d]
    rhs(t + half, a, p, tables, fa)
    _block_nonlinear(fa, a, cols, rows, cf, na)
    for i in range(n):
        b_[i] = x[i] + half * fa[i]
    _block_stage(x, na, cols, rows, local, cf, b_)
    for d in range(diag.shape[0]):
        j = diag[d]
        na[nr + d] = fa[j] - dcf[C_L, d] * a[j]
        b_[j] = dcf[C_E2, d] * x[j] + dcf[C_Q, d] * na[nr + d]
    rhs(t + half, b_, p, tables, fb)
    _block_nonlinear(fb, b_, cols, rows, cf, nb)
    for i in range(n):
        c_[i] = a[i] + half * (2.0 * fb[i] - fx[i])
    for q in range(nr):
        mix[q] = 2.0 * nb[q] - nu[q]
    _block_stage(a, mix, cols, rows, local, cf, c_)
    for d in range(diag.shape[0]):
        j = diag[d]
        nb[nr + d] = fb[j] - dcf[C_L, d] * b_[j]
        c_[j] = dcf[C_E2, d] * a[j] + dcf[C_Q, d] * (2.0 * nb[nr + d] - nu[nr + d])
    rhs(t_new, c_, p, tables, fc)
    _block_nonlinear(fc, c_, cols, rows, cf, nc)
    h6 = h / 6.0
    h3 = h / 3.0
    for i in range(n):
        x_new[i] = x[i] + h6 * (fx[i] + fc[i]) + h3 * (fa[i] + fb[i])
    for d in range(diag.shape[0]):
        j = diag[d]
        nc_d = fc[j] - dcf[C_L, d] * c_[j]
        x_new[j] = (
            dcf[C_E, d] * x[j]
            + dcf[C_F1, d] * nu[nr + d]
            + dcf[C_F2, d] * (na[nr + d] + nb[nr + d])
            + dcf[C_F3, d] * nc_d
        )
    for q in range(nr):
        acc = 0.0
        for c in range(MAX_BLOCK):
            j = local[q, c]
            acc += (
                cf[C_E, q, c] * x[cols[q, c]]
                + cf[C_F1, q, c] * nu[j]
                + cf[C_F2, q, c] * (na[j] + nb[j])
                + cf[C_F3, q, c] * nc[j]
            )
        x_new[rows[q]] = acc


def _hermite(t, h, x, f, x_new, f_new, t_at, out, row):
    """Cubic Hermite interpolant of a step at ``t_at`` (local error O(h⁴)), into ``out[row]``
    (written in place: no row view, whose reference count would cost atomic operations)."""
    s = (t_at - t) / h
    s2 = s * s
    h00 = 1.0 - s2 * (3.0 - 2.0 * s)
    h01 = 1.0 - h00
    h10 = h * s * (1.0 - s) * (1.0 - s)
    h11 = h * s2 * (s - 1.0)
    for i in range(x.shape[0]):
        out[row, i] = h00 * x[i] + h01 * x_new[i] + h10 * f[i] + h11 * f_new[i]


def _finite_pair(u, v):
    """True when every entry of ``u`` and ``v`` is finite: their sum is (an infinity or NaN
    propagates through it), one pass without a branch per entry."""
    acc = 0.0
    for i in range(u.shape[0]):
        acc += 0.0 * u[i] + 0.0 * v[i]
    return acc == 0.0


def _step_error(h, f_c, f_new, weights):
    """The step's error estimate in the quantity ``Σ_j weights_j x_j``.

    ``(h/6) (f(t + h, c) − f(t + h, x_new))`` is classical RK4's embedded third-order error
    estimate (the weights (1/6, 1/3, 1/3, 0, 1/6) on the four stages and the derivative at the
    new state, the next step's first: no extra right-hand side). Exact for the rows RK4
    integrates (``L = 0``); the weights should sit on such rows (the rig's roller-shaft twist
    θ5 − θ6 times its stiffness: the estimate in N.m of T56).
    """
    acc = 0.0
    for j in range(f_new.shape[0]):
        acc += weights[j] * (f_c[j] - f_new[j])
    return abs(acc) * h / 6.0


def workspace(n, static_blocks, dynamic_blocks):
    """The arrays :func:`_segment` works in, for a state of ``n`` entries and these blocks,
    allocated once per run (a replayed recording makes thousands of segments):
    ``(blocks, sizes, cols, rows, first, cf, coef, lin, scratch, vec, local, nl, diag, slot,
    dcf)``, ``vec`` (12, n), ``nl`` (5, rows + diagonal states), ``dcf`` (7, diagonal states)
    the 1 x 1 blocks' coefficients (:func:`_block_rows`)."""
    ns = static_blocks.shape[0]
    nd = dynamic_blocks.shape[0]
    blocks = np.empty((ns + nd, MAX_BLOCK), dtype=np.int64)
    for b in range(ns + nd):
        for c in range(MAX_BLOCK):
            blocks[b, c] = static_blocks[b, c] if b < ns else dynamic_blocks[b - ns, c]
    sizes = _block_sizes(blocks)
    cols, rows, first, local, diag, slot = _block_rows(blocks, sizes)
    cf = np.empty((_N_COEF, rows.shape[0], MAX_BLOCK))
    coef = np.zeros((_N_COEF, MAX_BLOCK, MAX_BLOCK))
    lin = np.zeros((MAX_BLOCK, MAX_BLOCK))
    scratch = np.empty((7, MAX_BLOCK, MAX_BLOCK))
    vec = np.empty((12, n))
    nl = np.empty((5, rows.shape[0] + diag.shape[0]))
    dcf = np.empty((_N_COEF, diag.shape[0]))
    return blocks, sizes, cols, rows, first, cf, coef, lin, scratch, vec, local, nl, diag, slot, dcf


def _prepare(x0, t0, t1, p, tables, h_max, ns, ws, memo):
    """The number of steps of the segment ``[t0, t1]`` from ``x0``, or -1 where it needs the
    fallback (the stable step is below ``0.2 h_max``, or the state or its derivative is not
    finite); the state and its derivative left in the workspace ``ws`` (:func:`workspace`)
    for :func:`_segment`. ``memo`` (two floats, zeros at the start of a run) holds the last
    stable step and when it was estimated; a segment starting within
    :data:`STABILITY_RECHECK` of it reuses it.

    Apart from :func:`_segment` because the stability estimate allocates (its eigenvalues),
    which a function compiled without reference counting cannot.
    """
    blocks, sizes = ws[0], ws[1]
    vec = ws[9]
    x = vec[0]
    fx = vec[1]
    for j in range(x0.shape[0]):
        x[j] = x0[j]
    rhs(t0, x, p, tables, fx)
    if not _finite_pair(x, fx):
        return -1
    if memo[0] > 0.0 and t0 - memo[1] < STABILITY_RECHECK:
        h_stable = memo[0]
    else:
        h_stable = _stable_step(t0, x, fx, p, tables, blocks, sizes, h_max)
        memo[0] = h_stable
        memo[1] = t0
    if h_stable < _MIN_STEP_RATIO * h_max:
        return -1
    return _grid(t0, t1, h_stable)[0]


def _block_matrices(t, h, ns, nd, ws, p, tables, first_block):
    """The matrices of blocks ``first_block..ns + nd - 1`` at ``(t, x)`` (``x``, ``f(t, x)``
    in the workspace's first two rows) for the step ``h``."""
    blocks, sizes, first, cf, coef, lin, scratch, vec = (
        ws[0], ws[1], ws[4], ws[5], ws[6], ws[7], ws[8], ws[9]
    )  # fmt: skip
    slot = ws[13]
    dcf = ws[14]
    for b in range(first_block, ns + nd):
        _block_jacobian(t, vec[0], vec[1], p, tables, blocks[b], sizes[b], lin, vec[2], vec[3])
        _block_coefficients(lin, sizes[b], h, coef, scratch)
        if slot[b] >= 0:
            for k in range(_N_COEF):
                dcf[k, slot[b]] = coef[k, 0, 0]
        else:
            _store_block(coef, sizes[b], first[b], cf)


def _grid(t, t1, h_rung):
    """The steps from ``t`` to the segment's end ``t1`` at about ``h_rung`` [s]: ``(count,
    step)``, the step the largest not above ``h_rung`` that divides what is left."""
    n = max(1, int(np.ceil((t1 - t) / h_rung * (1.0 - 1e-12))))
    return n, (t1 - t) / n


def _segment(
    t0, t1, m, t_out, p, tables, relinearise, ns, ws, x_out, counts, err_weights, err_limit,
    divisors, rungs,
):  # fmt: skip
    """ETDRK4 over one smooth segment ``[t0, t1]`` in ``m`` steps (:func:`_prepare`, which
    left the start state in ``ws``); ``x_out[k]`` at ``t_out[k]`` (in ``[t0, t1]``,
    increasing), the last row ``t_out[-1] == t1`` being the end state; ``ns`` static blocks,
    then the dynamic ones, in the workspace ``ws`` (:func:`workspace`).

    The step-error guard: a step whose error estimate exceeds ``err_limit``
    (:func:`_step_error`), or whose state is not finite, is rejected, and the segment goes on
    from the last accepted state at the full step divided by the next of ``divisors``
    (``divisors[0] == 1``; at most ``rungs`` of them: 0 allows no shorter step), re-divided so
    as to land on ``t1``. After :data:`GROW_AFTER` steps in a row whose estimates would pass at
    the next longer step (the estimate scales as the step's fourth power; with a factor
    :data:`GROW_SAFETY`) it goes back to that step. So a shaft's ringing after a release is
    integrated at the shorter step while it rings, and the rest of the segment at the full
    step.

    Returns a status: 0 done; -1 the segment failed (a rejected step with no shorter rung
    left), which the driver hands to the fallback. ``counts`` gets the accepted steps (0), the
    rejected ones (1), the linearisations (2) and, once, a segment that took a shorter step
    (4) added, a failed attempt's too.

    Compiled without reference counting (``_nrt=False``; it allocates nothing): with it, the
    arrays handed to the inlined helpers and the rows of the workspace took and gave back
    references in every step, atomic operations that were 12 % of the solve's samples (perf,
    2026-11-30).
    """
    blocks, cols, rows, cf, vec, local, nl = ws[0], ws[2], ws[3], ws[5], ws[9], ws[10], ws[11]
    diag, dcf = ws[12], ws[14]
    n = vec.shape[1]
    n_out = t_out.shape[0]
    nd = blocks.shape[0] - ns
    x = vec[0]
    fx = vec[1]
    x_new = vec[4]
    f_new = vec[5]
    sa = vec[6]
    sb = vec[7]
    sc = vec[8]
    fa = vec[9]
    fb = vec[10]
    fc = vec[11]
    h_full = (t1 - t0) / m
    h = h_full
    _block_matrices(t0, h, ns, nd, ws, p, tables, 0)
    counts[2] += 1
    k = 0
    while k < n_out and t_out[k] <= t0:
        _wd._store_row(x_out, k, x)
        k += 1
    # A segment shorter than two intervals is an input's fast transition (a load or torque
    # step over a few ms), where the contact's operating point moves fastest: its block is
    # re-linearised every step. A load step from 20 to 4.3 kN in 10 ms under 1 400 N.m at
    # 10 km/h, linearised once, was off by 2.5 N.m (every step: 0.035), with the step-error
    # guard silent, since it sees only the states RK4 integrates (2026-11-30).
    every = relinearise if m >= 2 * relinearise else 1
    since = 0
    t = t0
    base = t0  # where the current grid of steps starts
    n_grid = m  # its steps to t1
    i = 0  # its steps taken
    rung = 0
    calm = 0
    while i < n_grid:
        t_new = t1 if i == n_grid - 1 else base + (i + 1) * h
        if since >= every and nd > 0:
            _block_matrices(t, h, ns, nd, ws, p, tables, ns)
            counts[2] += 1
            since = 0
        _step(
            t, h, t_new, x, fx, p, tables, cols, rows, local, cf, x_new, sa, sb, sc, fa, fb, fc, nl,
            diag, dcf,
        )  # fmt: skip
        rhs(t_new, x_new, p, tables, f_new)
        err = 0.0
        if err_limit > 0.0:
            err = _step_error(h, fc, f_new, err_weights)
        regrid = not _finite_pair(x_new, f_new) or err > err_limit
        if regrid:  # rejected: on from the last accepted state at the next shorter step
            counts[1] += 1
            if rung >= rungs:
                return -1
            if rung == 0:
                counts[4] += 1
            rung += 1
        else:
            while k < n_out and t_out[k] < t_new:
                _hermite(t, h, x, fx, x_new, f_new, t_out[k], x_out, k)
                k += 1
            for j in range(n):
                x[j] = x_new[j]
                fx[j] = f_new[j]
            t = t_new
            i += 1
            since += 1
            counts[0] += 1
            while k < n_out and t_out[k] <= t:
                _wd._store_row(x_out, k, x)
                k += 1
            if rung > 0 and i < n_grid:
                ratio = divisors[rung] / divisors[rung - 1]
                calm = calm + 1 if err * GROW_SAFETY * ratio**4 <= err_limit else 0
                if calm >= GROW_AFTER:  # back to the next longer step
                    rung -= 1
                    regrid = True
        if regrid:
            n_grid, h = _grid(t, t1, h_full / divisors[rung])
            base = t
            i = 0
            _block_matrices(t, h, ns, nd, ws, p, tables, 0)
            counts[2] += 1
            since = 0
            calm = 0
    return 0


_NAMED: dict[str, object] = {}


def bind(driver, name: str):
    """The ETDRK4 segment integrator compiled for the right-hand side of a W-method driver.

    Parameters
    ----------
    driver : rollerrig.solve._wdriver.Driver
        A bound driver (:func:`rollerrig.solve.ros34pw.bind`) whose ``rhs`` and
        ``fd_jacobian`` the method uses.
    name : str
        Cache name (the package's own models only: their sources are in the cache key).

    Returns
    -------
    (numba dispatcher, numba dispatcher, numba dispatcher)
        ``workspace(n, static_blocks, dynamic_blocks) -> ws`` (once per run),
        ``prepare(x0, t0, t1, p, tables, h_max, n_static, ws, memo) -> steps`` and
        ``segment(t0, t1, steps, t_out, p, tables, relinearise, n_static, ws, x_out, counts,
        err_weights, err_limit) -> status`` (see the templates :func:`workspace`,
        :func:`_prepare` and ``_segment``).
    """
    if name in _NAMED:
        return _NAMED[name]
    ns = dict(globals())
    ns["rhs"] = driver.rhs
    ns["fd_jacobian"] = driver.fd_jacobian
    # The step's helpers are inlined into the step loop (numba's IR inlining): a call of a
    # separately compiled function passes every array with a reference count taken and given
    # back, which cost about 1 µs a step, as much as three right-hand sides.
    for template, inline in (
        (_block_jacobian, "never"),
        (_block_sizes, "never"),
        (_block_rows, "never"),
        (_store_block, "always"),
        (_stable_step, "never"),
        (_block_nonlinear, "always"),
        (_block_stage, "always"),
        (_step, "always"),
        (_hermite, "always"),
        (_finite_pair, "always"),
        (_step_error, "always"),
        (workspace, "never"),
        (_prepare, "never"),
        (_block_matrices, "always"),
        (_grid, "always"),
        (_segment, "never"),
    ):
        options = {"_nrt": False} if template is _segment else {}
        # No fast-math flag, not even LLVM's "contract" (fused multiply-adds): it made the
        # default solve 3-5 % faster (2026-12-01), but which products LLVM fused then depended
        # on what was compiled first (the CLI or the Python API, a test's order), so the same
        # install gave three different results of the same run, bit for bit, from three
        # caches; without it every compile gives the same bits.
        ns[template.__name__] = _wd._compiled_copy(
            template, ns, f"etdrk4_{name}", True, error_model="numpy", inline=inline, **options
        )
    _NAMED[name] = (ns["workspace"], ns["_prepare"], ns["_segment"])
    return _NAMED[name]
