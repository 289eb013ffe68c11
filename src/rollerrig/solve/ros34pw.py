"""Compiled third-order Rosenbrock W-method ROS34PW2 for the stiff roller-rig digital twin.

The twin is a stiff ODE system ``x' = f(t, x, p)`` whose right-hand side is a numba-jitted
function with the signature::

    rhs(t: float, x: float64[:], p: float64[:], tables: float64[:, :], dx: float64[:]) -> None

that writes the derivative into ``dx`` in place (``p`` is a flat parameter vector, ``tables``
2-D lookup data; the right-hand side must not write to ``x``, ``p`` or ``tables``).

The method is ROS34PW2 of Rang & Angermann (2005), Table 4.1 and Sec. 4: four stages, order 3
for *any* matrix ``A`` in ``W = I − γ h A`` (W-method), embedded order 2, stiffly accurate and
L-stable (``R(∞) = 0``), ``γ = 0.435866521508459``. It is used in the transformed form of
Hairer & Wanner (1996), eq. IV.7.25, with ``u_i = Σ_j γ_ij k_j``, which needs no matrix-vector
products::

    (I − γ h A) u_i = γ h f(t + α_i h, x + Σ_{j<i} a_ij u_j) + γ Σ_{j<i} c_ij u_j
                      + γ h² γ_i f_t,                                          i = 1..4
    x_new = x + Σ m_i u_i,        err = Σ (m_i − m̂_i) u_i

(``a = α Γ⁻¹``, ``c = diag(1/γ) − Γ⁻¹`` off the diagonal, ``m = b Γ⁻¹``, ``m̂ = b̂ Γ⁻¹``). The
coefficients are those of the paper in this transformed form, as listed with 21 digits in the
ParMooN finite-element package (``TimeDiscRout.C``, "ros34PW2"; its ``C_IJ`` has the opposite
sign convention) and cross-checked against the ``(α_ij, γ_ij, b, b̂)`` form of the paper
(``a = α Γ⁻¹`` etc. reproduce them to 1e-15, and the classical order conditions up to order 3
hold to 1e-12 with those 17-digit values); the tests check order 3 on a nonstiff problem with
the exact, a perturbed and a zero Jacobian (the W-property).

Because the method is a W-method, ``A`` may be a stale forward-difference Jacobian: it is
refreshed at the start of an integration, after a rejected step and every ``jac_every``
accepted steps. ``W`` is inverted explicitly (:func:`invert_w`), so that each of the four stage
solves is one vectorised matrix-vector product, and the inverse built for a step ``h_w`` is
reused for a step ``h`` while ``h_w/h`` stays within ``[1/1.1, 1.1]`` (the same method with
``A = (h_w/h) J``; over that range the method stays A-stable on the negative real and the
imaginary axis with ``|R(∞)| ≤ 0.19``, see :func:`stability_function`; below ``h_w/h ≈ 0.62``
it would not be; a wider window, e.g. 1.25 with ``|R(∞)| ≤ 0.41``, saves inversions but
costs rejections on very stiff problems, where the error estimate of the stiff components
suffers). An explicit time dependence enters through the ``γ_i f_t`` terms (the
autonomous form ``(x, t)' = (f, 1)`` with ``A = [[J, f_t], [0, 0]]``); ``f_t`` is a forward
difference (:func:`rollerrig.solve._wdriver.fd_time_derivative`). Since ``Σ b_i γ_i = 0`` (a
condition of order 3 for any ``f_t``) it changes a step only at ``O(h⁴)``, so ``FT_NONE``
(one right-hand-side evaluation less per step) is a legitimate choice. The step size follows
the error exponent ``1/3`` (embedded order 2 plus one) with Gustafsson's predictive controller
(Hairer & Wanner 1996, Sec. IV.8), which cuts rejections on oscillatory solutions. The
adaptive and fixed-step drivers (step-size control, output landing, reuse of ``J`` and ``W``,
failure statuses) are the generic W-method drivers of :mod:`rollerrig.solve._wdriver`, given the
step and the inversion of ``W`` of this module; the batch runs the adaptive one on threads.

Compilation and caching
-----------------------
The integrators are compiled for one right-hand side at a time: :func:`bind` (the W-method
templates of :mod:`rollerrig.solve._wdriver` with this module's step) returns them as a
:class:`~rollerrig.solve._wdriver.Driver`, whose functions other jitted code calls directly
(a segment-by-segment driver, :mod:`rollerrig.solve.fast`, avoiding the Python dispatch
overhead of ~10 µs per call). A named binding, such as the rig model's
(:data:`rollerrig.solve._compiled.RIG`), is cached on disk and loaded by every later process;
the functions below that take ``rhs`` as their first argument bind it once per process (a few
seconds of compilation per right-hand side).

References
----------
- J. Rang, L. Angermann, "New Rosenbrock W-methods of order 3 for partial differential
  algebraic equations of index 1", BIT Numer. Math. 45 (2005) 761-787.
- E. Hairer, G. Wanner, "Solving Ordinary Differential Equations II", 2nd ed., Springer 1996,
  Sec. IV.7 (Rosenbrock and W-methods, transformed form eq. 7.25), IV.8 (step-size control).
- ParMooN, ``src/General/TimeDiscRout.C`` (coefficient listing of ROS34PW2), cross-checked with
  the untransformed listing in the public ``rabbit`` solver (``solver/rodas5p.py``).

Examples
--------
Each driver's docstring has one: :func:`ros34pw2_integrate` (adaptive, with dense output at
given times) and :func:`ros34pw2_fixed` (fixed steps). They are not repeated here: each new
right-hand side compiles the driver again (about 8 s).
"""

