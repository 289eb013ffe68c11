"""Figures of an analysed adhesion test: the test's overview, the rig's CoA against the
corrected one, and the corrected CoA with its uncertainty and budget (the report's
:func:`rollerrig.report.analysis.write_analysis` and notebooks draw them).
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np

from rollerrig.analysis.adhesion import TestAnalysis
from rollerrig.report.lines import PLOT_POINTS, envelope

__all__ = ["coa_uncertainty_figure", "overview_figure", "rig_versus_corrected_figure"]


_SCATTER_POINTS = 50_000
"""Most points of a scatter of the whole test in a report figure [-] (every k-th sample)."""

_PHASE_COLOURS = {
    "free_rolling": "#e8f4e8",
    "ramp_up": "#fdf0d5",
    "hold": "#fbd5d5",
    "release": "#f4c2f4",
    "rest": "#e8eef8",
    "ramp_down": "#eeeeee",
}


def _shade_phases(ax, phases) -> None:
    for ph in phases:
        ax.axvspan(ph.start, ph.end, color=_PHASE_COLOURS.get(ph.name, "#f5f5f5"), lw=0, zorder=0)


def overview_figure(result: TestAnalysis):
    """Torque request and torque, speeds and creep over the test, phases shaded."""
    rec = result.recording
    t = rec.time
    fig, axes = plt.subplots(3, 1, figsize=(11, 8), sharex=True)
    a, b, c = axes
    if "torque_request" in rec:
        a.plot(*envelope(t, rec["torque_request"]), color="k", lw=1, label="torque request (wheel)")
    a.plot(*envelope(t, rec["torque"]), color="0.6", lw=0.6, label="roller-shaft torque T56 (raw)")
    a.plot(*envelope(t, rec["torque_smoothed"]), color="tab:blue", lw=1.2, label="T56 smoothed")
    a.set_ylabel("torque [N·m]")
    b.plot(*envelope(t, rec["wheel_speed"]), color="tab:green", lw=0.6, label="wheel (encoder)")
    b.plot(*envelope(t, rec["roller_speed"]), color="tab:brown", lw=0.6, label="roller (encoder)")
    b.set_ylabel("speed [rad/s]")
    c.plot(*envelope(t, 100 * rec["creep"]), color="0.6", lw=0.5, label="creep from encoders")
    c.plot(*envelope(t, 100 * rec["creep_smoothed"]), color="tab:purple", lw=1.2, label="smoothed")
    c.set_ylabel("creep [%]")
    c.set_xlabel("time [s]")
    for ax in axes:
        _shade_phases(ax, result.phases)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
    names = sorted({ph.name for ph in result.phases})
    handles = [plt.Rectangle((0, 0), 1, 1, color=_PHASE_COLOURS.get(n, "#f5f5f5")) for n in names]
    words = [n.replace("_", " ") for n in names]  # "free_rolling" -> "free rolling"
    fig.legend(handles, words, loc="upper center", ncol=len(names), fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0, 1, 0.96))
    return fig


def rig_versus_corrected_figure(result: TestAnalysis, truth=None):
    """The CoA the rig reports, the dynamics-corrected CoA and (synthetic data) the true CoA."""
    rec = result.recording
    t = rec.time
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.5))
    a.plot(*envelope(t, rec["coa_smoothed"]), color="tab:blue", lw=1, label="rig: T56 / (r_r S)")
    a.plot(
        *envelope(t, rec["coa_corrected"]), color="tab:red", lw=1, label="corrected: + J5·α5 + R05"
    )
    true_coa = result.true_coa
    if true_coa is None and truth is not None and truth["coa"].size == t.size:
        true_coa = truth["coa"].values
    if true_coa is not None:
        a.plot(*envelope(t, true_coa), "k--", lw=0.8, label="true contact CoA (twin)")
    _shade_phases(a, result.phases)
    a.set_xlabel("time [s]")
    a.set_ylabel("CoA [-]")
    a.set_title("Adhesion coefficient over the test")
    idx = np.concatenate([br.ascending for br in result.branches]) if result.branches else []
    step = max(1, -(-t.size // _SCATTER_POINTS))  # every step-th sample, bounded points
    every = "" if step == 1 else f" (one sample in {step})"
    b.plot(
        100 * rec["creep_smoothed"][::step],
        rec["coa_smoothed"][::step],
        ".",
        ms=1,
        color="tab:blue",
        alpha=0.4,
        label=f"rig CoA, whole test{every}",
    )
    b.plot(
        100 * rec["creep_smoothed"][::step],
        rec["coa_corrected"][::step],
        ".",
        ms=1,
        color="tab:red",
        alpha=0.4,
        label=f"corrected CoA, whole test{every}",
    )
    s = np.linspace(
        0, max(float(np.max(rec["creep_smoothed"][idx])) if len(idx) else 0.05, 1e-3), 300
    )
    for fit, colour, name in (
        (result.fit_rig_coa, "tab:blue", "rig"),
        (result.fit, "tab:red", "corrected"),
    ):
        if fit is not None:
            b.plot(
                100 * s,
                fit.curve(s, rolling_speed=_rolling_speed(result)),
                color=colour,
                lw=2,
                label=f"Polach fit to {name} CoA (μ0 = {fit.parameters.static_friction:.3f})",
            )
    b.set_xlim(0, 100 * s[-1])
    b.set_xlabel("creep [%]")
    b.set_ylabel("CoA [-]")
    b.set_title("Creep–CoA")
    for ax in (a, b):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    return fig


_BUDGET_LABELS = {
    "torque_class": "torque sensor class",
    "torque_noise": "torque noise",
    "pressure_class": "pressure sensor class",
    "pressure_noise": "pressure noise",
    "air_spring_area": "air-spring area",
    "roller_radius": "roller radius",
    "roller_inertia": "roller inertia J5",
    "bearing_loss": "bearing loss R05",
    "bearing_friction": "bearing f_g (calibrated)",
    "bearing_radius": "bearing radius (calibrated)",
    "roller_weight": "roller weight (calibrated)",
    "encoder_quantisation": "encoder quantisation (α5)",
    "arm_pivot_height": "arm: pivot height h",
    "arm_length": "arm: length l",
    "arm_dead_weight": "arm: dead weight W_d",
    "residual_steady": "residual: in-band lines",
    "residual_release": "residual: release transient",
}
"""Words for the inputs of the uncertainty budget (rollerrig.estimation.uncertainty.INPUT_NAMES)."""


def _labels(unc) -> dict[str, str]:
    """Input name -> words; the α5 noise is the speed's when the recording had no counts."""
    labels = {i.name: _BUDGET_LABELS.get(i.name, i.name) for i in unc.inputs}
    for i in unc.inputs:
        if i.name == "encoder_quantisation" and i.unit != "count":
            labels[i.name] = "roller speed noise (α5)"
    return labels


