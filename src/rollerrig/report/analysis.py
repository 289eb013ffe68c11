"""Report of an analysed adhesion test: figures, tables, the HTML report, the results files."""

from __future__ import annotations

import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from rollerrig._display import key_words, number
from rollerrig.analysis.adhesion import TestAnalysis
from rollerrig.fit.polach import PARAMETER_NAMES
from rollerrig.measure.quantities import ANALYSIS_CHANNELS, DERIVED_CHANNELS
from rollerrig.output import json_text, provenance, write_json, write_table
from rollerrig.recordings.recording import CANONICAL_CHANNELS
from rollerrig.report.adhesion import adhesion_figure
from rollerrig.report.filters import filter_comparison_figure, study_ranking_figure
from rollerrig.report.html import HtmlReport, relative_paths
from rollerrig.report.lines import PLOT_POINTS, envelope
from rollerrig.report.spectra import spectrum_figure
from rollerrig.signal.smoothing import smooth

__all__ = [
    "analysis_columns",
    "channel_attributes",
    "coa_uncertainty_figure",
    "overview_figure",
    "rig_versus_corrected_figure",
    "uncertainty_columns",
    "write_analysis",
]


_SCATTER_POINTS = 50_000
"""Most points of a scatter of the whole test in a report figure [1] (every k-th sample)."""

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


def phase_words(name: str) -> str:
    """A phase's name as words: ``ramp_up`` -> ``ramp up``."""
    return str(name).replace("_", " ")


def cycle_number(cycle) -> int | None:
    """A cycle as the console numbers it: 1 to n; ``None`` (shown "–") before the first."""
    return None if cycle is None or int(cycle) < 0 else int(cycle) + 1


def _contribution(value: float) -> str:
    """A budget entry [10⁻³ of CoA], two significant digits; below 0.001 shown as such."""
    if value == 0 or not np.isfinite(value):
        return number(value)
    return number(value, 2) if abs(value) >= 1e-3 else "< 0.001"


def _ms(seconds) -> float | None:
    """A time in s as ms rounded to 0.01 ms (a filter's lag: samples are ms apart)."""
    if seconds is None or not np.isfinite(seconds):
        return None
    return round(1e3 * float(seconds), 2) + 0.0  # + 0.0: no -0


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
    y = np.arange(len(names))
    height = 0.8 / max(len(kinds), 1)
    for j, kind in enumerate(kinds):
        c.barh(y + (j - (len(kinds) - 1) / 2) * height, 1e3 * values[j], height=height,
               color=_PHASE_COLOURS.get(kind, "#cccccc"), edgecolor="0.3", lw=0.4,
               label=kind.replace("_", " "))  # fmt: skip
    words = _labels(unc)
    c.set_yticks(y, [words.get(n, n) for n in names], fontsize=7)
    c.invert_yaxis()
    c.set_xscale("symlog", linthresh=0.1)
    c.set_xlabel("contribution |c_i| u(x_i) [10⁻³ CoA], median sample of the phase")
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


def _params_at(row, sample_rate: float) -> dict:
    """A study row's filter parameters for a signal at ``sample_rate`` [Hz].

    The study's windows count samples at the rate it ran at (``row.sample_rate``: 250 Hz for a
    recording faster than 500 Hz); the same span in seconds at ``sample_rate``, made odd.
    """
    params = dict(row.params)
    rate = getattr(row, "sample_rate", None)
    if "window" not in params or rate is None or abs(rate - sample_rate) <= 1e-9 * sample_rate:
        return params
    w = round((params["window"] - 1) * sample_rate / rate) + 1
    w += 1 - w % 2
    order = int(params.get("order", 1))
    params["window"] = max(w, order + 1 + order % 2)  # odd and longer than the order
    return params


def _at_rate(row, sample_rate: float) -> str:
    """Label suffix when a study row's window was rescaled to ``sample_rate``."""
    params = _params_at(row, sample_rate)
    if params.get("window") == row.params.get("window"):
        return ""
    return f" (w{params['window']} at {sample_rate:.6g} Hz)"


