"""What an adhesion-test analysis found (:class:`TestAnalysis`) and its JSON-ready summary.

:func:`rollerrig.analysis.adhesion.analyze_test` fills a :class:`TestAnalysis`;
:meth:`TestAnalysis.summary` says every result with units in the keys and never holds NaN or
inf (a number that cannot be given is ``None`` with the reason beside it).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rollerrig._display import fmt, html_table, short_list, text_block
from rollerrig.estimation.budget import CoaBudget
from rollerrig.fit.model import PARAMETER_NAMES
from rollerrig.fit.polach import PolachFit
from rollerrig.measure.facts import recording_facts
from rollerrig.measure.prepare import nominal_rate
from rollerrig.measure.segmentation import Branches, Hysteresis, Phase
from rollerrig.recordings.recording import Recording
from rollerrig.signal.scoring import StudyRow
from rollerrig.signal.workflow import ExplainedSpectrum

__all__ = ["FIT_KEYS", "TRUTH_SIGMA", "TestAnalysis"]

SYMBOLS = {
    "static_friction": "μ0",
    "limit_ratio": "A",
    "friction_decay": "B",
    "k_adhesion": "kA",
    "k_slip": "kS",
}
"""Polach's symbols for :data:`rollerrig.fit.model.PARAMETER_NAMES`."""

TRUTH_SIGMA = 3.0
"""Fitted parameters further than this many standard errors from a known truth are flagged."""


