"""The :class:`~rollerrig.calibrate.calibration.Calibration` assembled from a finished fit
(:func:`build_calibration`): standard errors and correlations in the values' units, each
channel's residuals before and after, the warnings and notes, the calibrated rig and friction
law (of the creep law fitted) with their provenance, the fit's settings.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from rollerrig.calibrate.calibration import _UNITS, Calibration, ChannelFit, FittedParameter
from rollerrig.calibrate.diagnostics import (
    _LAG1_MARGIN,
    _QUANTISATION_LAG1,
    DELAY_SHARE,
    _invalid_reasons,
    channel_delay,
    channel_structured,
    conditional_note,
    identified_combinations,
    model_suggestion,
)
from rollerrig.calibrate.measurement import load_sigma
from rollerrig.calibrate.problem import (
    LAW_KEY_PREFIXES,
    FreeParameter,
    fd_steps,
    split_values,
    with_polach,
)
from rollerrig.calibrate.settings import FD_STEP, HAC_WINDOW, MAX_CORRELATION
from rollerrig.calibrate.stats import block_mean_test, whiteness
from rollerrig.contact.creep import PolachParameters
from rollerrig.contact.laws import FastsimParameters
from rollerrig.rig.parameters import RigParameters

__all__ = ["build_calibration"]

_MISFIT_FACTOR = 5.0  # residual RMS above this many sensor sigmas: the twin misses the data


def _identified_rig(
    rig: RigParameters, fitted: dict[str, FittedParameter], source: str, sha: str | None
) -> RigParameters:
    """``rig`` with the identified rig keys replaced, their provenance the calibration's."""
    values = {k: p.value for k, p in fitted.items() if p.identified and "." in k}
    not_rig = (*LAW_KEY_PREFIXES, "experiment.")
    values = {k: v for k, v in values.items() if not k.startswith(not_rig)}
    if not values:
        return rig
    out = rig.with_overrides(values)
    provenance = {k: dict(v) for k, v in out.provenance.items()}
    where = f"{source}" + (f" (sha256 {sha[:12]})" if sha else "")
    for key in values:
        p = fitted[key]
        old = rig.provenance.get(key, {})
        old_text = old.get("source") or old.get("assumption") or "no provenance"
        old_value = f"{old['value']} {old['unit']}" if "value" in old else f"{p.initial:g}"
        provenance[key] = {
            "value": p.value,
            "unit": p.unit,
            "source": (
                f"calibrated by rollerrig calibrate on {where}: {p.value:.6g} +- "
                f"{p.standard_error:.3g}{_unit_text(p.unit)} (one standard error: Newey-West and "
                "the sensors' stated classes); "
                f"started from {old_value} ({old_text})"
            ),
        }
    meta = out.meta.model_copy(
        update={
            "name": f"{rig.meta.name}-calibrated",
            "description": (
                f"{rig.meta.description} Calibrated by rollerrig calibrate on {where}: "
                f"{', '.join(values)}."
            ),
        }
    )
    return out.model_copy(update={"provenance": provenance, "meta": meta})


