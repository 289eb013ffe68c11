"""Compiled linearly implicit ROS2 W-method for the stiff roller-rig digital twin.

The twin is a stiff ODE system ``x' = f(t, x, p)`` whose right-hand side is a numba-jitted
function with the signature::

    rhs(t: float, x: float64[:], p: float64[:], tables: float64[:, :], dx: float64[:]) -> None

that writes the derivative into ``dx`` in place (``p`` is a flat parameter vector, ``tables``
2-D lookup data; the right-hand side must not write to ``x``, ``p`` or ``tables``).

The integrator is the two-stage, second-order Rosenbrock W-method ROS2 of Verwer, Spee, Blom
and Hundsdorfer (1999) in the transformed form used there, applied to the autonomous form
``(x, t)' = (f, 1)`` so that an approximation ``f_t`` of ``∂f/∂t`` enters as the last column of
the W-matrix:

.. math::

    y_{n+1} &= y_n + \\tfrac32 h k_1 + \\tfrac12 h k_2, \\\\
    W k_1 &= f(t_n, y_n) + \\gamma h f_t, \\\\
    W k_2 &= f(t_n + h, y_n + h k_1) - 2 k_1 - \\gamma h f_t, \\qquad W = I - \\gamma h J,
    \\quad \\gamma = 1 + 1/\\sqrt{2}.

It is second order for *any* ``J`` and ``f_t`` (W-method property), and L-stable (stability
function ``R(∞) = 0``) for ``J = ∂f/∂x``; the exact ``f_t`` keeps stiff components that follow
a time-dependent target second-order accurate (without it they lag by ``O(h)``).

This is what makes Jacobian reuse legitimate: ``J`` is a finite difference Jacobian that is
refreshed only at the start of an integration, after a rejected step or every ``jac_every``
accepted steps, and the LU factors of ``W`` are reused while the step size stays within a factor
``_LU_REUSE_RATIO`` of the one they were built for (reusing ``W`` built for ``h'`` is the same
method with ``J`` scaled by ``h'/h``; for that ratio range ``|R(∞)| ≤ 0.2``). The embedded
first-order solution is ``ŷ_{n+1} = y_n + h k_1`` (Verwer et al. 1999), so the local error
estimate is ``y_{n+1} − ŷ_{n+1} = ½ h (k_1 + k_2)`` and the step-size controller uses the
exponent ``1/2`` (Hairer & Wanner 1996, Sec. IV.8).

Compilation and caching
-----------------------
All functions are ``numba.njit(cache=True)``, but the integrators are specialised on the type of
the ``rhs`` dispatcher, which numba keys by object identity, so the specialisation for a given
right-hand side is compiled once per process (measured with numba 0.68 on a loaded 2-core
machine: ``ros2_integrate`` ~2-4 s, ``ros2_fixed`` ~1 s, ``ros2_integrate_batch`` ~6 s). Calls
from other jitted code (a segment-by-segment driver) avoid the Python dispatch overhead of
~10 µs per call.

References
----------
- J. G. Verwer, E. J. Spee, J. G. Blom, W. Hundsdorfer, "A second-order Rosenbrock method
  applied to photochemical dispersion problems", SIAM J. Sci. Comput. 20 (1999) 1456-1480.
- E. Hairer, G. Wanner, "Solving Ordinary Differential Equations II", 2nd ed., Springer 1996,
  Sec. IV.7 (Rosenbrock and W-methods), IV.8 (step-size control).
- G. H. Golub, C. F. Van Loan, "Matrix Computations", 4th ed., Alg. 3.4.1 (LU with partial
  pivoting).

Examples
--------
See :func:`ros2_integrate` (scalar Prothero-Robinson problem).
"""

import numba
import numpy as np

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
    "fd_jacobian",
    "fd_time_derivative",
    "lu_factor",
    "lu_solve",
    "ros2_fixed",
    "ros2_integrate",
    "ros2_integrate_batch",
    "ros2_step",
]

#: ROS2 parameter γ = 1 + 1/√2 (Verwer et al. 1999), makes the method L-stable.
GAMMA = 1.0 + 1.0 / np.sqrt(2.0)

#: Return codes of the integrators.
STATUS_OK = 0
STATUS_MAX_STEPS = 1
STATUS_STEP_UNDERFLOW = 2
STATUS_NONFINITE = 3
STATUS_BAD_INPUT = 4

