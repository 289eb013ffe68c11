"""Analysis of one adhesion test: from a recording to phases, corrected CoA, branches and fits.

The thin orchestration layer over :mod:`rollerrig.measure` (quantities, segmentation,
correction), :mod:`rollerrig.signal` (Savitzky-Golay tuning, filter study, spectra) and
:mod:`rollerrig.fit` (Polach). Each step is a public function of those modules; this module only
chains them in the order an analyst would and keeps what each step found.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from rollerrig.fit.polach import PolachFit, creep_stiffness_for_rig, fit_polach
from rollerrig.measure.correction import corrected_adhesion
from rollerrig.measure.quantities import derive_quantities
from rollerrig.measure.recording import Recording, RecordingError
from rollerrig.measure.segmentation import (
    Branches,
    Hysteresis,
    Phase,
    adhesion_branches,
    hysteresis,
    segment_test,
)
from rollerrig.signal.scoring import StudyRow, prepare_study_signal
from rollerrig.signal.smoothing import savitzky_golay
from rollerrig.signal.workflow import ExplainedSpectrum, explain_recording

__all__ = [
    "ANALYSIS_RATE",
    "DECIMATE_ABOVE",
    "MAX_FIT_POINTS",
    "TestAnalysis",
    "analysis_recording",
    "analyze_test",
    "check_channel_values",
    "describe_channel",
    "fill_short_gaps",
    "quiet_phase",
    "recording_facts",
    "recording_note_lines",
    "true_polach_parameters",
]

# Channels the analysis reads, checked for values it can compute with.
_ANALYSED_CHANNELS = (
    "torque",
    "torque_request",
    "wheel_speed",
    "roller_speed",
    "wheel_encoder_counts",
    "roller_encoder_counts",
    "air_spring_pressure",
    "normal_load",
)
ANALYSIS_RATE = 1000.0
"""Rate [Hz] :func:`analyze_test` works at for recordings faster than :data:`DECIMATE_ABOVE`.

The anti-alias decimation (:func:`rollerrig.signal.decimate.decimate_recording`) keeps
0-400 Hz (within 0.03 %): the torsional modes of the rig (up to ~112 Hz), the motor lines and
the roller acceleration of the dynamics correction, at 1/19 of the samples of a 19.2 kHz
recording (one hour: 3.6 M samples per channel instead of 69 M).
"""

DECIMATE_ABOVE = 1500.0
"""Recordings faster than this [Hz] are decimated to :data:`ANALYSIS_RATE` before the analysis."""

MAX_FIT_POINTS = 5000
"""Most ascending-branch points a Polach fit uses; above it every k-th point is taken [1]."""

_TORQUE_RANGE_FACTOR = 10.0  # torque beyond 10 x the sensor's range: a unit or scale mistake
_TRUTH_SIGMA = 3.0  # fitted parameters further than this from a known truth are flagged
_SYMBOLS = {
    "static_friction": "μ0",
    "limit_ratio": "A",
    "friction_decay": "B [s/m]",
    "k_adhesion": "kA",
    "k_slip": "kS",
}


@dataclass
class TestAnalysis:
    """What :func:`analyze_test` found. Arrays on the recording's time axis, SI units."""

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
    fit_rig_coa: PolachFit | None  # to the CoA as the rig reports it, T56 / (r_r N)
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
            else {"window [s]": list(self.spectrum_window), **self.spectrum.summary()},
            "filter_study_top10": [row.as_dict() for row in self.study[:10]],
            "filter_study_basis": None if basis is None else basis.as_dict(),
            "filter_study_unscored": dict(getattr(self.study, "unscored", {}) or {}),
            "truth_errors": self.truth_errors,
            "notes": self.notes,
        }
        if basis is None:
            out["filter_study_basis_null_because"] = "the filter study was not run (run_study)"
        return out

    def _smoothing(self) -> dict:
        rate = _rate(self.recording)
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


def _rate(recording: Recording) -> float:
    """Sample rate [Hz] of a uniform recording, to 10 significant digits (19200, not 19199.99)."""
    return float(f"{recording.sample_rate:.10g}")


