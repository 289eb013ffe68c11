"""Analysis of one adhesion test: from a recording to phases, corrected CoA, branches and fits.

The orchestration layer over :mod:`rollerrig.measure` (quantities, segmentation, correction),
:mod:`rollerrig.signal` (Savitzky-Golay tuning, filter study, spectra) and :mod:`rollerrig.fit`
(Polach). Each step is a public function of those modules; :func:`analyze_test` only chains them
in the order an analyst would and keeps what each step found in a
:class:`~rollerrig.analysis.findings.TestAnalysis`.

What the steps around it live in: :mod:`rollerrig.measure.checks` (inputs and values an
analysis can compute with), :mod:`rollerrig.measure.prepare` (uniform time base, analysis
rate), :mod:`rollerrig.measure.facts` (what is known about a recording, the twin's truth),
:mod:`rollerrig.analysis.findings` (the result and its summary). Steps of its own, each in its
module: :mod:`rollerrig.analysis.smoothed_channels` (the smoothed channels and the corrected
CoA), :mod:`rollerrig.analysis.polach_fits` (the fit points, one friction condition, the Polach
fits), :mod:`rollerrig.analysis.coa_estimates` (the corrected CoA's uncertainty, the online and
model-based estimates). Their public names are also importable from here.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig._warnings import DomainWarning
from rollerrig.analysis.coa_estimates import (
    MODEL_BASED,
    SHAFT_KEYS,
    SHAFT_RELATIVE_ERROR,
    _coa_uncertainty,
    _implausible_coa,
    _note_arm,
    _note_release_creep,
    _note_wheel_drive_voltage,
    shaft_calibrated,
)
from rollerrig.analysis.findings import TestAnalysis
from rollerrig.analysis.polach_fits import (
    FRICTION_SLOPE_RATIO,
    _fit_points,
    _note_friction_change,
    _note_truth_distance,
    _one_friction_condition,
    _polach_fits,
    _with_systematic_errors,
)
from rollerrig.analysis.smoothed_channels import CORRECTION_WINDOW, _smoothed_and_corrected
from rollerrig.analysis.truth import rig_mismatch, truth_mismatch
from rollerrig.estimation.uncertainty import calibration_covariance
from rollerrig.measure.checks import (
    ANALYSED_CHANNELS,
    check_channel_values,
    require_adhesion_test,
    require_analysis_inputs,
)
from rollerrig.measure.facts import (
    describe_channel,
    friction_schedule,
    recording_facts,
    recording_note_lines,
    true_polach_parameters,
    truth_coa,
)
from rollerrig.measure.prepare import (
    ANALYSIS_RATE,
    DECIMATE_ABOVE,
    analysis_rate_facts,
    analysis_recording,
    fill_short_gaps,
)
from rollerrig.measure.quantities import derive_quantities
from rollerrig.measure.segmentation import (
    Branches,
    Hysteresis,
    Phase,
    adhesion_branches,
    hysteresis,
    quiet_phase,
    segment_test,
)
from rollerrig.output import rig_sha256
from rollerrig.recordings.recording import Recording, RecordingError
from rollerrig.recordings.timebase import require_uniform_time
from rollerrig.signal.channel_checks import check_varies
from rollerrig.signal.scoring import prepare_study_signal
from rollerrig.signal.workflow import ExplainedSpectrum, explain_recording

__all__ = [
    "ANALYSIS_RATE",
    "CORRECTION_WINDOW",
    "DECIMATE_ABOVE",
    "FRICTION_SLOPE_RATIO",
    "MAX_FIT_POINTS",
    "MODEL_BASED",
    "SHAFT_KEYS",
    "SHAFT_RELATIVE_ERROR",
    "TestAnalysis",
    "analysis_recording",
    "analyze_test",
    "check_channel_values",
    "describe_channel",
    "fill_short_gaps",
    "quiet_phase",
    "recording_facts",
    "recording_note_lines",
    "shaft_calibrated",
    "true_polach_parameters",
]

MAX_FIT_POINTS = 5000
"""Most ascending-branch points a Polach fit uses; above it every k-th point is taken [-]."""


def analyze_test(
    recording: Recording,
    rig=None,
    *,
    truth=None,
    smoothing: tuple[int, int] | None = None,
    run_study: bool = True,
    analysis_rate: float | None = None,
    max_fit_points: int | None = None,
    calibration=None,
    progress: Callable[[str], None] | None = None,
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
    ranked. The corrected CoA's uncertainty (JCGM 100 per sample, JCGM 101 Monte Carlo at the
    creep–CoA points; :mod:`rollerrig.estimation.uncertainty`, :mod:`rollerrig.estimation.budget`),
    per phase and per point with its budget, is the result's ``coa_uncertainty``
    (a :class:`~rollerrig.estimation.budget.CoaBudget`).

    Parameters
    ----------
    recording : Recording or RecordingSource
        Needs ``torque``, speeds or encoder counts, and the normal load or air-spring pressure.
        An open :class:`rollerrig.recordings.source.RecordingSource` (a long file) is decimated
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
        Rate [Hz] recordings faster than :data:`DECIMATE_ABOVE` are analysed at, at least
        :data:`~rollerrig.measure.prepare.MIN_ANALYSIS_RATE` (250 Hz); default
        :data:`ANALYSIS_RATE`.
    max_fit_points : int, optional
        Most points a Polach fit uses; default :data:`MAX_FIT_POINTS`.
    calibration : mapping, optional
        What ``calibration.json`` holds (``rollerrig calibrate``): ``{"parameters": {key:
        {"value": v, "standard_error": s}}, "correlation": {"keys": [...], "matrix": [[...]]}}``
        (or ``"correlation": [[...]]`` with a top-level ``"keys"``), dotted rig keys in SI
        (the creep law's ``polach.*``, ``fastsim.*`` keys are ignored here; see
        :func:`~rollerrig.estimation.uncertainty.calibration_covariance`). The calibrated values
        replace the rig's (noted); the keys the corrected CoA depends on
        (:data:`~rollerrig.estimation.uncertainty.MODEL_KEYS`: J5, r_r, A, f_g, r_b, W_r) enter its
        uncertainty with their standard errors and correlations instead of the rig's stated
        accuracies.

    progress : callable, optional
        Called as ``progress(step)`` with a few words as each step starts ("fitting the
        Polach law", ...): what a command or a notebook shows while the analysis runs.

    Returns
    -------
    TestAnalysis
    """
    from rollerrig.rig.parameters import default_rig

    say = progress if progress is not None else (lambda step: None)

    notes: list[str] = []
    if rig is None:
        rig = default_rig()
        notes.append("no rig given: the bundled default rig's parameters were used")
    # The rig the recording states it was made on (the keys a calibration replaces aside).
    calibrated = {} if calibration is None else calibration_covariance(calibration)[0]
    other_rig = rig_mismatch(recording.metadata, rig, ignore=calibrated)
    if calibration is not None:
        rig = _calibrated_rig(rig, calibrated, notes)
    cap = MAX_FIT_POINTS if max_fit_points is None else int(max_fit_points)
    if cap < 10:
        raise RecordingError(f"max_fit_points must be at least 10, got {max_fit_points!r}")
    require_analysis_inputs(recording)
    say("reading the recording")
    if hasattr(recording, "iter_chunks"):  # an open file, read strictly chunk by chunk
        recording, rate_note = analysis_recording(recording, rate=analysis_rate)
        check_channel_values(recording, ANALYSED_CHANNELS, rig)
        truth_on = None if truth is None else truth_coa(truth, recording)
    else:
        check_channel_values(recording, ANALYSED_CHANNELS, rig)
        recording, _ = fill_short_gaps(recording)  # the notes go into the metadata's notes
        truth_on = None if truth is None else truth_coa(truth, recording)
        recording, rate_note = analysis_recording(recording, rate=analysis_rate)
    if truth is not None and (other := truth_mismatch(recording.metadata, truth)) is not None:
        notes.append(other)
    source = recording.metadata.get("source") or "the recording"
    if other_rig is not None:
        notes.append(other_rig)
        warnings.warn(f"{source}: {other_rig}", DomainWarning, stacklevel=2)
    require_uniform_time(recording.time, str(source), "the analysis")  # one check, file named
    try:  # the spectrum's and the filter study's check; here a warning: phases still come
        check_varies(recording["torque"], "channel 'torque'", "carries no measured CoA")
    except ParameterError as exc:
        warnings.warn(f"{source}: {exc}", DomainWarning, stacklevel=2)
    if rate_note:
        notes.append(rate_note)
    say("deriving the quantities and the phases")
    rec = derive_quantities(recording, rig)
    rec.require("torque", "creep", "coa", "normal_load", "roller_speed", "wheel_speed")
    check_channel_values(rec, ("creep", "coa", "normal_load", "roller_speed", "wheel_speed"))
    t = rec.time
    true_coa = None if truth_on is None else np.interp(t, *truth_on)  # on the analysis axis

    phases = segment_test(rec)
    require_adhesion_test(rec, phases)
    # One study signal (the torque at the study's rate) for the tuning and the filter study.
    study_signal = (
        prepare_study_signal(t, rec["torque"]) if smoothing is None or run_study else None
    )
    say("tuning the smoothing" if smoothing is None else "smoothing")
    if smoothing is None:
        order, window, table = study_signal.tune_savitzky_golay()
    else:
        (order, window), table = smoothing, []
    rec = _smoothed_and_corrected(rec, rig, window, order)
    creep_s, coa_s = rec["creep_smoothed"], rec["coa_smoothed"]

    branches = adhesion_branches(t, creep_s, phases)
    hyst = _hysteresis_per_cycle(branches, creep_s, coa_s, notes)
    points, available, step = _fit_points(branches, creep_s, coa_s, cap, notes)
    schedule = friction_schedule(recording, truth)
    points, condition = _one_friction_condition(t, points, schedule, notes)
    if schedule is None:
        _note_friction_change(branches, creep_s, coa_s, rec["normal_load"], rig, notes)
    say("fitting the Polach law")
    fit, fit_rig = _polach_fits(rec, rig, points, notes)
    say("the corrected CoA's uncertainty (law of propagation, Monte Carlo)")
    budget = _coa_uncertainty(
        rec, rig, phases, branches, (order, window), true_coa, calibration, notes
    )
    fit = _with_systematic_errors(fit, budget, points, notes)
    if (implausible := _implausible_coa(budget, rig)) is not None:
        notes.append(implausible)
        warnings.warn(f"{source}: {implausible}", DomainWarning, stacklevel=2)
    _note_arm(budget, rig, notes)
    _note_wheel_drive_voltage(rec, rig, notes)
    _note_release_creep(rec, phases, notes)
    true_params, true_source = true_polach_parameters(recording, truth, condition)
    if true_params is not None:
        _note_truth_distance({"corrected CoA": fit, "rig CoA": fit_rig}, true_params, notes)
    say("the spectrum of the quiet phase")
    spectrum, window_s = _quiet_phase_spectrum(rec, rig, phases, notes)
    if run_study:
        say("the smoothing-filter study")
    study = study_signal.filter_study() if run_study else []

    result = TestAnalysis(
        recording=rec,
        rig_name=rig.meta.name,
        rig_sha256=rig_sha256(rig),
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
        truth_errors={}
        if true_coa is None
        else _truth_errors(rec, true_coa, budget.online_coa, budget.model_coa),
        true_parameters=true_params,
        true_parameters_source=true_source,
        fit_points_available=available,
        fit_points_step=step,
        fit_points_cap=cap,
        true_coa=true_coa,
        analysis_rate=analysis_rate_facts(rec, DECIMATE_ABOVE),
        coa_uncertainty=budget,
    )
    return result