def _band(t, low, high):
    """``t``, lower and upper edge of a band, reduced to PLOT_POINTS bins (min/max per bin)."""
    n = t.size
    if n <= PLOT_POINTS:
        return t, low, high
    k = -(-n // (PLOT_POINTS // 2))
    m = n // k * k
    tb = t[:m].reshape(-1, k)[:, 0]
    return tb, low[:m].reshape(-1, k).min(axis=1), high[:m].reshape(-1, k).max(axis=1)


def coa_uncertainty_figure(result: TestAnalysis):
    """The corrected CoA with its expanded uncertainty (k = 2) over the test, the creep–CoA
    points with their error bars, and the budget by phase (what dominates).

    Panels: (a) the rig's CoA, the corrected CoA and its band ±U, the online estimate when the
    analysis has one, the twin's contact CoA for a synthetic recording; (b) the creep–CoA
    points (one per correction window) with U and the creep's U as error bars; (c) the median
    contribution |c_i| u(x_i) of each input in each kind of phase, in 10⁻³ of CoA.
    """
    budget = result.coa_uncertainty
    unc = budget.uncertainty
    rec = result.recording
    t = rec.time
    fig = plt.figure(figsize=(12, 12))
    grid = fig.add_gridspec(3, 2, height_ratios=(1.0, 1.0, 1.1))
    a = fig.add_subplot(grid[0, :])
    z = fig.add_subplot(grid[1, 0])
    b = fig.add_subplot(grid[1, 1])
    c = fig.add_subplot(grid[2, :])
    releases = [ph for ph in result.phases if ph.name == "release"]
    if releases:
        zoom = (releases[0].start - 1.5, releases[0].end + 3.0)
    else:
        zoom = (t[0], t[0] + min(5.0, t[-1] - t[0]))
    for ax, span in ((a, None), (z, zoom)):
        sel = slice(None) if span is None else (t >= span[0]) & (t <= span[1])
        tb, lo, hi = _band(t[sel], (unc.value - unc.expanded)[sel], (unc.value + unc.expanded)[sel])
        ax.fill_between(tb, lo, hi, color="tab:red", alpha=0.3, lw=0,
                        label="corrected ± U (k = 2)")  # fmt: skip
        ax.plot(*envelope(t[sel], rec["coa_smoothed"][sel]), color="tab:blue", lw=0.8,
                label="rig CoA")  # fmt: skip
        ax.plot(*envelope(t[sel], unc.value[sel]), color="tab:red", lw=0.8, label="corrected CoA")
        if budget.online_coa is not None:
            ax.plot(*envelope(t[sel], budget.online_coa[sel]), color="tab:green", lw=0.6,
                    alpha=0.8, label="online estimate (causal)")  # fmt: skip
        if budget.model_choice and budget.model_choice[0] in budget.model_coa:
            chosen = budget.model_choice[0]
            which = "chain" if chosen == "coa_smoother_chain" else "roller alone"
            ax.plot(*envelope(t[sel], budget.model_coa[chosen][0][sel]),
                    color="tab:purple", lw=0.7, alpha=0.9,
                    label=f"model-based, two-sided ({which})")  # fmt: skip
        if result.true_coa is not None:
            ax.plot(*envelope(t[sel], result.true_coa[sel]), "k--", lw=0.7,
                    label="true contact CoA (twin)")  # fmt: skip
        _shade_phases(ax, result.phases)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("CoA [-]")
    z.set_xlim(*zoom)
    a.set_title("Corrected CoA with its expanded uncertainty")
    z.set_title(f"Zoom {zoom[0]:.1f}–{zoom[1]:.1f} s" + (" (first release)" if releases else ""))
    a.legend(fontsize=7, loc="upper right", ncol=3)

    points = budget.points
    if points:
        for branch, marker in (("ascending", "o"), ("descending", "s")):
            sel = [p for p in points if p["branch"] == branch]
            if not sel:
                continue
            x = np.array([100 * p["creep [-]"] for p in sel])
            xerr = np.array(
                [0.0 if p["u_creep [-]"] is None else 200 * p["u_creep [-]"] for p in sel]
            )
            b.errorbar(x, [p["corrected_coa [-]"] for p in sel],
                       yerr=[p["U [-]"] for p in sel], xerr=xerr, fmt=marker, ms=3,
                       color="tab:red", ecolor="tab:red", elinewidth=0.7, capsize=1.5,
                       mfc="tab:red" if branch == "ascending" else "white",
                       label=f"corrected, {branch} ± U")  # fmt: skip
            b.plot(x, [p["rig_coa [-]"] for p in sel], marker, ms=2.5, color="tab:blue",
                   mfc="tab:blue" if branch == "ascending" else "white",
                   label=f"rig, {branch}")  # fmt: skip
            if "true_coa [-]" in sel[0]:
                b.plot(x, [p["true_coa [-]"] for p in sel], "k+", ms=4,
                       label="true (twin)" if branch == "ascending" else None)  # fmt: skip
    b.set_xlabel("creep [%]")
    b.set_ylabel("CoA [-]")
    b.set_title("Creep–CoA points (one per correction window)")
    b.legend(fontsize=7, loc="lower right")

    kinds = [k for k in ("free_rolling", "ramp_up", "hold", "release", "rest")
             if any(r["name"] == k for r in budget.phases)]  # fmt: skip
    names = list(unc.contributions)
    values = np.array([
        [np.median([r["budget_sample_median [-]"][n] for r in budget.phases if r["name"] == k])
         for n in names]
        for k in kinds
    ])  # fmt: skip
    # An input that contributes nothing in any phase (the in-band residual of a recording with
    # no line in the correction's pass band) is named under the panel, not drawn as an empty
    # row among the others.
    words = _labels(unc)
    drawn = [j for j in range(len(names)) if np.any(values[:, j] > 0.0)] if kinds else []
    zero = [words.get(names[j], names[j]) for j in range(len(names)) if j not in drawn]
    if drawn:
        names = [names[j] for j in drawn]
        values = values[:, drawn]
    y = np.arange(len(names))
    height = 0.8 / max(len(kinds), 1)
    for j, kind in enumerate(kinds):
        c.barh(y + (j - (len(kinds) - 1) / 2) * height, 1e3 * values[j], height=height,
               color=_PHASE_COLOURS.get(kind, "#cccccc"), edgecolor="0.3", lw=0.4,
               label=kind.replace("_", " "))  # fmt: skip
    c.set_yticks(y, [words.get(n, n) for n in names], fontsize=7)
    c.invert_yaxis()
    c.set_xscale("symlog", linthresh=0.1)
    c.set_xlabel(
        "contribution |c_i| u(x_i) [10⁻³ CoA], median sample of the phase"
        + (f"\nzero in every phase, not drawn: {', '.join(zero)}" if drawn and zero else "")
    )
    c.set_title("Uncertainty budget by phase")
    c.legend(fontsize=7, loc="upper right")
    for ax in (a, z, b, c):
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    return fig


def _rolling_speed(result: TestAnalysis) -> float:
    """Median roller peripheral speed over the fitted points [m/s] (slip velocity / creep)."""
    rec = result.recording
    idx = result.fit_points
    creep = rec["creep_smoothed"][idx]
    ok = np.abs(creep) > 1e-3
    if not np.any(ok):
        return 1.0
    return float(np.median(rec["slip_velocity_smoothed"][idx][ok] / creep[ok]))
