"""The result of a calibration: values, standard errors, correlations, residuals, the rig.

:class:`Calibration` holds what :func:`rollerrig.calibrate.calibrate` found;
:meth:`Calibration.to_json` is the content of ``calibration.json``, :attr:`Calibration.rig`
the calibrated :class:`~rollerrig.rig.parameters.RigParameters` (written as
``calibrated-rig.toml`` by :func:`write_calibration`, which every ``--rig`` accepts), and
:meth:`Calibration.fit_dataset` the recorded channels beside the simulated ones before and
after the fit (``calibration-fit.nc``) for the report's figure.
"""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rollerrig._display import fmt, html_table, pretty_unit, text_block
from rollerrig.calibrate.problem import ROLLER_DRIVES, FreeParameter, split_values, with_polach
from rollerrig.calibrate.settings import FD_STEP, HAC_WINDOW, MAX_CORRELATION
from rollerrig.calibrate.stats import LJUNG_BOX_LAGS, whiteness
from rollerrig.contact.creep import PolachParameters
from rollerrig.rig.parameters import RigParameters

__all__ = [
    "CALIBRATED_RIG_NAME",
    "CALIBRATION_JSON_NAME",
    "FIT_DATASET_NAME",
    "Calibration",
    "ChannelFit",
    "FittedParameter",
    "write_calibration",
]

CALIBRATION_JSON_NAME = "calibration.json"
CALIBRATED_RIG_NAME = "calibrated-rig.toml"
FIT_DATASET_NAME = "calibration-fit.nc"

_UNITS = {"torque": "N.m", "wheel_speed": "rad/s", "roller_speed": "rad/s", "normal_load": "N"}
_MEANING = {
    "torque": "roller-shaft torque T56",
    "wheel_speed": "wheel encoder speed (gate of one sample interval)",
    "roller_speed": "roller encoder speed (gate of one sample interval)",
    "normal_load": "normal load (air-spring pressure x effective area)",
}
_MISFIT_FACTOR = 5.0  # residual RMS above this many sensor sigmas: the twin misses the data
_QUANTISATION_LAG1 = -0.5  # lag-1 autocorrelation of a gated speed's quantisation error
_LAG1_MARGIN = 0.1  # above -0.5 + this: structure beyond the quantisation

STRUCTURE_LAG1 = 0.5
"""Lag-1 autocorrelation of a channel's residuals above which they show structure the model
does not explain, whatever Ljung-Box says (white residuals of the >= 1000 samples of a test
give |r1| < 0.1; the twin that made a synthetic recording leaves r1 = 0.00 in the torque once
its lines are fitted, a wrong drive model 0.88 to 0.99)."""

STRUCTURE_ALPHA = 0.01
"""Level of the Ljung-Box test of whiteness (:func:`rollerrig.calibrate.stats.whiteness`)."""

STRUCTURE_TAU = 2.0
"""Integrated autocorrelation time [samples] a channel's residuals must also exceed for a
Ljung-Box rejection to count as structure: with thousands of samples Ljung-Box rejects the
DAQ's anti-alias filter over white sensor noise (the demo's torque: lag-1 0.26, 1.1 samples),
which the Newey-West standard errors already account for; a wrong drive model leaves far more
(lag-1 0.88-0.99)."""

WORSE_MARGIN = 0.01
"""A channel ends "worse than it started" when its residual RMS after the fit exceeds the one
before by more than this fraction and exceeds its sensor noise (a channel at its noise, such as
the normal load, moves by 1e-7 between fits)."""

CONDITIONAL_NOTE = (
    "conditional on the model: the residuals show structure the fitted model does not explain "
    "(Ljung-Box p < {alpha:g} with an autocorrelation time above {tau:g} samples, or lag-1 "
    "autocorrelation > {lag1:g}, in a channel; the encoders' "
    "quantisation (lag-1 -0.5) excepted); each standard error is what the data allow if the "
    "model were right, not the distance to the truth"
)

