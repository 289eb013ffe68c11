"""Fast backend: the compiled model integrated segment by segment, by ETDRK4 or ROS34PW2.

The default method is the exponential integrator ETDRK4 (:mod:`rollerrig.solve.etdrk4`): the
stator mounts and the contact exact, classical RK4 on the rest, a fixed step per protocol
segment set by the explicit part's stability, the adaptive ROS34PW2 W-method
(:mod:`rollerrig.solve.ros34pw`) as the fallback of a segment it cannot take (near standstill,
a ramp to or from standstill, or where its step-error guard trips: at a quarter step, or near
standstill at the full step), at a tolerance no looser than ``FAST_DEFAULTS["fallback_rtol"]``;
``method="ros34pw2"`` runs ROS34PW2 throughout. One compiled call runs an experiment (every
protocol segment, with its own friction parameters, up to the one that holds the last output
instant: nothing after it is integrated), except that a segment ETDRK4
leaves to its fallback returns to Python, which runs ROS34PW2's driver on it and resumes (so
ROS34PW2 compiles only when a run first needs it); :func:`integrate_batch` runs many
variants of it in parallel threads (the same compiled driver, which releases the GIL), for
sweeps. The drivers are compiled once and then loaded from the on-disk cache
(:mod:`rollerrig.solve._cache`; :func:`is_compiled` says whether a run will compile). A
failure is a status, not an exception: the stats give it with the simulated time reached and
:func:`failure_reason` says what failed and what to try.
"""

from __future__ import annotations

import numpy as np

from rollerrig._validation import require_instants_within
from rollerrig.rig.model import (
    N_STATES,
    P_VOLTAGE_LIMITED,
    SEGMENT_NODES,
    X_FRAME_V,
    X_ID,
    X_IQ,
    X_OMEGA,
    X_THETA,
    lowest_speed_setpoint,
    segment_tables,
    speed_setpoint_bounds,
    start_solver_copy,
)
from rollerrig.solve import _cache, _cold_start, etdrk4
from rollerrig.solve import _wdriver as _wd
from rollerrig.solve._compiled import RIG
from rollerrig.solve._threads import run_each, thread_rows
from rollerrig.solve.ros34pw import (
    DEFAULT_MAX_STEPS,
    FT_NONE,
    STATUS_BAD_INPUT,
    STATUS_MAX_STEPS,
    STATUS_NONFINITE,
    STATUS_OK,
    STATUS_STEP_UNDERFLOW,
)

__all__ = [
    "CURRENTS_EXACT_ABOVE",
    "FAST_DEFAULTS",
    "IDEAL_SPEED_EXP_STEP",
    "METHODS",
    "SWEEP_EXP_STEP",
    "SWEEP_H_MAX",
    "default_exp_step",
    "default_tolerances",
    "dq_tolerances",
    "failure_reason",
    "integrate_batch",
    "integrate_experiment",
    "is_compiled",
    "needs_fallback",
    "sweep_settings",
]

METHODS = ("etdrk4", "ros34pw2")
"""Methods of the fast backend: the exponential integrator (default) and the W-method."""