import numpy as np

from rollerrig.solve import _cache
from rollerrig.solve import _wdriver as _wd
from rollerrig.solve._threads import run_each
from rollerrig.solve._wdriver import (
    DEFAULT_MAX_STEPS,
    FT_EVERY_STEP,
    FT_NONE,
    FT_WITH_JACOBIAN,
    STATUS_BAD_INPUT,
    STATUS_MAX_STEPS,
    STATUS_NONFINITE,
    STATUS_OK,
    STATUS_STEP_UNDERFLOW,
    Driver,
    rhs,
)

__all__ = [
    "FT_EVERY_STEP",
    "FT_NONE",
    "FT_WITH_JACOBIAN",
    "GAMMA",
    "STATUS_BAD_INPUT",
    "STATUS_MAX_STEPS",
    "STATUS_NONFINITE",
    "STATUS_OK",
    "STATUS_STEP_UNDERFLOW",
    "bind",
    "invert_w",
    "ros34pw2_fixed",
    "ros34pw2_integrate",
    "ros34pw2_integrate_batch",
    "ros34pw2_step",
    "stability_function",
]

#: ROS34PW2 diagonal coefficient γ (Rang & Angermann 2005, Table 4.1), root of the L-stability
#: polynomial 6γ³ − 18γ² + 9γ − 1 = 0 (the same γ as the 3-stage L-stable SDIRK method).
GAMMA = 4.35866521508459003886e-01

# Stage times α_i and time-derivative coefficients γ_i = Σ_j γ_ij (Rang & Angermann 2005).
_ALPHA2 = 8.71733043016918007773e-01
_ALPHA3 = 7.31579957788852430767e-01
_GAMMA2 = -4.35866521508459003886e-01
_GAMMA3 = -4.13333376233886440332e-01
# Transformed coefficients a = α Γ⁻¹, c = diag(1/γ) − Γ⁻¹ (Hairer & Wanner eq. IV.7.25).
_A21 = 2.0
_A31 = 1.41921731745576473749e00
_A32 = -2.59232211672969725669e-01
_A41 = 4.18476048231916042397e00
_A42 = -2.85192017355495874842e-01
_A43 = 2.29428036027904180827e00
_C21 = -4.58856072055808361654e00
_C31 = -4.18476048231916042397e00
_C32 = 2.85192017355495874842e-01
_C41 = -6.36817920012835703147e00
_C42 = -6.79562094446683584437e00
_C43 = 2.87009860433105590261e00
# Solution weights m = b Γ⁻¹ (stiffly accurate: m_j = a_4j, m_4 = 1) and m − m̂ (error).
_M1 = _A41
_M2 = _A42
_M3 = _A43
_M4 = 1.0
_E1 = _M1 - 3.90701053467119185925e00
_E2 = _M2 - 1.11804787782050318867e00
_E3 = _M3 - 5.21650232611490682899e-01
_E4 = _M4 - 0.5