def _fit_dict(fit: PolachFit | None, points: dict, truth: dict | None = None) -> dict | None:
    if fit is None:
        return None
    p = fit.parameters
    stderr = {k: _finite_or_none(v) for k, v in fit.stderr.items()}
    out = {
        "mu0": p.static_friction,
        "A": p.limit_ratio,
        "B [s/m]": p.friction_decay,
        "kA": p.k_adhesion,
        "kS": p.k_slip,
        "stderr": stderr,
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
        "truth_distance": None if truth is None else fit.truth_distance(truth, _TRUTH_SIGMA),
        "truth_distance_warn_sigma": _TRUTH_SIGMA,
    }
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


def describe_channel(recording: Recording, name: str) -> str:
    """How to find a channel in the user's file: its name, file column and map entry."""
    columns = recording.metadata.get("columns") or {}
    column = columns.get(name) if isinstance(columns, dict) else None
    where = f", file column {column!r}" if column else ""
    return f"channel {name!r} (map entry [channels.{name}]{where})"


def _source(recording: Recording) -> str:
    src = recording.metadata.get("source")
    return f"{src}: " if src else ""


def check_channel_values(recording: Recording, names, rig=None) -> None:
    """Refuse channels whose values no analysis can compute with, naming channel and map entry.

    Every given channel (those present) must be finite and small enough that sums of squares
    over the recording stay finite; the torque must stay within 10 x the torque sensor's range
    of the rig (``sensors.torque_sensor_range``), beyond which it is a unit or scale mistake.

    Parameters
    ----------
    recording : Recording
    names : iterable of str
        Channels to check (absent ones are skipped).
    rig : RigParameters, optional
        For the torque sensor's range.

    Raises
    ------
    RecordingError
        Naming the file, the channel, its file column and map entry, and what to check.

    Examples
    --------
    >>> t = np.arange(4) / 250.0
    >>> rec = Recording(t, {"torque": np.full(4, 1e300)}, {"torque": "N.m"})
    >>> check_channel_values(rec, ["torque"])
    Traceback (most recent call last):
    ...
    rollerrig.measure.recording.RecordingError: channel 'torque' (map entry [channels.torque]) reaches 1e+300 N.m: too large to compute with (its squares overflow); check the unit, scale and offset of that map entry
    """  # noqa: E501
    for name in names:
        if name not in recording:
            continue
        x = np.asarray(recording[name], dtype=float)
        unit = recording.units.get(name, "")
        what = f"{_source(recording)}{describe_channel(recording, name)}"
        bad = ~np.isfinite(x)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise RecordingError(
                f"{what} has {int(bad.sum())} NaN/inf samples, first at sample {k}; a lenient "
                "read (--lenient) interpolates short runs"
            )
        peak = float(np.max(np.abs(x))) if x.size else 0.0
        with np.errstate(over="ignore"):
            overflow = not np.isfinite(np.sum(x * x))
        if overflow:
            raise RecordingError(
                f"{what} reaches {peak:.3g} {unit}: too large to compute with (its squares "
                "overflow); check the unit, scale and offset of that map entry"
            )
        if name == "torque" and rig is not None:
            rated = float(getattr(rig.sensors, "torque_sensor_range", 0.0) or 0.0)
            if rated > 0 and peak > _TORQUE_RANGE_FACTOR * rated:
                raise RecordingError(
                    f"{what} reaches {peak:.3g} N.m, more than {_TORQUE_RANGE_FACTOR:g} x the "
                    f"torque sensor's range ({rated:g} N.m, sensors.torque_sensor_range of the "
                    "rig file): check the unit and scale of that map entry (or the rig file)"
                )