def build_calibration(
    *,
    params: tuple[FreeParameter, ...],
    n_free: int,
    measurement,
    model,
    fit,
    point,
    active: np.ndarray,
    covariance_z: np.ndarray,
    white_z: np.ndarray,
    dropped: dict[int, str],
    systematic_z: dict[str, np.ndarray] | None = None,
    sensor_inputs: tuple = (),
    before: dict[str, np.ndarray],
    start_prediction: dict[str, np.ndarray],
    converged: bool,
    recording,
    wall_time: float,
) -> Calibration:
    """Assemble the :class:`Calibration` from the state of a finished fit.

    ``covariance_z`` and ``white_z``: the statistical covariances of the active z;
    ``systematic_z``: each stated sensor input's shift of the active z for an error of one
    standard uncertainty (:mod:`rollerrig.calibrate.systematic`), whose outer products add to
    the statistical covariance; ``sensor_inputs``: those inputs.
    """
    from rollerrig.measure.facts import recording_facts

    act = np.flatnonzero(active)
    scale = np.array([params[i].value(point.z[i]) - params[i].lower for i in act])
    cov_stat = covariance_z * np.outer(scale, scale)
    shifts = {name: dz * scale for name, dz in (systematic_z or {}).items()}
    cov = cov_stat + sum((np.outer(d, d) for d in shifts.values()), np.zeros_like(cov_stat))
    cov_white = white_z * np.outer(scale, scale)
    se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    se_stat = np.sqrt(np.clip(np.diag(cov_stat), 0.0, None))
    se_white = np.sqrt(np.clip(np.diag(cov_white), 0.0, None))
    corr = _correlation(cov)
    position = {int(i): k for k, i in enumerate(act)}

    fitted: dict[str, FittedParameter] = {}
    for i, p in enumerate(params):
        if i in position:
            k = position[i]
            value = p.value(point.z[i])
            fitted[p.key] = FittedParameter(
                p.key,
                p.unit,
                p.initial,
                float(value),
                float(se[k]),
                float(se_white[k]),
                True,
                at_bound=bool(p.upper is not None and value >= p.upper * (1 - 1e-9)),
                standard_error_statistical=float(se_stat[k]),
                systematic={name: float(d[k]) for name, d in shifts.items()},
            )
        else:
            fitted[p.key] = FittedParameter(
                p.key, p.unit, p.initial, None, None, None, False, dropped.get(i, "fixed")
            )
    free = {p.key: fitted[p.key] for p in params[:n_free]}
    nuisance = {p.key: fitted[p.key] for p in params[n_free:]}
    keys = tuple(params[i].key for i in act)

    warnings = [f"{k}: {p.reason}" for k, p in free.items() if not p.identified]
    # What the recording determines is a matter of its statistics: one sensor error moving two
    # keys together (the load's offset moves k56 and the load) is no combination the recording
    # fixes. The groups come from the statistical covariance, their errors from the total.
    values = [fitted[k].value for k in keys]
    combinations = _with_total_errors(
        identified_combinations(
            keys, values, [fitted[k].unit for k in keys], cov_stat, MAX_CORRELATION
        ),
        keys,
        values,
        cov,
    )
    corr_stat = _correlation(cov_stat)
    combined = {k for c in combinations for k in c["keys"]}
    for a in range(len(keys)):
        for b in range(a + 1, len(keys)):
            if abs(corr_stat[a, b]) > MAX_CORRELATION and not {keys[a], keys[b]} <= combined:
                warnings.append(
                    f"{keys[a]} and {keys[b]} are correlated ({corr_stat[a, b]:+.3f}): the "
                    "recording determines mainly a combination of the two"
                )
    for c in combinations:
        warnings.append(
            f"{', '.join(c['keys'])} are correlated (|r| up to {c['max_abs_correlation']:.4f}): "
            f"the recording determines {c['expression']} = {c['value']:.6g}"
            f"{_unit_text(c['unit'])} +- {100 * c['relative_standard_error']:.3g} %, "
            f"hardly {c['undetermined']['expression']} (+- "
            f"{100 * c['undetermined']['relative_standard_error']:.3g} %); each key's own "
            "standard error is only the shadow of that combination"
        )
    for k, p in free.items():
        if p.at_bound:
            warnings.append(f"{k}: the fit stops at its upper bound; its error is one-sided")
    if not converged:
        warnings.append(
            f"the fit did not converge within {fit.iterations} iterations; the values are the "
            "best found (raise max_iterations)"
        )

    notes = _systematic_notes(free, sensor_inputs, shifts) + list(measurement.notes)
    residual_after = fit.channel_residuals(point.prediction)
    # The load channel's offset from the twin's load is the sensors' classes' (the fit weighs
    # its mean by them: rollerrig.calibrate.measurement.load_sigma), said below; its
    # whiteness is that of its scatter about the offset.
    tested = dict(residual_after)
    if "normal_load" in tested:
        tested["normal_load"] = tested["normal_load"] - np.mean(tested["normal_load"])
        found = _load_offset(measurement, residual_after["normal_load"], point.prediction)
        if found is not None:
            (warnings if found[0] else notes).append(found[1])
    white = {c: whiteness(e) | block_mean_test(e) for c, e in tested.items()}
    sigma_sensor = {c: float(measurement.sensor_noise[c]) for c in measurement.channels}
    sigma_basis = dict(measurement.noise_basis)
    if "normal_load" in sigma_sensor and measurement.normal_load_class > 0.0:
        scatter = sigma_sensor["normal_load"]
        sigma_sensor["normal_load"] = load_sigma(measurement, scatter)
        sigma_basis["normal_load"] = (
            f"the channel's scatter about its mean ({scatter:.3g} N) and, over its samples, the "
            f"standard uncertainty of its mean from the sensors' stated classes "
            f"({measurement.normal_load_class:.3g} N: the pressure sensor's offset and the air "
            "spring's area), so that the mean weighs as one measurement of the load with that "
            "error (rollerrig.calibrate.measurement.load_sigma)"
        )
    channels = {}
    for c in measurement.channels:
        channels[c] = ChannelFit(
            name=c,
            unit=_UNITS[c],
            samples=int(measurement.valid[c].sum()),
            sigma_sensor=sigma_sensor[c],
            sigma_basis=sigma_basis[c],
            sigma_used=float(fit.sigma[c]),
            rms_before=float(np.sqrt(np.mean(before[c] ** 2))),
            rms_after=float(np.sqrt(np.mean(residual_after[c] ** 2))),
            whiteness=white[c],
            lines=(
                measurement.line_amplitudes(measurement.values[c] - point.prediction[c])
                if c == "torque"
                else []
            ),
        )
        w = white[c]
        if channels[c].rms_after > _MISFIT_FACTOR * channels[c].sigma_sensor:
            gap = (
                f"residual RMS {channels[c].rms_after:.3g} {_UNITS[c]} after the fit against a "
                f"sensor noise of {channels[c].sigma_sensor:.3g} {_UNITS[c]} "
                f"({measurement.noise_basis[c]})"
            )
            if w["white"]:  # white: noise larger than the stated one, not a twin that misses
                notes.append(
                    f"{c}: {gap}; the residuals are white: the channel is noisier than that "
                    "level, which the fit's re-weighting takes from the residuals"
                )
            else:
                warnings.append(
                    f"the twin does not reproduce {c}: {gap}; check the rig file, the channel "
                    "map (units, signs) and which parameters are free"
                )
        quantised = c in ("wheel_speed", "roller_speed") and measurement.encoder_counts
        if quantised:
            w["expected_lag1_autocorrelation"] = _QUANTISATION_LAG1
        if w["white"]:
            continue
        what = (
            f"residuals of {c} are not white (Ljung-Box p = {w['ljung_box_p']:.2g}, lag-1 "
            f"autocorrelation {w['lag1_autocorrelation']:+.2f})"
        )
        if channel_structured(w, bool(quantised)):
            warnings.append(
                f"{what}: structure the twin does not explain; the standard errors use the "
                "Newey-West covariance, which accounts for its correlation, not for a bias"
            )
        elif quantised and w["lag1_autocorrelation"] <= _QUANTISATION_LAG1 + _LAG1_MARGIN:
            notes.append(
                f"{what}, as the encoder's quantisation makes them (the difference of two count "
                f"errors: lag-1 autocorrelation {_QUANTISATION_LAG1:+g})"
            )
        else:
            tau = w.get("integrated_autocorrelation_time [samples]", float("nan"))
            # the verdict first: the console cuts a long note after its first clauses
            notes.append(
                f"residuals of {c}: no structure the twin misses; their correlation is "
                f"short-range only (integrated autocorrelation time {tau:.2g} samples, no bias "
                f"in the block means; Ljung-Box p = {w['ljung_box_p']:.2g}, lag-1 "
                f"autocorrelation {w['lag1_autocorrelation']:+.2f}): what a DAQ's anti-alias "
                "filter and the sensor's lines leave, which the Newey-West standard errors "
                "account for"
            )

    structured = tuple(
        c
        for c in measurement.channels
        if channel_structured(
            white[c], c in ("wheel_speed", "roller_speed") and measurement.encoder_counts
        )
    )
    roller = model.drives.roller
    suggestion = ""
    delay = _torque_delay(fit, measurement, point) if "torque" in structured else ""
    if delay:
        warnings.append(delay)
    if structured:
        free = {
            k: dataclasses.replace(p, conditional_on_model=p.identified) for k, p in free.items()
        }
        nuisance = {
            k: dataclasses.replace(p, conditional_on_model=p.identified)
            for k, p in nuisance.items()
        }
        suggestion = model_suggestion(roller, model.drives.law)
        if delay:
            suggestion = (
                "the torque channel's delay against the encoders is the likely cause (see its "
                f"warning); else {suggestion}"
            )
        note_text = conditional_note()
        warnings.append(
            f"every standard error is {note_text} (structured: {', '.join(structured)})"
            + (f"; {suggestion}" if suggestion else "")
        )
    voltage = _wheel_drive_voltage(measurement, model.rig, model.drives)
    if voltage:
        warnings.append(voltage)
    invalid = _invalid_reasons(channels, converged, fit.iterations)
    if invalid:
        warnings.insert(
            0,
            "NOT A VALID CALIBRATION: " + "; ".join(invalid) + ": no calibrated rig is written "
            "and rollerrig analyze --calibration refuses this calibration.json",
        )

    values = [p.value(point.z[i]) for i, p in enumerate(params)]
    _, _, experiment = split_values(params, values)
    identified_law = {
        p.key.partition(".")[2]: v
        for p, v in zip(params, values, strict=True)
        if p.kind in ("polach", "fastsim") and fitted[p.key].identified
    }
    friction = with_polach(model.friction, identified_law)
    if identified_law:
        friction = _renamed(friction, "calibrated")
    facts = recording_facts(recording)
    rig = _identified_rig(model.rig, free, measurement.source, facts.get("sha256"))

    series: dict[str, Any] = {"time": measurement.time + measurement.start_time}
    for c in measurement.channels:
        series[c] = {
            "measured": measurement.values[c],
            "start": start_prediction[c],
            "fitted": point.prediction[c],
            "in_fit": measurement.valid[c],
        }
        if c == "torque":  # the lines fitted to each residual: what the RMS leaves out
            for which, pred in (("start", start_prediction[c]), ("fitted", point.prediction[c])):
                raw = measurement.values[c] - pred
                series[c][f"lines_{which}"] = raw - measurement.project_lines(raw)
    speed = experiment.get("roller_speed", measurement.roller_speed_start)
    if measurement.encoder_counts:
        notes.append(
            "encoder speeds from the counts by the analysis' own function (gate of one sample "
            "interval); the twin's counts are not floored: its speeds are the gate means, the "
            "quantisation is the noise model (variance (2 pi/(CPR dt))^2/6, lag-1 correlation "
            "-1/2)"
        )
    notes.append(
        "the recorded wheel-torque request replayed at a constant normal load and roller speed "
        "set point (nuisance parameters fitted with the others); the torque's motor and order "
        "lines fitted as linear nuisance parameters"
    )

    return Calibration(
        parameters=free,
        nuisance=nuisance,
        keys=keys,
        covariance=cov,
        correlation=corr,
        covariance_statistical=cov_stat,
        sensor_inputs=tuple(
            item.as_dict() | {"carried": item.quantity.name in shifts} for item in sensor_inputs
        ),
        channels=channels,
        rig=rig,
        friction=friction,
        warnings=warnings,
        notes=notes,
        combinations=tuple(combinations),
        experiment={
            "normal_load [N]": measurement.normal_load,
            "normal_load_spread [N]": measurement.normal_load_spread,
            "roller_speed_setpoint [m/s]": float(speed),
            "duration [s]": float(measurement.time[-1]),
            "samples": int(measurement.time.size),
            "sample_rate [Hz]": 1.0 / measurement.sample_interval,
            "free_rolling_until [s]": measurement.quiet_until,
            "friction_start": model.friction.to_dict(),
            "drives": {
                "wheel": model.drives.wheel,
                "roller": model.drives.roller,
                "law": model.drives.law,
            },
        },
        fit={
            "method": "Levenberg-Marquardt in z = ln(value - lower bound), forward differences "
            "in batches of the fast backend, central differences at the optimum",
            "converged": bool(converged),
            "iterations": int(fit.iterations),
            "simulations": int(model.simulations),
            "wall_time [s]": float(wall_time),
            "finite_difference_step_z": _fd_step(),
            **_law_steps(params),
            "solver": _solver_settings(model),
            "lag_window [s]": float(fit.lag_window),
            "lag_window_rule": (
                "Andrews (1991) AR(1) plug-in, Bartlett kernel"
                if HAC_WINDOW is None
                else f"fixed {HAC_WINDOW:g} s"
            ),
            "history": fit.history,
            "parameters_fixed": {params[i].key: r for i, r in dropped.items()},
        },
        recording=facts,
        series=series,
        start_rig=model.rig,
        valid=not invalid,
        invalid_reasons=tuple(invalid),
        conditional=bool(structured),
        structured_channels=structured,
        roller_drive=roller,
        law=model.drives.law,
        suggestion=suggestion,
    )