# Step-size controller (Hairer & Wanner 1996, eqs. IV.8.21 and IV.8.25): error exponent 1/3
# (embedded order 2), with Gustafsson's predictive controller.
_EXPONENT = 1.0 / 3.0
_PREDICTIVE = True
# The inverse of W = I − γ h' J is reused for a step h while h'/h lies in [1/ratio, ratio].
_LU_REUSE_RATIO = 1.1
_N_WORK = 6  # rows of scratch space of ros34pw2_step


def stability_function(z, ratio=1.0):
    """Stability function ``R(z)`` of ROS34PW2 applied to ``x' = λ x`` with ``A = ratio · λ``.

    ``z = h λ``; ``ratio = h_w/h`` describes a W-matrix built for the step ``h_w`` and reused
    for ``h`` (``ratio = 1``: the exact Jacobian). ``R(z) = 1 + z bᵀ (I − z α − z·ratio Γ)⁻¹ 𝟙``
    in the untransformed form, evaluated here through the transformed coefficients.

    Parameters
    ----------
    z : complex or array_like of complex
        ``h λ`` [-].
    ratio : float
        ``h_w/h`` [-].

    Returns
    -------
    complex or ndarray of complex
        ``R(z)`` [-].

    Examples
    --------
    >>> abs(stability_function(-1e12)) < 1e-10  # L-stable
    True
    >>> bool(abs(stability_function(-1e-3) - np.exp(-1e-3)) < 1e-12)  # order 3: error O(z⁴)
    True
    """
    z = np.asarray(z, dtype=complex)
    a = np.array(
        [[0, 0, 0, 0], [_A21, 0, 0, 0], [_A31, _A32, 0, 0], [_A41, _A42, _A43, 0]], dtype=float
    )
    c = np.array(
        [[0, 0, 0, 0], [_C21, 0, 0, 0], [_C31, _C32, 0, 0], [_C41, _C42, _C43, 0]], dtype=float
    )
    m = np.array([_M1, _M2, _M3, _M4])
    out = np.empty(z.shape, dtype=complex)
    for idx, zz in np.ndenumerate(z):
        # (1 − γ zr) u_i = γ z (1 + Σ a_ij u_j) + γ Σ c_ij u_j, x_new = 1 + Σ m_i u_i
        u = np.zeros(4, dtype=complex)
        den = 1.0 - GAMMA * zz * ratio
        for i in range(4):
            u[i] = (GAMMA * zz * (1.0 + a[i] @ u) + GAMMA * (c[i] @ u)) / den
        out[idx] = 1.0 + m @ u
    return out if out.ndim else complex(out)


