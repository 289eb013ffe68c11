"""Compiled third-order Rosenbrock W-method ROS34PW2 for the stiff roller-rig digital twin.

Same right-hand-side convention and calling convention as
:func:`rollerrig.solve.rosenbrock.ros2_integrate`, so that either integrator can drive the
model::

    rhs(t: float, x: float64[:], p: float64[:], tables: float64[:, :], dx: float64[:]) -> None

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
difference (:func:`rollerrig.solve.rosenbrock.fd_time_derivative`). Since ``Σ b_i γ_i = 0`` (a
condition of order 3 for any ``f_t``) it changes a step only at ``O(h⁴)``, so ``FT_NONE``
(one right-hand-side evaluation less per step) is a legitimate choice. The step size follows
the error exponent ``1/3`` (embedded order 2 plus one) with Gustafsson's predictive controller
(Hairer & Wanner 1996, Sec. IV.8), which cuts rejections on oscillatory solutions.

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
>>> import numba
>>> import numpy as np
>>> from rollerrig.solve.ros34pw import ros34pw2_integrate
>>> @numba.njit
... def decay(t, x, p, tables, dx):
...     dx[0] = -p[0] * x[0]
>>> x_out = np.empty((2, 1))
>>> n_steps, n_rejected, n_jac, status = ros34pw2_integrate(
...     decay, np.array([1.0]), 0.0, 1.0, np.array([0.5, 1.0]), np.array([2.0]),
...     np.zeros((1, 1)), 1e-8, 1e-10, 0.0, 1.0, 10, x_out)
>>> status
0
>>> bool(abs(x_out[1, 0] - np.exp(-2.0)) < 1e-7)
True
"""

import numba
import numpy as np

from rollerrig.solve.rosenbrock import (
    FT_EVERY_STEP,
    FT_NONE,
    FT_WITH_JACOBIAN,
    STATUS_BAD_INPUT,
    STATUS_MAX_STEPS,
    STATUS_NONFINITE,
    STATUS_OK,
    STATUS_STEP_UNDERFLOW,
    fd_jacobian,
    fd_time_derivative,
)

