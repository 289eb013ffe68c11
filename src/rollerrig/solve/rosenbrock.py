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
The step-size control, output landing, Jacobian and ``W`` reuse and failure handling are the
drivers shared with ROS34PW2 (:mod:`rollerrig.solve._wdriver`); the integrators here pass them
:func:`ros2_step` and the LU factorisation of ``W``. The kernels are ``numba.njit(cache=True)``,
but the integrators are specialised on the type of the ``rhs`` dispatcher (and the drivers on
that of the step function), which numba keys by object identity and cannot cache, so the
specialisation for a given right-hand side is compiled once per process (measured with numba
0.68 on a loaded 2-core machine: ``ros2_integrate`` ~2-4 s, ``ros2_fixed`` ~1 s,
``ros2_integrate_batch`` ~6 s). Calls from other jitted code (a segment-by-segment driver)
avoid the Python dispatch overhead of ~10 µs per call.

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

from rollerrig.solve import _wdriver as _wd
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
    fd_jacobian,
    fd_time_derivative,
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

# Error exponent 1/2 of the step-size controller (embedded order 1, Hairer & Wanner 1996,
# eq. IV.8.21), without the predictive controller.
_EXPONENT = 0.5
_PREDICTIVE = False
# LU of W = I - γ h' J is reused for a step h while h'/h lies in [1/ratio, ratio].
_LU_REUSE_RATIO = 1.25
_N_WORK = 3  # rows of scratch space of ros2_step


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
def _factor(jac, h, w, piv, w_work):
    """LU factors of ``W = I − γ h J`` into ``w``, ``piv`` (the driver's ``factor``)."""
    _build_w(jac, GAMMA * h, w)
    return lu_factor(w, piv)


@numba.njit  # not cached (module docstring)
def ros2_integrate(
    rhs, x0, t0, t1, t_out, p, tables, rtol, atol, h0, h_max, jac_every, x_out,
    max_steps=DEFAULT_MAX_STEPS, time_derivative=FT_EVERY_STEP,
):  # fmt: skip
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
    return _wd.integrate(
        ros2_step, _factor, _N_WORK, _LU_REUSE_RATIO, _EXPONENT, _PREDICTIVE,
        rhs, x0, t0, t1, t_out, p, tables, rtol, atol, h0, h_max, jac_every, x_out, max_steps,
        time_derivative, None,
    )  # fmt: skip


@numba.njit  # not cached (module docstring)
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
    return _wd.fixed(
        ros2_step, _factor, _N_WORK,
        rhs, x0, t0, t1, h, t_out, p, tables, x_out, jac_every, time_derivative,
    )  # fmt: skip


@numba.njit  # not cached (module docstring)
def ros2_integrate_batch(
    rhs, X0, t0, t1, t_out, P, tables, rtol, atol, h0, h_max, jac_every, X_out,
    max_steps=DEFAULT_MAX_STEPS, time_derivative=FT_EVERY_STEP,
):  # fmt: skip
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
    return _wd.integrate_batch(
        ros2_integrate,
        rhs, X0, t0, t1, t_out, P, tables, rtol, atol, h0, h_max, jac_every, X_out, max_steps,
        time_derivative,
    )  # fmt: skip