def _zoom_windows(result: TestAnalysis) -> dict:
    """A 2 s quiet window and a window around the first release [s], for the filter figure."""
    windows = {}
    quiet = [ph for ph in result.phases if ph.name in ("rest", "free_rolling")]
    if quiet:
        q = max(quiet, key=lambda ph: ph.end - ph.start)
        windows["steady_window"] = (max(q.start, q.end - 2.0), q.end)
    release = [ph for ph in result.phases if ph.name == "release"]
    if release:
        r = release[0]
        windows["transient_window"] = (r.start - 1.0, r.end + 1.5)
    return windows


def channel_attributes(recording) -> dict[str, dict[str, str]]:
    """NetCDF attributes of each channel of an analysed recording: ``units`` and ``long_name``.

    Units are the recording's (SI), except for the channels the analysis adds, whose units and
    meanings are :data:`ANALYSIS_CHANNELS`; meanings of the others come from
    :data:`rollerrig.recordings.recording.CANONICAL_CHANNELS` and
    :data:`rollerrig.measure.quantities.DERIVED_CHANNELS` (else the channel's name).

    Examples
    --------
    >>> from rollerrig.recordings.recording import Recording
    >>> rec = Recording(np.arange(3.0), {"roller_acceleration": np.zeros(3)},
    ...                 {"roller_acceleration": "1"})
    >>> channel_attributes(rec)["roller_acceleration"]["units"]
    'rad/s^2'
    """
    known = {**CANONICAL_CHANNELS, **DERIVED_CHANNELS, **ANALYSIS_CHANNELS}
    attrs = {}
    for name in recording.channels:
        unit, meaning = known.get(name, (None, name))
        if name not in ANALYSIS_CHANNELS:
            unit = recording.units.get(name, unit or "1")
        attrs[name] = {"units": unit, "long_name": meaning}
    return attrs


def analysis_columns(recording) -> dict[str, tuple]:
    """The analysed channels as :func:`rollerrig.output.write_table` columns.

    ``name -> (values, unit, long_name, attrs)`` with the units and meanings of
    :func:`channel_attributes`; a channel that holds NaN says why (``nan_meaning``), as the NaN
    policy of :mod:`rollerrig.output` asks.

    Parameters
    ----------
    recording : Recording
        The analysed recording (:attr:`rollerrig.analysis.adhesion.TestAnalysis.recording`).

    Returns
    -------
    dict
    """
    columns = {}
    for name, attrs in channel_attributes(recording).items():
        values = np.asarray(recording[name])
        extra = {}
        if values.dtype.kind == "f" and not np.all(np.isfinite(values)):
            extra["nan_meaning"] = (
                "no value at these samples in the recording as read (see the recording_notes, "
                "gaps and interpolated attributes)"
            )
        columns[name] = (values, attrs["units"], attrs["long_name"], extra)
    return columns


def _recording_section(rep: HtmlReport, result: TestAnalysis) -> None:
    """What the reader and the generator said: notes, interpolated runs, gaps, injected lines."""
    from rollerrig.analysis.adhesion import recording_facts, recording_note_lines

    facts = recording_facts(result.recording)
    lines = recording_note_lines(result.recording)
    rep.heading("The recording as read")
    if not lines:
        rep.paragraph(
            "The reader noted nothing: no interpolated samples, no gaps, no conversions to "
            "mention, no injected lines."
        )
    for line in lines:
        rep.paragraph(line, note=True)
    if facts["interpolated"]:
        rep.table(
            ["channel", "first sample", "last sample", "from [s]", "to [s]", "method"],
            [
                [r.get("channel"), r.get("first_sample"), r.get("last_sample"),
                 r.get("start_s"), r.get("end_s"), r.get("method")]
                for r in facts["interpolated"]
            ],
        )  # fmt: skip
    if facts["gaps"]:
        rep.table(
            ["after sample", "from [s]", "to [s]", "duration [s]", "missing samples"],
            [
                [g.get("sample"), g.get("start_s"), g.get("end_s"), g.get("duration_s"),
                 g.get("missing_samples")]
                for g in facts["gaps"]
            ],
        )  # fmt: skip
    if facts["injected_lines"]:
        rep.table(
            ["injected line", "frequency [Hz]", "amplitude [N.m]", "channel"],
            [
                [x.get("name"), x.get("frequency [Hz]"), x.get("amplitude [N.m]"),
                 x.get("channel")]
                for x in facts["injected_lines"]
            ],
        )  # fmt: skip