def _hysteresis_per_cycle(
    branches: list[Branches], creep: np.ndarray, coa: np.ndarray, notes: list[str]
) -> list[Hysteresis | None]:
    """The hysteresis of each cycle's branches (None, noted, where they share no creep)."""
    hyst: list[Hysteresis | None] = []
    for br in branches:
        try:
            hyst.append(
                hysteresis(
                    creep[br.ascending],
                    coa[br.ascending],
                    creep[br.descending],
                    coa[br.descending],
                )
            )
        except ValueError as exc:  # branches that do not overlap in creep
            hyst.append(None)
            notes.append(f"cycle {br.cycle}: no hysteresis ({exc})")
    return hyst


def _quiet_phase_spectrum(
    rec: Recording, rig, phases: list[Phase], notes: list[str]
) -> tuple[ExplainedSpectrum | None, tuple[float, float] | None]:
    """The explained torque spectrum of the longest quiet phase [s] (skipped, noted, if short)."""
    spectrum, window_s = None, quiet_phase(phases)
    if window_s is not None and (window_s[1] - window_s[0]) * rec.sample_rate >= 256:
        quiet = rec.select(*window_s)
        # The one spectrum workflow: settings from the signal, the twin's damped modes.
        try:
            spectrum = explain_recording(quiet, "torque", rig)
        except RecordingError as exc:  # e.g. a torque without variation in the quiet phase
            notes.append(f"spectrum of the quiet phase skipped: {exc}")
    else:
        notes.append("no quiet phase of at least 256 samples: spectrum skipped")
    return spectrum, window_s


