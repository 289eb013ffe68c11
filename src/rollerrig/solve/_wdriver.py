"""Generic drivers of a compiled linearly implicit W-method (private; used by ROS34PW2).

A linearly implicit W-method advances ``x' = f(t, x, p)`` with stages that solve linear systems
with ``W = I − γ h J``, where ``J`` may be any approximation of ``∂f/∂x`` (Hairer & Wanner
1996, Sec. IV.7). Everything around the stages is the same for every such method and is written
once here:

- ``integrate``: adaptive step size (Hairer & Wanner 1996, Sec. IV.8: mixed error norm,
  standard controller, optionally Gustafsson's predictive controller), steps shortened to land
  exactly on the output times, reuse of ``J`` over ``jac_every`` accepted steps and of the
  factored ``W`` while the step size stays within a ratio of the one it was built for,
  recovery from non-finite values by shorter steps, failure statuses;
- ``fixed``: equal steps between consecutive output times (deterministic cost);
- ``fd_jacobian``, ``fd_time_derivative``: the forward-difference ``J`` and ``f_t``

(the fields of a :class:`Driver`, compiled by :func:`bind`; :func:`fd_jacobian` and
:func:`fd_time_derivative` also take the right-hand side as their first argument).

A method enters as a :class:`Method`: the step, written as a template that calls ``rhs`` (see
below), the jitted factorisation of ``W`` and the controller constants::

    factor(jac, h, w, w_work) -> int   # factor or invert W = I − γ h J into w; 0 = ok
    step(t, h, t_new, x, f0, ft, h_w, p, tables, w, x_new, err, work) -> None

``step`` advances from ``(t, x)`` (``f0 = f(t, x)``, ``ft ≈ ∂f/∂t``) by ``h`` to ``t_new``
with ``w`` built for the step ``h_w`` and writes the new state and the local error estimate;
``work`` has ``n_work`` rows of scratch space. ROS34PW2 (:mod:`rollerrig.solve.ros34pw`)
inverts ``W`` explicitly.

Templates bound to a right-hand side
------------------------------------
The drivers are written once, as templates: plain functions that call the right-hand side
``rhs``, the method's ``step`` and ``factor`` and read its constants (``N_WORK``,
``REUSE_RATIO``, ``EXPONENT``, ``PREDICTIVE``) as *global* names. :func:`bind` compiles copies
of them whose globals are one right-hand side and one method. numba resolves those calls at
compile time into direct, inlinable calls; passing the functions as arguments would do the same
but embeds their addresses in the machine code, which numba then cannot cache on disk (and
whose cache index, keyed by the function objects, never hits and grows with every process). A
binding with a ``name`` is cached (:mod:`rollerrig.solve._cache`): the fast backend binds the
rig model once (:data:`rollerrig.solve._compiled.RIG`) and loads it from the cache in every
later process. Unnamed bindings (tests, a user's right-hand side) are compiled once per
process. The step must be the method's step itself, not a wrapper around it (one more call
layer in the step loop cost ~4 % of the run time of the fast backend, measured with numba
0.68).

References
----------
- E. Hairer, G. Wanner, "Solving Ordinary Differential Equations II", 2nd ed., Springer 1996,
  Sec. IV.7 (W-methods), IV.8 (step-size control, eqs. IV.8.20, IV.8.21, IV.8.25).
- E. Hairer, S. P. Nørsett, G. Wanner, "Solving Ordinary Differential Equations I", 2nd ed.,
  Springer 1993, Sec. II.4 (starting step size).
- J. E. Dennis, R. B. Schnabel, "Numerical Methods for Unconstrained Optimization and Nonlinear
  Equations", SIAM 1996, Sec. 5.4 (finite-difference increments).

Examples
--------
See :func:`rollerrig.solve.ros34pw.ros34pw2_integrate`.
"""

import functools
import types
from collections.abc import Callable
from typing import NamedTuple

import numba
import numpy as np

from rollerrig.solve import _cache

#: Return codes of the integrators.
STATUS_OK = 0
STATUS_MAX_STEPS = 1
STATUS_STEP_UNDERFLOW = 2
STATUS_NONFINITE = 3
STATUS_BAD_INPUT = 4