def _correlation(cov: np.ndarray) -> np.ndarray:
    """Correlation matrix of ``cov`` [-] (0 where a variance is 0, 1 on the diagonal)."""
    se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(se, se)
    corr = np.where(np.isfinite(corr), corr, 0.0)
    np.fill_diagonal(corr, 1.0)
    return corr


def _with_total_errors(combinations: list[dict], keys, values, cov: np.ndarray) -> list[dict]:
    """``combinations`` (found on the statistical covariance) with their standard errors from
    the total ``cov``, the statistical ones kept as ``*_statistical`` (delta method in ln v,
    as :func:`~rollerrig.calibrate.diagnostics.identified_combinations`)."""
    v = np.asarray(values, dtype=float)
    out = []
    for c in combinations:
        idx = [keys.index(k) for k in c["keys"]]
        rel = cov[np.ix_(idx, idx)] / np.outer(v[idx], v[idx])

        def u_rel(exponents: dict, idx=idx, rel=rel) -> float:
            g = np.array([exponents[keys[i]] for i in idx])
            return float(np.sqrt(max(float(g @ rel @ g), 0.0)))

        fixed, loose = u_rel(c["exponents"]), u_rel(c["undetermined"]["exponents"])
        out.append(
            c
            | {
                "standard_error": c["value"] * fixed,
                "relative_standard_error": fixed,
                "relative_standard_error_statistical": c["relative_standard_error"],
                "undetermined": c["undetermined"]
                | {
                    "relative_standard_error": loose,
                    "relative_standard_error_statistical": c["undetermined"][
                        "relative_standard_error"
                    ],
                },
            }
        )
    return out