def _fit_honesty_section(rep: HtmlReport, result: TestAnalysis) -> None:
    """What the data constrain, residual structure and, with a truth, the distance in σ."""
    fits = [(lbl, f) for lbl, f in (("corrected CoA", result.fit), ("rig CoA", result.fit_rig_coa))]
    fits = [(lbl, f) for lbl, f in fits if f is not None]
    if not fits:
        return
    rep.heading("How far the Polach fit can be trusted")
    rep.paragraph(
        "A and B act only through the friction coefficient μ(w), and μ only where the contact "
        "saturates (η ≥ 0.5: the CoA at least half proportional to μ). The saturated points' "
        "slip velocities are where A and B are constrained. Residuals are tested in creep order "
        "(Durbin–Watson, lag-1 autocorrelation, runs test); structured residuals mean a "
        "systematic misfit, and standard errors that are too small."
    )
    rows = []
    for label, f in fits:
        c, r = f.coverage, f.residual_structure
        sat = c.saturated_slip_velocity_range if c is not None else None
        rows.append(
            [
                label,
                "–"
                if c is None
                else f"{c.slip_velocity_range[0]:.3g}–{c.slip_velocity_range[1]:.3g}",
                "none" if sat is None else f"{sat[0]:.3g}–{sat[1]:.3g}",
                "–" if c is None else c.saturated_points,
                "–" if c is None else c.falling_branch_points,
                "–" if c is None else ("yes" if c.a_and_b_identifiable else "NO"),
                "–" if r is None else f"{r.durbin_watson:.3f} (< {r.durbin_watson_threshold:.3f})",
                "–" if r is None else f"{r.runs_z:+.2f} (< {r.runs_z_threshold:+.0f})",
                "–" if r is None else ("yes" if r.structured else "no"),
            ]
        )
    rep.table(
        ["fit to", "slip velocity [m/s]", "A, B constrained over [m/s]", "saturated points",
         "past the peak", "A, B identifiable", "Durbin–Watson (structured below)",
         "runs z (structured below)", "structured residuals"],
        rows,
    )  # fmt: skip
    for label, f in fits:
        if f.coverage is not None and not f.coverage.a_and_b_identifiable:
            rep.paragraph(
                f"Fit to the {label}: A and B not identifiable: " + "; ".join(f.coverage.reasons),
                note=True,
            )
    if result.true_parameters is None:
        return
    rep.paragraph(f"Truth: {result.true_parameters_source}.")
    names = dict(zip(PARAMETER_NAMES, ("μ0", "A", "B [s/m]", "kA", "kS"), strict=True))
    trows = []
    for key in PARAMETER_NAMES:
        row = [names[key], result.true_parameters[key]]
        for _, f in fits:
            d = f.truth_distance(result.true_parameters)[key]
            sigma = (
                "–"
                if d["sigma"] is None
                else f"{d['sigma']:.1f} σ" + (" (> 3 σ)" if d["beyond_warn_sigma"] else "")
            )
            row.append(sigma)
        trows.append(row)
    rep.table(["parameter", "true (twin)", *[f"distance, fit to {lbl}" for lbl, _ in fits]], trows)