@dataclass
class TestAnalysis:
    """What :func:`rollerrig.analysis.adhesion.analyze_test` found.

    Arrays on the recording's time axis, SI units.
    """

    __test__ = False  # not a pytest class, despite its name

    recording: Recording  # raw, derived, smoothed and corrected channels
    rig_name: str
    phases: list[Phase]
    smoothing_order: int
    smoothing_window: int  # [samples]
    smoothing_table: list[StudyRow]
    branches: list[Branches]
    hysteresis: list[Hysteresis | None]
    fit: PolachFit | None  # to the dynamics-corrected CoA
    fit_rig_coa: PolachFit | None  # to the CoA as the rig reports it, T56 / (r_r S)
    fit_points: np.ndarray  # indices of the samples both fits used
    spectrum: ExplainedSpectrum | None
    spectrum_window: tuple[float, float] | None  # [s]
    study: list[StudyRow]
    notes: list[str] = field(default_factory=list)
    truth_errors: dict = field(default_factory=dict)
    true_parameters: dict | None = None  # the twin's Polach set (synthetic recordings)
    true_parameters_source: str = ""
    fit_points_available: int | None = None  # ascending-branch points before thinning
    fit_points_step: int = 1  # every k-th available point was fitted
    fit_points_cap: int | None = None  # the most points a fit uses (MAX_FIT_POINTS)
    true_coa: np.ndarray | None = None  # the twin's contact CoA on the analysis time axis
    analysis_rate: dict | None = None  # rate of the analysis and the decimation before it
    coa_uncertainty: CoaBudget | None = None  # the corrected CoA's uncertainty and budget
    rig_sha256: str | None = None  # rollerrig.output.rig_sha256 of the rig analysed with

    @property
    def spectrum_phase(self) -> Phase | None:
        """The phase the spectrum was computed over (the longest quiet one), if any."""
        if self.spectrum_window is None:
            return None
        start, end = self.spectrum_window
        return next((p for p in self.phases if (p.start, p.end) == (start, end)), None)

    def spectrum_basis(self) -> str | None:
        """One sentence for outputs: over which window [s] and phase the spectrum was computed
        (its caption gives the segments, not where they lie); None without a spectrum.

        E.g. "spectrum of the torque over 23.52-30.00 s: the rest phase of cycle 3, the longest
        phase without torque activity" (cycles numbered from 1, as the printed tables and the
        report number them; :attr:`phases` holds them from 0).
        """
        if self.spectrum is None or self.spectrum_window is None:
            return None
        start, end = self.spectrum_window
        text = f"spectrum of the {self.spectrum.channel} over {start:.2f}-{end:.2f} s"
        phase = self.spectrum_phase
        if phase is None:
            return text
        what = phase.name.replace("_", " ")
        # the cycle as the tables number it (from 1; a rest belongs to the cycle it ends)
        of = f" of cycle {phase.cycle + 1}" if phase.cycle >= 0 else ""
        return f"{text}: the {what} phase{of}, the longest phase without torque activity"

    def _repr_rows(self) -> tuple[str, list[tuple[str, str]]]:
        """The title and the (what, value) rows of the repr and the HTML table."""
        from pathlib import Path

        source = self.recording.metadata.get("source")
        name = Path(str(source)).name if source else "a recording"
        title = f"TestAnalysis of {name} on {self.rig_name}"
        rec = self.recording
        rows = [
            ("recording", f"{rec.time.size} samples at {fmt(rec.sample_rate)} Hz, "
             f"{fmt(rec.duration)} s"),
            ("phases", f"{len(self.phases)} ({short_list([p.name for p in self.phases], 4)})"),
            ("smoothing", f"Savitzky-Golay, order {self.smoothing_order}, "
             f"{self.smoothing_window} samples"),
        ]  # fmt: skip
        for label, fit in (("corrected CoA", self.fit), ("rig's CoA", self.fit_rig_coa)):
            if fit is None:
                rows.append((f"Polach fit, {label}", "none"))
                continue
            text = ", ".join(f"{SYMBOLS[k]} {fit.shown(k)}" for k in PARAMETER_NAMES)
            verdict = "identifiable" if fit.identifiable else "not identifiable (see .notes)"
            rows.append((f"Polach fit, {label}", f"{text}; RMS {fmt(fit.rmse, 3)}; {verdict}"))
        rows.append(("notes", f"{len(self.notes)} (.notes); every result: .summary()"))
        return title, rows

    def __repr__(self) -> str:
        """A few lines: the recording, phases, smoothing, the Polach fits and their verdicts."""
        title, rows = self._repr_rows()
        return text_block(title, [f"{what}: {value}" for what, value in rows])

    def _repr_html_(self) -> str:
        """The same as :meth:`__repr__`, as a small HTML table."""
        title, rows = self._repr_rows()
        return html_table(title, rows)

    @property
    def smoothing_tuned_at(self) -> float | None:
        """Rate the Savitzky-Golay tuning ran at [Hz] (None when the filter was given)."""
        basis = getattr(self.smoothing_table, "basis", None)
        return None if basis is None else float(basis.analysis_rate)

    def summary(self) -> dict:
        """A JSON-ready summary of every result, with units in the keys.

        Never holds NaN or inf: a number that cannot be given is ``None`` with a reason beside
        it. ``recording`` carries what the reader and the generator said about the recording
        (notes, interpolated NaN runs, gaps, injected lines); ``analysis_rate`` the rate the
        analysis ran at and the decimation that brought the recording to it.
        """
        basis = getattr(self.study, "basis", None)
        out = {
            "rig": self.rig_name,
            "recording": recording_facts(self.recording),
            "phases": [
                {"name": ph.name, "start [s]": ph.start, "end [s]": ph.end, "cycle": ph.cycle}
                for ph in self.phases
            ],
            "analysis_rate": self.analysis_rate,
            "smoothing": self._smoothing(),
            "hysteresis": [
                _hysteresis_dict(b, h) for b, h in zip(self.branches, self.hysteresis, strict=True)
            ],
            "polach_fit_corrected_coa": _fit_dict(self.fit, self._points(), self.true_parameters),
            "polach_fit_rig_coa": _fit_dict(self.fit_rig_coa, self._points(), self.true_parameters),
            "true_polach_parameters": None
            if self.true_parameters is None
            else {"parameters": self.true_parameters, "source": self.true_parameters_source},
            "spectrum": None
            if self.spectrum is None
            else {
                "window [s]": list(self.spectrum_window),
                "phase": None if self.spectrum_phase is None else self.spectrum_phase.name,
                "window_note": self.spectrum_basis(),
                **self.spectrum.summary(),
            },
            "filter_study_top10": [row.as_dict() for row in self.study[:10]],
            "filter_study_basis": None if basis is None else basis.as_dict(),
            "filter_study_unscored": dict(getattr(self.study, "unscored", {}) or {}),
            "truth_errors": self.truth_errors,
            "notes": self.notes,
        }
        if basis is None:
            out["filter_study_basis_null_because"] = "the filter study was not run (run_study)"
        if self.coa_uncertainty is None:
            out["coa_uncertainty"] = None
            out["coa_uncertainty_null_because"] = "the analysis was made without an uncertainty"
        else:
            out["coa_uncertainty"] = self.coa_uncertainty.summary()
        return out

    def _smoothing(self) -> dict:
        rate = nominal_rate(self.recording)
        out = {
            "method": "Savitzky-Golay",
            "order": self.smoothing_order,
            "window [samples]": self.smoothing_window,
            "samples at [Hz]": rate,
            "window [s]": self.smoothing_window / rate,
            "tuned at [Hz]": self.smoothing_tuned_at,
        }
        if self.smoothing_tuned_at is None:
            out["tuned_at_null_because"] = "the order and window were given, not tuned"
        return out

    def _points(self) -> dict:
        """Points the fits used, of how many available, and the thinning step."""
        used = int(self.fit_points.size)
        available = used if self.fit_points_available is None else int(self.fit_points_available)
        return {
            "used": used,
            "available": available,
            "step": int(self.fit_points_step),
            "cap": self.fit_points_cap,
        }