def _wheel_drive_voltage(measurement, rig: RigParameters, drives) -> str:
    """A warning where the wheel's PMSM ran at its voltage limit in the recording ('' if not).

    As ``rollerrig analyze`` notes it (:func:`rollerrig.drives.pmsm_envelope.
    pmsm_voltage_share` of the recorded torque request at the measured wheel speed, from
    :data:`~rollerrig.drives.pmsm_envelope.VOLTAGE_LIMIT_SHARE` on): there the twin's wheel
    torque collapses within tens of ms, and the replay's result hangs on the PMSM's voltage
    parameters and the wheel's creep. On the quarter-scale rig at its limit (52 % creep) the
    fit had been marked invalid without a word of the cause (2026-12-03).
    """
    from rollerrig.drives.pmsm_envelope import VOLTAGE_LIMIT_SHARE, pmsm_voltage_share

    if drives.wheel != "pmsm":
        return ""
    ok = measurement.valid["wheel_speed"] & np.isfinite(measurement.values["wheel_speed"])
    if not np.any(ok):
        return ""
    omega = measurement.values["wheel_speed"][ok]
    share = pmsm_voltage_share(measurement.torque_request[ok], omega, rig.pmsm)
    at_limit = share >= VOLTAGE_LIMIT_SHARE
    if not np.any(at_limit):
        return ""
    t = measurement.time[ok] + measurement.start_time
    k = int(np.argmax(share))
    return (
        f"wheel drive at its voltage limit: the PMSM (rig [pmsm], i_d = 0 control, no field "
        f"weakening) needs {100 * VOLTAGE_LIMIT_SHARE:g} % or more of its inverter's voltage "
        f"for {int(np.count_nonzero(at_limit)) * measurement.sample_interval:.3g} s of the "
        f"recording from t = {float(t[at_limit][0]):.2f} s, up to {100 * float(share[k]):.3g} % "
        f"at t = {float(t[k]):.2f} s (wheel at {float(omega[k]):.4g} rad/s, rated "
        f"{rig.pmsm.rated_speed:.4g} rad/s; from the torque request and the measured wheel "
        "speed). There its torque falls short of the request and collapses within tens of ms: "
        "the replay hangs on the PMSM's voltage and current parameters (rig [pmsm]) and the "
        "wheel's creep, which the free keys may not cover; calibrate on a test below the limit"
    )