def _fit_rows(result: TestAnalysis, truth_parameters=None):
    names = ("μ0", "A", "B [s/m]", "kA", "kS")
    keys = ("static_friction", "limit_ratio", "friction_decay", "k_adhesion", "k_slip")
    rows = []
    for i, (name, key) in enumerate(zip(names, keys, strict=True)):
        row = [name]
        for fit in (result.fit, result.fit_rig_coa):
            if fit is None:
                row.append("–")
            else:
                value = fit.parameters.as_tuple()[i]
                row.append(f"{value:.4g} ± {fit.stderr[key]:.2g}")
        if truth_parameters is not None:
            row.append(f"{truth_parameters[key]:.4g}")
        rows.append(row)
    return rows


def uncertainty_columns(result: TestAnalysis) -> dict[str, tuple]:
    """The corrected CoA's uncertainty per sample (and the online CoA) as table columns.

    ``coa_corrected_standard_uncertainty`` and ``coa_corrected_expanded_uncertainty`` (k = 2),
    and ``coa_online`` when the analysis ran the causal estimator; empty without an
    uncertainty. Same form as :func:`analysis_columns`.
    """
    budget = result.coa_uncertainty
    if budget is None:
        return {}
    unc = budget.uncertainty
    k = unc.coverage_factor
    columns = {
        "coa_corrected_standard_uncertainty": (
            unc.u,
            "1",
            "combined standard uncertainty of the corrected CoA (JCGM 100 law of propagation)",
            {},
        ),
        "coa_corrected_expanded_uncertainty": (
            unc.expanded,
            "1",
            f"expanded uncertainty of the corrected CoA, k = {k:g}",
            {"coverage_factor": k},
        ),
    }
    if budget.online_coa is not None:
        columns["coa_online"] = (
            budget.online_coa,
            "1",
            "CoA from the causal online contact-torque estimator",
            {},
        )
    for name, (coa, what) in budget.model_coa.items():
        columns[name] = (coa, "1", what, {})
    return columns


