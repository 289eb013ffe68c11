"""Reference backend: scipy's stiff solvers on the compiled right-hand side.

The trusted solution every other backend is checked against. It integrates segment by segment
between the protocol's breakpoints with an adaptive implicit method (Radau IIA, order 5, by
default), a Jacobian by finite differences of the compiled right-hand side, and tight
tolerances. ``python_rhs=True`` runs the plain Python model instead: that is the baseline a user
would write, used by the benchmarks.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from rollerrig._validation import ParameterError, did_you_mean, require_in_range
from rollerrig.rig import model as _model
from rollerrig.solve.fast import _output_instants, _uses_dq, default_tolerances, dq_tolerances

__all__ = ["METHODS", "integrate_reference"]

METHODS = ("Radau", "BDF", "LSODA")
"""The stiff methods of ``solve_ivp`` the reference backend takes."""


def integrate_reference(
    inputs,
    t_out,
    rtol: float = 1e-9,
    method: str = "Radau",
    python_rhs: bool = False,
    progress=None,
):
    """Integrate one experiment with scipy's ``solve_ivp``.

    Parameters
    ----------
    inputs, t_out
        Model inputs and output times [s], as in
        :func:`rollerrig.solve.fast.integrate_experiment`.
    rtol : float
        Relative tolerance; per-state absolute tolerances follow from it.
    method : str
        A stiff ``solve_ivp`` method: "Radau", "BDF" or "LSODA".
    python_rhs : bool
        Use the plain Python right-hand side and scipy's own finite-difference Jacobian (the
        baseline a user would write) instead of the compiled one.
    progress : callable, optional
        Called as ``progress(t_reached, t_end)`` after each segment (``t_end``: the end of
        the segment that holds the last output instant, as far as the run integrates).

    Returns
    -------
    x_out : ndarray, shape (len(t_out), n_states)
        States (29 with the roller drive ``"induction_dq"``, else 22).
    stats : dict
        ``rhs_evaluations``, ``jacobians``, ``status`` (0: success, else scipy's),
        ``t_stop`` (the simulated time reached [s]) and, on a failure, ``reason``.
    """
    # scipy's own errors named neither the parameter nor its range (rtol NaN: "array must
    # not contain infs or NaNs"); an explicit method would have taken a non-stiff one.
    rtol = require_in_range(
        "rtol", rtol, 1e-13, 0.1, "1", low_inclusive=True, high_inclusive=True, single=True
    )
    if not isinstance(method, str) or method not in METHODS:
        hint = did_you_mean(method, METHODS) if isinstance(method, str) else ""
        raise ParameterError(
            f"method must be one of {METHODS} (stiff solve_ivp methods), got {method!r}{hint}"
        )
    if progress is not None and not callable(progress):
        raise ParameterError(f"progress must be a callable or None, got {progress!r}")
    t_out, segments = _output_instants(inputs, t_out)
    dq = _uses_dq(inputs)  # the roller drive "induction_dq": the model of rig.model_dq
    _, at = (dq_tolerances if dq else default_tolerances)(rtol, 0.1 * rtol)
    n_states = inputs.initial_state.size
    tables = inputs.tables
    if python_rhs:
        if dq:
            from rollerrig.rig.model_dq import rig_dq_rhs as rhs_impl
        else:
            rhs_impl = _model.rig_rhs
        jac_factory = None
    else:
        if dq:
            from rollerrig.solve._compiled_dq import RIG_DQ as RIG
        else:
            from rollerrig.solve._compiled import RIG

        rhs_impl = RIG.rhs
        fd_jacobian = RIG.fd_jacobian  # bound to the compiled model, cached on disk

        def jac_factory(p):
            jac = np.empty((n_states, n_states))
            f0 = np.empty(n_states)
            work = np.empty((2, n_states))

            def jac_fun(t, x):
                rhs_impl(t, x, p, tables, f0)
                fd_jacobian(t, x, p, tables, f0, jac, work)
                return jac.copy()

            return jac_fun

    x = inputs.initial_state.copy()
    x_out = np.full((t_out.size, n_states), np.nan)
    k = 0
    while k < t_out.size and t_out[k] <= inputs.segments[0].start:
        x_out[k] = x
        k += 1
    nfev = njev = 0
    status = 0
    t_stop = inputs.segments[0].start
    reason = None
    for seg in segments:
        p = seg.params

        def fun(t, y, p=p):
            dy = np.empty(n_states)
            rhs_impl(t, y, p, tables, dy)
            return dy

        k_end = int(np.searchsorted(t_out, seg.end, side="right"))
        inner = t_out[k:k_end]
        ends_on_sample = inner.size > 0 and inner[-1] == seg.end
        t_eval = inner if ends_on_sample else np.concatenate([inner, [seg.end]])
        sol = solve_ivp(
            fun,
            (seg.start, seg.end),
            x,
            method=method,
            t_eval=t_eval,
            rtol=rtol,  # scipy takes one relative tolerance; per-state atol below
            atol=at,
            jac=None if jac_factory is None else jac_factory(p),
        )
        nfev += sol.nfev
        njev += sol.njev
        t_stop = float(sol.t[-1]) if sol.t.size else seg.start
        if sol.status != 0:
            status = sol.status
            reason = (
                f"at t = {t_stop:.6g} s scipy's {method} stopped: {sol.message}; check the rig "
                "parameters (an inertia, radius or load near zero, a very large stiffness, "
                "damping or controller gain)"
            )
            break
        x_out[k:k_end] = sol.y[:, : k_end - k].T
        x = sol.y[:, -1].copy()
        k = k_end
        if progress is not None:
            progress(seg.end, segments[-1].end)
    stats = {"rhs_evaluations": nfev, "jacobians": njev, "status": status, "t_stop": t_stop}
    if reason is not None:
        stats["reason"] = reason
    return x_out, stats