@_cache.njit
def invert_w(jac, gh, winv_t, work):
    """Transposed inverse of ``W = I − gh · jac`` by Gauss-Jordan elimination.

    Partial (row) pivoting (Golub & Van Loan 2013, Sec. 3.4; Gauss-Jordan form, Sec. 3.1). The
    explicit inverse turns each of the four stage solves of a step into one matrix-vector
    product ``u = W⁻¹ r`` computed column by column (``u += r_j · winv_t[j, :]``), which
    vectorises, instead of two triangular solves whose inner products form a chain of
    dependent additions (for ``n = 20`` about 0.07 µs against 0.5-0.8 µs for the two
    triangular solves of an LU factorisation, measured with the LU of the former ROS2 backend;
    the inversion, about 5 µs, 3x an LU, is reused over many steps).

    Parameters
    ----------
    jac : ndarray of float64, shape (n, n)
        Jacobian approximation ``A`` [1/s].
    gh : float
        ``γ h`` [s].
    winv_t : ndarray of float64, shape (n, n)
        Output, ``(W⁻¹)ᵀ`` [-].
    work : ndarray of float64, shape (n, n)
        Scratch space.

    Returns
    -------
    int
        0 on success, ``k + 1`` if the pivot of column ``k`` is zero or not finite (``W``
        singular or not finite).

    Examples
    --------
    >>> import numpy as np
    >>> jac = np.array([[-2.0, 1.0], [0.5, -3.0]])
    >>> winv_t = np.empty((2, 2))
    >>> invert_w(jac, 0.1, winv_t, np.empty((2, 2)))
    0
    >>> np.allclose(winv_t.T @ (np.eye(2) - 0.1 * jac), np.eye(2))
    True
    """
    n = jac.shape[0]
    a = work
    inv = winv_t  # holds W⁻¹ during the elimination, transposed at the end
    for i in range(n):
        for j in range(n):
            a[i, j] = -gh * jac[i, j]
            inv[i, j] = 0.0
        a[i, i] += 1.0
        inv[i, i] = 1.0
    for k in range(n):
        p = k
        amax = abs(a[k, k])
        for i in range(k + 1, n):
            v = abs(a[i, k])
            if v > amax:
                amax = v
                p = i
        if not (amax > 0.0) or not np.isfinite(amax):
            return k + 1
        if p != k:
            for j in range(n):
                tmp = a[k, j]
                a[k, j] = a[p, j]
                a[p, j] = tmp
                tmp = inv[k, j]
                inv[k, j] = inv[p, j]
                inv[p, j] = tmp
        piv = 1.0 / a[k, k]
        for j in range(n):
            a[k, j] *= piv
            inv[k, j] *= piv
        for i in range(n):
            if i != k:
                f = a[i, k]
                if f != 0.0:
                    for j in range(n):
                        a[i, j] -= f * a[k, j]
                        inv[i, j] -= f * inv[k, j]
    for i in range(n):
        for j in range(i + 1, n):
            tmp = inv[i, j]
            inv[i, j] = inv[j, i]
            inv[j, i] = tmp
    return 0


@_cache.njit
def _apply(winv_t, r, out):
    """``out = W⁻¹ r`` from the transposed inverse, as a sum of columns (vectorises).

    Four columns at a time: one load and store of ``out`` per four columns instead of one per
    column (the product is bound by those; 64 against 78 ns for n = 20, numba 0.68).
    """
    n = r.shape[0]
    for i in range(n):
        out[i] = 0.0
    j = 0
    while j + 4 <= n:
        r0 = r[j]
        r1 = r[j + 1]
        r2 = r[j + 2]
        r3 = r[j + 3]
        for i in range(n):
            out[i] += (r0 * winv_t[j, i] + r1 * winv_t[j + 1, i]) + (
                r2 * winv_t[j + 2, i] + r3 * winv_t[j + 3, i]
            )
        j += 4
    while j < n:
        rj = r[j]
        for i in range(n):
            out[i] += rj * winv_t[j, i]
        j += 1