def _finite_or_none(value: float) -> float | None:
    value = float(value)
    return value if np.isfinite(value) else None


FIT_KEYS = {
    "static_friction": "mu0",
    "limit_ratio": "A",
    "friction_decay": "B [s/m]",
    "k_adhesion": "kA",
    "k_slip": "kS",
}
"""JSON key of each Polach parameter in a fit's block: its value's key, and the same key in the
block's per-parameter dicts (``stderr``, ``stderr_statistical``, ``systematic_shifts``,
``truth_distance``), which had been keyed by the API's names (``static_friction``, ...)."""


def _by_fit_key(values: dict | None, convert=lambda v: v) -> dict | None:
    """A per-parameter dict keyed as the fit's values are (:data:`FIT_KEYS`)."""
    if values is None:
        return None
    return {FIT_KEYS.get(k, k): convert(v) for k, v in values.items()}


def _fit_dict(fit: PolachFit | None, points: dict, truth: dict | None = None) -> dict | None:
    if fit is None:
        return None
    p = fit.parameters
    stderr = _by_fit_key(fit.stderr, _finite_or_none)
    out = {
        "mu0": p.static_friction,
        "A": p.limit_ratio,
        "B [s/m]": p.friction_decay,
        "kA": p.k_adhesion,
        "kS": p.k_slip,
        "stderr": stderr,
        "stderr_statistical": _by_fit_key(fit.stderr_statistical, _finite_or_none),
        "systematic_shifts": None
        if fit.systematic is None
        else {name: _by_fit_key(shift) for name, shift in fit.systematic.items()},
        "rmse [-]": float(fit.rmse),
        "points": points["used"],
        "points_available": points["available"],
        "points_step": points["step"],
        "identifiable": bool(fit.identifiable),
        "A_B_identifiable": None
        if fit.coverage is None
        else bool(fit.coverage.a_and_b_identifiable),
        "slip_velocity_coverage": None if fit.coverage is None else fit.coverage.as_dict(),
        "residual_structure": None
        if fit.residual_structure is None
        else fit.residual_structure.as_dict(),
        "truth_distance": None
        if truth is None
        else _by_fit_key(fit.truth_distance(truth, TRUTH_SIGMA)),
        "truth_distance_warn_sigma": TRUTH_SIGMA,
    }
    if fit.stderr_statistical is None:
        why = "stderr is the points' scatter alone: no systematic errors added to it"
        out["stderr_statistical_null_because"] = why
        out["systematic_shifts_null_because"] = why
    missing = [k for k, v in stderr.items() if v is None]
    if missing:
        out["stderr_null_because"] = (
            f"{', '.join(missing)}: not determined by the data (J^T J singular), no finite "
            "standard error"
        )
    if fit.residual_structure is None:
        out["residual_structure_null_because"] = "exact fit: residuals at round-off level"
    if points["step"] > 1:
        out["points_note"] = (
            f"one in {points['step']} of the {points['available']} ascending-branch points "
            f"fitted ({points['used']} used; a fit uses at most {points['cap']} points)"
        )
    return out


def _hysteresis_dict(branch: Branches, h: Hysteresis | None) -> dict | None:
    if h is None:
        return None
    return {
        "cycle": branch.cycle,
        "area [-]": h.area,
        "abs_area [-]": h.abs_area,
        "max_difference [-]": h.max_difference,
        "creep_at_max_difference [-]": h.creep_at_max_difference,
    }
