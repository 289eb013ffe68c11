"""Sections of the HTML report of an analysed adhesion test: the recording as read, the
corrected CoA's uncertainty, how far the Polach fit can be trusted, the torque's spectrum, the
smoothing-filter study, and the words and numbers their tables use.

:func:`rollerrig.report.analysis.write_analysis` puts them in order.
"""

from __future__ import annotations

import numpy as np

from rollerrig._display import number
from rollerrig.analysis.adhesion import TestAnalysis
from rollerrig.fit.polach import PARAMETER_NAMES
from rollerrig.report.analysis_figures import _labels, coa_uncertainty_figure
from rollerrig.report.filters import filter_comparison_figure, study_ranking_figure
from rollerrig.report.html import HtmlReport
from rollerrig.report.spectra import spectrum_figure
from rollerrig.signal.smoothing import smooth

__all__ = ["cycle_number", "phase_words"]


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
    for name, key in zip(names, keys, strict=True):
        row = [name]
        for fit in (result.fit, result.fit_rig_coa):
            if fit is None:
                row.append("–")
            else:
                row.append(fit.shown(key))
        if truth_parameters is not None:
            row.append(f"{truth_parameters[key]:.4g}")
        rows.append(row)
    return rows


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


def _spectrum_section(rep: HtmlReport, result: TestAnalysis) -> None:
    """The roller-shaft torque's spectrum in the longest quiet phase, its peaks attributed."""
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


def _filter_study_section(rep: HtmlReport, result: TestAnalysis) -> None:
    """The smoothing-filter study: the filters ranked, the best against the analysis' own."""
    rec = result.recording
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