FAST_DEFAULTS = {
    "method": "etdrk4",
    "rtol": 1e-5,
    "angle_atol": 1e-6,
    "h_max": 0.9e-3,
    "jac_every": 100,
    "exp_step": 1.6e-3,
    "relinearise": 16,
    "exp_error": 0.007,
    "fallback_rtol": 1e-7,
}
"""Default settings of the fast backend: the method (:data:`METHODS`); for ROS34PW2 (also the
fallback of ETDRK4) the relative tolerance [-], absolute tolerance of the angles [rad], largest
step [s] and Jacobian refresh interval [accepted steps]; for ETDRK4 the largest fixed step
``exp_step`` [s] (shorter where the explicit part's stability needs it), the interval of the
contact block's re-linearisation ``relinearise`` [steps], the step-error guard ``exp_error``
[N.m] and ``fallback_rtol`` [-], the loosest relative tolerance of its fallback.

**The fallback's tolerance** (``fallback_rtol``). ETDRK4 hands ROS34PW2 only what it cannot
take: ramps of the roller to or from standstill (:data:`STOP_SPEED`) and macro-slip its guard
catches. There ROS34PW2 at its own default (1e-5) was off by more than the hard case's
0.2 N.m, an error of its tolerance, not of the model: max |ΔT56| against Radau at rtol 1e-11
(2026-11-30), ROS34PW2 at 1e-5 / 1e-6 / 1e-7 as ETDRK4's fallback:

- from standstill to 5 km/h under 200 N.m: 0.46 / 0.26 / 0.10 N.m (swings of 1 100 N.m);
- the slip reversal followed by a stop (tests/solve/test_simulation.py): 0.59 / 0.56 / 0.13;
- 3 km/h to standstill under 200 N.m: 0.11 / 0.0065 / 0.0048;
- the macro-slip ramps at 5 and 7.5 km/h below: 0.058 / 0.060 / 0.042 and 0.054 / 0.052 /
  0.034.

At 1e-7 those runs cost 1.3-2 times as much (the fallback's segments twice as many steps);
runs without a fallback segment (the default test, the hard case) are unchanged. The fallback
takes the tighter of ``rtol`` and this.

ROS34PW2's were chosen for max |ΔT56| <= 0.1 N.m: on the bundled 30 s dry experiment at 250 Hz
output 0.075 N.m against Radau at rtol 1e-10 (``python benchmarks/run.py``), an error set by
``h_max`` (third order: 2, 1, 0.9, 0.8 ms give 0.86, 0.103, 0.075, 0.053 N.m), the phase drift
of the lightly damped 13.8 Hz shaft mode ringing for seconds after a torque release. ETDRK4 is
of fourth order, with the stiff mounts and contact exact: at ``exp_step`` 1.6 ms (0.4 ms with
the ideal speed source: :data:`IDEAL_SPEED_EXP_STEP`) max |ΔT56| is 0.027 N.m on that
experiment (1.33 and 1 ms: 0.014 and 0.005 N.m; the issue's target 0.05),
0.084 N.m on a pulse to 1 400 N.m at 20 kN and 10 km/h, where the contact's pole reaches
−12 000 1/s. Re-linearising the contact every 1, 4, 8, 16 or 32 steps gives the same to
3e-3 N.m (0.0854, 0.0843, 0.0837, 0.0818, 0.0817 N.m on that pulse; 0.0274, 0.0270, 0.0272,
0.0275, 0.0284 on the 30 s test; never 0.50); every 16 by default. A re-linearisation (two
right-hand sides and the block's φ-functions) costs about 0.74 µs, four to five steps' right-hand
sides: every 16 steps 5.6 % of the default solve. Every 32 would be 2.4 % faster, and was as
accurate (Radau at rtol 1e-9, max |ΔT56|) on the pulse (0.0855 -> 0.0857 N.m), the macro-slip
ramps below at 5, 10 and 30 km/h (0.076 -> 0.069, 0.084 -> 0.052, 0.047 -> 0.046), a load drop
from 20 to 4.3 kN in 10 ms under 1 400 N.m with the default, dq + flexible-frame and modified
FASTSIM drives and the 10 km/h wet test, but not with the ideal speed source on that load drop
(0.29 -> 0.43 N.m, a segment to the fallback), so it is not the default (2026-11-30). A segment
shorter than two intervals (an input's fast transition) re-linearises every step: a load step
from 20 to 4.3 kN in 10 ms under 1 400 N.m at 10 km/h was off by 2.5 N.m linearised once, 0.076
so. The step
actually taken is shorter where RK4's stability on the rest needs it (1.6 ms is about that
limit on the default rig, set by the PMSM current loops); ``python benchmarks/run.py`` prints
these figures.

**The step-error guard** (``exp_error``, N.m). ETDRK4's step is fixed per segment: its
accuracy above is what was measured, not a tolerance, and through macro-slip at low speed it
does not hold. A torque ramp from −900 to +900 N.m at 4.3 kN, past the adhesion limit in
braking and in traction, then released, gave max |ΔT56| 5.5, 4.7, 2.8, 0.41 and 0.035 N.m at
5, 7.5, 10, 15 and 30 km/h against Radau at rtol 1e-9 (at 20 kN 0.08-0.48), and with the roller
then decelerated to standstill 15 N.m; re-linearising every step did not cure it (4.95 N.m at
5 km/h). Each step therefore estimates its own error in T56, classical RK4's embedded
third-order estimate on the roller shaft's twist (``etdrk4._step_error``, no extra
right-hand side). A step whose estimate exceeds ``exp_error`` is rejected, and the segment
goes on from the last accepted state at a shorter step, 1.25, 2 and 4 times shorter in turn
(:data:`GUARD_STEP_DIVISORS`, away from standstill), back to the longer step once 64
estimates in a row say it would pass there (``etdrk4.GROW_AFTER``); where the shortest step
is rejected too, the segment goes to ROS34PW2, whose error is controlled.

Measured (2026-11-30, max |ΔT56| against Radau at rtol 1e-9/1e-10), with 0.007 N.m and the
step halved on a trip (the shorter steps of :data:`GUARD_STEP_DIVISORS` since 2026-12-01: the
same on 16 of 17 hostile protocols; on the macro-slip ramp at 7.5 km/h 0.056 where halving
gave 0.034):

- the default test, the hard case and the other validated cases keep every segment at the
  full step (the largest estimates: 0.0023 N.m on the default test, 0.0018 on the hard case);
- the macro-slip ramps at 4.3 kN: 0.058, 0.054, 0.059, 0.015 and 0.028 N.m at 5, 7.5, 10, 15
  and 30 km/h (one or two of five segments at a halved step, one by ROS34PW2 at 5 and
  7.5 km/h; with the fallback at ``fallback_rtol`` 0.042 and 0.034 there); at 20 kN
  0.029-0.064 N.m, every segment at the full step. Since 2026-12-02, the shorter step only
  as long as the estimates need it: 0.042, 0.070, 0.071, 0.022 and 0.030 N.m at 4.3 kN in
  4 491, 2 541, 2 483, 2 480 and 2 437 steps (ETDRK4's and, at 5 km/h, ROS34PW2's on one
  segment; 7.5 km/h no longer needs the fallback) where the whole segments at the shorter
  steps took 8 736, 9 083, 7 811, 7 871 and 4 791 for 0.042, 0.056, 0.059, 0.015 and 0.028;
  at 20 kN unchanged;
- a sweep of the roller shaft's stiffness (43.5-143.5 kN.m/rad) and the motor's lag
  (0-0.36 s) on the bundled test, 24 variants: at most 0.061 N.m, 14 with the ringing after
  each release at half the step, none by ROS34PW2 (at 1.25 times shorter, 2026-12-01: 17
  variants, 28 % fewer steps on each, still at most 0.061 N.m; since 2026-12-02 the shorter
  step only while the shaft rings, :data:`GUARD_STEP_DIVISORS`). With 0.01 N.m and no halving
  (before), the stiffest shafts' ringing went to ROS34PW2, off by 0.25-0.31 N.m at its
  defaults, and a variant the guard passed was off by 0.105 N.m;
- the slip reversal followed by a stop to standstill (tests/solve/test_simulation.py):
  0.60 N.m, two segments by ROS34PW2 at its default tolerance; 0.13 with three segments by
  ROS34PW2 at ``fallback_rtol`` 1e-7, the default since. That is no defect of ETDRK4:
  ROS34PW2 alone is off by as much there (0.60 at its defaults, 0.56 at rtol 1e-6, 0.14 at
  1e-7; Radau 1e-9 against 1e-10: 1e-5). It grows through the deceleration and the second
  after the stop, where the speeds of the roller and its motor stay within 0.5 rad/s of zero
  (the bearings' friction in its tanh regularisation) and T56 swings between −80 and +260 N.m
  in the lightly damped 13.8 Hz shaft mode: the error is that mode's phase, about 0.2 % of
  the swing.

``exp_error=0`` turns the guard off.
"""

SWEEP_H_MAX = 2e-3
"""ROS34PW2's largest step in sweeps [s] (``method="ros34pw2"``; ETDRK4's sweeps take
:func:`sweep_settings`): about twice the throughput of its default at max |ΔT56| <= 1.2 N.m
(0.86-1.1 N.m on the bundled experiment), but 2.4 N.m with a roller shaft 3.3 times stiffer
(``python benchmarks/run.py``'s sweep, 2026-11-30)."""

SWEEP_EXP_STEP = 2.2e-3
"""ETDRK4's step in sweeps [s] (:func:`sweep_settings`), with the PMSM's currents exact
(:data:`CURRENT_BLOCKS`), for sweeps' accuracy of 0.1 N.m of T56 (issue 20) where a single run
is held to 0.05. On the benchmark's sweep (24 variants: the roller shaft's stiffness
43.5-143.5 kN.m/rad times four motor lags; max |ΔT56| against Radau 1e-10 over the default
variant and the stiffest shaft's four; 2026-12-03): 15 444 steps a run on average against
19 080 at the default settings, at 0.083 N.m against 0.051 (2 ms: 16 208 steps, 0.076 N.m;
the step-error guard shortens the step while the stiffer shafts ring after each release, on
every variant); in a full ``python benchmarks/run.py`` 203.9 runs/s on two threads against
186.6 at the default settings. On 4.3 kN pulses against Radau 1e-9: a flexible frame 0.094
N.m, the servo roller drive 0.092, the wheel's PMSM at its voltage limit 0.071 (such segments
are integrated again at a single run's settings: :func:`_integrate_exp`). Not within 0.1 N.m:
the hard case (20 kN, 10 km/h, 1 400 N.m), 0.233 N.m against 0.079 at the default settings.
Beyond 2.2 ms the error grows past the sweeps' 0.1 N.m on the sweep (2.4 ms: up to 0.109,
measured 2026-12-02)."""


def sweep_settings(h_max: float | None = None) -> dict:
    """Keyword arguments of :func:`integrate_batch` for a sweep's runs (:mod:`rollerrig.studies`,
    ``python benchmarks/run.py``): ETDRK4 with the PMSM's currents exact and a longer step
    (:data:`SWEEP_EXP_STEP`), a sweep's accuracy (0.1 N.m of T56) rather than a single run's
    (0.05); at the PMSM's voltage limit a single run's settings (:data:`CURRENT_BLOCKS`).

    Parameters
    ----------
    h_max : float, optional
        A cap of the step [s] (a study file's ``solver.h_max``); it also caps the step of
        ROS34PW2, which takes the segments ETDRK4 leaves (its default otherwise).

    Examples
    --------
    >>> sweep_settings()
    {'sweep': True, 'h_max': None}
    """
    return {"sweep": True, "h_max": h_max}