def _uncertainty_section(rep: HtmlReport, result: TestAnalysis) -> None:
    """The corrected CoA's uncertainty: figure, inputs, budget per phase, validation, truth."""
    budget = result.coa_uncertainty
    unc = budget.uncertainty
    summary = budget.summary()
    typical = summary["typical"]
    words = _labels(unc)
    rep.heading("Uncertainty of the corrected CoA (JCGM 100 and JCGM 101)")
    rep.paragraph(
        "μ = F_x / N + e_res with F_x r_r = T56 + δT + e_T + J5 (α5 + e_α) + k_b R05, the "
        "contact's load N = S + W_d + σ (h/l) F_x (the swinging arm) and the air spring's force "
        "S = (p + δp + e_p) A. "
        "Systematic inputs (sensor accuracy classes, air-spring area, radius, J5, bearing "
        "loss) take one error for the whole test, so they do not average down in a phase mean; "
        "random inputs (torque and pressure noise, encoder quantisation) pass the correction's "
        "filters, whose weights give their variance per sample and per phase mean; the residual "
        "covers what the correction cannot resolve (in-band disturbance lines, the contact's "
        "transient after a release). Law of propagation per sample, U = 2u; Monte Carlo "
        "(JCGM 101) at the creep–CoA points, compared with it as JCGM 101 §8 asks.",
        math=True,
    )
    rep.paragraph(
        f"Typical expanded uncertainty (k = 2): {typical['U_k2_median_all_samples [-]']:.3g} "
        f"(median over the test, load {typical['normal_load [N]'] / 1e3:.3g} kN), dominated by "
        f"{words.get(typical['dominant_all_samples'])}."
    )
    rep.figure(
        coa_uncertainty_figure(result),
        "Corrected CoA with its band ±U (k = 2); creep–CoA points with U; the budget by phase.",
    )
    rep.table(
        ["input", "symbol", "kind", "PDF", "estimate", "u(x)", "unit", "basis"],
        [
            [words[i.name], i.symbol, i.kind, i.distribution,
             "per sample" if i.estimate is None else i.estimate,
             "per sample" if i.standard_uncertainty is None else i.standard_uncertainty,
             i.unit, i.basis]
            for i in unc.inputs
        ],
        math_columns=(1,),
    )  # fmt: skip
    names = list(unc.contributions)
    rep.paragraph(
        "The corrected CoA per phase: its mean, U of the phase mean (systematic inputs do not "
        "average down), U of the phase's median sample, and the input that dominates each."
    )
    rep.table(
        ["phase", "cycle", "rig CoA", "corrected CoA", "U of the mean", "U of a sample",
         "dominant (sample)", "dominant (mean)"],
        [
            [phase_words(r["name"]), cycle_number(r["cycle"]), r["rig_coa_mean [-]"],
             r["corrected_coa_mean [-]"], r["U_mean [-]"], r["U_sample_median [-]"],
             words.get(r["dominant_sample"]), words.get(r["dominant_mean"])]
            for r in budget.phases
        ],
    )  # fmt: skip
    rep.paragraph(
        "Budget per phase: each input's contribution |c_i| u(x_i) to the phase's median sample, "
        "in 10⁻³ of CoA.",
        math=True,
    )
    rep.table(
        ["phase", "cycle", *[words.get(n, n) for n in names]],
        [
            [phase_words(r["name"]), cycle_number(r["cycle"]),
             *[_contribution(1e3 * r["budget_sample_median [-]"][n]) for n in names]]
            for r in budget.phases
        ],
    )  # fmt: skip
    validation = summary["validation"]
    if validation is not None:
        mc = summary["monte_carlo"]
        rep.paragraph(
            f"Monte Carlo: {mc['draws per point']} draws per point at {validation['points']} "
            f"creep–CoA points ({mc['method']}). u of the law of propagation agrees at "
            f"{validation['u_agree']} of {validation['points']} points (largest relative "
            f"difference {validation['largest |u_MC - u_LPU| / u_LPU']:.2g}); the interval "
            f"y ± 1.96u is validated (JCGM 101 §8) at {validation['interval_validated']}. "
            + validation["reading"]
            + "."
        )
    truth = summary["truth_coverage"]
    if truth is not None:
        rep.paragraph(
            "Against the twin's contact CoA: the band covers "
            f"{100 * truth['samples_covered [-]']:.1f} % of the samples"
            + (
                ""
                if truth["curve_points_covered [-]"] is None
                else f" and {100 * truth['curve_points_covered [-]']:.1f} % of the curve points"
            )
            + f" ({truth['note']})."
        )
    for note in summary["notes"]:
        rep.paragraph(note, note=True)