STANDARD_ERROR_CONVENTION = (
    "standard_error: one standard deviation [SI unit of the value] from the Newey-West "
    "(Bartlett kernel) sandwich covariance N/(N-p) H^-1 Omega H^-1 of the weighted least-squares "
    "fit in z = ln(value - lower bound), H = A^T A of the central-difference weighted Jacobian A "
    "at the optimum, Omega from the autocovariance of the per-instant scores over a lag window "
    "(lag_window [s]); mapped to the value by the delta method, value - lower bound times the "
    "standard error of z. standard_error_white: s^2 (A^T A)^-1 with s^2 = r^T r/(N - p), which "
    "assumes independent residuals; inflation = standard_error / standard_error_white. Weights: "
    "each channel divided by its sigma (sigma_sensor for the first fit, then the RMS of its own "
    "residuals: sigma_used)."
)


@dataclass(frozen=True)
class FittedParameter:
    """One free parameter after the fit.

    Attributes
    ----------
    key : str
        Dotted key.
    unit : str
        SI unit.
    initial : float
        Starting value [unit].
    value : float or None
        Fitted value [unit]; None when the recording does not identify it.
    standard_error : float or None
        One standard error [unit] (Newey–West); None when not identified.
    standard_error_white : float or None
        The standard error that independent residuals would give [unit].
    identified : bool
        Whether the recording determines it (relative standard error at most
        :data:`rollerrig.calibrate.fit.MAX_RELATIVE_SE`).
    reason : str
        Why it is not identified (empty when it is).
    at_bound : bool
        Whether the value sits at its upper bound.
    """

    key: str
    unit: str
    initial: float
    value: float | None
    standard_error: float | None
    standard_error_white: float | None
    identified: bool
    reason: str = ""
    at_bound: bool = False
    conditional_on_model: bool = False

    @property
    def relative_standard_error(self) -> float | None:
        """standard_error / |value| [-]."""
        if self.value is None or self.standard_error is None or self.value == 0:
            return None
        return self.standard_error / abs(self.value)

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready (null with ``why`` where no number can be given)."""
        out: dict[str, Any] = {
            "value": self.value,
            "standard_error": self.standard_error,
            "unit": self.unit,
            "initial": self.initial,
            "identified": self.identified,
        }
        if self.identified:
            inflation = (
                self.standard_error / self.standard_error_white
                if self.standard_error_white
                else None
            )
            out |= {
                "relative_standard_error": self.relative_standard_error,
                "standard_error_white": self.standard_error_white,
                "inflation": inflation,
                "at_upper_bound": self.at_bound,
                "conditional_on_model": self.conditional_on_model,
            }
        else:
            out["why_null"] = self.reason
        return out


@dataclass(frozen=True)
class ChannelFit:
    """How one fitted channel matches before and after the fit.

    Attributes
    ----------
    name, unit : str
        Channel and its SI unit.
    samples : int
        Samples fitted [1].
    sigma_sensor : float
        Sensor noise of the first weights [unit], with ``sigma_basis``.
    sigma_used : float
        σ of the final weights: the RMS of the residuals after the first fit [unit].
    rms_before, rms_after : float
        RMS of the residuals with the starting and the fitted parameters [unit].
    whiteness : dict
        :func:`rollerrig.calibrate.stats.whiteness` of the final residuals.
    lines : list of dict
        For the torque: each modelled line's fitted amplitude [N.m] and phase [rad]
        (:func:`rollerrig.calibrate.measurement.line_regressors`); empty otherwise.
    """

    name: str
    unit: str
    samples: int
    sigma_sensor: float
    sigma_basis: str
    sigma_used: float
    rms_before: float
    rms_after: float
    whiteness: dict
    lines: list = field(default_factory=list)

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready."""
        return {
            "unit": self.unit,
            "meaning": _MEANING[self.name],
            "samples": self.samples,
            "sigma_sensor": self.sigma_sensor,
            "sigma_sensor_basis": self.sigma_basis,
            "sigma_used": self.sigma_used,
            "rms_before": self.rms_before,
            "rms_after": self.rms_after,
            "whiteness": self.whiteness,
            **({"lines": self.lines} if self.lines else {}),
        }