__all__ = [
    "FT_EVERY_STEP",
    "FT_NONE",
    "FT_WITH_JACOBIAN",
    "GAMMA",
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

_EPS = np.finfo(np.float64).eps
# Step-size controller (Hairer & Wanner 1996, eq. IV.8.21 with the error exponent 1/3).
_SAFETY = 0.9
_FAC_MIN = 0.2
_FAC_MAX = 5.0
_FAC_NONFINITE = 0.25
_EXPONENT = 1.0 / 3.0
_PREDICTIVE = True
# The inverse of W = I − γ h' J is reused for a step h while h'/h lies in [1/ratio, ratio].
_LU_REUSE_RATIO = 1.1
_DEFAULT_MAX_STEPS = 1_000_000


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


@numba.njit(cache=True)
def _all_finite(v):
    for i in range(v.shape[0]):
        if not np.isfinite(v[i]):
            return False
    return True


@numba.njit(cache=True)
def _fill_nan_from(x_out, k):
    for i in range(k, x_out.shape[0]):
        for j in range(x_out.shape[1]):
            x_out[i, j] = np.nan


@numba.njit(cache=True)
def _check_times(t0, t1, t_out):
    if not (np.isfinite(t0) and np.isfinite(t1)) or t1 < t0:
        return False
    prev = t0
    for k in range(t_out.shape[0]):
        if not (t_out[k] >= prev and t_out[k] <= t1):
            return False
        prev = t_out[k]
    return True


@numba.njit(cache=True)
def _jacobians(rhs, t, x, p, tables, f0, jac, ft, work, t_end, time_derivative, x_typ):
    """``J`` and (``time_derivative > 0``) ``f_t`` by forward differences.

    Returns True when ``f_t`` is identically zero (no explicit time dependence seen).
    """
    fd_jacobian(rhs, t, x, p, tables, f0, jac, work, x_typ)
    if time_derivative > 0:
        fd_time_derivative(rhs, t, x, p, tables, f0, ft, work[0], t_end)
    else:
        ft[:] = 0.0
    for i in range(ft.shape[0]):
        if ft[i] != 0.0:
            return False
    return True


@numba.njit(cache=True)
def invert_w(jac, gh, winv_t, work):
    """Transposed inverse of ``W = I − gh · jac`` by Gauss-Jordan elimination.

    Partial (row) pivoting (Golub & Van Loan 2013, Sec. 3.4; Gauss-Jordan form, Sec. 3.1). The
    explicit inverse turns each of the four stage solves of a step into one matrix-vector
    product ``u = W⁻¹ r`` computed column by column (``u += r_j · winv_t[j, :]``), which
    vectorises, instead of two triangular solves whose inner products form a chain of
    dependent additions (for ``n = 20`` about 0.07 µs against 0.5-0.8 µs for the two
    triangular solves of :func:`rollerrig.solve.rosenbrock.lu_solve`; the inversion, about
    5 µs, 3x an LU, is reused over many steps).

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


@numba.njit(cache=True)
def _apply(winv_t, r, out):
    """``out = W⁻¹ r`` from the transposed inverse, as a sum of columns (vectorises)."""
    n = r.shape[0]
    for i in range(n):
        out[i] = 0.0
    for j in range(n):
        rj = r[j]
        if rj != 0.0:
            for i in range(n):
                out[i] += rj * winv_t[j, i]


@numba.njit(cache=True)
def ros34pw2_step(rhs, t, h, t_new, x, f0, ft, h_w, p, tables, winv_t, x_new, err, work):
    """One ROS34PW2 step with a given inverse of ``W = I − γ h_w J``.

    Transformed form (module docstring) with ``A = (h_w/h) J`` and the time column
    ``(h_w/h) f_t``::

        W u_i = γ h f(t + α_i h, x + Σ a_ij u_j) + γ Σ c_ij u_j + γ γ_i h h_w f_t
        x_new = x + Σ m_i u_i,    err = Σ (m_i − m̂_i) u_i

    Third order for any ``J``, ``f_t`` and ``h_w`` (W-method), ``err`` is the difference to the
    embedded second-order solution.

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


@numba.njit(cache=True)
def ros34pw2_integrate(
    rhs,
    x0,
    t0,
    t1,
    t_out,
    p,
    tables,
    rtol,
    atol,
    h0,
    h_max,
    jac_every,
    x_out,
    max_steps=_DEFAULT_MAX_STEPS,
    time_derivative=FT_EVERY_STEP,
    x_typ=None,
):
    """Adaptive ROS34PW2 W-method from ``t0`` to ``t1`` with output at prescribed times.

    Steps are shortened to land exactly on every ``t_out[k]`` (the state there is the step's
    end state, no interpolation) and on ``t1``. The step size follows the standard controller
    ``h ← h · min(5, max(0.2, 0.9 · err^(−1/3)))`` (no growth right after a rejection), limited
    by Gustafsson's prediction ``0.9 (h_n/h_{n−1}) (err_{n−1}/err_n²)^(1/3)``, with the mixed
    norm ``err = rms(e_i / (atol_i + rtol_i · max(|x_i|, |x_new_i|)))`` (Hairer & Wanner 1996,
    eqs. IV.8.20 and IV.8.25). The Jacobian is a forward difference
    (:func:`rollerrig.solve.rosenbrock.fd_jacobian`) recomputed at the start, after a rejected
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
        Initial step [s]; ``≤ 0`` selects it automatically.
    h_max : float
        Largest step [s]; ``≤ 0`` means ``t1 − t0``.
    jac_every : int
        Recompute the Jacobian every ``jac_every`` accepted steps [-] (1 = every step, i.e. a
        classical Rosenbrock method).
    x_out : ndarray of float64, shape (m, n)
        Output, ``x_out[k] = x(t_out[k])`` [state units]; rows not reached are NaN on failure.
    max_steps : int, optional
        Cap on accepted plus rejected steps [-] (default 1 000 000).
    time_derivative : int, optional
        ``FT_NONE`` (0), ``FT_WITH_JACOBIAN`` (1) or ``FT_EVERY_STEP`` (2, default), as in
        :func:`rollerrig.solve.rosenbrock.ros2_integrate`; for this method ``f_t`` enters at
        ``O(h⁴)`` only, and ``FT_NONE`` saves one right-hand-side evaluation per step.
    x_typ : ndarray of float64, shape (n,), optional
        Typical state magnitudes [state units] for the Jacobian increments (default 1).

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
        ``STATUS_NONFINITE`` (3) or ``STATUS_BAD_INPUT`` (4), as in ``ros2_integrate``.

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
    n = x0.shape[0]
    n_out = t_out.shape[0]
    if (
        not _check_times(t0, t1, t_out)
        or x_out.shape[0] != n_out
        or (n_out > 0 and x_out.shape[1] != n)
    ):
        if x_out.shape[0] == n_out:
            _fill_nan_from(x_out, 0)
        return 0, 0, 0, STATUS_BAD_INPUT

    rtol_v = np.zeros(n) + rtol
    atol_v = np.zeros(n) + atol
    if h_max <= 0.0:
        h_max = t1 - t0
    if jac_every < 1:
        jac_every = 1

    x = x0.copy()
    x_new = np.empty(n)
    f0 = np.empty(n)
    f_new = np.empty(n)
    err = np.empty(n)
    jac = np.empty((n, n))
    ft = np.empty(n)
    winv_t = np.empty((n, n))
    w_work = np.empty((n, n))
    work = np.empty((6, n))

    t = t0
    k_out = 0
    while k_out < n_out and t_out[k_out] == t0:
        x_out[k_out, :] = x
        k_out += 1
    if t1 == t0:
        return 0, 0, 0, STATUS_OK

    rhs(t, x, p, tables, f0)
    if not (_all_finite(x) and _all_finite(f0)):
        _fill_nan_from(x_out, k_out)
        return 0, 0, 0, STATUS_NONFINITE
    ft_zero = _jacobians(rhs, t, x, p, tables, f0, jac, ft, work, t1, time_derivative, x_typ)
    n_jac = 1
    jac_current = True  # J was evaluated at the present (t, x)
    steps_since_jac = 0

    # Initial step (Hairer & Wanner, Vol. I, Sec. II.4, first part of the starting-step rule).
    h = h0
    if h <= 0.0:
        d0 = 0.0
        d1 = 0.0
        for i in range(n):
            sc = atol_v[i] + rtol_v[i] * abs(x[i])
            d0 += (x[i] / sc) ** 2
            d1 += (f0[i] / sc) ** 2
        d0 = np.sqrt(d0 / n)
        d1 = np.sqrt(d1 / n)
        if d0 < 1e-5 or d1 < 1e-5:
            h = 1e-6
        else:
            h = 0.01 * d0 / d1
    h = min(h, h_max, t1 - t0)

    h_lu = 0.0  # step size the inverse in winv_t belongs to (0: none)
    n_steps = 0
    n_rejected = 0
    rejected_last = False
    h_acc = 0.0  # last accepted step and its error norm (predictive controller)
    err_acc = 1.0
    status = STATUS_OK
    while t < t1:
        if n_steps + n_rejected >= max_steps:
            status = STATUS_MAX_STEPS
            break
        target = t_out[k_out] if k_out < n_out else t1
        remaining = target - t
        if remaining <= h * (1.0 + 1e-8):
            h_try = remaining
            t_new = target
        elif remaining < 2.0 * h:
            h_try = 0.5 * remaining
            t_new = t + h_try
        else:
            h_try = h
            t_new = t + h_try
        clipped = h_try < h
        if h_try <= 8.0 * _EPS * max(abs(t), abs(t_new)) or t_new <= t:
            status = STATUS_STEP_UNDERFLOW
            break

        if h_lu == 0.0 or h_try > _LU_REUSE_RATIO * h_lu or h_try * _LU_REUSE_RATIO < h_lu:
            if invert_w(jac, GAMMA * h_try, winv_t, w_work) != 0:
                h_lu = 0.0
                n_rejected += 1
                h = 0.5 * h_try
                rejected_last = True
                continue
            h_lu = h_try

        ros34pw2_step(rhs, t, h_try, t_new, x, f0, ft, h_lu, p, tables, winv_t, x_new, err, work)
        enorm = 0.0
        for i in range(n):
            sc = atol_v[i] + rtol_v[i] * max(abs(x[i]), abs(x_new[i]))
            enorm += (err[i] / sc) ** 2
        enorm = np.sqrt(enorm / n)
        finite = np.isfinite(enorm)
        if finite and enorm <= 1.0:
            rhs(t_new, x_new, p, tables, f_new)
            finite = _all_finite(f_new)
        if finite and enorm <= 1.0:
            # accept
            t = t_new
            for i in range(n):
                x[i] = x_new[i]
                f0[i] = f_new[i]
            n_steps += 1
            while k_out < n_out and t_out[k_out] == t:
                x_out[k_out, :] = x
                k_out += 1
            steps_since_jac += 1
            if steps_since_jac >= jac_every:
                ft_zero = _jacobians(
                    rhs, t, x, p, tables, f0, jac, ft, work, t1, time_derivative, x_typ
                )
                n_jac += 1
                steps_since_jac = 0
                jac_current = True
                h_lu = 0.0
            else:
                jac_current = False
                if time_derivative == FT_EVERY_STEP and not ft_zero and t < t1:
                    fd_time_derivative(rhs, t, x, p, tables, f0, ft, work[0], t1)
            if enorm == 0.0:
                fac = _FAC_MAX
            else:
                fac = min(_FAC_MAX, max(_FAC_MIN, _SAFETY * enorm**-_EXPONENT))
            if _PREDICTIVE and h_acc > 0.0:
                # Gustafsson's predictive controller (Hairer & Wanner 1996, eq. IV.8.25)
                e_cl = max(enorm, 1e-10)
                fac_g = _SAFETY * (h_try / h_acc) * (err_acc / (e_cl * e_cl)) ** _EXPONENT
                fac = min(fac, max(_FAC_MIN, fac_g))
            h_acc = h_try
            err_acc = max(1e-2, enorm)
            if rejected_last:
                fac = min(fac, 1.0)
            h_new = h_try * fac
            if clipped and fac >= 1.0:
                h_new = max(h_new, h)
            h = min(h_new, h_max)
            rejected_last = False
        else:
            n_rejected += 1
            if finite:
                h = h_try * max(_FAC_MIN, _SAFETY * enorm**-_EXPONENT)
            else:
                h = h_try * _FAC_NONFINITE
            if not jac_current:
                ft_zero = _jacobians(
                    rhs, t, x, p, tables, f0, jac, ft, work, t1, time_derivative, x_typ
                )
                n_jac += 1
                steps_since_jac = 0
                jac_current = True
            h_lu = 0.0
            rejected_last = True
            if not finite and h <= 8.0 * _EPS * max(abs(t), abs(t1)):
                status = STATUS_NONFINITE
                break

    if status != STATUS_OK:
        _fill_nan_from(x_out, k_out)
    return n_steps, n_rejected, n_jac, status


@numba.njit(cache=True)
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
    rhs : numba dispatcher
        Right-hand side ``rhs(t, x, p, tables, dx)``.
    x0 : ndarray of float64, shape (n,)
        Initial state at ``t0`` [state units].
    t0, t1 : float
        Start and end time [s].
    h : float
        Largest step [s], ``> 0``.
    t_out : ndarray of float64, shape (m,)
        Output times [s], non-decreasing, within ``[t0, t1]``.
    p, tables : ndarray of float64
        Passed to ``rhs``.
    x_out : ndarray of float64, shape (m, n)
        Output, ``x_out[k] = x(t_out[k])`` [state units].
    jac_every : int
        Steps between Jacobian evaluations [-].
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
    n = x0.shape[0]
    n_out = t_out.shape[0]
    if (
        not _check_times(t0, t1, t_out)
        or not (h > 0.0)
        or x_out.shape[0] != n_out
        or (n_out > 0 and x_out.shape[1] != n)
    ):
        if x_out.shape[0] == n_out:
            _fill_nan_from(x_out, 0)
        return 0, 0, STATUS_BAD_INPUT
    if jac_every < 1:
        jac_every = 1

    x = x0.copy()
    x_new = np.empty(n)
    f0 = np.empty(n)
    err = np.empty(n)
    jac = np.empty((n, n))
    ft = np.empty(n)
    winv_t = np.empty((n, n))
    w_work = np.empty((n, n))
    work = np.empty((6, n))

    t = t0
    k_out = 0
    n_steps = 0
    n_jac = 0
    h_lu = 0.0
    since_jac = 0
    ft_zero = True
    status = STATUS_OK
    while k_out < n_out and t_out[k_out] == t0:
        x_out[k_out, :] = x
        k_out += 1
    while t < t1 and status == STATUS_OK:
        target = t_out[k_out] if k_out < n_out else t1
        length = target - t
        m = max(1, int(np.ceil(length / h * (1.0 - 1e-12))))
        hs = length / m
        t_start = t
        for i in range(m):
            t_new = target if i == m - 1 else t_start + (i + 1) * hs
            rhs(t, x, p, tables, f0)
            if not (_all_finite(x) and _all_finite(f0)):
                status = STATUS_NONFINITE
                break
            if n_jac == 0 or since_jac >= jac_every:
                ft_zero = _jacobians(
                    rhs, t, x, p, tables, f0, jac, ft, work, t1, time_derivative, None
                )
                n_jac += 1
                since_jac = 0
                h_lu = 0.0
            elif time_derivative == FT_EVERY_STEP and not ft_zero:
                fd_time_derivative(rhs, t, x, p, tables, f0, ft, work[0], t1)
            if hs != h_lu:
                if invert_w(jac, GAMMA * hs, winv_t, w_work) != 0:
                    status = STATUS_NONFINITE
                    break
                h_lu = hs
            ros34pw2_step(rhs, t, hs, t_new, x, f0, ft, h_lu, p, tables, winv_t, x_new, err, work)
            for j in range(n):
                x[j] = x_new[j]
            t = t_new
            n_steps += 1
            since_jac += 1
        if status != STATUS_OK:
            break
        if not _all_finite(x):
            status = STATUS_NONFINITE
            break
        while k_out < n_out and t_out[k_out] == t:
            x_out[k_out, :] = x
            k_out += 1
    if status != STATUS_OK:
        _fill_nan_from(x_out, k_out)
    return n_steps, n_jac, status


@numba.njit(cache=True, parallel=True)
def ros34pw2_integrate_batch(
    rhs,
    X0,
    t0,
    t1,
    t_out,
    P,
    tables,
    rtol,
    atol,
    h0,
    h_max,
    jac_every,
    X_out,
    max_steps=_DEFAULT_MAX_STEPS,
    time_derivative=FT_EVERY_STEP,
):
    """Independent adaptive integrations of the rows of ``X0``/``P`` in parallel (``prange``).

    Row ``b`` runs ``ros34pw2_integrate(rhs, X0[b], t0, t1, t_out, P[b], tables, rtol, atol,
    h0, h_max, jac_every, X_out[b], max_steps, time_derivative)``; the result is identical to
    the serial calls. ``tables`` is shared, so ``rhs`` must not write to it.

    Parameters
    ----------
    rhs : numba dispatcher
        Right-hand side ``rhs(t, x, p, tables, dx)``.
    X0 : ndarray of float64, shape (B, n)
        Initial states [state units].
    t0, t1, t_out, tables, rtol, atol, h0, h_max, jac_every, max_steps, time_derivative
        As in :func:`ros34pw2_integrate`.
    P : ndarray of float64, shape (B, q)
        Parameter vectors [mixed units], one row per problem.
    X_out : ndarray of float64, shape (B, m, n)
        Output states [state units].

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
    >>> stats[:, 3].tolist(), np.allclose(X_out[:, 0, 0], np.exp(-np.arange(1.0, 4.0)))
    ([0, 0, 0], True)
    """
    n_batch = X0.shape[0]
    stats = np.zeros((n_batch, 4), dtype=np.int64)
    if P.shape[0] != n_batch or X_out.shape[0] != n_batch:
        stats[:, 3] = STATUS_BAD_INPUT
        return stats
    for b in numba.prange(n_batch):
        n_steps, n_rej, n_jac, status = ros34pw2_integrate(
            rhs,
            X0[b],
            t0,
            t1,
            t_out,
            P[b],
            tables,
            rtol,
            atol,
            h0,
            h_max,
            jac_every,
            X_out[b],
            max_steps,
            time_derivative,
        )
        stats[b, 0] = n_steps
        stats[b, 1] = n_rej
        stats[b, 2] = n_jac
        stats[b, 3] = status
    return stats