#: Treatment of ∂f/∂t (see :func:`rollerrig.solve.ros34pw.ros34pw2_integrate`).
FT_NONE = 0
FT_WITH_JACOBIAN = 1
FT_EVERY_STEP = 2

DEFAULT_MAX_STEPS = 1_000_000

_EPS = np.finfo(np.float64).eps
_SQRT_EPS = np.sqrt(_EPS)
# Step-size controller (Hairer & Wanner 1996, eq. IV.8.21; the error exponent is the method's).
_SAFETY = 0.9
_FAC_MIN = 0.2
_FAC_MAX = 5.0
_FAC_NONFINITE = 0.25


# ---------------------------------------------------------------------------------------------
# Names a binding replaces (bind): the right-hand side and the method. The templates below call
# and read them as globals; these placeholders only keep the templates readable and importable.
# ---------------------------------------------------------------------------------------------
def rhs(t, x, p, tables, dx):
    """Placeholder of the right-hand side ``rhs(t, x, p, tables, dx)`` of a binding."""
    raise NotImplementedError("a driver template runs only when bound: see _wdriver.bind")


step = factor = rhs
N_WORK = 2  # rows of scratch space of the method's step [-]
REUSE_RATIO = 1.0  # W built for h_w is reused while h_w/h is in [1/ratio, ratio] [-]
EXPONENT = 0.5  # error exponent of the controller, 1/(embedded order + 1) [-]
PREDICTIVE = False  # Gustafsson's predictive controller


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
    return bind(rhs).fd_jacobian(t, x, p, tables, f0, jac_out, work, x_typ)