def ros34pw2_step(rhs, t, h, t_new, x, f0, ft, h_w, p, tables, winv_t, x_new, err, work):
    """One ROS34PW2 step with a given inverse of ``W = I − γ h_w J``.

    Transformed form (module docstring) with ``A = (h_w/h) J`` and the time column
    ``(h_w/h) f_t``::

        W u_i = γ h f(t + α_i h, x + Σ a_ij u_j) + γ Σ c_ij u_j + γ γ_i h h_w f_t
        x_new = x + Σ m_i u_i,    err = Σ (m_i − m̂_i) u_i

    Third order for any ``J``, ``f_t`` and ``h_w`` (W-method), ``err`` is the difference to the
    embedded second-order solution.

    The drivers of :mod:`rollerrig.solve._wdriver` call the bound step itself (a wrapper around
    it in the step loop cost ~4 % of the run time of the fast backend, measured with numba 0.68).

    Parameters
    ----------
    rhs : numba dispatcher
        Right-hand side ``rhs(t, x, p, tables, dx)``.
    t : float
        Step start time [s].
    h : float
        Step size [s].
    t_new : float
        Step end time [s], ``t + h`` (passed separately so that output times are hit exactly).
    x : ndarray of float64, shape (n,)
        State at ``t`` [state units].
    f0 : ndarray of float64, shape (n,)
        ``f(t, x)`` [state units/s].
    ft : ndarray of float64, shape (n,)
        Approximation of ``∂f/∂t`` [state units/s²], may be zero.
    h_w : float
        Step size [s] the inverse of ``W`` was built for.
    p, tables : ndarray of float64
        Passed through to ``rhs``.
    winv_t : ndarray of float64, shape (n, n)
        ``(W⁻¹)ᵀ`` from :func:`invert_w`.
    x_new : ndarray of float64, shape (n,)
        Output, state at ``t_new`` [state units].
    err : ndarray of float64, shape (n,)
        Output, local error estimate [state units].
    work : ndarray of float64, shape (6, n)
        Scratch space.

    Examples
    --------
    >>> import numba
    >>> import numpy as np
    >>> @numba.njit
    ... def f(t, x, p, tables, dx):
    ...     dx[0] = 3.0 * t * t
    >>> winv_t = np.ones((1, 1))  # W = I (J = 0)
    >>> x_new = np.empty(1); err = np.empty(1)
    >>> ros34pw2_step(f, 1.0, 0.5, 1.5, np.array([1.0]), np.array([3.0]), np.array([6.0]),
    ...               0.5, np.zeros(1), np.zeros((1, 1)), winv_t, x_new, err,
    ...               np.empty((6, 1)))
    >>> round(float(x_new[0]), 12)  # exact for cubics: 1.5**3
    3.375
    """
    bind(rhs).step(t, h, t_new, x, f0, ft, h_w, p, tables, winv_t, x_new, err, work)


def _step(t, h, t_new, x, f0, ft, h_w, p, tables, winv_t, x_new, err, work):
    """Template of :func:`ros34pw2_step` (``rhs`` bound by :func:`bind`)."""
    n = x.shape[0]
    u1 = work[0]
    u2 = work[1]
    u3 = work[2]
    u4 = work[3]
    xs = work[4]
    r = work[5]
    gh = GAMMA * h
    ght = GAMMA * h * h_w
    # stage 1
    for i in range(n):
        r[i] = gh * f0[i] + ght * GAMMA * ft[i]
    _apply(winv_t, r, u1)
    # stage 2
    for i in range(n):
        xs[i] = x[i] + _A21 * u1[i]
    rhs(t + _ALPHA2 * h, xs, p, tables, r)
    for i in range(n):
        r[i] = gh * r[i] + GAMMA * (_C21 * u1[i]) + ght * _GAMMA2 * ft[i]
    _apply(winv_t, r, u2)
    # stage 3
    for i in range(n):
        xs[i] = x[i] + _A31 * u1[i] + _A32 * u2[i]
    rhs(t + _ALPHA3 * h, xs, p, tables, r)
    for i in range(n):
        r[i] = gh * r[i] + GAMMA * (_C31 * u1[i] + _C32 * u2[i]) + ght * _GAMMA3 * ft[i]
    _apply(winv_t, r, u3)
    # stage 4 (α_4 = 1, γ_4 = 0)
    for i in range(n):
        xs[i] = x[i] + _A41 * u1[i] + _A42 * u2[i] + _A43 * u3[i]
    rhs(t_new, xs, p, tables, r)
    for i in range(n):
        r[i] = gh * r[i] + GAMMA * (_C41 * u1[i] + _C42 * u2[i] + _C43 * u3[i])
    _apply(winv_t, r, u4)
    for i in range(n):
        x_new[i] = xs[i] + u4[i]  # stiffly accurate: m_j = a_4j, m_4 = 1
        err[i] = _E1 * u1[i] + _E2 * u2[i] + _E3 * u3[i] + _E4 * u4[i]