def _truth_errors(
    rec: Recording, true_coa: np.ndarray, online: np.ndarray | None = None, model=None
) -> dict[str, float]:
    """RMS and largest errors of the rig's, smoothed, corrected (and online and model-based)
    CoA against the true one."""

    def rms(x):
        return float(np.sqrt(np.mean((x - true_coa) ** 2)))

    coa_c = rec["coa_corrected"]
    out = {
        "rig_coa_vs_true_rms [-]": rms(rec["coa"]),
        "smoothed_rig_coa_vs_true_rms [-]": rms(rec["coa_smoothed"]),
        "corrected_coa_vs_true_rms [-]": rms(coa_c),
        "corrected_coa_vs_true_max [-]": float(np.max(np.abs(coa_c - true_coa))),
    }
    if online is not None:
        out["online_coa_vs_true_rms [-]"] = rms(online)
    for name, (coa, _) in (model or {}).items():
        out[f"{name}_vs_true_rms [-]"] = rms(coa)
        out[f"{name}_vs_true_max [-]"] = float(np.max(np.abs(coa - true_coa)))
    return out


def _calibrated_rig(rig, values: dict[str, float], notes: list[str]):
    """``rig`` with a calibration's values (key -> value, :func:`calibration_covariance`'s
    first; noted); the creep law's keys (``polach.*``, ``fastsim.*``) skipped."""
    overrides = {k: v for k, v in values.items() if not k.startswith(("polach.", "fastsim."))}
    if not overrides:
        return rig
    try:
        out = rig.with_overrides(overrides)
    except ParameterError as exc:
        raise ParameterError(f"calibration: the rig does not take its values: {exc}") from None
    notes.append(
        "calibrated values used: "
        + ", ".join(f"{k} = {v:.6g}" for k, v in sorted(overrides.items()))
    )
    return out