#: Treatment of ∂f/∂t (see :func:`ros2_integrate`).
FT_NONE = 0
FT_WITH_JACOBIAN = 1
FT_EVERY_STEP = 2

_EPS = np.finfo(np.float64).eps
_SQRT_EPS = np.sqrt(_EPS)
# Step-size controller (Hairer & Wanner 1996, eq. IV.8.21 with the error exponent 1/2).
_SAFETY = 0.9
_FAC_MIN = 0.2
_FAC_MAX = 5.0
_FAC_NONFINITE = 0.25
# LU of W = I - γ h' J is reused for a step h while h'/h lies in [1/ratio, ratio].
_LU_REUSE_RATIO = 1.25
_DEFAULT_MAX_STEPS = 1_000_000


@numba.njit(cache=True)
def lu_factor(a, piv):
    """Factor a square matrix in place, ``P a = L U``, with partial (row) pivoting.

    Golub & Van Loan, Alg. 3.4.1. ``L`` (unit diagonal) is stored below the diagonal of ``a``
    and ``U`` on and above it; rows are physically swapped and ``piv[k]`` is the row that was
    swapped with row ``k`` at elimination step ``k``.

    Parameters
    ----------
    a : ndarray of float64, shape (n, n)
        Matrix [-], overwritten by its LU factors.
    piv : ndarray of int64, shape (n,)
        Pivot rows [-], output.

    Returns
    -------
    int
        0 on success, ``k + 1`` if the pivot of column ``k`` is zero or not finite.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.array([[0.0, 2.0], [1.0, 1.0]])
    >>> piv = np.empty(2, dtype=np.int64)
    >>> lu_factor(a, piv)
    0
    >>> b = np.array([2.0, 2.0])
    >>> lu_solve(a, piv, b)
    >>> b
    array([1., 1.])
    """
    n = a.shape[0]
    for k in range(n):
        p = k
        amax = abs(a[k, k])
        for i in range(k + 1, n):
            v = abs(a[i, k])
            if v > amax:
                amax = v
                p = i
        piv[k] = p
        if not (amax > 0.0) or not np.isfinite(amax):
            return k + 1
        if p != k:
            for j in range(n):
                tmp = a[k, j]
                a[k, j] = a[p, j]
                a[p, j] = tmp
        inv = 1.0 / a[k, k]
        for i in range(k + 1, n):
            lik = a[i, k] * inv
            a[i, k] = lik
            if lik != 0.0:
                for j in range(k + 1, n):
                    a[i, j] -= lik * a[k, j]
    return 0


@numba.njit(cache=True)
def lu_solve(lu, piv, b):
    """Solve ``A z = b`` in place from the factors of :func:`lu_factor`.

    Parameters
    ----------
    lu : ndarray of float64, shape (n, n)
        LU factors [-] from :func:`lu_factor`.
    piv : ndarray of int64, shape (n,)
        Pivot rows [-] from :func:`lu_factor`.
    b : ndarray of float64, shape (n,)
        Right-hand side [any unit], overwritten by the solution.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.array([[4.0, 1.0], [2.0, 3.0]])
    >>> piv = np.empty(2, dtype=np.int64)
    >>> _ = lu_factor(a, piv)
    >>> b = np.array([5.0, 5.0])
    >>> lu_solve(a, piv, b)
    >>> b
    array([1., 1.])
    """
    n = lu.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            tmp = b[k]
            b[k] = b[p]
            b[p] = tmp
    for i in range(1, n):
        s = b[i]
        for j in range(i):
            s -= lu[i, j] * b[j]
        b[i] = s
    for i in range(n - 1, -1, -1):
        s = b[i]
        for j in range(i + 1, n):
            s -= lu[i, j] * b[j]
        b[i] = s * (1.0 / lu[i, i])  # the division is off the dependency chain