def fill_short_gaps(recording: Recording) -> tuple[Recording, list[str]]:
    """The recording on a uniform time base, short gaps filled; for analyses that need one.

    A lenient read keeps gaps (dropped samples, ``metadata["gaps"]``). Gaps of at most
    :data:`rollerrig.measure.readers.MAX_INTERPOLATED_NAN_RUN` missing samples are filled by
    linear interpolation of every channel onto the uniform grid t0 + k/f_s (the policy of
    NaN runs); a longer gap is an error naming it. The recording's metadata keeps its
    ``gaps``; the notes say what was filled.

    Returns
    -------
    (Recording, list of str)
        The uniform recording (the input itself when it has no gap) and one note per gap.

    Raises
    ------
    RecordingError
        A gap longer than the interpolation limit, with its time and size.
    """
    from rollerrig.measure.readers import GAP_FACTOR, MAX_INTERPOLATED_NAN_RUN

    t = recording.time
    dt = np.diff(t)
    step = float(np.median(dt))
    if not np.any(dt > GAP_FACTOR * step) and np.all(np.abs(dt - step) <= 0.01 * step):
        return recording, []
    notes = []
    for k in np.flatnonzero(dt > GAP_FACTOR * step):
        missing = round(float(dt[k]) / step) - 1
        where = (
            f"{_source(recording)}gap of {dt[k]:.6g} s after t = {t[k]:.6g} s (sample {k}, "
            f"about {missing} missing sample(s))"
        )
        if missing > MAX_INTERPOLATED_NAN_RUN:
            raise RecordingError(
                f"{where}: too long to fill for the analysis (at most "
                f"{MAX_INTERPOLATED_NAN_RUN} samples); analyse the parts before and after it "
                "separately"
            )
        notes.append(f"{where} filled by linear interpolation onto the uniform time base")
    n = round(float(t[-1] - t[0]) / step) + 1
    grid = t[0] + np.arange(n) * step
    grid[-1] = min(grid[-1], t[-1])
    channels = {name: np.interp(grid, t, x) for name, x in recording.channels.items()}
    if not notes:
        notes.append(
            "irregular sample times (jitter above 1 % of the step) put onto a uniform time base"
            " by linear interpolation"
        )
    meta = dict(recording.metadata)
    meta["notes"] = [*list(meta.get("notes") or []), *notes]
    return Recording(grid, channels, dict(recording.units), meta), notes


def _stored(recording: Recording) -> dict:
    stored = recording.metadata.get("stored_metadata")
    return stored if isinstance(stored, dict) else {}


def recording_facts(recording: Recording) -> dict:
    """What the reader and the generator said about a recording, JSON-ready.

    Returns
    -------
    dict
        ``source``, ``format``, ``sha256``, ``validate``; ``notes`` (the reader's notes and,
        for a synthetic recording, the generator's), ``interpolated`` (NaN/inf runs filled by
        a lenient read: channel, samples, times, method), ``gaps`` (dropped samples kept by a
        lenient read), ``resampled`` (channels put on a common time base), ``injected_lines``
        (lines injected by hand into a synthetic recording, with frequency and amplitude) and
        ``synthetic``.
    """
    md = recording.metadata
    stored = _stored(recording)
    notes = [str(n) for n in (md.get("notes") or [])]
    for n in stored.get("notes") or []:
        if str(n) not in notes:
            notes.append(str(n))
    injected = list(md.get("injected_lines") or stored.get("injected_lines") or [])
    synthetic = bool(
        md.get("synthetic")
        or stored.get("synthetic")
        or md.get("source") == "synthetic"
        or stored.get("source") == "synthetic"
    )
    return {
        "source": md.get("source"),
        "format": md.get("format"),
        "sha256": md.get("sha256"),
        "validate": md.get("validate"),
        "notes": notes,
        "interpolated": list(md.get("interpolated") or []),
        "gaps": list(md.get("gaps") or []),
        "resampled": md.get("resampled"),
        "injected_lines": injected,
        "synthetic": synthetic,
    }


def recording_note_lines(recording: Recording) -> list[str]:
    """The same facts as :func:`recording_facts`, one human-readable line each."""
    facts = recording_facts(recording)
    lines = list(facts["notes"])
    for run in facts["interpolated"]:
        lines.append(
            f"interpolated NaN/inf run (lenient read): channel {run.get('channel')!r}, samples "
            f"{run.get('first_sample')}..{run.get('last_sample')} "
            f"(t = {run.get('start_s', float('nan')):.6g}..{run.get('end_s', float('nan')):.6g} s),"
            f" {run.get('method', 'linear')}"
        )
    for gap in facts["gaps"]:
        lines.append(
            f"gap kept (lenient read): {gap.get('duration_s', float('nan')):.6g} s after "
            f"t = {gap.get('start_s', float('nan')):.6g} s (sample {gap.get('sample')}, about "
            f"{gap.get('missing_samples')} missing sample(s))"
        )
    for line in facts["injected_lines"]:
        text = (
            f"synthetic recording: a line at {line.get('frequency [Hz]')} Hz, "
            f"{line.get('amplitude [N.m]')} N.m on {line.get('channel', 'torque')} was INJECTED"
        )
        if not any("INJECTED" in n for n in lines):
            lines.append(text + " by hand; it is not a finding")
    return lines


