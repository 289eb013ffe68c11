"""Analysis of one adhesion test: from a recording to phases, corrected CoA, branches and fits.

The orchestration layer over :mod:`rollerrig.measure` (quantities, segmentation, correction),
:mod:`rollerrig.signal` (Savitzky-Golay tuning, filter study, spectra) and :mod:`rollerrig.fit`
(Polach). Each step is a public function of those modules; :func:`analyze_test` only chains them
in the order an analyst would and keeps what each step found in a
:class:`~rollerrig.analysis.findings.TestAnalysis`.

What the steps around it live in: :mod:`rollerrig.measure.checks` (inputs and values an
analysis can compute with), :mod:`rollerrig.measure.prepare` (uniform time base, analysis
rate), :mod:`rollerrig.measure.facts` (what is known about a recording, the twin's truth),
:mod:`rollerrig.analysis.findings` (the result and its summary). Their public names are also
importable from here.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.analysis.findings import TRUTH_SIGMA, TestAnalysis
from rollerrig.estimation.budget import CoaBudget, coa_budget, creep_uncertainty
from rollerrig.estimation.estimator import (
    choose_smoother,
    estimate_from_recording,
    smooth_from_recording,
)
from rollerrig.estimation.uncertainty import calibration_covariance, corrected_coa_uncertainty
from rollerrig.fit.polach import PolachFit, creep_stiffness_for_rig, fit_polach
from rollerrig.measure.checks import (
    ANALYSED_CHANNELS,
    check_channel_values,
    require_adhesion_test,
    require_analysis_inputs,
)
from rollerrig.measure.correction import corrected_adhesion
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
from rollerrig.measure.quantities import ANALYSIS_CHANNELS, derive_quantities
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
from rollerrig.signal.scoring import prepare_study_signal
from rollerrig.signal.smoothing import savitzky_golay
from rollerrig.signal.workflow import ExplainedSpectrum, explain_recording

__all__ = [
    "ANALYSIS_RATE",
    "CORRECTION_WINDOW",
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

MAX_FIT_POINTS = 5000
"""Most ascending-branch points a Polach fit uses; above it every k-th point is taken [1]."""

CORRECTION_WINDOW = 0.2
"""Span of the dynamics correction's quartic Savitzky-Golay filter [s] (the acceleration needs
less smoothing than the noise does: a 0.2 s quartic filter keeps the transients; measured: CoA
error 0.009 against 0.019 with a 0.8 s quadratic one)."""

_SYMBOLS = {
    "static_friction": "μ0",
    "limit_ratio": "A",
    "friction_decay": "B [s/m]",
    "k_adhesion": "kA",
    "k_slip": "kS",
}


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
        Rate [Hz] recordings faster than :data:`DECIMATE_ABOVE` are analysed at; default
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
    if calibration is not None:
        rig = _calibrated_rig(rig, calibration, notes)
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
    _note_arm(budget, rig, notes)
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


def _smoothed_and_corrected(rec: Recording, rig, window: int, order: int) -> Recording:
    """``rec`` with the smoothed torque, creep, slip velocity and CoA, and the corrected CoA.

    Savitzky-Golay (``window`` [samples], ``order``) smoothing of the torque and the speeds, the
    creep and the rig's CoA from them; the CoA corrected for the roller's inertia and bearing
    loss (:func:`rollerrig.measure.correction.corrected_adhesion`) and the roller acceleration.
    """
    fs = rec.sample_rate
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
        window=_odd(CORRECTION_WINDOW * fs),
        order=4,
        load_transfer=rig.arm.transfer_ratio,
        dead_weight=rig.arm.dead_weight,
    )
    return rec.with_channels(
        torque_smoothed=torque_s,
        creep_smoothed=creep_s,
        slip_velocity_smoothed=slip_s,
        coa_smoothed=coa_s,
        coa_corrected=coa_c,
        roller_acceleration=alpha,
        units={name: unit for name, (unit, _) in ANALYSIS_CHANNELS.items()},
    )


def _odd(n: float) -> int:
    k = max(round(n), 7)
    return k if k % 2 else k + 1


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


def _fit_points(
    branches: list[Branches], creep: np.ndarray, coa: np.ndarray, cap: int, notes: list[str]
) -> tuple[np.ndarray, int, int]:
    """Indices of the ascending-branch samples the fits use, how many were available, the step.

    Samples with creep above 1e-4 and CoA above 0.01; above ``cap`` every k-th (noted).
    """
    points = np.array([], dtype=int)
    if branches:
        points = np.concatenate([br.ascending for br in branches])
        points = points[(creep[points] > 1e-4) & (coa[points] > 0.01)]
    available, step = int(points.size), max(1, math.ceil(points.size / cap))
    if step > 1:
        points = points[::step]
        notes.append(
            f"Polach fits on one in {step} of the {available} ascending-branch points "
            f"({points.size} used; a fit uses at most {cap} points, MAX_FIT_POINTS): the "
            "points are consecutive samples of smooth branches, so the thinned set spans the "
            "same creep and slip-velocity range"
        )
    return points, available, step


FRICTION_SLOPE_RATIO = 1.6
"""Cycles whose initial creep-CoA slopes (normalised by the rig's creep stiffness) differ by
more than this factor are noted as a probable change of friction (a dry and a wet branch of
Polach's sets differ by 2.4-2.9; the cycles of one condition by at most 1.2)."""


def _one_friction_condition(
    t: np.ndarray, points: np.ndarray, schedule, notes: list[str]
) -> tuple[np.ndarray, str | None]:
    """The fit points under one friction condition, and that condition.

    A recording the twin made with several friction conditions (``schedule``:
    :func:`~rollerrig.measure.facts.friction_schedule`) is fitted on the condition with the
    most ascending-branch points only, noted: one law is never fitted across two conditions.
    Without a schedule, or with one condition, ``points`` as they are.
    """
    if not schedule or points.size == 0:
        return points, None
    starts = np.array([start for start, _ in schedule])
    names = np.array([name for _, name in schedule])
    which = names[np.clip(np.searchsorted(starts, t[points], side="right") - 1, 0, None)]
    counts = {str(c): int(np.sum(which == c)) for c in dict.fromkeys(which.tolist())}
    if len(counts) == 1:
        return points, next(iter(counts))
    chosen = max(counts, key=counts.get)
    kept = points[which == chosen]
    when = ", ".join(f"{name} from {start:g} s" for start, name in schedule)
    left = ", ".join(f"{n} under {c!r}" for c, n in counts.items() if c != chosen)
    notes.append(
        f"the test changes friction ({when}): the Polach fits use the {kept.size} "
        f"ascending-branch points under {chosen!r} only and leave out {left}, another law "
        "(one law is never fitted across two friction conditions; analyse the other "
        "condition's cycles on their own, Recording.select, to fit it)"
    )
    return kept, chosen


def _note_friction_change(
    branches: list[Branches],
    creep: np.ndarray,
    coa: np.ndarray,
    normal_load: np.ndarray,
    rig,
    notes: list[str],
) -> None:
    """A note when the cycles' initial creep-CoA slopes differ as a change of friction makes
    them (Polach's kA), for a recording that does not say its friction condition: the fits
    then take every cycle as one law, and the note says so."""
    slopes = {}
    for br in branches:
        a = br.ascending
        c, m = creep[a], coa[a]
        ok = (c > 1e-4) & (m > 0.01)
        if np.count_nonzero(ok) < 5:
            continue
        c, m, q = c[ok], m[ok], normal_load[a][ok]
        low = m <= 0.5 * float(np.max(m))  # the initial, nearly linear part
        if np.count_nonzero(low) < 3:
            continue
        q_med = float(np.median(q[low]))
        stiffness = creep_stiffness_for_rig(q_med, rig) / q_med  # slope of Kalker's line [-]
        slopes[br.cycle] = float(np.median(m[low] / c[low])) / stiffness
    if len(slopes) < 2:
        return
    low_c, high_c = min(slopes, key=slopes.get), max(slopes, key=slopes.get)
    ratio = slopes[high_c] / slopes[low_c]
    if ratio > FRICTION_SLOPE_RATIO:
        notes.append(
            f"the cycles' initial creep-CoA slopes differ by x{ratio:.2g} (cycle {high_c}: "
            f"{slopes[high_c]:.2g}, cycle {low_c}: {slopes[low_c]:.2g} of Kalker's slope): the "
            "friction condition probably changed during the test (water or contamination "
            "lowers Polach's kA), yet the Polach fits take every cycle as one law; analyse "
            "each condition's cycles on their own (Recording.select) if it did"
        )


def _polach_fits(
    rec: Recording, rig, points: np.ndarray, notes: list[str]
) -> tuple[PolachFit | None, PolachFit | None]:
    """Polach fits to the corrected and to the rig's smoothed CoA at ``points`` (warnings noted)."""
    if points.size < 10:
        notes.append("too few ascending-branch points for a Polach fit")
        return None, None
    creep_s, slip_s = rec["creep_smoothed"], rec["slip_velocity_smoothed"]
    spring = rec["normal_load"][points]
    corrected = rec["coa_corrected"][points]
    # The corrected CoA is on the contact's load N = S + W_d + κ μ N (the swinging arm), the
    # rig's on the air-spring force S it measures.
    arm = rig.arm
    contact_load = (spring + arm.dead_weight) / (1.0 - arm.transfer_ratio * corrected)
    fits = []
    for label, coa_points, load in (
        ("corrected CoA", corrected, contact_load),
        ("rig CoA", rec["coa_smoothed"][points], spring),
    ):
        # Kalker's stiffness scales with N^(2/3) (Hertz at a fixed a/b): per point, as the twin.
        q_med = float(np.median(load))
        stiffness = creep_stiffness_for_rig(q_med, rig) * np.cbrt((load / q_med) ** 2)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            fits.append(
                fit_polach(
                    creep_s[points], coa_points, load, stiffness, slip_velocity=slip_s[points]
                )
            )
            notes.extend(
                f"fit to the {label}: {m}" for m in dict.fromkeys(str(w.message) for w in caught)
            )
    return fits[0], fits[1]


def _note_arm(budget, rig, notes: list[str]) -> None:
    """A note on the swinging arm's share of this test: the contact's load against the air
    spring's at the largest corrected CoA, and what dividing by S instead of N does there."""
    terms = budget.uncertainty.terms
    if terms.contact_load is None or not np.any(np.isfinite(terms.coa)):
        return
    i = int(np.nanargmax(terms.coa))
    spring, load = float(terms.normal_load[i]), float(terms.contact_load[i])
    arm = rig.arm
    notes.append(
        f"swinging arm (rig [arm]: h/l = {arm.transfer_ratio:.3g} ± "
        f"{arm.transfer_ratio_uncertainty:.2g}, W_d = {arm.dead_weight:g} ± "
        f"{arm.dead_weight_uncertainty:g} N): at the largest corrected CoA "
        f"({float(terms.coa[i]):.3f}, t = {budget.uncertainty.time[i]:.2f} s) the contact carries "
        f"N = {load:.0f} N against the air spring's S = {spring:.0f} N "
        f"({100.0 * (load / spring - 1.0):+.1f} %); the CoA on S would be "
        f"{float(terms.contact_force[i]) / spring:.3f}"
    )


def _note_truth_distance(
    fits: dict[str, PolachFit | None], true_params: dict, notes: list[str]
) -> None:
    """A note for each fit that misses the twin's true Polach set by more than TRUTH_SIGMA."""
    for label, f in fits.items():
        if f is None:
            continue
        far = {
            name: row
            for name, row in f.truth_distance(true_params, TRUTH_SIGMA).items()
            if row["beyond_warn_sigma"]
        }
        if far:
            notes.append(
                f"fit to the {label} misses the twin's true Polach set by more than "
                f"{TRUTH_SIGMA:g} standard errors: "
                + ", ".join(
                    f"{_SYMBOLS[n]} {r['fitted']:.4g} ± {r['stderr']:.2g} against "
                    f"{r['true']:.4g} ({r['sigma']:.1f} σ)"
                    for n, r in far.items()
                )
                + "; the standard errors cover the noise, not the systematic errors of the "
                "data (smoothing, the dynamics correction, unidentifiable A and B)"
            )


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


def _calibrated_rig(rig, calibration, notes: list[str]):
    """``rig`` with the calibrated values of ``calibration`` (noted); the creep law's keys
    (``polach.*``, ``fastsim.*``) skipped."""
    values, *_ = calibration_covariance(calibration)
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


def _coa_uncertainty(
    rec: Recording,
    rig,
    phases: list[Phase],
    branches: list[Branches],
    smoothing: tuple[int, int],
    true_coa: np.ndarray | None,
    calibration,
    notes: list[str],
) -> CoaBudget:
    """The corrected CoA's uncertainty per sample, phase and creep–CoA point, and the online
    estimator's CoA (:mod:`rollerrig.estimation.estimator`)."""
    fs = rec.sample_rate
    unc = corrected_coa_uncertainty(
        rec,
        rig,
        window=_odd(CORRECTION_WINDOW * fs),
        order=4,
        releases=[(ph.start, ph.end) for ph in phases if ph.name == "release"],
        quiet=[(ph.start, ph.end) for ph in phases if ph.name in ("free_rolling", "rest")],
        calibration=calibration,
    )
    order, window = smoothing
    creep_u = creep_uncertainty(rec, rig, window, order)
    budget = coa_budget(unc, rec, phases, branches, creep_u=creep_u, true_coa=true_coa)
    budget.online_coa = _online_coa(rec, rig, budget.notes)
    budget.model_coa, budget.model_choice = _model_based_coa(rec, rig, budget.notes, calibration)
    return budget


MODEL_BASED = {
    "coa_smoother": (
        None,
        "CoA from the two-sided Kalman (RTS) smoother of the roller: T56 as input, the encoder "
        "angle as measurement",
    ),
    "coa_smoother_chain": (
        "induction",
        "CoA from the two-sided Kalman (RTS) smoother of roller, shaft, motor rotor and the "
        "drive's lag model linearised (its noise by maximum likelihood), T56 and the encoder as "
        "measurements, order lines removed (needs k56 and J6 of a calibrated rig)",
    ),
}
"""The model-based estimates :func:`analyze_test` makes: name -> (chain of
:func:`rollerrig.estimation.estimator.smooth_from_recording`, description)."""

SHAFT_KEYS = ("stiffness.roller_shaft", "inertia.am_rotor")
"""The rig keys the chain smoother needs from a calibration (k56, J6)."""

SHAFT_RELATIVE_ERROR = 0.03
"""Largest relative standard error of k56 and J6 at which a calibration counts as knowing the
roller shaft's mode (the chain's error doubles at ±10 % of k56; ±5 % keeps it under the
roller alone's on the bundled test) [1]."""


def shaft_calibrated(calibration) -> tuple[bool, str]:
    """Whether ``calibration`` (calibration.json's content) gives k56 and J6 well enough for the
    chain smoother: each with a value, a standard error within :data:`SHAFT_RELATIVE_ERROR` of
    it, not conditional on the model, in a calibration not marked invalid; and why not."""
    if not calibration:
        return False, "no calibration was given"
    if calibration.get("valid") is False:
        return False, "the calibration is not valid"
    params = calibration.get("parameters") or {}
    for key in SHAFT_KEYS:
        entry = params.get(key)
        if not isinstance(entry, dict) or entry.get("value") in (None, 0):
            return False, f"the calibration does not give {key}"
        se = entry.get("standard_error")
        if se is None or not math.isfinite(se) or se > SHAFT_RELATIVE_ERROR * abs(entry["value"]):
            return False, f"{key} is not calibrated to {SHAFT_RELATIVE_ERROR:.0%}"
        if entry.get("conditional_on_model"):
            return False, f"the calibration of {key} is conditional on its model"
    return True, "k56 and J6 calibrated"


def _model_based_coa(rec: Recording, rig, notes: list[str], calibration=None):
    """The two-sided model-based CoA estimates on the analysis axis (name -> (CoA,
    description)) and the one to trust ((name, why),
    :func:`rollerrig.estimation.estimator.choose_smoother`); none (noted) without the roller
    encoder counts they need."""
    if "roller_encoder_counts" not in rec:
        notes.append("model-based estimates: not made (they need roller_encoder_counts)")
        return {}, ()
    out, made = {}, {}
    for name, (chain, what) in MODEL_BASED.items():
        options = {} if chain is None else {"drive_noise": "ml"}
        try:
            made[name] = smooth_from_recording(rec, rig, chain=chain, **options)
        except ParameterError as exc:  # a rig or recording the model cannot take
            notes.append(f"{name}: not made ({exc})")
            made[name] = str(exc)
            continue
        out[name] = (np.asarray(made[name].coa, dtype=float), what)
    if "coa_smoother" not in out:
        return out, ()
    known, why_not = shaft_calibrated(calibration)
    chosen = choose_smoother(
        made["coa_smoother"], made.get("coa_smoother_chain"), known, f"here {why_not}"
    )
    name = "coa_smoother" if chosen.drive_noise is None else "coa_smoother_chain"
    why = chosen.choice
    notes.append(f"model-based estimate to trust: {name}, {why}")
    return out, (name, why)


def _online_coa(rec: Recording, rig, notes: list[str]) -> np.ndarray | None:
    """The causal estimator's CoA on the analysis axis
    (:func:`rollerrig.estimation.estimator.estimate_contact_torque`), None (noted) without the
    roller encoder counts it needs."""
    if "roller_encoder_counts" not in rec:
        notes.append(
            "online estimate: not made (it needs roller_encoder_counts; the recording gives "
            "the roller speed)"
        )
        return None
    return np.asarray(estimate_from_recording(rec, rig).coa, dtype=float)