def fd_time_derivative(rhs, t, x, p, tables, f0, ft_out, work, t_end):
    """Forward-difference time derivative ``∂f/∂t`` of a right-hand side.

    The increment ``δ = √ε · max(|t|, 1 s)`` points towards ``t_end`` (backwards if ``t_end``
    lies before ``t + δ``), so that a right-hand side with a breakpoint at the segment end is
    never evaluated beyond it.

    Parameters
    ----------
    rhs, t, x, p, tables, f0
        Right-hand side, time [s], state [state units], parameters, tables and ``f(t, x)``
        [state units/s], as in :func:`fd_jacobian`.
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
    return bind(rhs).fd_time_derivative(t, x, p, tables, f0, ft_out, work, t_end)


def _fd_jacobian(t, x, p, tables, f0, jac_out, work, x_typ=None):
    """Template of :func:`fd_jacobian` (``rhs`` bound)."""
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


def _fd_time_derivative(t, x, p, tables, f0, ft_out, work, t_end):
    """Template of :func:`fd_time_derivative` (``rhs`` bound)."""
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


def _jacobians(t, x, p, tables, f0, jac, ft, work, t_end, time_derivative, x_typ):
    """``J = ∂f/∂x`` and (``time_derivative > 0``) ``f_t = ∂f/∂t`` by forward differences.

    Returns True when ``f_t`` is identically zero (no explicit time dependence seen).
    """
    _fd_jacobian(t, x, p, tables, f0, jac, work, x_typ)
    if time_derivative > 0:
        _fd_time_derivative(t, x, p, tables, f0, ft, work[0], t_end)
    else:
        for i in range(ft.shape[0]):
            ft[i] = 0.0
    for i in range(ft.shape[0]):
        if ft[i] != 0.0:
            return False
    return True


@_cache.njit(_nrt=False)
def _all_finite(v):
    for i in range(v.shape[0]):
        if not np.isfinite(v[i]):
            return False
    return True


# Rows are copied by loops, not by slice assignment (``x_out[k, :] = x``): numba compiles a
# slice assignment with its shape check and error message (string formatting included), about
# 8 s of a cold start's compilation for the drivers (measured with numba's compile events).
# These helpers allocate nothing: compiled without reference counting (_nrt=False), a call
# takes and gives back no reference (two atomic operations per array otherwise).
@_cache.njit(_nrt=False)
def _store_row(x_out, k, x):
    """``x_out[k, :] = x``."""
    for j in range(x.shape[0]):
        x_out[k, j] = x[j]


@_cache.njit(_nrt=False)
def _copy_rows(dst, k, src, m):
    """``dst[k:k + m, :] = src[:m, :]``."""
    for i in range(m):
        for j in range(src.shape[1]):
            dst[k + i, j] = src[i, j]


@_cache.njit(_nrt=False)
def _fill_nan_from(x_out, k):
    for i in range(k, x_out.shape[0]):
        for j in range(x_out.shape[1]):
            x_out[i, j] = np.nan


@_cache.njit
def _check_times(t0, t1, t_out):
    if not (np.isfinite(t0) and np.isfinite(t1)) or t1 < t0:
        return False
    prev = t0
    for k in range(t_out.shape[0]):
        if not (t_out[k] >= prev and t_out[k] <= t1):
            return False
        prev = t_out[k]
    return True


@_cache.njit
def _bad_input(ok, t0, t1, t_out, n, x_out):
    """True (and ``x_out`` NaN where its shape allows) unless ``ok`` and times, shapes agree."""
    n_out = t_out.shape[0]
    if (
        not ok
        or not _check_times(t0, t1, t_out)
        or x_out.shape[0] != n_out
        or (n_out > 0 and x_out.shape[1] != n)
    ):
        if x_out.shape[0] == n_out:
            _fill_nan_from(x_out, 0)
        return True
    return False


@_cache.njit
def _workspace(x0, n_work):
    """The state ``x`` (a copy of ``x0``) and scratch arrays ``x_new, f0, f_new, err, jac, ft,
    w, w_work, work``."""
    n = x0.shape[0]
    return (
        x0.copy(),
        np.empty(n),
        np.empty(n),
        np.empty(n),
        np.empty(n),
        np.empty((n, n)),
        np.empty(n),
        np.empty((n, n)),
        np.empty((n, n)),
        np.empty((n_work, n)),
    )


@_cache.njit
def _land(t, x, t_out, x_out, k_out):
    """Store ``x`` in every output row due at ``t`` from row ``k_out`` on; the next row."""
    while k_out < t_out.shape[0] and t_out[k_out] == t:
        _store_row(x_out, k_out, x)
        k_out += 1
    return k_out


@_cache.njit
def _hermite(t, h, x, f, x_new, f_new, t_at, out):
    """Cubic Hermite interpolation of a step from ``(t, x, f)`` to ``(t + h, x_new, f_new)``
    at ``t_at``, into ``out``.

    Exact for cubics, local error O(h⁴) like the third-order step itself (Hairer, Nørsett &
    Wanner 1993, Sec. II.6, eq. 6.7).
    """
    s = (t_at - t) / h
    s2 = s * s
    h00 = 1.0 - s2 * (3.0 - 2.0 * s)
    h01 = 1.0 - h00
    h10 = h * s * (1.0 - s) * (1.0 - s)
    h11 = h * s2 * (s - 1.0)
    for i in range(x.shape[0]):
        out[i] = h00 * x[i] + h01 * x_new[i] + h10 * f[i] + h11 * f_new[i]


@_cache.njit
def _error_factor(enorm, exponent):
    """``0.9 · enorm^(−exponent)``, the step factor of the standard controller."""
    if exponent == 0.5:
        return _SAFETY / np.sqrt(enorm)  # correctly rounded, unlike pow
    return _SAFETY * enorm**-exponent


def _integrate(
    x0, t0, t1, t_out, p, tables, rtol, atol, h0, h_max, jac_every, x_out,
    max_steps=DEFAULT_MAX_STEPS, time_derivative=FT_EVERY_STEP, x_typ=None, t_stop=None,
    dense=False,
):  # fmt: skip
    """Template of ``integrate``: adaptive W-method from ``t0`` to ``t1``, output at given times.

    The method is the bound ``step``, ``factor`` and constants (module docstring); the
    parameters, the returns and the behaviour are those of
    :func:`rollerrig.solve.ros34pw.ros34pw2_integrate`. A non-finite value (or a singular
    ``W``) is retried with a shorter step; the integration ends with ``STATUS_NONFINITE`` once
    that step falls to ``8 ε max(|t|, |t1|)`` or the next step underflows.

    Parameters
    ----------
    x0, t0, t1, t_out, p, tables, rtol, atol, h0, h_max, jac_every, x_out, max_steps
        As in :func:`rollerrig.solve.ros34pw.ros34pw2_integrate`.
    time_derivative : int
        ``FT_NONE``, ``FT_WITH_JACOBIAN`` or ``FT_EVERY_STEP``.
    x_typ : ndarray of float64, shape (n,), or None
        Typical state magnitudes [state units] for :func:`fd_jacobian`.
    t_stop : ndarray of float64, shape (1,), or None
        Output: the time the integration reached [s] (``t1`` on success, where it stopped on
        a failure).
    dense : bool
        Interpolate the output times inside a step (:func:`_hermite`) instead of shortening
        steps to land on them: the step is then free of the output grid, so ``W`` is reused
        across output times instead of being refactored for the short steps before each one.

    Returns
    -------
    n_steps, n_rejected, n_jac, status : int
        Accepted and rejected steps, Jacobian evaluations [-] and the status.
    """
    n = x0.shape[0]
    n_out = t_out.shape[0]
    if t_stop is not None:
        t_stop[0] = t0
    if _bad_input(True, t0, t1, t_out, n, x_out):
        return 0, 0, 0, STATUS_BAD_INPUT

    rtol_v = np.zeros(n) + rtol
    atol_v = np.zeros(n) + atol
    if h_max <= 0.0:
        h_max = t1 - t0
    jac_every = max(jac_every, 1)
    x, x_new, f0, f_new, err, jac, ft, w, w_work, work = _workspace(x0, N_WORK)

    t = t0
    k_out = _land(t, x, t_out, x_out, 0)
    if t1 == t0:
        return 0, 0, 0, STATUS_OK

    rhs(t, x, p, tables, f0)
    if not (_all_finite(x) and _all_finite(f0)):
        _fill_nan_from(x_out, k_out)
        return 0, 0, 0, STATUS_NONFINITE
    ft_zero = _jacobians(t, x, p, tables, f0, jac, ft, work, t1, time_derivative, x_typ)
    n_jac = 1
    jac_current = True  # J was evaluated at the present (t, x)
    steps_since_jac = 0

    # Initial step (Hairer, Nørsett & Wanner 1993, Sec. II.4, first part of the starting rule).
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

    h_lu = 0.0  # step size the factors in w belong to (0: none)
    n_steps = 0
    n_rejected = 0
    rejected_last = False
    nonfinite_last = False  # the last attempt failed on a non-finite value or a singular W
    h_acc = 0.0  # last accepted step and its error norm (predictive controller)
    err_acc = 1.0
    status = STATUS_OK
    while t < t1:
        if n_steps + n_rejected >= max_steps:
            status = STATUS_MAX_STEPS
            break
        target = t_out[k_out] if (k_out < n_out and not dense) else t1
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

        if h_lu == 0.0 or h_try > REUSE_RATIO * h_lu or h_try * REUSE_RATIO < h_lu:
            if factor(jac, h_try, w, w_work) != 0:
                h_lu = 0.0
                n_rejected += 1
                h = 0.5 * h_try
                rejected_last = True
                nonfinite_last = True
                continue
            h_lu = h_try

        step(t, h_try, t_new, x, f0, ft, h_lu, p, tables, w, x_new, err, work)
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
            if dense:
                while k_out < n_out and t_out[k_out] < t_new:
                    _hermite(t, h_try, x, f0, x_new, f_new, t_out[k_out], x_out[k_out])
                    k_out += 1
            t = t_new
            for i in range(n):
                x[i] = x_new[i]
                f0[i] = f_new[i]
            n_steps += 1
            k_out = _land(t, x, t_out, x_out, k_out)
            steps_since_jac += 1
            if steps_since_jac >= jac_every:
                ft_zero = _jacobians(t, x, p, tables, f0, jac, ft, work, t1, time_derivative, x_typ)
                n_jac += 1
                steps_since_jac = 0
                jac_current = True
                h_lu = 0.0
            else:
                jac_current = False
                if time_derivative == FT_EVERY_STEP and not ft_zero and t < t1:
                    _fd_time_derivative(t, x, p, tables, f0, ft, work[0], t1)
            if enorm == 0.0:
                fac = _FAC_MAX
            else:
                fac = min(_FAC_MAX, max(_FAC_MIN, _error_factor(enorm, EXPONENT)))
            if PREDICTIVE and h_acc > 0.0:
                # Gustafsson's predictive controller (Hairer & Wanner 1996, eq. IV.8.25)
                e_cl = max(enorm, 1e-10)
                fac_g = _SAFETY * (h_try / h_acc) * (err_acc / (e_cl * e_cl)) ** EXPONENT
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
            nonfinite_last = False
        else:
            n_rejected += 1
            if finite:
                h = h_try * max(_FAC_MIN, _error_factor(enorm, EXPONENT))
            else:
                h = h_try * _FAC_NONFINITE
            if not jac_current:
                ft_zero = _jacobians(t, x, p, tables, f0, jac, ft, work, t1, time_derivative, x_typ)
                n_jac += 1
                steps_since_jac = 0
                jac_current = True
            h_lu = 0.0
            rejected_last = True
            nonfinite_last = not finite
            if not finite and h <= 8.0 * _EPS * max(abs(t), abs(t1)):
                status = STATUS_NONFINITE
                break

    if t_stop is not None:
        t_stop[0] = t
    if status != STATUS_OK:
        _fill_nan_from(x_out, k_out)
    return n_steps, n_rejected, n_jac, status


def _fixed(x0, t0, t1, h, t_out, p, tables, x_out, jac_every, time_derivative=FT_EVERY_STEP):
    """Template of ``fixed``: equal steps of at most ``h`` between consecutive stops.

    The method is the bound ``step``, ``factor`` and ``N_WORK``; the parameters, the returns
    and the behaviour are those of :func:`rollerrig.solve.ros34pw.ros34pw2_fixed`.

    Returns
    -------
    n_steps, n_jac, status : int
        Steps taken, Jacobian evaluations [-] and the status.
    """
    n = x0.shape[0]
    n_out = t_out.shape[0]
    if _bad_input(h > 0.0, t0, t1, t_out, n, x_out):
        return 0, 0, STATUS_BAD_INPUT
    jac_every = max(jac_every, 1)
    x, x_new, f0, _, err, jac, ft, w, w_work, work = _workspace(x0, N_WORK)

    t = t0
    n_steps = 0
    n_jac = 0
    h_lu = 0.0
    since_jac = 0
    ft_zero = True
    status = STATUS_OK
    k_out = _land(t, x, t_out, x_out, 0)
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
                ft_zero = _jacobians(t, x, p, tables, f0, jac, ft, work, t1, time_derivative, None)
                n_jac += 1
                since_jac = 0
                h_lu = 0.0
            elif time_derivative == FT_EVERY_STEP and not ft_zero:
                _fd_time_derivative(t, x, p, tables, f0, ft, work[0], t1)
            if hs != h_lu:
                if factor(jac, hs, w, w_work) != 0:
                    status = STATUS_NONFINITE
                    break
                h_lu = hs
            step(t, hs, t_new, x, f0, ft, h_lu, p, tables, w, x_new, err, work)
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
        k_out = _land(t, x, t_out, x_out, k_out)
    if status != STATUS_OK:
        _fill_nan_from(x_out, k_out)
    return n_steps, n_jac, status


# ---------------------------------------------------------------------------------------------
# Binding
# ---------------------------------------------------------------------------------------------
class Method(NamedTuple):
    """A linearly implicit W-method for the drivers.

    Attributes
    ----------
    name : str
        Short name (part of the compiled functions' names).
    step : function
        Template of the step ``step(t, h, t_new, x, f0, ft, h_w, p, tables, w, x_new, err,
        work)``: a plain function that calls the global ``rhs`` (bound with it).
    factor : numba dispatcher
        ``factor(jac, h, w, w_work) -> int``, 0 on success.
    n_work : int
        Rows of scratch space ``step`` needs (at least 2) [-].
    reuse_ratio : float
        The factors of ``W`` built for ``h_w`` are reused for a step ``h`` while ``h_w/h`` lies
        in ``[1/reuse_ratio, reuse_ratio]`` [-].
    exponent : float
        Error exponent of the controller, 1/(embedded order + 1) [-].
    predictive : bool
        Limit the step factor by Gustafsson's prediction (Hairer & Wanner 1996, eq. IV.8.25).
    """

    name: str
    step: Callable
    factor: Callable
    n_work: int
    reuse_ratio: float
    exponent: float
    predictive: bool


class Driver(NamedTuple):
    """The drivers compiled for one right-hand side and one method (see :func:`bind`).

    The functions take the arguments of the templates ``_fd_jacobian``, ``_fd_time_derivative``,
    ``_jacobians``, the method's step, ``_integrate`` and ``_fixed`` (those of the public
    functions without ``rhs``); without a method the last three are None. ``integrate``
    releases the GIL: independent runs go on threads
    (:func:`rollerrig.solve._threads.run_each`).
    """

    rhs: Callable
    fd_jacobian: Callable
    fd_time_derivative: Callable
    jacobians: Callable
    step: Callable | None
    integrate: Callable | None
    fixed: Callable | None


_NAMED: dict[str, tuple] = {}


def _compiled_copy(template, namespace, suffix, cached, **options):
    """A numba dispatcher of a copy of ``template`` whose globals are ``namespace``."""
    fn = types.FunctionType(template.__code__, namespace, template.__name__, template.__defaults__)
    fn.__kwdefaults__ = template.__kwdefaults__
    fn.__qualname__ = f"{template.__qualname__}__{suffix}"
    fn.__module__ = template.__module__
    fn.__doc__ = template.__doc__
    if cached:
        return _cache.njit(fn, **options)
    dispatcher = numba.njit(**options)(fn)
    _cache._compile_at_opt_level(dispatcher)
    return dispatcher


@functools.cache
def bind(rhs, method: Method | None = None, name: str | None = None) -> Driver:
    """Compile the driver templates for the right-hand side ``rhs`` (and a method).

    Parameters
    ----------
    rhs : numba dispatcher
        Right-hand side ``rhs(t, x, p, tables, dx)``.
    method : Method, optional
        The W-method of ``step``, ``integrate`` and ``fixed``; without it
        only the finite differences are bound.
    name : str, optional
        Cache the compiled code on disk under this name (:mod:`rollerrig.solve._cache`), for
        the package's own models, whose sources are part of the cache key. One name, one
        right-hand side and method per process. Unnamed bindings are compiled once per process.

    Returns
    -------
    Driver
        The compiled functions (compiled on their first call).
    """
    if name is not None:
        if not name.isidentifier():
            raise ValueError(f"a driver name must be an identifier, got {name!r}")
        if _NAMED.setdefault(name, (rhs, method)) != (rhs, method):
            raise ValueError(f"a driver named {name!r} is bound to another right-hand side")
    suffix = "_".join(filter(None, (method.name if method else "fd", name or "bound")))
    cached = name is not None
    ns = dict(globals())
    ns["rhs"] = rhs

    def copy(template, namespace, **options):
        fn = _compiled_copy(template, namespace, suffix, cached, **options)
        namespace[template.__name__] = fn
        return fn

    fd_jac = copy(_fd_jacobian, ns)
    fd_time = copy(_fd_time_derivative, ns)
    jacobians = copy(_jacobians, ns)
    if method is None:
        return Driver(rhs, fd_jac, fd_time, jacobians, None, None, None)
    step_ns = dict(method.step.__globals__)
    step_ns["rhs"] = rhs
    ns.update(
        step=copy(method.step, step_ns),
        factor=method.factor,
        N_WORK=method.n_work,
        REUSE_RATIO=method.reuse_ratio,
        EXPONENT=method.exponent,
        PREDICTIVE=method.predictive,
    )
    integrate = copy(_integrate, ns, nogil=True)
    fixed = copy(_fixed, ns)
    return Driver(rhs, fd_jac, fd_time, jacobians, ns["step"], integrate, fixed)