def true_polach_parameters(recording: Recording, truth=None) -> tuple[dict | None, str]:
    """The twin's Polach parameters of a synthetic recording, if it ran with one friction set.

    Looked up in the recording's metadata (``true_polach_parameters``, written by
    :func:`rollerrig.measure.synthetic.synthetic_recording`, also after a round trip through a
    file as ``stored_metadata``), else in the twin's provenance (``friction_sets`` and the
    protocol's ``friction_condition``) stored with the recording or in the ``truth`` dataset.

    Returns
    -------
    (dict or None, str)
        The parameters by :data:`rollerrig.fit.polach.PARAMETER_NAMES` and where they came
        from; ``(None, reason)`` when no single true set is known.
    """
    import json

    md, stored = recording.metadata, _stored(recording)
    for where, holder in (("recording metadata", md), ("metadata stored in the file", stored)):
        sets = holder.get("true_polach_parameters")
        if isinstance(sets, dict) and sets:
            if len(sets) == 1:
                ((name, params),) = sets.items()
                return dict(params), f"{where}: the twin's '{name}' set"
            return None, f"{where}: several friction sets ({', '.join(sets)}), no single truth"
    candidates = [
        ("the twin's provenance in the recording", md.get("twin_provenance")),
        ("the twin's provenance stored in the file", stored.get("twin_provenance")),
        (
            "the truth dataset's provenance",
            None if truth is None else truth.attrs.get("provenance"),
        ),
    ]
    for where, raw in candidates:
        if raw is None:
            continue
        try:
            prov = json.loads(raw) if isinstance(raw, str) else dict(raw)
        except (TypeError, ValueError):
            continue
        sets = prov.get("friction_sets") or {}
        used = sorted(set(prov.get("protocol", {}).get("friction_condition", []) or []))
        if len(used) == 1 and used[0] in sets:
            return dict(sets[used[0]]), f"{where}: the twin's '{used[0]}' set"
    return None, "no twin truth known (not a synthetic recording)"


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


def _odd(n: float) -> int:
    k = max(round(n), 7)
    return k if k % 2 else k + 1


def quiet_phase(phases: list[Phase]) -> tuple[float, float] | None:
    """The longest phase without torque activity (free rolling or rest) [s], for spectra."""
    quiet = [ph for ph in phases if ph.name in ("free_rolling", "rest")]
    if not quiet:
        return None
    best = max(quiet, key=lambda ph: ph.end - ph.start)
    return best.start, best.end


def analysis_recording(recording, *, rate: float | None = None, above: float | None = None):
    """The recording at the rate the analysis works at, and a note saying what was done.

    A recording faster than ``above`` (default :data:`DECIMATE_ABOVE`, 1.5 kHz) is brought to
    ``rate`` (default :data:`ANALYSIS_RATE`, 1 kHz) by the zero-phase anti-alias FIR of
    :func:`rollerrig.signal.decimate.decimate_recording` (every channel; the metadata's
    ``notes`` and ``decimated`` say how). An open
    :class:`rollerrig.measure.source.RecordingSource` is decimated while it is read, chunk by
    chunk, and never held at its own rate; a source at or below ``above`` is read whole.

    Parameters
    ----------
    recording : Recording or RecordingSource
        Uniformly sampled (a lenient read's gaps filled first: :func:`fill_short_gaps`).
    rate : float, optional
        Analysis rate [Hz]; default :data:`ANALYSIS_RATE`. At or above the recording's own
        rate nothing is decimated.
    above : float, optional
        Recordings faster than this [Hz] are decimated; default :data:`DECIMATE_ABOVE`.

    Returns
    -------
    (Recording, str or None)
        The recording to analyse, and a note for the analysis' notes (None when nothing was
        done).

    Raises
    ------
    RecordingError
        Naming the file: a non-uniform time base, non-finite samples (a source is read
        strictly).

    Examples
    --------
    >>> t = np.arange(19200) / 19200.0
    >>> rec, note = analysis_recording(Recording(t, {"torque": 100.0 + t}, {"torque": "N.m"}))
    >>> round(rec.sample_rate), rec.metadata["decimated"]["from_rate_Hz"]
    (1000, 19200.0)
    >>> note[:48]
    'analysed at 1000 Hz: the recording (19200 Hz) wa'
    """
    from rollerrig.signal.decimate import decimate_recording

    rate = ANALYSIS_RATE if rate is None else float(rate)
    above = DECIMATE_ABOVE if above is None else float(above)
    streamed = hasattr(recording, "iter_chunks")
    fs = float(f"{float(recording.sample_rate):.10g}")
    if fs <= above or rate >= fs * (1.0 - 1e-9):
        if streamed:  # slow enough to hold: read it whole
            chunk = recording.read()
            meta = dict(recording.metadata)
            meta["notes"] = list(meta.get("notes") or [])
            return Recording(
                np.array(chunk.time),
                {name: np.array(v) for name, v in chunk.channels.items()},
                dict(recording.units),
                meta,
            ), None
        return recording, None
    out = decimate_recording(recording, rate)
    how = "while streaming it from the file, never holding it whole" if streamed else "first"
    note = (
        f"analysed at {out.metadata['decimated']['rate_Hz']:g} Hz: the recording ({fs:g} Hz) "
        f"was decimated {how} (recordings faster than {above:g} Hz are; ANALYSIS_RATE, "
        "DECIMATE_ABOVE); 0-400 Hz is kept, the rig's torsional modes and motor lines included"
    )
    return out, note