@_cache.njit
def _factor(jac, h, winv_t, w_work):
    """``(W⁻¹)ᵀ`` of ``W = I − γ h J`` into ``winv_t`` (the driver's ``factor``)."""
    return invert_w(jac, GAMMA * h, winv_t, w_work)


METHOD = _wd.Method(
    name="ros34pw2",
    step=_step,
    factor=_factor,
    n_work=_N_WORK,
    reuse_ratio=_LU_REUSE_RATIO,
    exponent=_EXPONENT,
    predictive=_PREDICTIVE,
)
"""ROS34PW2 for the W-method drivers of :mod:`rollerrig.solve._wdriver`."""


def bind(rhs, name: str | None = None) -> Driver:
    """ROS34PW2 compiled for the right-hand side ``rhs``: ``step``, ``integrate``, ``fixed``
    (and the finite differences), see :func:`rollerrig.solve._wdriver.bind`.

    The functions take the arguments of :func:`ros34pw2_step`, :func:`ros34pw2_integrate` and
    :func:`ros34pw2_fixed` without ``rhs`` (plus an
    optional output ``t_stop`` of ``integrate``: the time reached [s]); jitted code calls them
    directly. ``name`` caches the compiled code on disk (the package's own models only).
    """
    return _wd.bind(rhs, METHOD, name)