@numba.njit(cache=True)
def fd_jacobian(rhs, t, x, p, tables, f0, jac_out, work, x_typ=None):
    """Forward-difference Jacobian ``J[i, j] = ∂f_i/∂x_j`` of a right-hand side.

    Column ``j`` uses the increment ``δ_j = √ε · max(|x_j|, x_typ_j)`` (Dennis & Schnabel 1996,
    Sec. 5.4), rounded so that ``x_j + δ_j`` is exactly representable. The relative rule keeps
    the increment far above the rounding level of large states (angles ~1e3 rad, currents
    ~1e2 A, torques ~1e3 N·m), the floor ``x_typ`` (default 1 in the state's SI unit) keeps it
    finite for states that pass through zero.

    Parameters
    ----------
    rhs : numba dispatcher
        Right-hand side ``rhs(t, x, p, tables, dx)``.
    t : float
        Time [s].
    x : ndarray of float64, shape (n,)
        State [SI units of the states]; not modified.
    p : ndarray of float64
        Parameter vector [mixed units], passed through.
    tables : ndarray of float64, shape (m, k)
        Lookup tables [mixed units], passed through.
    f0 : ndarray of float64, shape (n,)
        ``f(t, x)`` [state units/s], already evaluated.
    jac_out : ndarray of float64, shape (n, n)
        Output Jacobian [1/s in state units].
    work : ndarray of float64, shape (2, n)
        Scratch space.
    x_typ : ndarray of float64, shape (n,), optional
        Typical magnitude of each state [state units]; default 1.

    Returns
    -------
    int
        Number of right-hand-side evaluations (``n``).

    Examples
    --------
    >>> import numba
    >>> import numpy as np
    >>> @numba.njit
    ... def f(t, x, p, tables, dx):
    ...     dx[0] = x[0] * x[1]
    ...     dx[1] = -3.0 * x[0]
    >>> x = np.array([2.0, 5.0])
    >>> f0 = np.empty(2)
    >>> f(0.0, x, np.zeros(1), np.zeros((1, 1)), f0)
    >>> jac = np.empty((2, 2))
    >>> _ = fd_jacobian(f, 0.0, x, np.zeros(1), np.zeros((1, 1)), f0, jac, np.empty((2, 2)))
    >>> np.allclose(jac, [[5.0, 2.0], [-3.0, 0.0]], rtol=1e-6)
    True
    """
    n = x.shape[0]
    xp = work[0]
    fp = work[1]
    for i in range(n):
        xp[i] = x[i]
    for j in range(n):
        xj = x[j]
        if x_typ is None:
            scale = max(abs(xj), 1.0)
        else:
            scale = max(abs(xj), abs(x_typ[j]))
        xp[j] = xj + _SQRT_EPS * scale
        delta = xp[j] - xj
        rhs(t, xp, p, tables, fp)
        inv = 1.0 / delta
        for i in range(n):
            jac_out[i, j] = (fp[i] - f0[i]) * inv
        xp[j] = xj
    return n


@numba.njit(cache=True)
def fd_time_derivative(rhs, t, x, p, tables, f0, ft_out, work, t_end):
    """Forward-difference time derivative ``∂f/∂t`` of a right-hand side.

    The increment ``δ = √ε · max(|t|, 1 s)`` points towards ``t_end`` (backwards if ``t_end``
    lies before ``t + δ``), so that a right-hand side with a breakpoint at the segment end is
    never evaluated beyond it.

    Parameters
    ----------
    rhs : numba dispatcher
        Right-hand side ``rhs(t, x, p, tables, dx)``.
    t : float
        Time [s].
    x : ndarray of float64, shape (n,)
        State [state units].
    p, tables : ndarray of float64
        Passed through to ``rhs``.
    f0 : ndarray of float64, shape (n,)
        ``f(t, x)`` [state units/s], already evaluated.
    ft_out : ndarray of float64, shape (n,)
        Output ``∂f/∂t`` [state units/s²].
    work : ndarray of float64, shape (n,)
        Scratch space.
    t_end : float
        End of the smooth segment [s].

    Examples
    --------
    >>> import numba
    >>> import numpy as np
    >>> @numba.njit
    ... def f(t, x, p, tables, dx):
    ...     dx[0] = 3.0 * t * t
    >>> ft = np.empty(1)
    >>> fd_time_derivative(f, 2.0, np.zeros(1), np.zeros(1), np.zeros((1, 1)),
    ...                    np.array([12.0]), ft, np.empty(1), 10.0)
    >>> bool(abs(ft[0] - 12.0) < 1e-5)
    True
    """
    n = x.shape[0]
    dt = _SQRT_EPS * max(abs(t), 1.0)
    if t + dt > t_end:
        dt = -dt
    t_p = t + dt
    dt = t_p - t
    rhs(t_p, x, p, tables, work)
    inv = 1.0 / dt
    for i in range(n):
        ft_out[i] = (work[i] - f0[i]) * inv