def _analysis_rate_facts(rec: Recording, above: float) -> dict:
    """What the summary says about the rate the analysis ran at."""
    decimated = rec.metadata.get("decimated")
    rate = _rate(rec)
    out = {
        "rate [Hz]": rate,
        "recording rate [Hz]": float(decimated["from_rate_Hz"]) if decimated else rate,
        "decimated above [Hz]": above,
        "decimation": dict(decimated) if decimated else None,
    }
    if not decimated:
        out["decimation_null_because"] = (
            f"the recording ({rate:g} Hz) is not faster than {above:g} Hz"
        )
    return out


# What an adhesion-test analysis needs, each as alternatives a channel map can give.
_ANALYSIS_INPUTS = (
    (("torque",), "the roller-shaft torque T56"),
    (("roller_speed", "roller_encoder_counts"), "the roller speed"),
    (("wheel_speed", "wheel_encoder_counts"), "the wheel speed"),
    (("normal_load", "air_spring_pressure"), "the normal load"),
)


def _require_analysis_inputs(recording) -> None:
    """RecordingError naming the channel-map entries to add when an input is missing."""
    have = set(recording.names if hasattr(recording, "iter_chunks") else recording.channels)
    missing = [
        (names, what) for names, what in _ANALYSIS_INPUTS if not any(n in have for n in names)
    ]
    if missing:
        source = recording.metadata.get("source", "the recording")
        wants = "; ".join(
            f"{what}: [channels.{names[0]}]"
            + (f" or [channels.{names[1]}]" if len(names) > 1 else "")
            for names, what in missing
        )
        raise RecordingError(
            f"{source}: an adhesion-test analysis needs {wants}; add these entries to the "
            f"channel map (--channels), the recording has {sorted(have)}"
        )


