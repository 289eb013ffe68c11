"""The uncertainty of an analysed test, per phase and per point of the creep–CoA curve.

:func:`coa_budget` takes the corrected CoA with its per-sample uncertainty
(:func:`rollerrig.estimation.uncertainty.corrected_coa_uncertainty`) and the analysis's phases
and branches, and gives:

- per phase: the rig's and the corrected CoA (phase means), the expanded uncertainty (k = 2)
  of the phase mean, the typical (median) and largest per-sample U, and the budget (each
  input's contribution |c_i| u(x_i), median over the phase's samples; for the phase mean,
  each input's contribution to its u), with the dominant input;
- per point of the creep–CoA curve (the ascending and descending branches, one sample per
  correction window, so that the points' random errors are nearly independent): creep and its
  uncertainty, the rig's and the corrected CoA, u and U (LPU), the JCGM 101 Monte Carlo mean,
  u and 95 % interval, and the JCGM 101 §8 validation of the LPU there;
- with a truth (synthetic recordings): how often the band covers the true contact CoA.

Everything in :meth:`CoaBudget.summary` is finite or ``None`` with its reason.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rollerrig.estimation.choice import uniform_rate
from rollerrig.estimation.filterweights import (
    BandedFilter,
    after_encoder_speed,
    savitzky_golay_matrix,
)
from rollerrig.estimation.montecarlo import MonteCarloResult, jcgm101_validation, monte_carlo
from rollerrig.estimation.uncertainty import CoaUncertainty, noise_level
from rollerrig.signal.smoothing import savitzky_golay

__all__ = ["MC_DRAWS", "MC_MAX_POINTS", "CoaBudget", "coa_budget", "creep_uncertainty"]

MC_DRAWS = 100_000
"""Monte Carlo draws per curve point in an analysis (10 runs of 10⁴, fixed M, JCGM 101 §7.2)."""

MC_MAX_POINTS = 100
"""Most curve points the Monte Carlo runs at; above it every k-th point (the others: LPU)."""


@dataclass
class CoaBudget:
    """The uncertainty tables of an analysed test (see the module docstring).

    Attributes
    ----------
    uncertainty : CoaUncertainty
        Per-sample value, u and contributions.
    phases : list of dict
    points : list of dict
    monte_carlo : MonteCarloResult or None
    validation : dict or None
        :func:`rollerrig.estimation.uncertainty.jcgm101_validation` at the points.
    truth_coverage : dict or None
    online_coa : ndarray or None
        The online estimator's CoA on the analysis axis, when it ran.
    model_coa : dict
        The two-sided model-based estimates (:func:`rollerrig.estimation.estimator.
        smooth_contact_torque`) on the analysis axis: name -> (CoA, description).
    model_choice : tuple of str
        (name in ``model_coa``, why) of the model-based estimate to trust
        (:func:`rollerrig.estimation.estimator.choose_smoother`); empty when none was made.
    notes : list of str
    """

    uncertainty: CoaUncertainty
    phases: list
    points: list
    monte_carlo: MonteCarloResult | None = None
    validation: dict | None = None
    truth_coverage: dict | None = None
    online_coa: np.ndarray | None = None
    model_coa: dict = field(default_factory=dict)
    model_choice: tuple = ()
    notes: list = field(default_factory=list)

    def summary(self) -> dict:
        """JSON-ready: model, inputs, phases, points, Monte Carlo, validation, truth coverage."""
        unc = self.uncertainty
        out = {
            "method": "JCGM 100 law of propagation per sample (sensitivity coefficients, "
            "covariances of calibrated parameters), U = k u with k = 2; JCGM 101 Monte Carlo "
            "at the creep–CoA points, validated by JCGM 101 §8",
            "model": "mu = F_x / N + e_res, F_x = (T56 + dT + e_T + J5 (alpha5 + e_alpha) + "
            "k_b b (W_r + S + W_d)) / (r_r - kappa k_b b), N = S + W_d + kappa F_x, "
            "S = (p + dp + e_p) A, b = f_g r_b tanh(omega5/omega_reg), kappa = sigma h/l",
            "coverage_factor": unc.coverage_factor,
            "inputs": [inp.as_dict() for inp in unc.inputs],
            "typical": self.typical(),
            "phases": self.phases,
            "curve_points": self.points,
            "monte_carlo": None if self.monte_carlo is None else self.monte_carlo.as_dict(),
            "validation": self._validation_summary(),
            "truth_coverage": self.truth_coverage,
            "notes": list(unc.notes) + list(self.notes),
        }
        if self.model_choice:
            out["model_based_estimate"] = {
                "name": self.model_choice[0],
                "why": self.model_choice[1],
            }
        if self.monte_carlo is None:
            out["monte_carlo_null_because"] = "no creep–CoA points (no branches)"
        if self.truth_coverage is None:
            out["truth_coverage_null_because"] = "no truth given (a real recording)"
        return out

    def typical(self) -> dict:
        """The median U (k = 2) over the test and over the branch points, the dominant input."""
        unc = self.uncertainty
        load = float(np.median(unc.terms.normal_load))
        out = {
            "normal_load [N]": load,
            "U_k2_median_all_samples [-]": float(np.median(unc.expanded)),
            "dominant_all_samples": unc.dominant(),
        }
        if self.points:
            big_u = [p["U [-]"] for p in self.points]
            out["U_k2_median_curve_points [-]"] = float(np.median(big_u))
            idx = np.array([p["index"] for p in self.points])
            out["dominant_curve_points"] = unc.dominant(idx)
        else:
            out["U_k2_median_curve_points [-]"] = None
            out["U_k2_median_curve_points_null_because"] = "no creep–CoA points"
        return out

    def _validation_summary(self) -> dict | None:
        if self.validation is None:
            return None
        v = self.validation
        n = int(v["u_agrees"].size)
        return {
            "criterion": "JCGM 101 §8: d_low = |y - U95 - y_low|, d_high = |y + U95 - y_high| "
            "<= delta (2 significant digits of u), U95 = 1.96 u; and |u_LPU - u_MC| <= delta",
            "points": n,
            "u_agree": int(np.sum(v["u_agrees"])),
            "interval_validated": int(np.sum(v["interval_validated"])),
            "largest |u_MC - u_LPU| / u_LPU": float(np.max(np.abs(v["u_relative_difference"]))),
            "reading": "u agreeing at every point says the model is near linear over the "
            "inputs' uncertainties. An interval not validated says the output is not normal "
            "to two digits there: flat-topped where a rectangular input (a sensor class) or "
            "the release ring (arcsine) dominates, so that y ± 2u is wider than the 95 % "
            "interval (conservative); skewed by 1/N (about 6 u_rel(N)) and J5·α5 at high CoA, "
            "the upper end then lying a few hundredths of u beyond y + 2u",
        }


def creep_uncertainty(recording, rig, smoothing_window: int, smoothing_order: int) -> np.ndarray:
    """Standard uncertainty of the smoothed creep per sample [-] (JCGM 100 LPU).

    s = ω_w r_w / (ω_r r_r) − 1 from the smoothed speeds: the radii's tolerances (rectangular,
    ``sensors.wheel_radius_tolerance`` and ``roller_radius_tolerance``, systematic) and the
    encoders' quantisation through the encoder speed and the smoothing (random; type A white
    noise of the speeds when the recording gives speeds, not counts).
    """
    fs = uniform_rate(recording, "the uncertainty budget")  # a gap refused, not one step
    n = recording.time.size
    s, g = rig.sensors, rig.geometry
    w_w = savitzky_golay(recording["wheel_speed"], smoothing_window, smoothing_order)
    w_r = savitzky_golay(recording["roller_speed"], smoothing_window, smoothing_order)
    safe = np.where(np.abs(w_r) > 1e-6, w_r, 1e-6)
    ratio = w_w * g.wheel_radius_x / (safe * g.roller_radius_x)  # 1 + s
    var = (ratio / g.wheel_radius_x * s.wheel_radius_tolerance) ** 2 / 3.0
    var += (ratio / g.roller_radius_x * s.roller_radius_tolerance) ** 2 / 3.0
    half = smoothing_window // 2
    cpr = s.encoder_counts_per_revolution
    sensitivities = (  # ∂s/∂ω_w, ∂s/∂ω_r [s/rad]
        ("wheel", g.wheel_radius_x / (safe * g.roller_radius_x)),
        ("roller", -ratio / safe),
    )
    gains = {}  # the same filter for both encoders: built once
    for which, sens in sensitivities:
        if f"{which}_encoder_counts" in recording:
            decimated = recording.metadata.get("decimated") or {}
            sigma = math.sqrt(min(1.0, fs / float(decimated.get("from_rate_Hz", fs))) / 12.0)
            if "counts" not in gains:
                gains["counts"] = BandedFilter(
                    lambda m: after_encoder_speed(
                        savitzky_golay_matrix(m, smoothing_window, smoothing_order), fs, cpr
                    ),
                    n,
                    half + 1,
                ).row_norm2()
            gain = gains["counts"]
        else:
            sigma = noise_level(np.asarray(recording[f"{which}_speed"], dtype=float))
            if "speed" not in gains:
                gains["speed"] = BandedFilter(
                    lambda m: savitzky_golay_matrix(m, smoothing_window, smoothing_order), n, half
                ).row_norm2()
            gain = gains["speed"]
        var += (sens * sigma) ** 2 * gain
    return np.sqrt(var)


def coa_budget(
    unc: CoaUncertainty,
    recording,
    phases,
    branches,
    *,
    creep_u: np.ndarray | None = None,
    true_coa: np.ndarray | None = None,
    mc_draws: int = MC_DRAWS,
    mc_max_points: int = MC_MAX_POINTS,
    seed: int = 0,
) -> CoaBudget:
    """Per-phase and per-point tables of the corrected CoA's uncertainty.

    Parameters
    ----------
    unc : CoaUncertainty
    recording : Recording
        The analysed recording (``coa_smoothed``, ``creep_smoothed``).
    phases : list of Phase
    branches : list of Branches
    creep_u : ndarray, optional
        u of the creep per sample [-] (:func:`creep_uncertainty`).
    true_coa : ndarray, optional
        The twin's contact CoA on the analysis axis [-].
    mc_draws : int
        Monte Carlo draws per point (in runs of 10⁴).
    mc_max_points : int
        Most points the Monte Carlo runs at (every k-th point above it; noted).
    seed : int
        Monte Carlo seed.

    Returns
    -------
    CoaBudget
    """
    t = unc.time
    rig_coa = np.asarray(recording["coa_smoothed"], dtype=float)
    window = int(unc._model["window"])
    names = list(unc.contributions)
    phase_rows = []
    for ph in phases:
        idx = np.flatnonzero((t >= ph.start) & (t < ph.end))
        if idx.size == 0:
            continue
        y, u, mean_budget = unc.phase_mean(int(idx[0]), int(idx[-1]) + 1)
        median = {k: float(np.median(unc.contributions[k][idx])) for k in names}
        row = {
            "name": ph.name,
            "cycle": ph.cycle,
            "start [s]": ph.start,
            "end [s]": ph.end,
            "samples": int(idx.size),
            "rig_coa_mean [-]": float(np.mean(rig_coa[idx])),
            "corrected_coa_mean [-]": y,
            "u_mean [-]": u,
            "U_mean [-]": unc.coverage_factor * u,
            "U_sample_median [-]": float(np.median(unc.expanded[idx])),
            "U_sample_max [-]": float(np.max(unc.expanded[idx])),
            "budget_sample_median [-]": median,
            "budget_mean [-]": mean_budget,
            "dominant_sample": max(median, key=median.get),
            "dominant_mean": max(mean_budget, key=mean_budget.get),
        }
        if true_coa is not None:
            true_mean = float(np.mean(true_coa[idx]))
            row["true_coa_mean [-]"] = true_mean
            row["mean_covered"] = bool(abs(y - true_mean) <= unc.coverage_factor * u)
            row["samples_covered [-]"] = float(
                np.mean(np.abs(unc.value[idx] - true_coa[idx]) <= unc.expanded[idx])
            )
        phase_rows.append(row)

    points = _curve_point_indices(branches, window, t.size)
    mc = validation = None
    point_rows = []
    notes = []
    if points.size:
        runs = max(1, round(mc_draws / 10_000))
        step = max(1, math.ceil(points.shape[0] / max(int(mc_max_points), 1)))
        chosen = points[::step, 0]
        if step > 1:
            notes.append(
                f"Monte Carlo at one in {step} of the {points.shape[0]} creep–CoA points "
                f"({chosen.size}; MC_MAX_POINTS = {mc_max_points}); the others by the law of "
                "propagation only"
            )
        mc = monte_carlo(unc, chosen, seed=seed, adaptive=False, max_runs=runs)
        validation = jcgm101_validation(unc, mc)
        at = {int(i): j for j, i in enumerate(chosen)}
        creep = np.asarray(recording["creep_smoothed"], dtype=float)
        for i, cycle, ascending in points:
            row = {
                "index": int(i),
                "time [s]": float(t[i]),
                "cycle": int(cycle),
                "branch": "ascending" if ascending else "descending",
                "creep [-]": float(creep[i]),
                "u_creep [-]": None if creep_u is None else float(creep_u[i]),
                "rig_coa [-]": float(rig_coa[i]),
                "corrected_coa [-]": float(unc.value[i]),
                "u [-]": float(unc.u[i]),
                "U [-]": float(unc.expanded[i]),
                "dominant": unc.dominant(np.array([i])),
            }
            j = at.get(int(i))
            if j is None:
                for key in ("mc_mean [-]", "mc_u [-]", "mc_low_95 [-]", "mc_high_95 [-]",
                            "u_agrees", "interval_validated"):  # fmt: skip
                    row[key] = None
                row["mc_null_because"] = "not among the Monte Carlo's points (MC_MAX_POINTS)"
            else:
                row.update({
                    "mc_mean [-]": float(mc.mean[j]),
                    "mc_u [-]": float(mc.u[j]),
                    "mc_low_95 [-]": float(mc.low[j]),
                    "mc_high_95 [-]": float(mc.high[j]),
                    "u_agrees": bool(validation["u_agrees"][j]),
                    "interval_validated": bool(validation["interval_validated"][j]),
                })  # fmt: skip
            if creep_u is None:
                row["u_creep_null_because"] = "creep uncertainty not evaluated"
            if true_coa is not None:
                row["true_coa [-]"] = float(true_coa[i])
            point_rows.append(row)
    truth = None
    if true_coa is not None:
        inside = np.abs(unc.value - true_coa) <= unc.expanded
        truth = {
            "samples_covered [-]": float(np.mean(inside)),
            "curve_points_covered [-]": None
            if not points.size
            else float(np.mean(inside[points[:, 0]])),
            "mc_interval_covers_points [-]": None
            if mc is None
            else float(np.mean((true_coa[mc.index] >= mc.low) & (true_coa[mc.index] <= mc.high))),
            "note": "a synthetic recording carries no sensor class, area, radius or inertia "
            "error unless they were put in: the systematic inputs then widen the band beyond "
            "the error and the coverage exceeds 95 %",
        }
    return CoaBudget(unc, phase_rows, point_rows, mc, validation, truth, notes=notes)


def _curve_point_indices(branches, window: int, n: int) -> np.ndarray:
    """(index, cycle, ascending) of one branch sample per correction window, in time order."""
    rows = []
    for br in branches:
        for ascending, idx in ((1, br.ascending), (0, br.descending)):
            idx = np.asarray(idx, dtype=int)
            idx = idx[(idx >= 0) & (idx < n)]
            for i in idx[:: max(1, window)]:
                rows.append((int(i), int(br.cycle), ascending))
    rows.sort()
    return np.array(rows, dtype=int).reshape(-1, 3)