_INPUT_TEXT = {
    "torque_class": (
        "the torque sensor's stated class (a zero offset)",
        "at one load and speed a constant torque (the bearing loss) is what a zero offset "
        "looks like: a zero reading of the sensor at standstill, or recordings at another load "
        "or speed, separate them",
    ),
    "torque_gain": (
        "the torque sensor's stated class (a gain error, class/√3 of the reading)",
        "",
    ),
    "pressure_class": ("the pressure sensor's stated class (an offset of the load)", ""),
    "air_spring_area": ("the air spring's stated area (a gain error of the load)", ""),
}


def _torque_delay(fit, measurement, point) -> str:
    """A warning where a delay of the torque channel against the twin (and so against the
    encoders), fitted jointly with the free keys, explains at least :data:`DELAY_SHARE` of the
    torque's structured residual, else "".

    Fitted after the keys alone, a delay leaves little in the residual: the shaft's keys take
    most of it (k56, the motor's lag and J5 moved 1-5 standard errors for a torque 1-4 ms late,
    a residual correlated with the twin's dT/dt by 3-7 %). The delay is therefore estimated as
    one more column of the fit's linearisation at the optimum (:func:`channel_delay` on the
    stacked, weighted residual with the Jacobian's columns beside the delay's): the torque late
    by 1, 2, 4 and -2 ms gave 0.77, 1.69, 4.18 and -2.11 ms, a recording without delay 0.10 ms
    with 0.2 % of its torque residual explained (2026-12-03)."""
    if point.jacobian is None:
        return ""
    m = measurement
    dt = float(m.sample_interval)
    rate = np.gradient(np.asarray(point.prediction["torque"], dtype=float), dt)
    zero = {c: np.zeros(m.time.size) for c in m.channels}
    found = channel_delay(
        fit.residuals(point), fit.stack(zero | {"torque": rate}), np.asarray(point.jacobian)
    )
    if found is None:
        return ""
    tau, reduction = found
    total = tau + measurement.torque_delay  # a delay given is removed from the data already
    torque = fit.stack(zero | {"torque": m.values["torque"] - point.prediction["torque"]})
    share = min(1.0, reduction / float(torque @ torque))
    if share < DELAY_SHARE or abs(tau) < 0.1 * dt:
        return ""
    return (
        f"the torque channel {'lags' if tau > 0 else 'leads'} the twin by about "
        f"{abs(tau) * 1e3:.2g} ms: a delay, fitted with the free keys, removes "
        f"{'nearly all' if share >= 0.95 else f'{100 * share:.0f} %'} of the torque residual's "
        "sum of squares (rollerrig.calibrate.diagnostics.channel_delay). "
        "A delay between the DAQ's channels (another module, an amplifier's filter) against "
        "the encoders' counts? The twin takes the channels as simultaneous, and such a delay "
        "moves the "
        "shaft's keys by several standard errors: align the channels and calibrate again "
        f"(rollerrig calibrate --torque-delay-ms {total * 1e3:.2g}; torque_delay={total:.2g} "
        "from Python), or align them in the DAQ"
    )