def write_analysis(
    result: TestAnalysis,
    out: str | os.PathLike,
    stem: str,
    *,
    source: str = "",
    truth=None,
    extra_provenance: dict | None = None,
    extra_sections=None,
    report_folder: str | os.PathLike | None = None,
) -> list[Path]:
    """Write the results (JSON summary, NetCDF channels) and the self-contained HTML report.

    Returns the written paths: ``<stem>-analysis.json`` (the summary, with its provenance),
    ``<stem>-analysis.nc`` (every analysed channel with its unit and long name, CF-1.10,
    written by :func:`rollerrig.output.write_table`; see :func:`analysis_columns`) and
    ``<stem>-report.html`` (self-contained: figures embedded as PNG data URIs). Each file
    replaces one of the same name.

    The report names files relative to ``report_folder`` (default ``out``; the folder the
    report will be read from, when ``out`` is a staging folder moved there afterwards): no
    absolute path, no home directory, in a report that is shared.
    """
    from rollerrig.output.provenance import current_run, run_context

    if current_run() is None and source and Path(source).is_file():
        # Called from Python: the recording named as the source is this run's input (the CLI
        # opens its own context with every input of the command).
        with run_context(inputs={"recording": source}):
            return write_analysis(
                result,
                out,
                stem,
                source=source,
                truth=truth,
                extra_provenance=extra_provenance,
                extra_sections=extra_sections,
                report_folder=report_folder,
            )
    out = Path(out)
    record = provenance(source=source, **(extra_provenance or {}))
    if record["rig"] is None and result.rig_sha256:
        record["rig"] = {"name": result.rig_name, "sha256": result.rig_sha256}
    summary = {"provenance": record, **result.summary()}
    paths = [write_json(out / f"{stem}-analysis.json", summary)]

    facts = summary["recording"]
    rec = result.recording
    name = source or str(rec.metadata.get("source", ""))
    # CF-1.10 NetCDF: units and long_name on every variable; the global attributes are strings
    # (lists as JSON, with the same NaN policy as the JSON summary).
    attrs = {
        "title": f"rollerrig analysis of the adhesion test {name}".strip(),
        "source": source,
        "recording_notes": json_text(facts["notes"]),
        "interpolated": json_text(facts["interpolated"]),
        "gaps": json_text(facts["gaps"]),
        "injected_lines": json_text(facts["injected_lines"]),
        "analysis_notes": json_text(result.notes),
    }
    paths.append(
        write_table(
            out / f"{stem}-analysis.nc",
            {**analysis_columns(rec), **uncertainty_columns(result)},
            time=rec.time,
            provenance=record,
            attrs=attrs,
            overwrite=True,  # like the JSON summary and the report beside it
        )
    )

    report_folder = out if report_folder is None else Path(report_folder)
    rep = HtmlReport(f"Adhesion test analysis: {stem}")
    shown = relative_paths(source, report_folder) or stem
    rep.paragraph(
        f"Recording {shown}: {rec.duration:.2f} s at {rec.sample_rate:.4g} Hz, "
        f"channels {', '.join(sorted(rec.channels))}. Rig: {result.rig_name}."
    )
    _recording_section(rep, result)
    if result.notes:
        for note in result.notes:
            rep.paragraph(note, note=True)
    rep.heading("Phases of the test")
    rep.table(
        ["phase", "cycle", "start [s]", "end [s]"],
        [[phase_words(ph.name), cycle_number(ph.cycle), ph.start, ph.end] for ph in result.phases],
    )
    rep.figure(overview_figure(result), "Torque, speeds and creep; phases shaded.")

    rep.heading("Adhesion: the rig's CoA and the CoA corrected for the rig's dynamics")
    rep.paragraph(
        "The torque sensor sits on the roller shaft, so the rig's CoA = T56/(r_r S) misses the "
        "torque that accelerates the roller and its bearing loss. The corrected CoA adds them: "
        "F_x r_r = T56 + J5·α5 + R05, with α5 the Savitzky–Golay derivative of the roller speed."
    )
    rep.figure(rig_versus_corrected_figure(result, truth), "Rig versus corrected CoA.")
    if result.coa_uncertainty is not None:
        _uncertainty_section(rep, result)
    truth_parameters = result.true_parameters
    header = ["parameter", "fit to corrected CoA", "fit to rig CoA"]
    if truth_parameters is not None:
        header.append("true (twin)")
    rep.table(header, _fit_rows(result, truth_parameters))
    _fit_honesty_section(rep, result)
    if result.truth_errors:
        rep.table(
            ["error against the true contact CoA", "value"],
            [[key_words(k), v] for k, v in result.truth_errors.items()],
        )
    if result.fit is not None:
        rep.figure(
            adhesion_figure(
                rec["creep_smoothed"],
                rec["coa_corrected"],
                result.branches,
                result.fit,
                title="Corrected CoA: ascending (solid) and descending (dashed) branches, fit",
            ),
            "Creep–CoA curve of the corrected CoA with the Polach fit and its residuals.",
        )
    rep.paragraph(
        "The descending branch follows the creep's fast fall after a release (tens of ms); "
        f"a smoothing window of {result.smoothing_window / rec.sample_rate:.2f} s smears it, so "
        "part of the loop between the branches is the filter's, not the contact's (the seed, "
        "§5, attributes the gap of its return curves to filtering as well).",
        note=True,
    )
    rows = []
    for br, h in zip(result.branches, result.hysteresis, strict=True):
        if h is not None:
            rows.append(
                [
                    cycle_number(br.cycle),
                    h.abs_area,
                    h.max_difference,
                    100 * h.creep_at_max_difference,
                ]
            )
    if rows:
        rep.heading("Hysteresis between ascending and descending branches (rig CoA)")
        rep.table(["cycle", "|area|", "largest ΔCoA", "at creep [%]"], rows)

    if result.spectrum is not None:
        rep.heading("Spectrum of the roller-shaft torque in the longest quiet phase")
        w = result.spectrum_window
        rep.paragraph(
            f"Window {w[0]:.2f}–{w[1]:.2f} s. Each peak is attributed to the induction motor's "
            "electrical frequency (pole pairs × roller rotation frequency) and its harmonics, "
            "rotation orders of wheel and roller, the PMSM electrical frequency, the damped "
            "modes of the coupled twin that can ring at this speed and load, or stated as "
            "unexplained with the reason."
        )
        rep.paragraph(f"Settings: {result.spectrum.caption()}.", note=True)
        rep.figure(spectrum_figure(result.spectrum), "Torque spectrum with labelled peaks.")
        if result.spectrum.rows:
            rep.table(
                ["f [Hz]", "power", "source", "Δf [Hz]", "also"],
                [
                    [
                        r["frequency_hz"],
                        "–" if r["power"] is None else r["power"],
                        r["label"] if r["explained"] else f"unexplained: {r['reason']}",
                        "–" if r["delta_f_hz"] is None else r["delta_f_hz"],
                        r["also"],
                    ]
                    for r in result.spectrum.table()
                ],
            )
        else:
            rep.paragraph(result.spectrum.empty_message + ".")

    if result.study:
        rep.heading("Smoothing-filter study (the seed's §4.5.2.5, scored)")
        rep.paragraph(
            f"Savitzky–Golay tuned on this recording: order {result.smoothing_order}, window "
            f"{result.smoothing_window} samples at {rec.sample_rate:.6g} Hz "
            f"({result.smoothing_window / rec.sample_rate:.3f} s). Lower cost is better: noise "
            "left in steady parts, transient peak height and timing kept, lag."
        )
        basis = getattr(result.study, "basis", None)
        if basis is not None:
            rep.paragraph(basis.note() + ".", note=True)
        for text in result.study.unscored_notes():
            rep.paragraph(f"{text}.", note=True)
        rep.figure(study_ranking_figure(result.study), "Filters ranked by cost.")
        best = result.study[0]
        filtered = {
            best.label + _at_rate(best, rec.sample_rate): smooth(
                rec["torque"],
                best.method,
                sample_rate=rec.sample_rate,
                **_params_at(best, rec.sample_rate),
            ),
            f"SG order {result.smoothing_order}, window {result.smoothing_window}": rec[
                "torque_smoothed"
            ],
            "Butterworth 2 @ 1.2 Hz causal": smooth(
                rec["torque"],
                "butterworth",
                sample_rate=rec.sample_rate,
                cutoff=1.2,
                order=2,
                zero_phase=False,
            ),
        }
        rep.figure(
            filter_comparison_figure(
                rec.time, rec["torque"], filtered, unit="N·m", **_zoom_windows(result)
            ),
            "Raw versus filtered torque, with zooms on a quiet part and on the first release.",
        )
        rep.table(
            ["rank", "filter", "noise left", "peak kept", "lag [ms]", "cost"],
            [
                [
                    r.rank,
                    r.label,
                    r.score.noise_left,
                    r.score.peak_kept,
                    _ms(r.score.lag),
                    r.score.cost,
                ]
                for r in result.study[:15]
            ],
            digits=3,
        )
    if extra_sections is not None:
        extra_sections(rep)
    rep.provenance(summary["provenance"], relative_to=report_folder)
    paths.append(rep.write(out / f"{stem}-report.html"))
    return paths