@dataclass(frozen=True)
class Calibration:
    """What :func:`rollerrig.calibrate.calibrate` found.

    Attributes
    ----------
    parameters : dict of str to FittedParameter
        The free keys, in the order given.
    nuisance : dict of str to FittedParameter
        Fitted beside them: ``experiment.roller_speed``, the roller drive's set point [m/s].
    keys : tuple of str
        The identified keys (nuisance last), the order of ``covariance`` and ``correlation``.
    covariance : ndarray
        Covariance of the identified values [products of their SI units] (Newey–West).
    correlation : ndarray
        Their correlation matrix [-].
    channels : dict of str to ChannelFit
        Residuals per channel before and after, weights, whiteness.
    rig : RigParameters
        The starting rig with the identified rig keys replaced; the provenance of each
        replaced key records the calibration.
    friction : PolachParameters
        The recording's friction law with the identified ``polach.*`` keys replaced.
    warnings : list of str
        Parameters not identified, strong correlations, a fit that did not converge,
        residuals that are not white.
    notes : list of str
        What was assumed (weights, the encoder model, the experiment).
    experiment : dict
        Normal load, roller set point, duration, samples, friction (JSON-ready).
    fit : dict
        Iterations, simulations, convergence, wall time, the settings (JSON-ready).
    recording : dict
        :func:`rollerrig.measure.facts.recording_facts` of the recording.
    series : dict
        ``time`` [s] and per channel ``measured``, ``start`` and ``fitted`` arrays.
    start_rig : RigParameters or None
        The rig the calibration started from: recorded in ``calibration.json`` (``rig``,
        :func:`rollerrig.calibrate.binding.rig_binding`), which binds the calibration to it.
    valid : bool
        False when the fit did not converge, ended with a larger cost than it started with,
        or with a larger residual in a channel (:attr:`invalid_reasons`): no calibrated rig is
        written and ``analyze --calibration`` refuses it.
    conditional : bool
        The residuals show structure (:data:`STRUCTURE_LAG1`, :data:`STRUCTURE_ALPHA`) in the
        channels :attr:`structured_channels`: every standard error is conditional on the model.
    roller_drive : str
        The roller drive of the twin that was fitted.
    suggestion : str
        What to try when the model looks inadequate (the other roller-drive model).
    model_discrepancy : dict or None
        The type-B term from the spread of the values between adequate drive models
        (:func:`rollerrig.calibrate.compare.compare_drives`), per key.
    """

    parameters: dict[str, FittedParameter]
    nuisance: dict[str, FittedParameter]
    keys: tuple[str, ...]
    covariance: np.ndarray
    correlation: np.ndarray
    channels: dict[str, ChannelFit]
    rig: RigParameters
    friction: PolachParameters
    warnings: list[str]
    notes: list[str]
    experiment: dict[str, Any]
    fit: dict[str, Any]
    recording: dict[str, Any]
    series: dict[str, Any] = field(repr=False)
    start_rig: RigParameters | None = field(default=None, repr=False)
    valid: bool = True
    invalid_reasons: tuple[str, ...] = ()
    conditional: bool = False
    structured_channels: tuple[str, ...] = ()
    roller_drive: str = "induction"
    suggestion: str = ""
    model_discrepancy: dict[str, Any] | None = None

    @property
    def values(self) -> dict[str, float | None]:
        """Key -> fitted value [SI] (None where not identified)."""
        return {k: p.value for k, p in self.parameters.items()}

    @property
    def standard_errors(self) -> dict[str, float | None]:
        """Key -> standard error [SI] (None where not identified)."""
        return {k: p.standard_error for k, p in self.parameters.items()}

    def _repr_rows(self) -> tuple[str, list[tuple[str, str]]]:
        """The title and the (what, value) rows of the repr and the HTML table."""
        source = (self.recording or {}).get("source")
        name = Path(str(source)).name if source else "a recording"
        verdict = "valid" if self.valid else "NOT valid: " + "; ".join(self.invalid_reasons)
        model = "conditional on the model" if self.conditional else "white residuals"
        title = f"Calibration to {name} ({verdict}; roller drive {self.roller_drive}; {model})"
        rows = []
        for key, p in self.parameters.items():
            unit = pretty_unit(p.unit)
            if p.identified and p.value is not None:
                se = fmt(p.standard_error, 2)
                text = f"{fmt(p.value)} ± {se} {unit} (start {fmt(p.initial)})"
            else:
                text = f"not identified ({p.reason or 'the recording does not determine it'})"
            rows.append((key, text))
        for name_, ch in self.channels.items():
            rows.append(
                (f"residual RMS, {name_}", f"{fmt(ch.rms_before, 3)} -> {fmt(ch.rms_after, 3)} "
                 f"{pretty_unit(ch.unit)}")
            )  # fmt: skip
        rows.append(("warnings", f"{len(self.warnings)} (.warnings); the file: .to_json()"))
        return title, rows

    def __repr__(self) -> str:
        """A few lines: validity, each free key with its standard error, the residuals."""
        title, rows = self._repr_rows()
        return text_block(title, [f"{what}: {value}" for what, value in rows])

    def _repr_html_(self) -> str:
        """The same as :meth:`__repr__`, as a small HTML table."""
        title, rows = self._repr_rows()
        return html_table(title, rows)

    def to_json(self) -> dict[str, Any]:
        """The content of ``calibration.json`` (SI units; null with a reason, never NaN)."""
        keys = list(self.keys)
        return {
            "what": "calibration of the rig's twin to a recorded test (rollerrig calibrate)",
            "valid": bool(self.valid),
            **({"invalid_reasons": list(self.invalid_reasons)} if not self.valid else {}),
            "roller_drive": self.roller_drive,
            "standard_errors_conditional_on_model": bool(self.conditional),
            "conditional_on_model": {
                "flag": bool(self.conditional),
                "structured_channels": list(self.structured_channels),
                "test": (
                    f"a channel's residuals show structure when Ljung-Box rejects whiteness at "
                    f"p < {STRUCTURE_ALPHA:g} with an integrated autocorrelation time above "
                    f"{STRUCTURE_TAU:g} samples, or the lag-1 autocorrelation exceeds "
                    f"{STRUCTURE_LAG1:g}; an encoder speed's lag-1 autocorrelation up to "
                    f"{_QUANTISATION_LAG1 + _LAG1_MARGIN:g} is its quantisation's"
                ),
                "meaning": CONDITIONAL_NOTE.format(
                    alpha=STRUCTURE_ALPHA, lag1=STRUCTURE_LAG1, tau=STRUCTURE_TAU
                )
                if self.conditional
                else "the residuals are white: the standard errors hold for the model fitted",
                "budget": "rollerrig analyze --calibration uses, for a key of a calibration "
                "conditional on the model, the larger of its standard error and the rig's "
                "stated type-B uncertainty of that input",
                **({"suggestion": self.suggestion} if self.suggestion else {}),
            },
            **(
                {"model_discrepancy": self.model_discrepancy}
                if self.model_discrepancy is not None
                else {}
            ),
            "recording": self.recording,
            "free": list(self.parameters),
            "parameters": {k: p.as_dict() for k, p in self.parameters.items()},
            "nuisance": {k: p.as_dict() for k, p in self.nuisance.items()},
            "values": {k: p.value for k, p in self.parameters.items() if p.identified},
            "covariance": {
                "keys": keys,
                "units": [self._unit(k) for k in keys],
                "matrix": self.covariance.tolist(),
                "what": "covariance of the identified values, SI (Newey-West); nuisance last",
            },
            "correlation": {"keys": keys, "matrix": self.correlation.tolist()},
            "standard_error_convention": STANDARD_ERROR_CONVENTION,
            "channels": {c: f.as_dict() for c, f in self.channels.items()},
            "whiteness_convention": (
                f"per channel, residuals in time order: lag-1 autocorrelation, Durbin-Watson and "
                f"runs test (structured when r1 > 3/sqrt(n) or runs z < -3), Ljung-Box Q over "
                f"{LJUNG_BOX_LAGS} lags (white when p >= 0.01), integrated autocorrelation time "
                "tau (Sokal window) and n/tau effective samples; the standard errors account "
                "for the correlation through the Newey-West covariance, not through n/tau"
            ),
            "friction": {
                "what": "Polach parameters of the recording's friction condition (not part of "
                "the rig file)",
                **self.friction.to_dict(),
            },
            "experiment": self.experiment,
            "fit": self.fit,
            "warnings": list(self.warnings),
            "notes": list(self.notes),
            **({} if self.start_rig is None else {"rig": self._rig_binding()}),
        }

    def _rig_binding(self) -> dict[str, Any]:
        from rollerrig.calibrate.binding import rig_binding

        replaced = [
            k
            for k, p in self.parameters.items()
            if p.identified and not k.startswith(("polach.", "experiment."))
        ]
        return rig_binding(self.start_rig, replaced)

    def _unit(self, key: str) -> str:
        p = self.parameters.get(key) or self.nuisance.get(key)
        return p.unit if p is not None else ""

    def fit_dataset(self):
        """Recorded, starting and fitted channels on the recording's time axis (xarray)."""
        import xarray as xr

        from rollerrig.output.jsonfile import json_text
        from rollerrig.output.provenance import provenance

        data = {}
        for c in self.channels:
            unit = _UNITS[c]
            for which, what in (
                ("measured", "recorded"),
                ("start", "twin with the starting parameters"),
                ("fitted", "twin with the calibrated parameters"),
            ):
                data[f"{c}_{which}"] = (
                    "time",
                    np.asarray(self.series[c][which], dtype=float),
                    {"units": unit, "long_name": f"{_MEANING[c]}, {what}"},
                )
        ds = xr.Dataset(
            data, coords={"time": ("time", np.asarray(self.series["time"]), {"units": "s"})}
        )
        ds.attrs["title"] = "rollerrig calibration: recorded against simulated channels"
        ds.attrs["provenance"] = json_text(provenance(what="calibration fit"))
        return ds