def analyze_test(
    recording: Recording,
    rig=None,
    *,
    truth=None,
    smoothing: tuple[int, int] | None = None,
    run_study: bool = True,
    analysis_rate: float | None = None,
    max_fit_points: int | None = None,
) -> TestAnalysis:
    """Analyse one adhesion test.

    Steps: a recording faster than :data:`DECIMATE_ABOVE` (1.5 kHz) brought to
    ``analysis_rate`` (default :data:`ANALYSIS_RATE`, 1 kHz) by an anti-alias FIR
    (:func:`analysis_recording`; stated in the notes and the summary's ``analysis_rate``); the
    physical quantities the rig derives (normal force from pressure, speeds from the encoders,
    creep, CoA = T/(r_r N)); the phases of the test; a Savitzky-Golay order and window tuned on
    the torque (or given); smoothed torque and speeds, and the creep and CoA from them; the CoA
    corrected for the roller's inertia and bearing loss
    (:func:`rollerrig.measure.correction.corrected_adhesion`); ascending and descending
    branches per cycle and their hysteresis; Polach fits to the ascending branches of the
    corrected and of the rig's CoA (on at most ``max_fit_points`` points: every k-th point
    when there are more, stated); the spectrum of the longest quiet phase with every peak
    explained (the rig's torsional modes among the candidates); the seed's filter study,
    ranked.

    Parameters
    ----------
    recording : Recording or RecordingSource
        Needs ``torque``, speeds or encoder counts, and the normal load or air-spring pressure.
        An open :class:`rollerrig.measure.source.RecordingSource` (a long file) is decimated
        while it is read and never held at its own rate (:func:`analysis_recording`).
    rig : RigParameters, optional
        The rig the test ran on (geometry, inertia, bearings, sensors); default the bundled rig.
    truth : xarray.Dataset, optional
        For synthetic recordings, the twin's truth on the recording's time axis (or, for a
        recording decimated by :func:`analysis_recording`, on the original one): adds the
        errors of the rig's and the corrected CoA against the true contact CoA, taken at the
        analysis instants.
    smoothing : (order, window), optional
        Fix the Savitzky-Golay filter instead of tuning it (window in samples at the analysis
        rate).
    run_study : bool
        Run the full filter study.
    analysis_rate : float, optional
        Rate [Hz] recordings faster than :data:`DECIMATE_ABOVE` are analysed at; default
        :data:`ANALYSIS_RATE`.
    max_fit_points : int, optional
        Most points a Polach fit uses; default :data:`MAX_FIT_POINTS`.

    Returns
    -------
    TestAnalysis
    """
    from rollerrig.rig.parameters import default_rig

    notes: list[str] = []
    if rig is None:
        rig = default_rig()
        notes.append("no rig given: the bundled default rig's parameters were used")
    cap = MAX_FIT_POINTS if max_fit_points is None else int(max_fit_points)
    if cap < 10:
        raise RecordingError(f"max_fit_points must be at least 10, got {max_fit_points!r}")
    _require_analysis_inputs(recording)
    if hasattr(recording, "iter_chunks"):  # an open file, read strictly chunk by chunk
        recording, rate_note = analysis_recording(recording, rate=analysis_rate)
        check_channel_values(recording, _ANALYSED_CHANNELS, rig)
        truth_on = None if truth is None else _truth_coa(truth, recording)
    else:
        check_channel_values(recording, _ANALYSED_CHANNELS, rig)
        recording, _ = fill_short_gaps(recording)  # the notes go into the metadata's notes
        truth_on = None if truth is None else _truth_coa(truth, recording)
        recording, rate_note = analysis_recording(recording, rate=analysis_rate)
    if rate_note:
        notes.append(rate_note)
    rec = derive_quantities(recording, rig)
    rec.require("torque", "creep", "coa", "normal_load", "roller_speed", "wheel_speed")
    check_channel_values(rec, ("creep", "coa", "normal_load", "roller_speed", "wheel_speed"))
    t, fs = rec.time, rec.sample_rate
    truth_coa = None if truth_on is None else np.interp(t, *truth_on)  # on the analysis axis

    phases = segment_test(rec)
    _require_a_test(rec, phases)
    # One study signal (the torque at the study's rate) for the tuning and the filter study.
    study_signal = (
        prepare_study_signal(t, rec["torque"]) if smoothing is None or run_study else None
    )
    if smoothing is None:
        order, window, table = study_signal.tune_savitzky_golay()
    else:
        (order, window), table = smoothing, []
    torque_s = savitzky_golay(rec["torque"], window, order)
    wheel_s = savitzky_golay(rec["wheel_speed"], window, order)
    roller_s = savitzky_golay(rec["roller_speed"], window, order)
    rw, rr = rig.geometry.wheel_radius_x, rig.geometry.roller_radius_x
    v_roller = roller_s * rr
    slip_s = wheel_s * rw - v_roller
    creep_s = np.divide(slip_s, v_roller, out=np.zeros_like(slip_s), where=np.abs(v_roller) > 1e-3)
    coa_s = torque_s / (rr * rec["normal_load"])
    b = rig.bearing
    coa_c, alpha = corrected_adhesion(
        rec["torque"],
        rec["roller_speed"],
        rec["normal_load"],
        fs,
        roller_radius=rr,
        roller_inertia=rig.inertia.roller,
        bearing_friction=b.friction_coefficient,
        bearing_radius=b.roller_bearing_radius,
        roller_weight=b.roller_subsystem_weight,
        regularisation_speed=b.regularisation_speed,
        # The acceleration needs less smoothing than the noise does: a 0.2 s quartic SG keeps
        # the transients (measured: CoA error 0.009 vs 0.019 with a 0.8 s quadratic one).
        window=_odd(0.2 * fs),
        order=4,
    )
    rec = rec.with_channels(
        torque_smoothed=torque_s,
        creep_smoothed=creep_s,
        slip_velocity_smoothed=slip_s,
        coa_smoothed=coa_s,
        coa_corrected=coa_c,
        roller_acceleration=alpha,
    )

    branches = adhesion_branches(t, creep_s, phases)
    hyst: list[Hysteresis | None] = []
    for br in branches:
        try:
            hyst.append(
                hysteresis(
                    creep_s[br.ascending],
                    coa_s[br.ascending],
                    creep_s[br.descending],
                    coa_s[br.descending],
                )
            )
        except ValueError as exc:  # branches that do not overlap in creep
            hyst.append(None)
            notes.append(f"cycle {br.cycle}: no hysteresis ({exc})")

    fit = fit_rig = None
    points = np.array([], dtype=int)
    if branches:
        points = np.concatenate([br.ascending for br in branches])
        points = points[(creep_s[points] > 1e-4) & (coa_s[points] > 0.01)]
    available, step = int(points.size), max(1, math.ceil(points.size / cap))
    if step > 1:
        points = points[::step]
        notes.append(
            f"Polach fits on one in {step} of the {available} ascending-branch points "
            f"({points.size} used; a fit uses at most {cap} points, MAX_FIT_POINTS): the "
            "points are consecutive samples of smooth branches, so the thinned set spans the "
            "same creep and slip-velocity range"
        )
    if points.size >= 10:
        load = rec["normal_load"][points]
        stiffness = creep_stiffness_for_rig(float(np.median(load)), rig)
        fits = []
        for label, coa_points in (("corrected CoA", coa_c[points]), ("rig CoA", coa_s[points])):
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                fits.append(
                    fit_polach(
                        creep_s[points], coa_points, load, stiffness, slip_velocity=slip_s[points]
                    )
                )
                notes.extend(
                    f"fit to the {label}: {m}"
                    for m in dict.fromkeys(str(w.message) for w in caught)
                )
        fit, fit_rig = fits
    else:
        notes.append("too few ascending-branch points for a Polach fit")
    true_params, true_source = true_polach_parameters(recording, truth)
    if true_params is not None:
        for label, f in (("corrected CoA", fit), ("rig CoA", fit_rig)):
            if f is None:
                continue
            far = {
                name: row
                for name, row in f.truth_distance(true_params, _TRUTH_SIGMA).items()
                if row["beyond_warn_sigma"]
            }
            if far:
                notes.append(
                    f"fit to the {label} misses the twin's true Polach set by more than "
                    f"{_TRUTH_SIGMA:g} standard errors: "
                    + ", ".join(
                        f"{_SYMBOLS[n]} {r['fitted']:.4g} ± {r['stderr']:.2g} against "
                        f"{r['true']:.4g} ({r['sigma']:.1f} σ)"
                        for n, r in far.items()
                    )
                    + "; the standard errors cover the noise, not the systematic errors of the "
                    "data (smoothing, the dynamics correction, unidentifiable A and B)"
                )

    spectrum, window_s = None, quiet_phase(phases)
    if window_s is not None and (window_s[1] - window_s[0]) * fs >= 256:
        quiet = rec.select(*window_s)
        # The one spectrum workflow: settings from the signal, the twin's damped modes.
        try:
            spectrum = explain_recording(quiet, "torque", rig)
        except RecordingError as exc:  # e.g. a torque without variation in the quiet phase
            notes.append(f"spectrum of the quiet phase skipped: {exc}")
    else:
        notes.append("no quiet phase of at least 256 samples: spectrum skipped")

    study = study_signal.filter_study() if run_study else []

    errors = {}
    if truth_coa is not None:
        true_coa = truth_coa

        def rms(x):
            return float(np.sqrt(np.mean((x - true_coa) ** 2)))

        errors = {
            "rig_coa_vs_true_rms [-]": rms(rec["coa"]),
            "smoothed_rig_coa_vs_true_rms [-]": rms(coa_s),
            "corrected_coa_vs_true_rms [-]": rms(coa_c),
            "corrected_coa_vs_true_max [-]": float(np.max(np.abs(coa_c - true_coa))),
        }
    return TestAnalysis(
        recording=rec,
        rig_name=rig.meta.name,
        phases=phases,
        smoothing_order=int(order),
        smoothing_window=int(window),
        smoothing_table=table,
        branches=branches,
        hysteresis=hyst,
        fit=fit,
        fit_rig_coa=fit_rig,
        fit_points=points,
        spectrum=spectrum,
        spectrum_window=window_s,
        study=study,
        notes=notes,
        truth_errors=errors,
        true_parameters=true_params,
        true_parameters_source=true_source,
        fit_points_available=available,
        fit_points_step=step,
        fit_points_cap=cap,
        true_coa=truth_coa,
        analysis_rate=_analysis_rate_facts(rec, DECIMATE_ABOVE),
    )