def _systematic_notes(free: dict, inputs, shifts: dict[str, np.ndarray]) -> list[str]:
    """What the standard errors include, and the keys whose error is mostly systematic."""
    if not inputs:
        return []
    names = [i.quantity.name for i in inputs]
    left = [n for n in names if n not in shifts]
    out = [
        "standard errors (the ±) include the systematic errors of the channels that the rig "
        f"file states ({', '.join(n for n in names if n in shifts)}: sensors section, "
        "converted as rollerrig analyze converts them), linearised at the optimum and added in "
        "quadrature to the statistical (Newey-West) part; calibration.json gives both "
        "(standard_error_statistical, standard_error_systematic, systematic per input). They "
        "hold conditional on those classes"
        + (f"; left out, the load variants not simulated: {', '.join(left)}" if left else "")
    ]
    for key, p in free.items():
        if not p.identified or not p.systematic:
            continue
        name, shift = max(p.systematic.items(), key=lambda kv: abs(kv[1]))
        stat = p.standard_error_statistical or 0.0
        if abs(shift) <= stat:
            continue
        what, hint = _INPUT_TEXT.get(name, (name, ""))
        hint = hint if key.startswith("bearing.") else ""  # the offset's twin is the bearing
        out.append(
            f"{key}: its standard error {p.standard_error:.3g}{_unit_text(p.unit)} is mostly "
            f"systematic: {what} moves it by {shift:+.3g} for one standard uncertainty, "
            f"against {stat:.3g} from the residuals" + (f"; {hint}" if hint else "")
        )
    return out