def ros34pw2_integrate(
    rhs, x0, t0, t1, t_out, p, tables, rtol, atol, h0, h_max, jac_every, x_out,
    max_steps=DEFAULT_MAX_STEPS, time_derivative=FT_EVERY_STEP, x_typ=None, dense=False,
):  # fmt: skip
    """Adaptive ROS34PW2 W-method from ``t0`` to ``t1`` with output at prescribed times.

    Steps are shortened to land exactly on every ``t_out[k]`` (the state there is the step's
    end state, no interpolation) and on ``t1``; with ``dense`` they land on ``t1`` only and the
    output times inside a step are interpolated by a cubic Hermite polynomial through both
    ends and their derivatives (local error O(h⁴), the method's own). The step size follows
    the standard controller
    ``h ← h · min(5, max(0.2, 0.9 · err^(−1/3)))`` (no growth right after a rejection), limited
    by Gustafsson's prediction ``0.9 (h_n/h_{n−1}) (err_{n−1}/err_n²)^(1/3)``, with the mixed
    norm ``err = rms(e_i / (atol_i + rtol_i · max(|x_i|, |x_new_i|)))`` (Hairer & Wanner 1996,
    eqs. IV.8.20 and IV.8.25). The Jacobian is a forward difference
    (:func:`rollerrig.solve._wdriver.fd_jacobian`) recomputed at the start, after a rejected
    step (if it is not already current) and every ``jac_every`` accepted steps; the inverse of
    ``I − γ h J`` (:func:`invert_w`) is rebuilt when ``J`` changes or the step size leaves
    ``[h_w/1.1, 1.1 h_w]``. Cost per accepted step: 4 right-hand-side evaluations (one more
    for ``FT_EVERY_STEP`` on a time-dependent problem) and 4 matrix-vector products.

    Parameters
    ----------
    rhs : numba dispatcher
        Right-hand side ``rhs(t, x, p, tables, dx)``; must be thread-safe for the batch variant.
    x0 : ndarray of float64, shape (n,)
        Initial state at ``t0`` [state units]; not modified.
    t0, t1 : float
        Start and end time [s], ``t1 ≥ t0``.
    t_out : ndarray of float64, shape (m,)
        Output times [s], non-decreasing, within ``[t0, t1]``.
    p : ndarray of float64
        Parameter vector [mixed units], passed to ``rhs``.
    tables : ndarray of float64, shape (r, c)
        Lookup tables [mixed units], passed to ``rhs``.
    rtol : float or ndarray of float64, shape (n,)
        Relative tolerance [-].
    atol : float or ndarray of float64, shape (n,)
        Absolute tolerance [state units].
    h0 : float
        Initial step [s]; ``≤ 0`` selects it automatically (Hairer, Nørsett & Wanner 1993,
        Sec. II.4).
    h_max : float
        Largest step [s]; ``≤ 0`` means ``t1 − t0``.
    jac_every : int
        Recompute the Jacobian every ``jac_every`` accepted steps [-] (1 = every step).
    x_out : ndarray of float64, shape (m, n)
        Output, ``x_out[k] = x(t_out[k])`` [state units]; rows not reached are NaN on failure.
    max_steps : int, optional
        Cap on accepted plus rejected steps [-] (default 1 000 000).
    time_derivative : int, optional
        Treatment of an explicit time dependence of ``f``: ``FT_NONE`` (0, no ``f_t``),
        ``FT_WITH_JACOBIAN`` (1, ``∂f/∂t`` refreshed with ``J``), ``FT_EVERY_STEP`` (2,
        default, refreshed after every accepted step at the cost of one right-hand-side
        evaluation, skipped while ``∂f/∂t`` is identically zero). For this method ``f_t``
        enters at ``O(h⁴)`` only, and ``FT_NONE`` saves one right-hand-side evaluation per step.
    x_typ : ndarray of float64, shape (n,), optional
        Typical state magnitudes [state units] for the Jacobian increments (default 1).
    dense : bool, optional
        Interpolate the outputs instead of landing on them (default False): for an output grid
        finer than, or out of step with, the step size the method wants; ``W`` is then not
        rebuilt for the short steps in front of every output time.

    Returns
    -------
    n_steps : int
        Accepted steps [-].
    n_rejected : int
        Rejected steps [-].
    n_jac : int
        Jacobian evaluations [-].
    status : int
        ``STATUS_OK`` (0), ``STATUS_MAX_STEPS`` (1), ``STATUS_STEP_UNDERFLOW`` (2),
        ``STATUS_NONFINITE`` (3, the right-hand side or the state became NaN/inf and could not
        be avoided by shortening the step) or ``STATUS_BAD_INPUT`` (4, inconsistent times or
        shapes).

    Examples
    --------
    >>> import numba
    >>> import numpy as np
    >>> @numba.njit
    ... def stiff(t, x, p, tables, dx):  # Prothero-Robinson, exact solution cos t
    ...     dx[0] = p[0] * (x[0] - np.cos(t)) - np.sin(t)
    >>> x_out = np.empty((1, 1))
    >>> res = ros34pw2_integrate(stiff, np.array([1.0]), 0.0, 1.0, np.array([1.0]),
    ...                          np.array([-1e4]), np.zeros((1, 1)), 1e-6, 1e-8, 0.0, 0.1,
    ...                          10, x_out)
    >>> res[3], bool(abs(x_out[0, 0] - np.cos(1.0)) < 1e-6)
    (0, True)
    """
    return bind(rhs).integrate(
        x0, t0, t1, t_out, p, tables, rtol, atol, h0, h_max, jac_every, x_out, max_steps,
        time_derivative, x_typ, None, dense,
    )  # fmt: skip


def ros34pw2_fixed(
    rhs, x0, t0, t1, h, t_out, p, tables, x_out, jac_every, time_derivative=FT_EVERY_STEP
):
    """Fixed-step ROS34PW2 W-method (deterministic cost; convergence studies and batches).

    Each interval between consecutive stops (``t0``, the output times, ``t1``) is divided into
    ``m = ceil(length / h)`` equal steps. The Jacobian is evaluated at ``t0`` and every
    ``jac_every`` steps (a value larger than the number of steps keeps the Jacobian of ``t0``
    throughout: the method stays third order), ``W`` is inverted again when ``J`` or the step
    changes; ``f_t`` as in :func:`ros34pw2_integrate`.

    Parameters
    ----------
    rhs, x0, t0, t1, h, t_out, p, tables, x_out, jac_every
        Right-hand side, initial state [state units], start and end time [s], largest step
        [s], output times [s], parameters, tables, output states [state units] and Jacobian
        interval [steps] (``h > 0``; the others as in :func:`ros34pw2_integrate`).
    time_derivative : int, optional
        As in :func:`ros34pw2_integrate` (default ``FT_EVERY_STEP``).

    Returns
    -------
    n_steps : int
        Steps taken [-].
    n_jac : int
        Jacobian evaluations [-].
    status : int
        0 on success, ``STATUS_NONFINITE`` (3) if the state became non-finite or ``W``
        singular, ``STATUS_BAD_INPUT`` (4) for inconsistent input.

    Examples
    --------
    >>> import numba
    >>> import numpy as np
    >>> @numba.njit
    ... def decay(t, x, p, tables, dx):
    ...     dx[0] = -x[0]
    >>> x_out = np.empty((1, 1))
    >>> ros34pw2_fixed(decay, np.array([1.0]), 0.0, 1.0, 0.05, np.array([1.0]), np.zeros(1),
    ...                np.zeros((1, 1)), x_out, 1)
    (20, 20, 0)
    >>> bool(abs(x_out[0, 0] - np.exp(-1.0)) < 1e-5)
    True
    """
    return bind(rhs).fixed(x0, t0, t1, h, t_out, p, tables, x_out, jac_every, time_derivative)


