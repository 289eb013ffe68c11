"""The corrected CoA's uncertainty and the model-based CoA estimates of an adhesion test's analysis.

Steps of :func:`rollerrig.analysis.adhesion.analyze_test`: the corrected CoA's uncertainty per
sample, phase and creep–CoA point with its budget (JCGM 100 and 101;
:mod:`rollerrig.estimation.uncertainty`, :mod:`rollerrig.estimation.budget`), the causal
estimator's CoA, the two-sided model-based estimates (:data:`MODEL_BASED`) and the one to trust
(the chain smoother only with the roller shaft calibrated, :func:`shaft_calibrated`), a
note on the swinging arm's share of the test, and one where the wheel's PMSM ran at its voltage
limit (:func:`_note_wheel_drive_voltage`), where the band does not hold.
"""

from __future__ import annotations

import math

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.analysis.smoothed_channels import CORRECTION_WINDOW, _odd
from rollerrig.drives.pmsm_envelope import VOLTAGE_LIMIT_SHARE, pmsm_voltage_share
from rollerrig.estimation.budget import CoaBudget, coa_budget, creep_uncertainty
from rollerrig.estimation.estimator import (
    choose_smoother,
    estimate_from_recording,
    smooth_from_recording,
)
from rollerrig.estimation.uncertainty import corrected_coa_uncertainty
from rollerrig.measure.segmentation import Branches, Phase
from rollerrig.recordings.recording import Recording

__all__ = ["MODEL_BASED", "SHAFT_KEYS", "SHAFT_RELATIVE_ERROR", "shaft_calibrated"]


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
"""The model-based estimates :func:`~rollerrig.analysis.adhesion.analyze_test` makes: name ->
(chain of :func:`rollerrig.estimation.estimator.smooth_from_recording`, description)."""

SHAFT_KEYS = ("stiffness.roller_shaft", "inertia.am_rotor")
"""The rig keys the chain smoother needs from a calibration (k56, J6)."""

SHAFT_RELATIVE_ERROR = 0.03
"""Largest relative standard error of k56 and J6 at which a calibration counts as knowing the
roller shaft's mode (the chain's error doubles at ±10 % of k56; ±5 % keeps it under the
roller alone's on the bundled test) [-]."""


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


PLAUSIBLE_COA = 1.0
"""Largest phase mean of the CoA [-] a steel wheel on a steel roller can have (dry rail gives
about 0.5): above it in magnitude the inputs are suspect, not the contact."""


def _implausible_coa(budget, rig) -> str | None:
    """What to warn where a phase mean of the rig's or the corrected CoA exceeds
    :data:`PLAUSIBLE_COA` in magnitude (the largest named), else None."""
    worst = None
    for row in [] if budget is None else budget.phases:
        for key, label in (
            ("corrected_coa_mean [-]", "corrected"),
            ("rig_coa_mean [-]", "rig"),
        ):
            value = row.get(key)
            if value is None or not math.isfinite(value) or abs(value) <= PLAUSIBLE_COA:
                continue
            if worst is None or abs(value) > abs(worst[0]):
                worst = (float(value), label, row)
    if worst is None:
        return None
    value, label, row = worst
    cycle = row.get("cycle", -1)
    phase = row["name"] if cycle is None or cycle < 0 else f"{row['name']} {cycle + 1}"
    count = sum(
        1
        for r in budget.phases
        if any(
            r.get(k) is not None and math.isfinite(r[k]) and abs(r[k]) > PLAUSIBLE_COA
            for k in ("corrected_coa_mean [-]", "rig_coa_mean [-]")
        )
    )
    others = "" if count == 1 else f", and above {PLAUSIBLE_COA:.1f} in {count - 1} other phase(s)"
    return (
        f"implausible CoA: the {label} CoA's mean is {value:.4g} in phase {phase} "
        f"({row['start [s]']:.2f}-{row['end [s]']:.2f} s){others}; steel on steel does not "
        f"reach {PLAUSIBLE_COA:.1f} (dry rail about 0.5). Likely causes: the wrong rig file "
        f"(in use: {rig.meta.name!r}), wrong units or channel map (torque in N.m, pressure in "
        "Pa; --channels), or a wrong air-spring area (sensors.air_spring_effective_area = "
        f"{rig.sensors.air_spring_effective_area:g} m²)"
    )


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