def _identified_rig(
    rig: RigParameters, fitted: dict[str, FittedParameter], source: str, sha: str | None
) -> RigParameters:
    """``rig`` with the identified rig keys replaced, their provenance the calibration's."""
    values = {k: p.value for k, p in fitted.items() if p.identified and "." in k}
    values = {k: v for k, v in values.items() if not k.startswith(("polach.", "experiment."))}
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
                f"{p.standard_error:.3g}{_unit_text(p.unit)} (one standard error, Newey-West); "
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
    before: dict[str, np.ndarray],
    start_prediction: dict[str, np.ndarray],
    converged: bool,
    recording,
    wall_time: float,
) -> Calibration:
    """Assemble the :class:`Calibration` from the state of a finished fit."""
    from rollerrig.measure.facts import recording_facts

    act = np.flatnonzero(active)
    scale = np.array([params[i].value(point.z[i]) - params[i].lower for i in act])
    cov = covariance_z * np.outer(scale, scale)
    cov_white = white_z * np.outer(scale, scale)
    se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    se_white = np.sqrt(np.clip(np.diag(cov_white), 0.0, None))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(se, se)
    corr = np.where(np.isfinite(corr), corr, 0.0)
    np.fill_diagonal(corr, 1.0)
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
            )
        else:
            fitted[p.key] = FittedParameter(
                p.key, p.unit, p.initial, None, None, None, False, dropped.get(i, "fixed")
            )
    free = {p.key: fitted[p.key] for p in params[:n_free]}
    nuisance = {p.key: fitted[p.key] for p in params[n_free:]}
    keys = tuple(params[i].key for i in act)

    warnings = [f"{k}: {p.reason}" for k, p in free.items() if not p.identified]
    for a in range(len(keys)):
        for b in range(a + 1, len(keys)):
            if abs(corr[a, b]) > MAX_CORRELATION:
                warnings.append(
                    f"{keys[a]} and {keys[b]} are correlated ({corr[a, b]:+.3f}): the recording "
                    "determines mainly a combination of the two"
                )
    for k, p in free.items():
        if p.at_bound:
            warnings.append(f"{k}: the fit stops at its upper bound; its error is one-sided")
    if not converged:
        warnings.append(
            f"the fit did not converge within {fit.iterations} iterations; the values are the "
            "best found (raise max_iterations)"
        )

    notes = list(measurement.notes)
    residual_after = fit.channel_residuals(point.prediction)
    white = {c: whiteness(e) for c, e in residual_after.items()}
    channels = {}
    for c in measurement.channels:
        channels[c] = ChannelFit(
            name=c,
            unit=_UNITS[c],
            samples=int(measurement.valid[c].sum()),
            sigma_sensor=float(measurement.sensor_noise[c]),
            sigma_basis=measurement.noise_basis[c],
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
        if channels[c].rms_after > _MISFIT_FACTOR * channels[c].sigma_sensor:
            warnings.append(
                f"the twin does not reproduce {c}: residual RMS {channels[c].rms_after:.3g} "
                f"{_UNITS[c]} after the fit against a sensor noise of "
                f"{channels[c].sigma_sensor:.3g} {_UNITS[c]}; check the rig file, the channel "
                "map (units, signs) and which parameters are free"
            )
        w = white[c]
        quantised = c in ("wheel_speed", "roller_speed") and measurement.encoder_counts
        if quantised:
            w["expected_lag1_autocorrelation"] = _QUANTISATION_LAG1
        if w["white"]:
            continue
        what = (
            f"residuals of {c} are not white (Ljung-Box p = {w['ljung_box_p']:.2g}, lag-1 "
            f"autocorrelation {w['lag1_autocorrelation']:+.2f})"
        )
        if quantised and w["lag1_autocorrelation"] <= _QUANTISATION_LAG1 + _LAG1_MARGIN:
            notes.append(
                f"{what}, as the encoder's quantisation makes them (the difference of two count "
                f"errors: lag-1 autocorrelation {_QUANTISATION_LAG1:+g})"
            )
        else:
            warnings.append(
                f"{what}: structure the twin does not explain; the standard errors use the "
                "Newey-West covariance, which accounts for its correlation, not for a bias"
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
    if structured:
        free = {
            k: dataclasses.replace(p, conditional_on_model=p.identified) for k, p in free.items()
        }
        nuisance = {
            k: dataclasses.replace(p, conditional_on_model=p.identified)
            for k, p in nuisance.items()
        }
        other = [d for d in ROLLER_DRIVES if d != roller]
        if other:
            suggestion = (
                f"the roller drive model {roller!r} may be the wrong one for this recording: "
                f"compare it with {other[0]!r} on the same recording (rollerrig calibrate "
                f"RECORDING --free ... --compare-drives, or --roller-drive {other[0]})"
            )
        note_text = CONDITIONAL_NOTE.format(
            alpha=STRUCTURE_ALPHA, lag1=STRUCTURE_LAG1, tau=STRUCTURE_TAU
        )
        warnings.append(
            f"every standard error is {note_text} (structured: {', '.join(structured)})"
            + (f"; {suggestion}" if suggestion else "")
        )
    invalid = _invalid_reasons(channels, converged, fit.iterations)
    if invalid:
        warnings.insert(
            0,
            "NOT A VALID CALIBRATION: " + "; ".join(invalid) + ": no calibrated rig is written "
            "and rollerrig analyze --calibration refuses this calibration.json",
        )

    values = [p.value(point.z[i]) for i, p in enumerate(params)]
    _, polach_values, experiment = split_values(params, values)
    identified_polach = {k: v for k, v in polach_values.items() if fitted[f"polach.{k}"].identified}
    friction = with_polach(model.friction, identified_polach)
    if identified_polach:
        friction = _renamed(friction, "calibrated")
    facts = recording_facts(recording)
    rig = _identified_rig(model.rig, free, measurement.source, facts.get("sha256"))

    series: dict[str, Any] = {"time": measurement.time + measurement.start_time}
    for c in measurement.channels:
        series[c] = {
            "measured": measurement.values[c],
            "start": start_prediction[c],
            "fitted": point.prediction[c],
        }
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
        channels=channels,
        rig=rig,
        friction=friction,
        warnings=warnings,
        notes=notes,
        experiment={
            "normal_load [N]": measurement.normal_load,
            "normal_load_spread [N]": measurement.normal_load_spread,
            "roller_speed_setpoint [m/s]": float(speed),
            "duration [s]": float(measurement.time[-1]),
            "samples": int(measurement.time.size),
            "sample_rate [Hz]": 1.0 / measurement.sample_interval,
            "free_rolling_until [s]": measurement.quiet_until,
            "friction_start": model.friction.to_dict(),
            "drives": {"wheel": model.drives.wheel, "roller": model.drives.roller},
        },
        fit={
            "method": "Levenberg-Marquardt in z = ln(value - lower bound), forward differences "
            "in batches of the fast backend, central differences at the optimum",
            "converged": bool(converged),
            "iterations": int(fit.iterations),
            "simulations": int(model.simulations),
            "wall_time [s]": float(wall_time),
            "finite_difference_step_z": _fd_step(),
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
        suggestion=suggestion,
    )


def channel_structured(w: dict, quantised: bool) -> bool:
    """Whether a channel's residuals show structure the model does not explain
    (:data:`STRUCTURE_ALPHA`, :data:`STRUCTURE_LAG1`; an encoder speed's quantisation, lag-1
    autocorrelation -0.5, is no structure)."""
    r1 = float(w["lag1_autocorrelation"])
    if quantised and r1 <= _QUANTISATION_LAG1 + _LAG1_MARGIN:
        return False
    tau = float(w.get("integrated_autocorrelation_time [samples]", np.inf))
    return bool((w["ljung_box_p"] < STRUCTURE_ALPHA and tau > STRUCTURE_TAU) or r1 > STRUCTURE_LAG1)


def _invalid_reasons(channels: dict[str, ChannelFit], converged: bool, iterations: int):
    """Why a fit is not a valid calibration (empty: valid): no convergence, a larger cost
    (with the sensor-noise weights) or a larger residual in a channel than at the start."""
    out = []
    if not converged:
        out.append(f"the fit did not converge within {iterations} iterations")

    def cost(which: str) -> float:
        return sum(
            ch.samples * (getattr(ch, which) / ch.sigma_sensor) ** 2 for ch in channels.values()
        )

    before, after = cost("rms_before"), cost("rms_after")
    if after > before:
        out.append(
            f"it ended with a larger cost than it started with ({after:.6g} against {before:.6g}, "
            "sum of squared residuals over the sensor noise)"
        )
    worse = [
        f"{c} ({ch.rms_after:.4g} against {ch.rms_before:.4g} {ch.unit})"
        for c, ch in channels.items()
        if ch.rms_after > (1.0 + WORSE_MARGIN) * ch.rms_before and ch.rms_after > ch.sigma_sensor
    ]
    if worse:
        out.append("it ended with larger residuals than it started with in " + ", ".join(worse))
    return out


def _solver_settings(model) -> dict[str, Any]:
    from rollerrig.solve.fast import FAST_DEFAULTS, SWEEP_H_MAX

    return {
        "backend": "fast (ROS34PW2 W-method, numba), integrate_batch",
        "h_max [s]": FAST_DEFAULTS["h_max"] if model.h_max is None else model.h_max,
        "rtol": FAST_DEFAULTS["rtol"] if model.rtol is None else model.rtol,
        "search_h_max [s]": SWEEP_H_MAX,
    }


def _fd_step() -> float:

    return FD_STEP


def _renamed(friction: PolachParameters, name: str) -> PolachParameters:
    from dataclasses import replace

    return replace(friction, name=name, source=f"calibrated from {friction.name}")


def write_calibration(
    calibration: Calibration,
    folder: str | os.PathLike,
    *,
    overwrite: bool = True,
    write_rig: bool = True,
) -> list[Path]:
    """Write ``calibration.json``, ``calibrated-rig.toml`` and ``calibration-fit.nc``.

    A calibration that is not valid (:attr:`Calibration.valid`: no convergence, or worse than
    its start) gets no ``calibrated-rig.toml``: its ``calibration.json`` says ``"valid":
    false`` and why. ``write_rig=False`` leaves the rig out in any case (the comparison of drive
    models when no model is adequate).

    Every file carries the provenance of the run (:mod:`rollerrig.output`); the rig file holds
    it as its first comment line, and each calibrated key's own provenance names the
    recording and the standard error.

    Parameters
    ----------
    calibration : Calibration
    folder : path
        Existing folder.
    overwrite : bool
        Replace existing files.

    Returns
    -------
    list of Path
    """
    from rollerrig.output import write_dataset, write_json, write_text
    from rollerrig.rig.rigfile import write_sections
    from rollerrig.rig.sections import SECTIONS

    folder = Path(folder)
    rig = calibration.rig
    paths = [
        write_json(folder / CALIBRATION_JSON_NAME, calibration.to_json(), overwrite=overwrite),
        write_dataset(folder / FIT_DATASET_NAME, calibration.fit_dataset(), overwrite=overwrite),
    ]
    if calibration.valid and write_rig:
        text = write_sections({s: getattr(rig, s) for s in SECTIONS}, rig.provenance)
        paths.insert(
            1, write_text(folder / CALIBRATED_RIG_NAME, text, overwrite=overwrite, comment="#")
        )
    return paths


def _unit_text(unit: str) -> str:
    return "" if unit == "1" else f" {unit}"