def ros34pw2_integrate_batch(
    rhs, X0, t0, t1, t_out, P, tables, rtol, atol, h0, h_max, jac_every, X_out,
    max_steps=DEFAULT_MAX_STEPS, time_derivative=FT_EVERY_STEP,
):  # fmt: skip
    """Independent adaptive integrations of the rows of ``X0``/``P`` in parallel threads.

    Row ``b`` runs ``ros34pw2_integrate(rhs, X0[b], t0, t1, t_out, P[b], tables, rtol, atol,
    h0, h_max, jac_every, X_out[b], max_steps, time_derivative)``; the result is identical to
    the serial calls. The rows go to ``numba.get_num_threads()`` threads
    (:func:`rollerrig.solve._threads.run_each`; the compiled driver releases the GIL); Ctrl-C
    drops the rows not started. ``tables`` is shared, so ``rhs`` must not write to it.

    Parameters
    ----------
    rhs, X0, t0, t1, t_out, P, tables, rtol, atol, h0, h_max, jac_every, X_out, max_steps
        Right-hand side, initial states (B, n) [state units], times [s], parameter vectors
        (B, q), tables, tolerances, steps [s], Jacobian interval, output states (B, m, n)
        [state units] and step cap, as in :func:`ros34pw2_integrate` (one row per problem).
    time_derivative : int, optional
        As in :func:`ros34pw2_integrate` (default ``FT_EVERY_STEP``).

    Returns
    -------
    ndarray of int64, shape (B, 4)
        Per row ``(n_steps, n_rejected, n_jac, status)``.

    Examples
    --------
    >>> import numba
    >>> import numpy as np
    >>> @numba.njit
    ... def decay(t, x, p, tables, dx):
    ...     dx[0] = -p[0] * x[0]
    >>> X_out = np.empty((3, 1, 1))
    >>> stats = ros34pw2_integrate_batch(decay, np.ones((3, 1)), 0.0, 1.0, np.array([1.0]),
    ...                                  np.array([[1.0], [2.0], [3.0]]), np.zeros((1, 1)),
    ...                                  1e-8, 1e-10, 0.0, 1.0, 10, X_out)
    >>> stats[:, 3].tolist()
    [0, 0, 0]
    >>> np.allclose(X_out[:, 0, 0], np.exp(-np.array([1.0, 2.0, 3.0])), rtol=1e-6)
    True
    """
    integrate = bind(rhs).integrate
    n_batch = X0.shape[0]
    stats = np.zeros((n_batch, 4), dtype=np.int64)
    if P.shape[0] != n_batch or X_out.shape[0] != n_batch:
        stats[:, 3] = STATUS_BAD_INPUT
        return stats

    def run(b):
        stats[b] = integrate(
            X0[b], t0, t1, t_out, P[b], tables, rtol, atol, h0, h_max, jac_every, X_out[b],
            max_steps, time_derivative,
        )  # fmt: skip

    run_each(run, n_batch)
    return stats