def _solver_settings(model) -> dict[str, Any]:
    from rollerrig.solve.fast import FAST_DEFAULTS, SWEEP_H_MAX

    rtol = FAST_DEFAULTS["rtol"] if model.rtol is None else model.rtol
    return {
        "backend": (
            f"fast ({FAST_DEFAULTS['method'].upper()} with the ROS34PW2 W-method as its "
            "fallback, numba), integrate_batch"
        ),
        "exp_step [s]": FAST_DEFAULTS["exp_step"],
        "h_max [s]": FAST_DEFAULTS["h_max"] if model.h_max is None else model.h_max,
        "rtol": rtol,
        "fallback rtol": min(rtol, FAST_DEFAULTS["fallback_rtol"]),
        "search_h_max [s]": SWEEP_H_MAX,
    }


def _fd_step() -> float:

    return FD_STEP


def _law_steps(params) -> dict[str, Any]:
    """The steps of a tabulated creep law's keys, where they differ from :data:`FD_STEP`."""
    steps = fd_steps(params)
    other = {p.key: float(h) for p, h in zip(params, steps, strict=True) if h != FD_STEP}
    if not other:
        return {}
    return {
        "finite_difference_step_z_law": other,
        "finite_difference_step_law_rule": "the creep law's force is tabulated (cubic Hermite "
        "between nodes): its keys step below one node spacing (FD_STEP_TABULATED)",
    }


def _renamed(
    friction: PolachParameters | FastsimParameters, name: str
) -> PolachParameters | FastsimParameters:
    from dataclasses import replace

    return replace(friction, name=name, source=f"calibrated from {friction.name}")


def _unit_text(unit: str) -> str:
    return "" if unit == "1" else f" {unit}"


def _load_offset(measurement, residual, prediction) -> tuple[bool, str] | None:
    """``(beyond the classes, text)`` on the load channel's offset from the twin's fitted
    load, or None where the channel is not fitted against a class."""
    u = float(measurement.normal_load_class)
    if not u > 0.0 or residual.size == 0:
        return None
    offset = float(np.mean(residual))
    load = float(np.mean(prediction["normal_load"]))
    bound = math.sqrt(3.0) * u  # the pressure class's bound, the larger part on the rig
    text = (
        f"the normal-load channel reads {offset:+.4g} N from the twin's load {load:.6g} N, "
        f"which the torque and speeds determine with it: {offset / u:+.2f} standard "
        f"uncertainties of the sensors' stated classes (the pressure sensor's offset and the "
        f"air spring's area, u = {u:.3g} N)"
    )
    if abs(offset) > 2.0 * bound:
        return True, (
            f"{text}, beyond twice their bound (±{bound:.3g} N): check the pressure sensor's "
            "zero, the air spring's area and the channel map's load or pressure unit"
        )
    return False, text
