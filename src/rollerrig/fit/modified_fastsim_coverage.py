"""Whether the data constrain A and B of a modified-FASTSIM fit: its slip-velocity coverage.

The :class:`~rollerrig.fit.diagnostics.SlipVelocityCoverage` of
:func:`rollerrig.fit.modified_fastsim.fit_modified_fastsim`, with the criteria and thresholds of
:mod:`rollerrig.fit.diagnostics` (those of the Polach fit); only the sensitivity of a point's
CoA to μ differs, taken numerically since the modified FASTSIM has no closed form. A helper of
the fit: no public names.
"""

from __future__ import annotations

import numpy as np

from rollerrig.fit import diagnostics as _diag
from rollerrig.fit.diagnostics import SlipVelocityCoverage
from rollerrig.fit.modified_fastsim_model import PARAMETER_UPPER, coa_kernel

__all__: list[str] = []


def _coverage(s, w, q, y, theta, model, best_cost, cost_with, ab_problems, n_ref, a, b, g, nu,
              grid) -> SlipVelocityCoverage:  # fmt: skip
    """The A/B coverage of :mod:`rollerrig.fit.diagnostics` for the modified FASTSIM.

    The sensitivity of a point's CoA to μ is taken numerically, η = d ln CoA / d ln μ0 (central
    difference, ±1 %); the peak and the falling branch from the fitted law at the median
    rolling speed; criteria and thresholds those of :mod:`rollerrig.fit.diagnostics`.
    """
    aw = np.abs(w)
    h = 0.01
    up, dn = model(theta, 1.0 + h), model(theta, 1.0 - h)
    base = model(theta)
    with np.errstate(divide="ignore", invalid="ignore"):
        eta = np.where(np.abs(base) > 0, (up - dn) / (2.0 * h * base), 0.0)
    saturated = eta >= _diag._SATURATION_SENSITIVITY
    n_sat = int(np.sum(saturated))
    sat_range = (float(aw[saturated].min()), float(aw[saturated].max())) if n_sat else None
    bb = float(theta[5])
    reached = 1.0 - float(np.exp(-bb * sat_range[1])) if sat_range else 0.0
    nz = np.abs(s) > 0
    ok = saturated & nz
    v = np.abs(w[ok] / s[ok]) if np.any(ok) else np.abs(w[nz] / s[nz])
    speed_ratio = float(np.percentile(v, 90) / np.percentile(v, 10)) if v.size else 1.0
    v_med = float(np.median(v)) if v.size else 1.0
    s_max = float(np.max(np.abs(s)))
    grid_s = np.linspace(s_max / 400, 2 * s_max, 400)
    curve = coa_kernel(grid_s, grid_s * v_med, n_ref, a, b, g, nu, theta, grid)
    at = int(np.argmax(curve))
    peak = float(grid_s[at])
    past_peak = s_max / peak
    reach = _diag.past_peak_words(past_peak, "modified-FASTSIM", at == grid_s.size - 1)
    # Past the peak: the fitted CoA falls with creep at the point's own rolling speed.
    xi_eq = s * np.cbrt(n_ref / q)
    hh = 1e-3
    c_up = coa_kernel(xi_eq * (1 + hh), w * (1 + hh), n_ref, a, b, g, nu, theta, grid)
    c_dn = coa_kernel(xi_eq * (1 - hh), w * (1 - hh), n_ref, a, b, g, nu, theta, grid)
    falling = int(np.sum(np.sign(s) * (c_up - c_dn) < 0))
    reasons = []
    if n_sat < _diag._MIN_SATURATED_POINTS:
        reasons.append(
            f"only {n_sat} point(s) where the contact saturates (CoA at least half proportional "
            f"to mu), {_diag._MIN_SATURATED_POINTS} needed"
        )
    if reached < 0.5:
        reasons.append(
            f"the saturated points reach {100 * reached:.0f} % of mu's fall from mu0 to A mu0 "
            f"(B w_max = {bb * (sat_range[1] if sat_range else 0.0):.3g}, "
            f"{_diag._MIN_FRICTION_FALL:.3g} needed): slip velocities too small for A"
        )
    if speed_ratio < _diag._MIN_SPEED_RATIO and past_peak < _diag._MIN_PAST_PEAK:
        reasons.append(
            f"one rolling speed (the saturated points' median {v_med:.3g} m/s, "
            f"{3.6 * v_med:.3g} km/h; 90/10 percentile ratio {speed_ratio:.2f}, "
            f"{_diag._MIN_SPEED_RATIO:g} needed) and {reach} "
            f"({_diag._MIN_PAST_PEAK:g} needed): with w = v s the fall of mu(w) trades "
            "with the curve's shape (k0, alpha_inf, beta)"
        )
    rise = {}
    if cost_with is not None and n_sat >= _diag._MIN_SATURATED_POINTS and bb > 0:
        aa = float(theta[4])
        trials = [
            ("B/4", 2, bb / _diag._PROFILE_FACTOR),
            ("4B", 2, min(bb * _diag._PROFILE_FACTOR, float(PARAMETER_UPPER[5]))),
            (f"A-{_diag._PROFILE_A_STEP:g}", 1, aa - _diag._PROFILE_A_STEP),
            (f"A+{_diag._PROFILE_A_STEP:g}", 1, aa + _diag._PROFILE_A_STEP),
        ]
        for label, index, value in trials:
            if index == 1 and not 0.0 < value <= 1.0:
                continue
            cost = cost_with(index, value)
            rise[label] = (cost - best_cost) / best_cost if best_cost > 0 else float("inf")
        flat = [lbl for lbl, r in rise.items() if not r > _diag._PROFILE_COST_RISE]
        if flat:
            reasons.append(
                "the data hardly feel A and B: fixing "
                + " or ".join(
                    f"{lbl} raises the cost by {_diag._percent(rise[lbl])} %" for lbl in flat
                )
                + f" (more than {100 * _diag._PROFILE_COST_RISE:.0f} % needed)"
            )
    elif cost_with is None:
        reasons.append("profile check of A and B not made (profile=False)")
    reasons.extend(ab_problems)
    rise = {k: (float(r) if np.isfinite(r) else None) for k, r in rise.items()}
    return SlipVelocityCoverage(
        slip_velocity_range=(float(aw.min()), float(aw.max())),
        saturated_points=n_sat,
        saturated_slip_velocity_range=sat_range,
        falling_branch_points=falling,
        rolling_speed_ratio=speed_ratio,
        creep_past_peak=past_peak,
        friction_fall_reached=reached,
        profile_cost_rise=rise,
        a_and_b_identifiable=not reasons,
        reasons=tuple(reasons),
    )