@numba.njit(cache=True)
def _jacobians(rhs, t, x, p, tables, f0, jac, ft, work, t_end, time_derivative):
    """``J = ∂f/∂x`` and (``time_derivative > 0``) ``f_t = ∂f/∂t`` by forward differences.

    Returns True when ``f_t`` is identically zero (no explicit time dependence seen).
    """
    fd_jacobian(rhs, t, x, p, tables, f0, jac, work)
    if time_derivative > 0:
        fd_time_derivative(rhs, t, x, p, tables, f0, ft, work[0], t_end)
    else:
        ft[:] = 0.0
    for i in range(ft.shape[0]):
        if ft[i] != 0.0:
            return False
    return True


@numba.njit(cache=True)
def _build_w(jac, gh, w):
    """``w = I − gh · jac``."""
    n = jac.shape[0]
    for i in range(n):
        for j in range(n):
            w[i, j] = -gh * jac[i, j]
        w[i, i] += 1.0


@numba.njit(cache=True)
def ros2_step(rhs, t, h, t_new, x, f0, ft, h_w, p, tables, lu, piv, x_new, err, work):
    """One ROS2 W-method step with given LU factors of ``W = I − γ h_w J``.

    Verwer et al. (1999), applied to the autonomous form ``(x, t)' = (f, 1)`` with
    the W-matrix ``A = [[J, f_t], [0, 0]]``::

        W k1 = f(t, x) + γ h_w f_t
        W k2 = f(t + h, x + h k1) − 2 k1 − γ h_w f_t
        x_new = x + 3/2 h k1 + 1/2 h k2,   err = x_new − (x + h k1) = ½ h (k1 + k2)

    Second order for any ``J``, ``f_t`` and ``h_w`` (a W built for ``h_w ≠ h`` is the method with
    ``A`` scaled by ``h_w/h``); ``f_t = 0`` gives the plain W-method. The ``f_t`` column restores
    the stiff accuracy for time-dependent forcing (Prothero-Robinson type problems): without it
    a stiff component that follows a moving target lags by ``O(h)``.

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
        Step size [s] the factors of ``W`` were built for.
    p, tables : ndarray of float64
        Passed through to ``rhs``.
    lu, piv : ndarray
        Factors of ``W`` from :func:`lu_factor`.
    x_new : ndarray of float64, shape (n,)
        Output, state at ``t_new`` [state units].
    err : ndarray of float64, shape (n,)
        Output, local error estimate ``½ h (k1 + k2)`` [state units].
    work : ndarray of float64, shape (3, n)
        Scratch space.

    Examples
    --------
    >>> import numba
    >>> import numpy as np
    >>> @numba.njit
    ... def f(t, x, p, tables, dx):
    ...     dx[0] = 2.0 * t
    >>> lu = np.ones((1, 1)); piv = np.zeros(1, dtype=np.int64)  # W = I (J = 0)
    >>> x_new = np.empty(1); err = np.empty(1)
    >>> ros2_step(f, 1.0, 0.5, 1.5, np.array([1.0]), np.array([2.0]), np.zeros(1), 0.5,
    ...           np.zeros(1), np.zeros((1, 1)), lu, piv, x_new, err, np.empty((3, 1)))
    >>> float(x_new[0])  # exact for quadratics: 1.5**2
    2.25
    """
    n = x.shape[0]
    k1 = work[0]
    k2 = work[1]
    xs = work[2]
    ght = GAMMA * h_w
    for i in range(n):
        k1[i] = f0[i] + ght * ft[i]
    lu_solve(lu, piv, k1)
    for i in range(n):
        xs[i] = x[i] + h * k1[i]
    rhs(t_new, xs, p, tables, k2)
    for i in range(n):
        k2[i] -= 2.0 * k1[i] + ght * ft[i]
    lu_solve(lu, piv, k2)
    for i in range(n):
        x_new[i] = x[i] + h * (1.5 * k1[i] + 0.5 * k2[i])
        err[i] = 0.5 * h * (k1[i] + k2[i])


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
def ros2_integrate(
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
):
    """Adaptive ROS2 W-method from ``t0`` to ``t1`` with output at prescribed times.

    Steps are shortened to land exactly on every ``t_out[k]`` (the state there is the step's
    end state, no interpolation) and on ``t1``. The step size follows the standard controller
    ``h ← h · min(5, max(0.2, 0.9 · err^(−1/2)))`` (no growth right after a rejection) with the
    mixed norm ``err = rms(e_i / (atol_i + rtol_i · max(|x_i|, |x_new_i|)))`` (Hairer & Wanner
    1996, eq. IV.8.20). The Jacobian is a forward difference (:func:`fd_jacobian`) recomputed at
    the start, after a rejected step (if it is not already current) and every ``jac_every``
    accepted steps; the LU of ``I − γ h J`` is refactored when ``J`` changes or the step size
    leaves ``[h_lu/1.25, 1.25 h_lu]``.

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
        Treatment of an explicit time dependence of ``f``: ``FT_NONE`` (0, plain W-method),
        ``FT_WITH_JACOBIAN`` (1, ``∂f/∂t`` refreshed with ``J``), ``FT_EVERY_STEP`` (2, default,
        refreshed after every accepted step at the cost of one right-hand-side evaluation,
        skipped while ``∂f/∂t`` is identically zero). A stale ``∂f/∂t`` keeps order 2 for
        non-stiff components but stiff components that follow a time-dependent target then lag
        by ``O(h)`` and the controller shortens the step (see :func:`ros2_step`).

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
    >>> res = ros2_integrate(stiff, np.array([1.0]), 0.0, 1.0, np.array([1.0]),
    ...                      np.array([-1e4]), np.zeros((1, 1)), 1e-6, 1e-8, 0.0, 0.1, 10,
    ...                      x_out)
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
    w = np.empty((n, n))
    piv = np.empty(n, dtype=np.int64)
    work = np.empty((3, n))

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
    ft_zero = _jacobians(rhs, t, x, p, tables, f0, jac, ft, work, t1, time_derivative)
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

    h_lu = 0.0  # step size the LU factors in w belong to (0: none)
    n_steps = 0
    n_rejected = 0
    rejected_last = False
    nonfinite_last = False
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
            status = STATUS_NONFINITE if nonfinite_last else STATUS_STEP_UNDERFLOW
            break

        if h_lu == 0.0 or h_try > _LU_REUSE_RATIO * h_lu or h_try * _LU_REUSE_RATIO < h_lu:
            _build_w(jac, GAMMA * h_try, w)
            if lu_factor(w, piv) != 0:
                h_lu = 0.0
                n_rejected += 1
                h = 0.5 * h_try
                rejected_last = True
                nonfinite_last = True
                continue
            h_lu = h_try

        ros2_step(rhs, t, h_try, t_new, x, f0, ft, h_lu, p, tables, w, piv, x_new, err, work)
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
                ft_zero = _jacobians(rhs, t, x, p, tables, f0, jac, ft, work, t1, time_derivative)
                n_jac += 1
                steps_since_jac = 0
                jac_current = True
                h_lu = 0.0
            else:
                jac_current = False
                if time_derivative == FT_EVERY_STEP and not ft_zero:
                    fd_time_derivative(rhs, t, x, p, tables, f0, ft, work[0], t1)
            if enorm == 0.0:
                fac = _FAC_MAX
            else:
                fac = min(_FAC_MAX, max(_FAC_MIN, _SAFETY / np.sqrt(enorm)))
            if rejected_last:
                fac = min(fac, 1.0)
            h_new = h_try * fac
            if clipped and fac >= 1.0:
                h_new = max(h_new, h)
            h = min(h_new, h_max)
            rejected_last = False
            nonfinite_last = False
        else:
            n_rejected += 1
            if finite:
                h = h_try * max(_FAC_MIN, _SAFETY / np.sqrt(enorm))
            else:
                h = h_try * _FAC_NONFINITE
            if not jac_current:
                ft_zero = _jacobians(rhs, t, x, p, tables, f0, jac, ft, work, t1, time_derivative)
                n_jac += 1
                steps_since_jac = 0
                jac_current = True
            h_lu = 0.0
            rejected_last = True
            nonfinite_last = not finite

    if status != STATUS_OK:
        _fill_nan_from(x_out, k_out)
    return n_steps, n_rejected, n_jac, status


@numba.njit(cache=True)
def ros2_fixed(
    rhs, x0, t0, t1, h, t_out, p, tables, x_out, jac_every, time_derivative=FT_EVERY_STEP
):
    """Fixed-step ROS2 W-method (deterministic cost, for batches).

    Each interval between consecutive stops (``t0``, the output times, ``t1``) is divided into
    ``m = ceil(length / h)`` equal steps, so every output time is hit exactly and no step is
    longer than ``h``. The Jacobian (:func:`fd_jacobian`) is evaluated at ``t0`` and every
    ``jac_every`` steps; the LU of ``I − γ h J`` is refactored when ``J`` or the step changes.

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
        Steps between Jacobian evaluations [-]; a value larger than the number of steps keeps
        the Jacobian of ``t0`` throughout (a W-method remains second order).
    time_derivative : int, optional
        As in :func:`ros2_integrate` (default ``FT_EVERY_STEP``).

    Returns
    -------
    n_steps : int
        Steps taken [-].
    n_jac : int
        Jacobian evaluations [-].
    status : int
        0 on success, ``STATUS_NONFINITE`` (3) if the state or the right-hand side became
        non-finite or ``W`` singular, ``STATUS_BAD_INPUT`` (4) for inconsistent input.

    Examples
    --------
    >>> import numba
    >>> import numpy as np
    >>> @numba.njit
    ... def decay(t, x, p, tables, dx):
    ...     dx[0] = -x[0]
    >>> x_out = np.empty((1, 1))
    >>> ros2_fixed(decay, np.array([1.0]), 0.0, 1.0, 0.01, np.array([1.0]), np.zeros(1),
    ...            np.zeros((1, 1)), x_out, 1)
    (100, 100, 0)
    >>> bool(abs(x_out[0, 0] - np.exp(-1.0)) < 1e-4)  # ROS2 error constant ~0.4 h²
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
    w = np.empty((n, n))
    piv = np.empty(n, dtype=np.int64)
    work = np.empty((3, n))

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
                ft_zero = _jacobians(rhs, t, x, p, tables, f0, jac, ft, work, t1, time_derivative)
                n_jac += 1
                since_jac = 0
                h_lu = 0.0
            elif time_derivative == FT_EVERY_STEP and not ft_zero:
                fd_time_derivative(rhs, t, x, p, tables, f0, ft, work[0], t1)
            if hs != h_lu:
                _build_w(jac, GAMMA * hs, w)
                if lu_factor(w, piv) != 0:
                    status = STATUS_NONFINITE
                    break
                h_lu = hs
            ros2_step(rhs, t, hs, t_new, x, f0, ft, h_lu, p, tables, w, piv, x_new, err, work)
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
def ros2_integrate_batch(
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

    Row ``b`` runs ``ros2_integrate(rhs, X0[b], t0, t1, t_out, P[b], tables, rtol, atol, h0,
    h_max, jac_every, X_out[b], max_steps, time_derivative)``; the result is identical to
    the serial calls.
    ``tables`` is shared, so ``rhs`` must not write to it.

    Parameters
    ----------
    rhs : numba dispatcher
        Right-hand side ``rhs(t, x, p, tables, dx)``.
    X0 : ndarray of float64, shape (B, n)
        Initial states [state units].
    t0, t1, t_out, tables, rtol, atol, h0, h_max, jac_every, max_steps, time_derivative
        As in :func:`ros2_integrate`.
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
    >>> P = np.array([[1.0], [2.0], [3.0]])
    >>> # compiling the parallel kernel takes ~10 s; tests/solve runs the same check
    >>> stats = ros2_integrate_batch(decay, np.ones((3, 1)), 0.0, 1.0, np.array([1.0]), P,
    ...                              np.zeros((1, 1)), 1e-8, 1e-10, 0.0, 1.0, 10,
    ...                              X_out)  # doctest: +SKIP
    >>> stats[:, 3].tolist()  # doctest: +SKIP
    [0, 0, 0]
    """
    n_batch = X0.shape[0]
    stats = np.zeros((n_batch, 4), dtype=np.int64)
    if P.shape[0] != n_batch or X_out.shape[0] != n_batch:
        stats[:, 3] = STATUS_BAD_INPUT
        return stats
    for b in numba.prange(n_batch):
        n_steps, n_rej, n_jac, status = ros2_integrate(
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