def default_tolerances(
    rtol: float, angle_atol: float | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Per-state (rtol, atol) vectors for the rig state.

    The angles are absolute (hundreds of rad after a test), so a relative tolerance on them
    would allow twist errors of ~1e-3 rad (tens of N.m on the roller shaft): they get rtol 0 and
    an absolute tolerance in rad. The other states get ``rtol`` and an absolute tolerance on
    their own scale (speeds in rad/s, currents in A, torques in N.m, integrals).
    """
    angle_atol = 0.1 * rtol if angle_atol is None else angle_atol
    rt = np.full(N_STATES, rtol)
    at = np.empty(N_STATES)
    rt[0:7] = 0.0
    at[0:7] = angle_atol  # [rad]
    at[7:14] = rtol  # speeds [rad/s]
    at[14:16] = 100.0 * rtol  # currents [A]
    at[16:18] = 0.1 * rtol  # PI integrals [A.s]
    at[18] = 100.0 * rtol  # lagged drive torque [N.m]
    at[19] = 0.1 * rtol  # speed-error integral [rad]
    at[20] = 1e-6 * rtol  # frame displacement [m]: tens of µm under the contact force
    at[21] = 1e-4 * rtol  # frame velocity [m/s]
    return rt, at


def dq_tolerances(rtol: float, angle_atol: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Per-state (rtol, atol) vectors for the state of the rig with the dq roller drive
    (:mod:`rollerrig.rig.model_dq`): :func:`default_tolerances` for the rig's 22 states, then
    the fluxes (about 1 Wb at the rated point: an absolute tolerance of 0.01 ``rtol`` Wb), the
    controller's filtered currents (100 ``rtol`` A, as the PMSM currents) and filtered slip
    (``rtol`` rad/s, as the speeds)."""
    rt, at = default_tolerances(rtol, angle_atol)
    return np.concatenate([rt, np.full(7, rtol)]), np.concatenate(
        [at, [0.01 * rtol] * 4, [100.0 * rtol] * 2, [rtol]]
    )


_DENSE = True
"""Output by cubic Hermite interpolation inside the steps (the step is free of the output grid)."""

_LANDING_TOLERANCE = 1e-12
"""Relative distance [-] below which a sample instant counts as a segment's start instant."""


_STATUS_REASONS = {
    STATUS_MAX_STEPS: (
        f"it took more than {DEFAULT_MAX_STEPS:,} steps in one protocol segment (the model is "
        "extremely stiff or oscillates very fast there)"
    ),
    STATUS_STEP_UNDERFLOW: (
        "the step size fell to the rounding level of the time (the model is too stiff or "
        "discontinuous there)"
    ),
    STATUS_NONFINITE: "the state or its derivative became NaN or infinite",
    STATUS_BAD_INPUT: "the output times or array shapes are inconsistent (a bug: please report)",
}
_HINT = (
    "check the rig parameters (an inertia, radius or load near zero, a very large stiffness, "
    "damping or controller gain) or try the reference solver (solver='reference', "
    "--solver reference)"
)


def failure_reason(status: int, t_stop: float) -> str:
    """What failed, at which simulated time and what to try, for a status of this backend.

    Examples
    --------
    >>> print(failure_reason(2, 0.0123))  # doctest: +ELLIPSIS
    at t = 0.0123 s the step size fell to the rounding level ...; check the rig parameters ...
    """
    what = _STATUS_REASONS.get(int(status), f"it stopped with status {int(status)}")
    return f"at t = {t_stop:.6g} s {what}; {_HINT}"


# rig_rhs and ROS34PW2 are bound into RIG.integrate (module-level global), so that this driver
# is cached on disk like every other compiled function (_cache).
_rig_integrate = RIG.integrate


@_cache.njit
def _segment_window(t_out, k, t0, t1, x, x_out):
    """The output rows of the segment ``[t0, t1]`` from row ``k``: ``(k, k_end, ts)``.

    The rows due at the segment's start get its start state ``x`` (also a sample instant a
    rounding error after ``t0``: a protocol duration summed from steps, 5.039999999999999 s
    against the 250 Hz sample at 5.04 s, is the start state; integrating to it would ask for a
    step of one ulp); rows ``k..k_end - 1`` lie inside the segment, and ``ts`` holds their
    times followed by ``t1``, which is always integrated to so that the next segment starts
    from the exact end state.
    """
    n_out = t_out.shape[0]
    while k < n_out and t_out[k] <= t0 + _LANDING_TOLERANCE * max(1.0, abs(t0)):
        _wd._store_row(x_out, k, x)
        k += 1
    k_end = k
    while k_end < n_out and t_out[k_end] <= t1:
        k_end += 1
    m = k_end - k
    ts = np.empty(m + 1)
    for i in range(m):
        ts[i] = t_out[k + i]
    ts[m] = t1
    return k, k_end, ts


# nogil: integrate_batch runs one variant per Python thread, in parallel.
@_cache.njit(nogil=True)
def _integrate(
    x0, bounds, params, tables, t_out, rtol, atol, h_max, jac_every, x_out, stats, t_stop
):
    n_out = t_out.shape[0]
    x = x0.copy()
    k = 0
    t_stop[0] = bounds[0, 0]
    while k < n_out and t_out[k] <= bounds[0, 0]:
        _wd._store_row(x_out, k, x)
        k += 1
    status = STATUS_OK
    local = np.empty((tables.shape[0], SEGMENT_NODES))
    for s in range(bounds.shape[0]):
        t0 = bounds[s, 0]
        t1 = bounds[s, 1]
        k, k_end, ts = _segment_window(t_out, k, t0, t1, x, x_out)
        m = k_end - k
        xs = np.empty((m + 1, x.shape[0]))
        seg_tables = local if segment_tables(tables, t0, t1, local) else tables
        # f_t is left out: it enters ROS34PW2 at O(h^4) and did not change T56 on the rig.
        n_steps, n_rej, n_jac, status = _rig_integrate(
            x,
            t0,
            t1,
            ts,
            params[s],
            seg_tables,
            rtol,
            atol,
            0.0,
            h_max,
            jac_every,
            xs,
            DEFAULT_MAX_STEPS,
            FT_NONE,
            None,
            t_stop,
            _DENSE,
        )
        stats[0] += n_steps
        stats[1] += n_rej
        stats[2] += n_jac
        if status != STATUS_OK:
            _wd._fill_nan_from(x_out, k)
            return status
        _wd._copy_rows(x_out, k, xs, m)
        x = xs[m].copy()
        k = k_end
    return status


_exp_workspace, _exp_prepare, _exp_segment = etdrk4.bind(RIG, "rig")


GUARD_STEP_DIVISORS = (1.25, 2.0, 4.0)
"""Where a step of ETDRK4 trips the step-error guard, it is rejected and its segment goes on
from the last accepted state at the segment's step divided by these, in turn, before it goes
to the fallback (ROS34PW2); after ``etdrk4.GROW_AFTER`` steps in a row whose error estimates
would pass at the next longer step (scaled by the steps' ratio to the fourth power and by
``etdrk4.GROW_SAFETY``), back to it. Only where the roller's speed set point stays at or above
:data:`RETRY_MIN_SPEED` throughout the segment.

Until 2026-12-01 a trip sent the whole segment back to its start at the shorter step: on the
sweep's stiffest shafts the ringing tripped the guard 9-23 steps after each release, and the
rest of the 5.5-6.5 s segment, long after the ringing had died away, ran at 1.28 ms. Going
back to the full step once the estimates allow (2026-12-02, the 8 variants of the two
stiffest shafts, against Radau 1e-10): 19 330 steps on average where there had been 21 530,
at most 0.051 N.m off where there had been 0.050; with a factor of 2 instead of 8 on the
scaled estimate, 18 850 steps but 0.0996 N.m.

On a roller shaft 3.3 times stiffer (143.5 kN.m/rad) the ringing after each release tripped the
guard at 1.6 ms; ROS34PW2 at its default tolerance was then off by 0.31 N.m against Radau
1e-10, ETDRK4 at 0.8 ms by 0.007 N.m, in fewer right-hand sides (2026-11-30). The first rung,
1.28 ms, is enough there: on the 24 variants of the sweep in ``benchmarks/run.py`` (43.5-143.5
kN.m/rad, motor lags 0-0.36 s) the 17 variants whose ringing tripped the guard took 21 500
steps at 1.25 where halving took 29 700, at most 0.050 N.m off (halving: 0.0073); every
variant at most 0.061 N.m (2026-12-01). The last rung is the 0.4 ms that two halvings
reached before."""

_GUARD_DIVISORS = np.array((1.0, *GUARD_STEP_DIVISORS))
_GUARD_RUNGS = len(GUARD_STEP_DIVISORS)

RETRY_MIN_SPEED = 1.0
"""Lowest roller speed set point [m/s] (3.6 km/h, 20 times the creep's and the bearings'
regularisation speeds at the roller's tread) over a segment for the shorter steps above.
Through a stop (the roller ramped from 5 km/h to standstill after a slip reversal) the guard
passed ETDRK4 at a halved step with T56 off by 43 N.m, and a shorter fixed step did not converge
there (0.8, 0.4, 0.2 ms: 216, 5.6, 16 N.m; 0.1 ms: 0.83), where ROS34PW2 at its defaults is
off by 0.6 N.m. That ramp now goes to the fallback before any attempt (:data:`STOP_SPEED`, its
cause); the shorter steps stay off near standstill, where the bearings' tanh friction and the
creep's regularisation can stiffen the right-hand side within a segment as well, unseen by
the stability estimate at its start (not measured apart from the stop, 2026-11-30)."""


STOP_SPEED = 0.01
"""A segment that ramps the roller's speed set point to, from or through below this [m/s] (a
ramp down to standstill, or up from it) goes to the fallback. As the open-loop V/f drive's supply
frequency goes to 0 its torque's gradient in the rotor's speed grows without bound (the slip
is relative to the synchronous speed), at the ramp's end or start, where the stability
estimate at the segment's start does not look (at a set point of 0 the supply is off and
there is no such gradient). Measured against Radau at rtol 1e-11 (2026-11-30):

- decelerated from 3 km/h to standstill under 200 N.m and held: ETDRK4 was off by 5.4 N.m
  (at 0.4 ms 6.4, re-linearised every step 5.4) with the step-error guard silent;
- accelerated from standstill to 5 km/h under 200 N.m (the supply off until then, so the
  wheel's torque had turned the roller and its motor ahead of the set point): ETDRK4 at
  ``exp_step`` 0.8 ms was off by 10.3 N.m with the guard silent (at 1.6 ms the guard
  tripped; without it 64 N.m), and converged only below 0.2 ms (0.0145 N.m at 0.2 ms).
"""


@_cache.njit
def _stops(tables, t0, t1):
    """True where the roller's speed set point ramps to or from below :data:`STOP_SPEED`
    between ``t0`` and ``t1`` (also through a breakpoint inside, as a replayed recording's
    set point may)."""
    lo, hi = speed_setpoint_bounds(tables, t0, t1)
    return lo < STOP_SPEED and hi > lo


def needs_fallback(inputs) -> bool:
    """True when ETDRK4 will hand a segment of this experiment to its fallback, ROS34PW2,
    whatever the solution: a ramp of the roller to or from standstill (:data:`STOP_SPEED`). The
    step-error guard's trips are known only by running. The CLI says so before ROS34PW2's
    first compilation (about 10 s once per install), which would otherwise stall a run."""
    return any(_stops.py_func(inputs.tables, s.start, s.end) for s in inputs.segments)


# A segment ETDRK4 leaves to its fallback ends the compiled driver with this status and the
# place to resume from; the Python wrapper (_with_fallback) runs ROS34PW2 on that segment and
# resumes. So ROS34PW2's driver is compiled only when a run first needs it, not as a callee of
# every ETDRK4 run: 7-10 s of a cold start's compilation, and the default experiment and most
# others never need it (issue 20).
STATUS_FALLBACK = -1


@_cache.njit(nogil=True)
def _integrate_exp(
    x0, bounds, params, tables, t_out, x_out, stats, t_stop, resume, memo,
    exp_step, relinearise, static_blocks, dynamic_blocks, err_weights, err_limit,
):  # fmt: skip
    """:func:`_integrate` with ETDRK4, from segment ``resume[0]`` and output row ``resume[1]``
    (``x0`` the state at that segment's start). Returns :data:`STATUS_FALLBACK` where a segment
    needs ROS34PW2, with ``resume`` set to it (its outputs before the segment's start landed),
    else :data:`STATUS_OK`."""
    n_out = t_out.shape[0]
    x = x0.copy()
    k = resume[1]
    s_first = resume[0]
    if s_first == 0:
        t_stop[0] = bounds[0, 0]
        while k < n_out and t_out[k] <= bounds[0, 0]:
            _wd._store_row(x_out, k, x)
            k += 1
    ws = _exp_workspace(x.shape[0], static_blocks, dynamic_blocks)
    n_static = static_blocks.shape[0]
    # The PMSM's currents taken exactly (1 x 1 blocks, a sweep's runs: CURRENT_BLOCKS) hold
    # only below its voltage limit: a segment that meets the limit is integrated again as a
    # single run integrates it (without them, at a single run's step, with its own stability
    # memo, memo[2:]), and by the fallback where that fails too; so is the segment after one
    # that met it (a wheel at high speed meets it in every segment, which then took twice a
    # single run's steps). Taken exactly past the limit, a wheel spinning up under 1 400 N.m
    # at 60 km/h was off by 1.84 N.m with the step-error guard silent (2026-12-03). An
    # abandoned attempt's steps stay counted in the stats (not its shortened segment).
    n_plain = 0
    for b in range(n_static):
        if static_blocks[b, 1] >= 0:
            n_plain += 1
    exact_currents = n_plain < n_static
    plain = np.empty((n_plain, static_blocks.shape[1]), dtype=np.int64)
    q = 0
    for b in range(n_static):
        if static_blocks[b, 1] >= 0:
            plain[q] = static_blocks[b]
            q += 1
    ws_plain = _exp_workspace(x.shape[0], plain, dynamic_blocks) if exact_currents else ws
    memo_plain = memo[2:] if exact_currents else memo[:2]
    step_plain = min(exp_step, CURRENTS_EXACT_ABOVE) if exact_currents else exp_step
    limited = False  # the segment before met the voltage limit
    # Each input's piece over the segment: the right-hand side's three table look-ups without
    # a bisection (model.segment_tables).
    local = np.empty((tables.shape[0], SEGMENT_NODES))
    for s in range(s_first, bounds.shape[0]):
        t0 = bounds[s, 0]
        t1 = bounds[s, 1]
        k, k_end, ts = _segment_window(t_out, k, t0, t1, x, x_out)
        m = k_end - k
        xs = np.empty((m + 1, x.shape[0]))
        seg_tables = local if segment_tables(tables, t0, t1, local) else tables
        done = -1
        if not _stops(tables, t0, t1):
            # Shorter steps where the step-error guard trips, only away from standstill.
            rungs = _GUARD_RUNGS if lowest_speed_setpoint(tables, t0, t1) >= RETRY_MIN_SPEED else 0
            exact = exact_currents and not limited
            if exact:
                params[s, P_VOLTAGE_LIMITED] = 0.0
                shortened = stats[4]
                steps = _exp_prepare(x, t0, t1, params[s], seg_tables, exp_step, n_static, ws, memo)
                if steps > 0 and params[s, P_VOLTAGE_LIMITED] == 0.0:
                    done = _exp_segment(
                        t0, t1, steps, ts, params[s], seg_tables, relinearise, n_static, ws, xs,
                        stats, err_weights, err_limit, _GUARD_DIVISORS, rungs,
                    )  # fmt: skip
                if params[s, P_VOLTAGE_LIMITED] != 0.0:  # at the limit: again, as a single run
                    exact = False
                    done = -1
                    stats[4] = shortened
            if not exact:
                params[s, P_VOLTAGE_LIMITED] = 0.0
                n_kept = plain.shape[0]  # an array's extent: the driver's own type (no literal)
                steps = _exp_prepare(
                    x, t0, t1, params[s], seg_tables, step_plain, n_kept, ws_plain, memo_plain
                )
                if steps > 0:
                    done = _exp_segment(
                        t0, t1, steps, ts, params[s], seg_tables, relinearise, n_kept,
                        ws_plain, xs, stats, err_weights, err_limit, _GUARD_DIVISORS, rungs,
                    )  # fmt: skip
            limited = exact_currents and params[s, P_VOLTAGE_LIMITED] != 0.0
        if done != 0:
            resume[0] = s
            resume[1] = k
            for j in range(x.shape[0]):
                x0[j] = x[j]
            return STATUS_FALLBACK
        t_stop[0] = t1
        _wd._copy_rows(x_out, k, xs, m)
        x = xs[m].copy()
        k = k_end
    return STATUS_OK


def _will_compile(dispatcher) -> bool:
    """True when calling ``dispatcher`` would compile it: neither loaded in this process nor
    in the on-disk cache."""
    return not dispatcher.signatures and not _cache.is_cached(dispatcher)


def _with_fallback(exp_driver, ros_driver, settings, notify=None):
    """The ETDRK4 driver with ROS34PW2 on the segments it leaves (``stats[3]`` counts them),
    taking :func:`_integrate`'s arguments; ``notify(message)`` is told before ROS34PW2
    compiles (its first use on an installation: 10-20 s in which the run seems to stall).

    The last stability estimate (``memo``, :func:`rollerrig.solve.etdrk4._prepare`) is kept
    across the calls of one bound driver: across a fallback's resume, and across the
    per-segment calls of :func:`integrate_experiment`'s progress path, which so takes the same
    steps as one call (a segment within ``STABILITY_RECHECK`` of the last estimate reuses it).
    One bound driver serves one run (:func:`_bound_driver`).
    """
    memo = np.zeros(4)  # [:2] the run's, [2:] a sweep's segments without the currents' blocks

    def integrate(x0, bounds, params, tables, t_out, rt, at, h_max, jac_every, x_out, stats,
                  t_stop):  # fmt: skip
        x = np.array(x0, dtype=float)  # the compiled driver leaves a fallback's start state here
        resume = np.zeros(2, dtype=np.int64)
        while True:
            status = exp_driver(
                x, bounds, params, tables, t_out, x_out, stats, t_stop, resume, memo, *settings
            )
            if status != STATUS_FALLBACK:
                return status
            s = int(resume[0])
            # The compiled driver landed the segment's start rows: this only finds its rows.
            k, k_end, ts = _segment_window(t_out, int(resume[1]), *bounds[s], x, x_out)
            chunk = np.empty((ts.size, x.size))
            stats[3] += 1
            if notify is not None and _will_compile(ros_driver):
                notify(
                    f"the segment from t = {bounds[s, 0]:g} s goes to the fast solver's "
                    "fallback (ROS34PW2), which compiles now for this installation "
                    "(once: 10-20 s)"
                )
            start_solver_copy(params[s])  # as ROS34PW2 alone would start the segment
            status = ros_driver(
                x, bounds[s : s + 1], params[s : s + 1], tables, ts, rt, at, h_max, jac_every,
                chunk, stats, t_stop,
            )  # fmt: skip
            x_out[k:k_end] = chunk[:-1]
            if status != STATUS_OK:
                x_out[k_end:] = np.nan
                return status
            x = chunk[-1].copy()
            resume[0] = s + 1
            resume[1] = k_end
            if s + 1 == bounds.shape[0]:
                return STATUS_OK

    return integrate


_DQ: dict[str, object] = {}


def _uses_dq(inputs) -> bool:
    """True for the roller drive ``"induction_dq"`` (the model of :mod:`rollerrig.rig.model_dq`)."""
    return inputs.drives.roller == "induction_dq"


def _dq_drivers():
    """``(_integrate, _integrate_exp)`` bound to the dq model (:data:`_compiled_dq.RIG_DQ`).

    Copies of the two drivers above whose globals ``_rig_integrate``, ``_exp_workspace``,
    ``_exp_prepare`` and ``_exp_segment`` are the dq model's, built (and compiled, or loaded
    from the cache) only when the dq drive is first used.
    """
    if not _DQ:
        from rollerrig.solve._compiled_dq import RIG_DQ

        ns = dict(globals())
        ns["_rig_integrate"] = RIG_DQ.integrate
        ns["_exp_workspace"], ns["_exp_prepare"], ns["_exp_segment"] = etdrk4.bind(RIG_DQ, "rig_dq")
        ns["_wd"] = _wd
        single = _wd._compiled_copy(_integrate.py_func, ns, "rig_dq", True, nogil=True)
        single_exp = _wd._compiled_copy(_integrate_exp.py_func, ns, "rig_dq", True, nogil=True)
        _DQ["single"], _DQ["single_exp"] = single, single_exp
    return _DQ["single"], _DQ["single_exp"]


def _ros34pw2_rtol(rtol, code):
    """ROS34PW2's relative tolerance [-]: ``rtol`` (default :data:`FAST_DEFAULTS`), and as
    ETDRK4's fallback (method code 0) no looser than ``FAST_DEFAULTS["fallback_rtol"]``."""
    rtol = FAST_DEFAULTS["rtol"] if rtol is None else rtol
    return min(rtol, FAST_DEFAULTS["fallback_rtol"]) if code == 0 else rtol


def _settings(rtol, h_max, jac_every, angle_atol, dq=False):
    """Tolerance vectors and step settings, defaults from :data:`FAST_DEFAULTS`."""
    rtol = FAST_DEFAULTS["rtol"] if rtol is None else rtol
    if angle_atol is None:  # scale the angle tolerance with rtol
        angle_atol = FAST_DEFAULTS["angle_atol"] * rtol / FAST_DEFAULTS["rtol"]
    rt, at = (dq_tolerances if dq else default_tolerances)(rtol, angle_atol)
    h_max = FAST_DEFAULTS["h_max"] if h_max is None else h_max
    jac_every = FAST_DEFAULTS["jac_every"] if jac_every is None else jac_every
    return rt, at, h_max, jac_every


_STATIC_BLOCKS = np.array(
    [[X_THETA + 0, X_OMEGA + 0, -1], [X_THETA + 6, X_OMEGA + 6, -1]], dtype=np.int64
)
"""ETDRK4's constant linear blocks: the PMSM and AM stator mounts, (θ1, ω1) and (θ7, ω7)."""

CURRENT_BLOCKS = np.array([[X_ID, -1, -1], [X_IQ, -1, -1]], dtype=np.int64)
"""The PMSM's currents ``i_d``, ``i_q`` as ETDRK4's 1 x 1 static blocks in a sweep's runs
(``sweep=True``, :func:`sweep_settings`): each current's own term of its current loop,
``−(k_p + R_s)/L`` (−1 337 1/s on the default rig; the loop's pole ``−k_p/L`` is
−1 257 1/s), is linear and constant below the drive's voltage limit, where it is taken once
per segment, so that RK4's stability no longer holds the step at the loops' poles (1.77 ms with
the margin; the wheel shaft's 112 Hz mode is next, at about 3 ms). At the voltage limit it is
not (−490 to −740 1/s on a wheel spinning up at 60 km/h, −1 054 to −1 453 and up to +345 at
120 km/h, with d-q cross terms): the model flags a solver's parameters
(``rollerrig.rig.model.P_VOLTAGE_LIMITED``) and a segment that meets the limit, and the one
after it, is integrated again without these blocks at a single run's step
(:func:`_integrate_exp`; taken exactly past the limit a wheel spinning up under 1 400 N.m at
60 km/h had been off by 1.84 N.m, with the step-error guard silent). Applied as scalars (not
as padded rows of the blocks: :func:`rollerrig.solve.etdrk4._block_rows`), they cost about 3 %
of a step (the default solve 10.89 against 10.59 ms at 1.6 ms; as padded rows 7 %,
2026-12-03). Not the default: at a
single run's accuracy the longer step they allow is not much longer (0.0445 N.m at 1.77 ms,
0.074 at 2 ms on the bundled test, against 0.0275 at 1.6 ms without them). With their PI
integrals in the blocks, ``(i_q, I_q)``, the error grew fourfold. Not added with the ideal
speed source (its 0.4 ms step is below the loops' limit) nor the ideal torque source (no
currents)."""


IDEAL_SPEED_EXP_STEP = 0.4e-3
"""ETDRK4's largest step [s] with the ideal speed source as the roller drive (``"ideal_speed"``),
where ``exp_step`` is not given. With the roller's motor held on its set point, the ringing of
the roller and the wheel after a release is hardly damped (on the bundled 30 s test T56 swings
by ±1 100 N.m, still ±350 N.m 6 s later; the open-loop drive's slip damps it within a second),
and an error of its phase grows as long as it rings: after 5.5 s the speeds of wheel and roller
were off by 1e-4 rad/s and the shaft's twist by 8e-6 rad, a frequency error of about 4e-6 of
the 3.8 Hz ringing, some 200 times what classical RK4 alone would make of that mode at 1.6 ms.
Its cause is not found (the roller's twist θ5 taken into the contact block, exact, made it
worse: 0.99 N.m with three segments halved). The step-error guard does not see it: its
estimates are local (summed over the run 2.1 N.m with this drive, 1.8 with the default drive,
whose error is 15 times smaller), and a local estimate does not tell a damped error from one
that stays. Max |ΔT56|
against Radau at rtol 1e-10 (2026-11-30) at 1.6 / 0.8 / 0.4 ms: the bundled test 0.41 / 0.038
/ 0.0030 N.m; the hard case (20 kN, 10 km/h, 1 400 N.m) 0.66 / 0.22 / 0.045; the macro-slip
ramp at 5 km/h 0.41 / 0.096 / 0.017 (ROS34PW2 at its defaults: 0.072, 0.008 and 4.4). At
0.4 ms the bundled test costs about four times the default drive's solve, less than
ROS34PW2's."""


CURRENTS_EXACT_ABOVE = FAST_DEFAULTS["exp_step"]
"""A single run's step [s], at which the current loops do not limit RK4's stability: a sweep's
run takes the currents exactly only at a longer step, and integrates a segment at the PMSM's
voltage limit at this one (:func:`_integrate_exp`)."""


def default_exp_step(inputs, sweep: bool = False) -> float:
    """ETDRK4's largest step [s] for ``inputs`` where none is given: ``FAST_DEFAULTS["exp_step"]``
    (:data:`SWEEP_EXP_STEP` for a sweep's run), :data:`IDEAL_SPEED_EXP_STEP` with the ideal
    speed source as the roller drive (a sweep's too: its ringing is hardly damped)."""
    if inputs.drives.roller == "ideal_speed":
        return IDEAL_SPEED_EXP_STEP
    return SWEEP_EXP_STEP if sweep else FAST_DEFAULTS["exp_step"]


def _exp_settings(inputs, method, exp_step, relinearise, h_max, exp_error=None, sweep=False):
    """``(method code, step [s], relinearise [steps], static blocks, dynamic blocks, error
    weights, error limit [N.m])``.

    The dynamic block is the contact's (ω4, ω5), with a flexible frame (ω4, ω5, v_f). The
    static blocks are the stator mounts' (:data:`_STATIC_BLOCKS`) and, for a ``sweep``'s run
    with the PMSM as the wheel drive, the currents' (:data:`CURRENT_BLOCKS`).
    An explicit ``h_max`` caps ETDRK4's step as well. The error weights make a step's error
    estimate one of T56 (the roller shaft's twist θ5 − θ6 times its stiffness; the same states
    in the dq model, whose first states are the rig's).
    """
    method = FAST_DEFAULTS["method"] if method is None else method
    if method not in METHODS:
        from rollerrig._validation import ParameterError

        raise ParameterError(f"method must be one of {METHODS}, got {method!r}")
    step = default_exp_step(inputs, sweep) if exp_step is None else float(exp_step)
    if h_max is not None:
        step = min(step, float(h_max))
    relinearise = FAST_DEFAULTS["relinearise"] if relinearise is None else int(relinearise)
    contact = [X_OMEGA + 3, X_OMEGA + 4, -1]
    if inputs.drives.frame != "rigid":
        contact[2] = X_FRAME_V
    dynamic = np.array([contact], dtype=np.int64)
    limit = FAST_DEFAULTS["exp_error"] if exp_error is None else float(exp_error)
    weights = np.zeros(inputs.initial_state.size)
    k56 = float(inputs.rig.stiffness.roller_shaft)
    weights[X_THETA + 4], weights[X_THETA + 5] = k56, -k56
    code = METHODS.index(method)
    static = _STATIC_BLOCKS
    if sweep and inputs.drives.wheel == "pmsm" and step > CURRENTS_EXACT_ABOVE:
        static = np.vstack([_STATIC_BLOCKS, CURRENT_BLOCKS])
    return code, step, max(1, relinearise), static, dynamic, weights, limit


def _needed_segments(segments, t_out):
    """The segments up to the one holding the last output instant (all where ``t_out`` is
    empty), which is as far as a run need integrate: a run asked for its first seconds, or a
    warm-up call of 10 ms, does not integrate the rest of the experiment. ``t_out`` has been
    validated (:func:`rollerrig._validation.require_instants_within`); an instant on a
    boundary between two segments is the first one's end."""
    if t_out.size == 0:
        return segments
    starts = np.array([s.start for s in segments])
    return segments[: max(1, int(np.searchsorted(starts, t_out[-1], side="left")))]


def _output_instants(inputs, t_out):
    """``t_out`` validated against the experiment's span (a clear error, not uninitialised
    rows past its end or a silent reorder) and the segments it needs."""
    segments = inputs.segments
    t_out = require_instants_within("t_out", t_out, segments[0].start, segments[-1].end)
    return np.ascontiguousarray(t_out), _needed_segments(segments, t_out)


def _segment_arrays(segments):
    bounds = np.array([[s.start, s.end] for s in segments], dtype=float)
    params = np.stack([s.params for s in segments])
    start_solver_copy(params)  # the run's own copy: the arm's loop carries its root in it
    return bounds, params


def _stats(counts, status, t_stop, method="ros34pw2") -> dict:
    status = int(status)
    out = {
        "method": method,
        "accepted_steps": int(counts[0]),
        "rejected_steps": int(counts[1]),
        "jacobians": int(counts[2]),
        "status": status,
        "t_stop": float(t_stop),
    }
    if method == "etdrk4":
        out["fallback_segments"] = int(counts[3])
        out["shortened_segments"] = int(counts[4])
    if status != STATUS_OK:
        out["reason"] = failure_reason(status, float(t_stop))
    return out


def is_compiled(dq: bool = False, method: str | None = None) -> bool:
    """True when the compiled driver is in the on-disk cache, so a run loads it (a fraction
    of a second) instead of compiling it (for the default driver 25-40 s on 2 cores, part of it
    in a helper process on the second core: :mod:`rollerrig.solve._cold_start`; once per
    install; ROS34PW2's, ETDRK4's fallback, compiles when a run first needs it: about 10 s
    more). :func:`integrate_batch` runs the same driver as :func:`integrate_experiment`.

    Parameters
    ----------
    dq : bool
        Ask about the drivers of the model with the dq roller drive (``"induction_dq"``).
    method : {"etdrk4", "ros34pw2"}, optional
        The method whose driver to ask about (default :data:`FAST_DEFAULTS`).
    """
    return _cache.is_cached(_driver(dq, METHODS.index(method or FAST_DEFAULTS["method"])))


def _driver(dq: bool, code: int):
    """The compiled driver of the method ``METHODS[code]``, of the dq model with ``dq``."""
    single, single_exp = _dq_drivers() if dq else (_integrate, _integrate_exp)
    return single_exp if code == 0 else single


def _bound_driver(inputs, method, exp_step, relinearise, h_max, exp_error=None, notify=None,
                  sweep=False):  # fmt: skip
    """``(driver, method code)``: the driver for ``inputs`` with ETDRK4's settings bound, so
    that both methods take ROS34PW2's arguments (``notify``: :func:`_with_fallback`). Where
    ETDRK4's driver is neither compiled nor cached, it is compiled now with a helper process on
    a second core (:mod:`rollerrig.solve._cold_start`; once a process and model)."""
    settings = _exp_settings(inputs, method, exp_step, relinearise, h_max, exp_error, sweep)
    code = settings[0]
    dq = _uses_dq(inputs)
    driver = _driver(dq, code)
    if code != 0:
        return driver, code
    _cold_start.compile_in_parallel(inputs, settings[1:], dq, lambda: _will_compile(driver))
    return _with_fallback(driver, _driver(dq, 1), settings[1:], notify), code


def _cold_start_helper():
    """The entry of :mod:`rollerrig.solve._cold_start`'s helper process."""
    _cold_start.helper_main(_segment_window, _STATIC_BLOCKS)


def integrate_experiment(
    inputs,
    t_out,
    rtol=None,
    h_max=None,
    jac_every=None,
    angle_atol=None,
    progress=None,
    method=None,
    exp_step=None,
    relinearise=None,
    exp_error=None,
    notify=None,
    sweep=False,
):
    """Integrate one experiment with the fast backend.

    Parameters
    ----------
    inputs : ModelInputs
        From :func:`rollerrig.rig.assemble.assemble`.
    t_out : ndarray
        Output times [s], finite, not decreasing, within the experiment's span (a
        :class:`~rollerrig._validation.ParameterError` otherwise). The run integrates only as
        far as the protocol segment that holds the last of them.
    rtol : float, optional
        ROS34PW2's relative tolerance (per-state absolute tolerances follow from it); as
        ETDRK4's fallback it is no looser than ``FAST_DEFAULTS["fallback_rtol"]``.
    angle_atol : float, optional
        Absolute tolerance of the angles [rad]; default scaled with ``rtol``.
    h_max : float, optional
        Largest step [s].
    jac_every : int, optional
        Jacobian refresh interval in accepted steps.
    progress : callable, optional
        ``progress(t_reached, t_end)`` [s], called after each smooth segment of the protocol
        (the compiled driver then runs segment by segment; the result is the same to the bit,
        since every segment starts its integration afresh anyway); ``t_end`` is the end of the
        segment that holds the last output instant.
    method : {"etdrk4", "ros34pw2"}, optional
        The integrator (:data:`METHODS`; default :data:`FAST_DEFAULTS`). ``rtol``,
        ``angle_atol``, ``h_max`` and ``jac_every`` are ROS34PW2's (ETDRK4's fallback);
        an explicit ``h_max`` also caps ETDRK4's step.
    exp_step : float, optional
        ETDRK4's largest step [s] (default :func:`default_exp_step`: 1.6 ms, 0.4 ms with the
        ideal speed source).
    relinearise : int, optional
        ETDRK4 re-linearises the contact block every this many steps [-].
    exp_error : float, optional
        ETDRK4's step-error guard [N.m]: a step whose error estimate of T56 exceeds it is
        rejected (``rejected_steps``) and its segment goes on at a shorter step
        (``shortened_segments``; 1.25, 2 and 4 times shorter in turn, away from standstill,
        back to the longer step once the estimates allow: :data:`GUARD_STEP_DIVISORS`); where
        the shortest is rejected too, ROS34PW2 takes the segment (``fallback_segments``); 0
        turns the guard off.
    notify : callable, optional
        ``notify(message)``: told when a segment goes to ROS34PW2 whose driver is not compiled
        yet (its first use on this installation: 10-20 s in which nothing seems to happen).
        Which segments need it is known only by running them (the step-error guard).
    sweep : bool, optional
        A sweep's run (default False; :func:`sweep_settings`): held to a sweep's accuracy
        (0.1 N.m of T56) rather than a single run's (0.05), for 1.2 times fewer steps. Its step
        is :data:`SWEEP_EXP_STEP` where ``exp_step`` is not given (:func:`default_exp_step`),
        and where that step exceeds 1.6 ms ETDRK4 takes the PMSM's currents exactly
        (:data:`CURRENT_BLOCKS`), so that the current loops' stability no longer holds it;
        a protocol segment where the PMSM meets its voltage limit, and the one after it, are
        integrated at a single run's settings instead.

    Returns
    -------
    x_out : ndarray, shape (len(t_out), n_states)
        States (``N_STATES``, or :data:`rollerrig.rig.model_dq.N_DQ_STATES` with the roller
        drive ``"induction_dq"``, whose model :func:`_dq_drivers` compiles on first use);
        NaN from the first output time the integration did not reach.
    stats : dict
        ``method``, ``accepted_steps``, ``rejected_steps``, ``jacobians`` (linearisations
        with ETDRK4; with ``sweep``, a segment's attempt abandoned at the voltage limit
        included), ``status`` (0: success), ``t_stop`` (the simulated time reached [s]: on
        a success the end of the segment that holds the last output instant),
        with ETDRK4 ``fallback_segments`` (segments ROS34PW2 took) and ``shortened_segments``
        (segments the guard gave a shorter step in) and, on a failure,
        ``reason`` (:func:`failure_reason`).
    """
    t_out, segments = _output_instants(inputs, t_out)  # before a first run's compile
    integrate, code = _bound_driver(
        inputs, method, exp_step, relinearise, h_max, exp_error, notify, sweep
    )
    rtol = _ros34pw2_rtol(rtol, code)
    rt, at, h_max, jac_every = _settings(rtol, h_max, jac_every, angle_atol, _uses_dq(inputs))
    name = METHODS[code]
    n_states = inputs.initial_state.size
    bounds, params = _segment_arrays(segments)
    x_out = np.empty((t_out.size, n_states))
    counts = np.zeros(5, dtype=np.int64)
    t_stop = np.zeros(1)
    if progress is None:
        status = integrate(
            inputs.initial_state,
            bounds,
            params,
            inputs.tables,
            t_out,
            rt,
            at,
            h_max,
            jac_every,
            x_out,
            counts,
            t_stop,
        )
        return x_out, _stats(counts, status, t_stop[0], name)
    # Segment by segment, with the state carried over: the outputs up to each segment's end
    # (those of the first one from the start), as the single call lands them.
    x = np.ascontiguousarray(inputs.initial_state, dtype=float)
    t_end = float(bounds[-1, 1])
    k = 0
    status = 0
    for s in range(bounds.shape[0]):
        k_end = int(np.searchsorted(t_out, bounds[s, 1], side="right"))
        if s == bounds.shape[0] - 1:
            k_end = t_out.size
        chunk = np.empty((k_end - k + 1, n_states))
        # The segment's end as an extra output instant: the next segment starts from it.
        t_chunk = np.append(t_out[k:k_end], bounds[s, 1])
        status = integrate(
            x, bounds[s : s + 1], params[s : s + 1], inputs.tables, t_chunk, rt, at, h_max,
            jac_every, chunk, counts, t_stop,
        )  # fmt: skip
        x_out[k:k_end] = chunk[:-1]
        if status != 0:
            x_out[k_end:] = np.nan
            break
        x = chunk[-1].copy()
        k = k_end
        progress(min(float(bounds[s, 1]), t_end), t_end)
    return x_out, _stats(counts, status, t_stop[0], name)


def integrate_batch(
    inputs_list,
    t_out,
    rtol=None,
    h_max=None,
    jac_every=None,
    angle_atol=None,
    method=None,
    exp_step=None,
    relinearise=None,
    exp_error=None,
    sweep=False,
):
    """Integrate several variants of one experiment in parallel threads.

    Each variant is one call of the compiled driver of :func:`integrate_experiment` (which
    releases the GIL; a segment left to ETDRK4's fallback returns to Python for it), taken by
    the next free thread of ``numba.get_num_threads()`` (variants differ in cost: a stiffer
    shaft or no lag takes more steps, so fixed shares would leave a thread idle). No second,
    parallel driver is compiled.

    All variants must share the protocol (segments and tables); they differ in parameters and
    initial state, e.g. a sweep of roller-shaft stiffness and motor lag. A variant that fails
    does not stop the others: its stats say why and its states are NaN from where it stopped.

    Parameters
    ----------
    inputs_list : sequence of ModelInputs
        The variants (:func:`rollerrig.rig.assemble.assemble`).
    t_out, rtol, h_max, jac_every, angle_atol, method, exp_step, relinearise, exp_error, sweep
        As in :func:`integrate_experiment`; a sweep's: :func:`sweep_settings`.

    Returns
    -------
    x_out : ndarray, shape (n_variants, len(t_out), n_states)
    stats : list of dict
        Per variant, as in :func:`integrate_experiment`.
    """
    first = inputs_list[0]
    dq = _uses_dq(first)
    if any(_uses_dq(i) != dq for i in inputs_list):
        from rollerrig._validation import ParameterError

        raise ParameterError(
            "integrate_batch: the variants mix the roller drive 'induction_dq' with other "
            "roller drives (different models); run them in separate batches"
        )
    t_out, segments = _output_instants(first, t_out)  # before a first run's compile
    # Each variant's own settings: a flexible frame adds its velocity to the contact block.
    runs = [
        _bound_driver(i, method, exp_step, relinearise, h_max, exp_error, None, sweep)
        for i in inputs_list
    ]
    rtol = _ros34pw2_rtol(rtol, runs[0][1])
    rt, at, h_max_ros, jac_every = _settings(rtol, h_max, jac_every, angle_atol, dq)
    bounds, _ = _segment_arrays(segments)
    n_segments = len(segments)
    n = len(inputs_list)
    x_out = np.empty((n, t_out.size, first.initial_state.size))
    # Written while the runs go (the step counters every step): rows on cache lines of
    # their own, or two runs side by side share a line (_threads.thread_rows).
    counts = thread_rows(n, 5)
    t_stop = thread_rows(n, 1, float)
    status = np.zeros(n, dtype=np.int64)

    def run(k):
        params = _segment_arrays(inputs_list[k].segments[:n_segments])[1]
        status[k] = runs[k][0](
            np.ascontiguousarray(inputs_list[k].initial_state, dtype=float), bounds, params,
            first.tables, t_out, rt, at, h_max_ros, jac_every, x_out[k], counts[k], t_stop[k],
        )  # fmt: skip

    run_each(run, n)  # one Python thread per numba thread; Ctrl-C drops the rest
    name = METHODS[runs[0][1]]
    return x_out, [_stats(counts[k], status[k], t_stop[k, 0], name) for k in range(n)]