def _truth_coa(truth, rec: Recording) -> tuple[np.ndarray, np.ndarray]:
    """The true contact CoA of a synthetic recording, checked against the recording's time.

    Returns ``(time, coa)``: the recording's time axis [s] when the truth has its samples, else
    the truth's own (a recording decimated by :func:`analysis_recording` while it was read,
    whose truth is at the original rate). The analysis takes the truth at its own instants by
    linear interpolation (exact at coinciding instants).
    """
    if "coa" not in getattr(truth, "data_vars", {}):
        raise RecordingError(
            "the truth dataset has no 'coa' variable: give the *-truth.nc file that "
            "synthetic_recording wrote beside the recording"
        )
    coa = np.asarray(truth["coa"].values, dtype=float).reshape(-1)
    where = getattr(truth, "encoding", {}).get("source")
    what = f"the truth {where}" if where else "the truth"
    t_truth = (
        np.asarray(truth["time"].values, dtype=float).reshape(-1)
        if "time" in getattr(truth, "coords", {})
        else None
    )
    if t_truth is not None and t_truth.size != coa.size:
        raise RecordingError(f"{what}: its 'coa' and 'time' differ in length")
    if not np.all(np.isfinite(coa)):
        raise RecordingError(f"{what}: its 'coa' has NaN/inf samples")
    if coa.size == rec.time.size:
        if t_truth is not None:
            dt = float(np.max(np.abs(t_truth - rec.time)))
            if dt > 0.5 / rec.sample_rate:
                raise RecordingError(
                    f"{what}: its time axis differs from the recording's by up to {dt:.3g} s: "
                    "it is not the truth of this recording"
                )
        return rec.time, coa
    decimated = rec.metadata.get("decimated")
    if decimated and t_truth is not None and t_truth.size >= 2:
        # A recording decimated while it was read: the truth is at the original rate.
        f_in = float(decimated["from_rate_Hz"])
        step = float(np.median(np.diff(t_truth)))
        start_off = abs(float(t_truth[0] - rec.time[0]))
        end_off = float(t_truth[-1] - rec.time[-1])
        out_step = 1.0 / rec.sample_rate
        if (
            abs(step * f_in - 1.0) <= 1e-3
            and start_off <= 0.5 / f_in
            and -0.5 / f_in <= end_off < out_step + 0.5 / f_in
        ):
            return t_truth, coa
    rate = f" ({rec.sample_rate:.6g} Hz)"
    if decimated:
        rate = f" at {rec.sample_rate:.6g} Hz, decimated from {decimated['from_rate_Hz']:g} Hz"
    raise RecordingError(
        f"{what} has {coa.size} samples, the recording {rec.time.size}{rate}: it is not the "
        "truth of this recording (give the *-truth.nc written with it)"
    )