def _note_release_creep(rec: Recording, phases, notes: list[str]) -> None:
    """A note where the wheel was released from more creep than the release residual is stated
    for (:data:`~rollerrig.estimation.release_residual.STATED_UP_TO_CREEP`): after such a
    release (a runaway) the corrected CoA's band is not validated. On the twin's recordings of
    runaways to 75-96 % creep it missed by up to 2.9-3.0 U at the re-adhesion, with nothing
    said (a review, 2026-12-03); the creep is measured, so it is said now."""
    from rollerrig.estimation.release_residual import STATED_UP_TO_CREEP

    if "creep_smoothed" not in rec:
        return
    t = np.asarray(rec.time, dtype=float)
    creep = np.abs(np.asarray(rec["creep_smoothed"], dtype=float))
    deep = []
    for ph in phases:
        if ph.name != "release":
            continue
        window = (t >= ph.start - 0.5) & (t <= ph.start + 0.05)
        if np.any(window) and np.any(np.isfinite(creep[window])):
            peak = float(np.nanmax(creep[window]))
            if peak > STATED_UP_TO_CREEP:
                deep.append((peak, ph.start))
    if deep:
        shown = ", ".join(f"{100 * c:.0f} % at t = {s:.2f} s" for c, s in deep[:4])
        notes.append(
            f"the wheel was released from deep slip ({shown}{', ...' if len(deep) > 4 else ''}),"
            f" beyond the {100 * STATED_UP_TO_CREEP:.0f} % creep up to which the release's "
            "residual is stated (derived on the twin): after such a release the corrected "
            "CoA's band is not validated (on the twin's runaways it missed by up to 3 U at "
            "the re-adhesion)"
        )


def _note_wheel_drive_voltage(rec: Recording, rig, notes: list[str]) -> None:
    """A note where the wheel's PMSM ran at its voltage limit during the test.

    The steady voltage its i_d = 0 control needs at the measured wheel speed and the recorded
    torque request (0 where the recording has none: the back-EMF alone), against the
    inverter's (:func:`rollerrig.drives.pmsm_envelope.pmsm_voltage_share`, the rig's
    ``[pmsm]``), from :data:`~rollerrig.drives.pmsm_envelope.VOLTAGE_LIMIT_SHARE` on. There
    the wheel torque can collapse within tens of ms, faster than the correction's smoothing
    follows; the data cannot show it (the dip sits within the encoders' noise), and on the
    twin's recordings of such a test the corrected CoA missed by up to 4 U there.
    """
    t = np.asarray(rec.time, dtype=float)
    omega = np.asarray(rec["wheel_speed"], dtype=float)
    has_request = "torque_request" in rec
    torque = np.asarray(rec["torque_request"], dtype=float) if has_request else np.zeros(t.size)
    ok = np.isfinite(omega) & np.isfinite(torque)
    if not np.any(ok):
        return
    share = np.full(t.size, np.nan)
    share[ok] = pmsm_voltage_share(torque[ok], omega[ok], rig.pmsm)
    at_limit = share >= VOLTAGE_LIMIT_SHARE
    if not np.any(at_limit):
        return
    k = int(np.nanargmax(share))
    dt = float(np.median(np.diff(t))) if t.size > 1 else 0.0
    pm = rig.pmsm
    basis = (
        "torque request and measured wheel speed"
        if has_request
        else "measured wheel speed, no torque request recorded: the back-EMF alone"
    )
    notes.append(
        f"wheel drive at its voltage limit: the PMSM (rig [pmsm], i_d = 0 control, no field "
        f"weakening) needs {100 * VOLTAGE_LIMIT_SHARE:g} % or more of its inverter's voltage "
        f"for {int(np.count_nonzero(at_limit)) * dt:.3g} s of the test from t = "
        f"{float(t[at_limit][0]):.2f} s, up to {100 * float(share[k]):.3g} % at t = "
        f"{float(t[k]):.2f} s (wheel at {float(omega[k]):.4g} rad/s, rated "
        f"{pm.rated_speed:.4g} rad/s; from the {basis}). There its torque can collapse within "
        "tens of ms, faster than the correction's "
        f"{CORRECTION_WINDOW:g} s smoothing follows, and the corrected CoA's band is not "
        "valid: on the twin's recordings of such a test it missed by up to 4 U at each "
        "torque ramp"
    )