def _require_a_test(rec: Recording, phases) -> None:
    """Refuse a recording without an adhesion test, naming the channel that was segmented."""
    source = "torque_request" if "torque_request" in rec else "torque"
    u = np.asarray(rec[source], dtype=float)
    t = rec.time
    # Noise of the segmented channel from successive differences (robust: MAD).
    d = np.diff(u)
    noise = 1.4826 * float(np.median(np.abs(d - np.median(d)))) / np.sqrt(2.0)
    rises = []
    for ph in phases:
        if ph.name != "ramp_up" or ph.start <= t[0]:
            continue
        i0, i1 = np.searchsorted(t, [ph.start, ph.end])
        i1 = min(int(i1), t.size - 1)
        a = float(np.median(u[max(int(i0) - 2, 0) : int(i0) + 3]))
        b = float(np.median(u[max(i1 - 2, 0) : i1 + 3]))
        rises.append(abs(b - a))
    if any(r > 5.0 * noise and r > 0 for r in rises):
        return
    unit = rec.units.get(source, "")
    lo, hi = float(np.min(u)), float(np.max(u))
    raise RecordingError(
        f"{_source(rec)}no adhesion test found: {describe_channel(rec, source)} shows no torque"
        f" ramp rising from a resting level (it stays within {lo:.4g}..{hi:.4g} {unit}, noise "
        f"{noise:.3g} {unit}). `rollerrig analyze` needs a test with ramp, hold and release; "
        "for free rolling use `rollerrig spectrum`, and check that the map entry names the "
        "right column"
    )
