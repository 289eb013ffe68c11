"""The result of a calibration: values, standard errors, correlations, residuals, the rig.

:class:`Calibration` holds what :func:`rollerrig.calibrate.calibrate` found;
:meth:`Calibration.to_json` is the content of ``calibration.json``, :attr:`Calibration.rig`
the calibrated :class:`~rollerrig.rig.parameters.RigParameters`, and
:meth:`Calibration.fit_dataset` the recorded channels beside the simulated ones before and
after the fit (``calibration-fit.nc``) for the report's figure. It is assembled by
:func:`rollerrig.calibrate.assembly.build_calibration` and written by
:func:`rollerrig.calibrate.files.write_calibration`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rollerrig._display import fmt, html_table, pretty_unit, text_block
from rollerrig.calibrate.diagnostics import (
    _LAG1_MARGIN,
    _QUANTISATION_LAG1,
    STRUCTURE_ALPHA,
    STRUCTURE_BLOCK_ALPHA,
    STRUCTURE_LAG1,
    STRUCTURE_TAU,
    conditional_note,
)
from rollerrig.calibrate.problem import LAW_KEY_PREFIXES
from rollerrig.calibrate.settings import MAX_CORRELATION
from rollerrig.calibrate.stats import BLOCK_MEAN_SAMPLES, LJUNG_BOX_LAGS
from rollerrig.calibrate.systematic import SYSTEMATIC_MEANING
from rollerrig.contact.creep import PolachParameters
from rollerrig.contact.laws import FastsimParameters
from rollerrig.rig.parameters import RigParameters

__all__ = [
    "RESIDUAL_RMS_MEANING",
    "STANDARD_ERROR_CONVENTION",
    "Calibration",
    "ChannelFit",
    "FittedParameter",
]

RESIDUAL_RMS_MEANING = (
    "rms_before, rms_after: root mean square of recorded minus twin [the channel's unit], "
    "unweighted, over the samples fitted (a speed's first sample has no gate); for the torque "
    "with the motor and order lines fitted to that residual removed (least squares on their "
    "regressors), i.e. the residual the fit minimises; calibration-fit.png plots the same and "
    "names the RMS with the lines left in"
)
"""What ``rms_before`` and ``rms_after`` of each channel are (``calibration.json``)."""


_UNITS = {"torque": "N.m", "wheel_speed": "rad/s", "roller_speed": "rad/s", "normal_load": "N"}
_MEANING = {
    "torque": "roller-shaft torque T56",
    "wheel_speed": "wheel encoder speed (gate of one sample interval)",
    "roller_speed": "roller encoder speed (gate of one sample interval)",
    "normal_load": "normal load (air-spring pressure x effective area)",
}


_LAW_PARAMETERS = {
    "polach": "Polach",
    "fastsim": "FASTSIM (mu0, A, B)",
    "modified-fastsim": "Modified FASTSIM",
    "fastrip": "FaStrip (mu0, A, B)",
}


STANDARD_ERROR_CONVENTION = (
    "standard_error: one standard deviation [SI unit of the value], the root sum of squares of "
    "standard_error_statistical and standard_error_systematic (systematic_inputs.meaning). "
    "standard_error_statistical: from the Newey-West "
    "(Bartlett kernel) sandwich covariance N/(N-p) H^-1 Omega H^-1 of the weighted least-squares "
    "fit in z = ln(value - lower bound), H = A^T A of the central-difference weighted Jacobian A "
    "at the optimum, Omega from the autocovariance of the per-instant scores over a lag window "
    "(lag_window [s]); mapped to the value by the delta method, value - lower bound times the "
    "standard error of z. standard_error_white: s^2 (A^T A)^-1 with s^2 = r^T r/(N - p), which "
    "assumes independent residuals; inflation = standard_error_statistical / "
    "standard_error_white. Weights: "
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
        One standard error [unit]: the statistical part (Newey–West) and the systematic part
        of the sensors' stated classes in quadrature; None when not identified.
    standard_error_white : float or None
        The statistical standard error that independent residuals would give [unit].
    identified : bool
        Whether the recording determines it (relative standard error at most
        :data:`rollerrig.calibrate.fit.MAX_RELATIVE_SE`).
    reason : str
        Why it is not identified (empty when it is).
    at_bound : bool
        Whether the value sits at its upper bound.
    conditional_on_model : bool
        Whether the residuals show structure the model does not explain.
    standard_error_statistical : float or None
        The statistical part [unit]: Newey–West, from the residuals; None when not identified
        (or, in an older result, equal to ``standard_error``).
    systematic : dict of str to float or None
        Each stated sensor input (:mod:`rollerrig.calibrate.systematic`) -> the value's shift
        for an error of one standard uncertainty of that input [unit], linearised.
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
    standard_error_statistical: float | None = None
    systematic: dict[str, float] | None = None

    @property
    def standard_error_systematic(self) -> float | None:
        """Root sum of squares of :attr:`systematic` [unit] (None when not identified)."""
        if self.standard_error is None:
            return None
        return float(np.sqrt(sum(d * d for d in (self.systematic or {}).values())))

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
            statistical = (
                self.standard_error
                if self.standard_error_statistical is None
                else self.standard_error_statistical
            )
            inflation = (
                statistical / self.standard_error_white if self.standard_error_white else None
            )
            out |= {
                "relative_standard_error": self.relative_standard_error,
                "standard_error_statistical": statistical,
                "standard_error_systematic": self.standard_error_systematic,
                "systematic": dict(self.systematic or {}),
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
        Samples fitted [-].
    sigma_sensor : float
        Sensor noise of the first weights [unit], with ``sigma_basis``.
    sigma_used : float
        σ of the final weights: the RMS of the residuals after the first fit [unit].
    rms_before, rms_after : float
        RMS of the residuals with the starting and the fitted parameters [unit]: over the
        fitted samples (a speed's first has no gate), the torque with its motor and order lines
        (fitted to each residual) removed, unweighted: the residual the fit minimises, as
        ``calibration-fit.png`` plots it (:data:`RESIDUAL_RMS_MEANING`).
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
        Covariance of the identified values [products of their SI units]: Newey–West plus the
        sensors' stated classes (:attr:`covariance_statistical` plus each input's Δθ Δθᵀ).
    correlation : ndarray
        Their correlation matrix [-] (of :attr:`covariance`).
    channels : dict of str to ChannelFit
        Residuals per channel before and after, weights, whiteness.
    rig : RigParameters
        The starting rig with the identified rig keys replaced; the provenance of each
        replaced key records the calibration.
    friction : PolachParameters or FastsimParameters
        The recording's friction law, of the creep law :attr:`law`, with its identified keys
        (``polach.*`` or ``fastsim.*``) replaced.
    warnings : list of str
        Parameters not identified, strong correlations, a fit that did not converge,
        residuals that are not white.
    notes : list of str
        What was assumed (weights, the encoder model, the experiment).
    combinations : tuple of dict
        Where keys are correlated beyond :data:`rollerrig.calibrate.settings.MAX_CORRELATION`:
        the power product of them the recording determines, with its standard error, and the
        one it hardly determines
        (:func:`rollerrig.calibrate.diagnostics.identified_combinations`).
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
        The residuals show structure
        (:func:`~rollerrig.calibrate.diagnostics.channel_structured`) in the channels
        :attr:`structured_channels`: every standard error is conditional on the model.
    roller_drive : str
        The roller drive of the twin that was fitted.
    law : str
        The creep law of the twin that was fitted (:class:`rollerrig.rig.model.DriveConfig`
        ``law``): the calibrated twin is this law with :attr:`friction`.
    suggestion : str
        What to try when the model looks inadequate: the other roller-drive model, the other
        creep law, and the comparison that tests each
        (:func:`~rollerrig.calibrate.diagnostics.model_suggestion`).
    model_discrepancy : dict or None
        The type-B term from the spread of the values between adequate drive models
        (:func:`rollerrig.calibrate.compare.compare_drives`), per key.
    covariance_statistical : ndarray or None
        The statistical part of :attr:`covariance` (Newey–West) [products of SI units].
    sensor_inputs : tuple of dict
        The systematic inputs of the fitted channels the rig file states, carried into the
        standard errors (:func:`rollerrig.calibrate.systematic.sensor_inputs`), JSON-ready.
    """

    parameters: dict[str, FittedParameter]
    nuisance: dict[str, FittedParameter]
    keys: tuple[str, ...]
    covariance: np.ndarray
    correlation: np.ndarray
    channels: dict[str, ChannelFit]
    rig: RigParameters
    friction: PolachParameters | FastsimParameters
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
    law: str = "polach"
    suggestion: str = ""
    model_discrepancy: dict[str, Any] | None = None
    combinations: tuple[dict[str, Any], ...] = ()
    covariance_statistical: np.ndarray | None = field(default=None, repr=False)
    sensor_inputs: tuple[dict[str, Any], ...] = ()

    def combination_of(self, key: str) -> dict[str, Any] | None:
        """The identified combination ``key`` belongs to (None when it is fixed on its own)."""
        return next((c for c in self.combinations if key in c["keys"]), None)

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
        title = (
            f"Calibration to {name} ({verdict}; roller drive {self.roller_drive}; creep law "
            f"{self.law}; {model})"
        )
        rows = []
        for key, p in self.parameters.items():
            unit = pretty_unit(p.unit)
            if p.identified and p.value is not None and self.combination_of(key):
                text = (
                    f"{fmt(p.value)} {unit} (start {fmt(p.initial)}; in the combination "
                    f"{self.combination_of(key)['expression']})"
                )
            elif p.identified and p.value is not None:
                se = fmt(p.standard_error, 2)
                split = (
                    ""
                    if p.standard_error_statistical is None
                    else f"; statistical {fmt(p.standard_error_statistical, 2)}, sensor classes "
                    f"{fmt(p.standard_error_systematic, 2)}"
                )
                text = f"{fmt(p.value)} ± {se} {unit} (start {fmt(p.initial)}{split})"
            else:
                text = f"not identified ({p.reason or 'the recording does not determine it'})"
            rows.append((key, text))
        for c in self.combinations:
            rel = fmt(100 * c["relative_standard_error"], 2)
            rows.append((c["expression"], f"{fmt(c['value'])} {pretty_unit(c['unit'])} ± {rel} %"))
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
            "law": self.law,
            "standard_errors_conditional_on_model": bool(self.conditional),
            "conditional_on_model": {
                "flag": bool(self.conditional),
                "structured_channels": list(self.structured_channels),
                "test": (
                    f"a channel's residuals show structure when Ljung-Box rejects whiteness at "
                    f"p < {STRUCTURE_ALPHA:g} with an integrated autocorrelation time above "
                    f"{STRUCTURE_TAU:g} samples, or the lag-1 autocorrelation exceeds "
                    f"{STRUCTURE_LAG1:g}, or the means of blocks of {BLOCK_MEAN_SAMPLES} "
                    f"samples are off zero (chi-square p < {STRUCTURE_BLOCK_ALPHA:g}); an "
                    f"encoder speed's lag-1 autocorrelation up to "
                    f"{_QUANTISATION_LAG1 + _LAG1_MARGIN:g} is its quantisation's"
                ),
                "meaning": conditional_note()
                if self.conditional
                else "the residuals are white: the standard errors hold for the model fitted, "
                "conditional on the sensors' stated classes (systematic_inputs), whose "
                "systematic errors they include",
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
            "parameters": {k: self._entry(p) for k, p in self.parameters.items()},
            "nuisance": {k: self._entry(p) for k, p in self.nuisance.items()},
            "combinations": [
                {
                    "what": "a group of keys correlated beyond |r| = "
                    f"{MAX_CORRELATION:g}: the recording determines this power product of them "
                    "(value, standard_error [unit], relative_standard_error [-]), hardly the "
                    "one under undetermined; each member's standard_error is its marginal",
                    **c,
                }
                for c in self.combinations
            ],
            "values": {k: p.value for k, p in self.parameters.items() if p.identified},
            "covariance": {
                "keys": keys,
                "units": [self._unit(k) for k in keys],
                "matrix": self.covariance.tolist(),
                "what": "covariance of the identified values, SI (Newey-West plus the sensors' "
                "stated classes: covariance_statistical plus each systematic input's outer "
                "product); nuisance last",
            },
            **(
                {}
                if self.covariance_statistical is None
                else {
                    "covariance_statistical": {
                        "keys": keys,
                        "matrix": self.covariance_statistical.tolist(),
                        "what": "the statistical part of covariance (Newey-West)",
                    }
                }
            ),
            "systematic_inputs": {
                "meaning": SYSTEMATIC_MEANING,
                "inputs": list(self.sensor_inputs),
            },
            "correlation": {"keys": keys, "matrix": self.correlation.tolist()},
            "standard_error_convention": STANDARD_ERROR_CONVENTION,
            "channels": {c: f.as_dict() for c, f in self.channels.items()},
            "residual_rms_convention": RESIDUAL_RMS_MEANING,
            "whiteness_convention": (
                f"per channel, residuals in time order: lag-1 autocorrelation, Durbin-Watson and "
                f"runs test (structured when r1 > 3/sqrt(n) or runs z < -3), Ljung-Box Q over "
                f"{LJUNG_BOX_LAGS} lags (white when p >= 0.01), integrated autocorrelation time "
                "tau (Sokal window) and n/tau effective samples; the standard errors account "
                "for the correlation through the Newey-West covariance, not through n/tau"
            ),
            "friction": {
                "what": f"{_LAW_PARAMETERS.get(self.law, self.law)} parameters of the "
                "recording's friction condition (not part of the rig file)",
                "law": self.law,
                **self.friction.to_dict(),
            },
            "experiment": self.experiment,
            "fit": self.fit,
            "warnings": list(self.warnings),
            "notes": list(self.notes),
            **({} if self.start_rig is None else {"rig": self._rig_binding()}),
        }

    def _entry(self, p: FittedParameter) -> dict[str, Any]:
        """A key's entry of ``calibration.json``, naming the combination it belongs to."""
        out = p.as_dict()
        c = self.combination_of(p.key)
        if c is not None:
            out["in_combination"] = c["expression"]
            out["standard_error_meaning"] = (
                "marginal only: the recording determines the combination "
                f"{c['expression']} (combinations), not this key on its own"
            )
        return out

    def _rig_binding(self) -> dict[str, Any]:
        from rollerrig.calibrate.binding import rig_binding

        replaced = [
            k
            for k, p in self.parameters.items()
            if p.identified and not k.startswith((*LAW_KEY_PREFIXES, "experiment."))
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
            for which, what in (("start", "starting"), ("fitted", "calibrated")):
                if f"lines_{which}" in self.series[c]:
                    data[f"{c}_lines_{which}"] = (
                        "time",
                        np.asarray(self.series[c][f"lines_{which}"], dtype=float),
                        {
                            "units": unit,
                            "long_name": f"motor and order lines fitted to the recorded minus "
                            f"the {what} twin's {c} (left out of its residual RMS)",
                        },
                    )
            if "in_fit" in self.series[c]:
                data[f"{c}_in_fit"] = (
                    "time",
                    np.asarray(self.series[c]["in_fit"], dtype=np.int8),
                    {
                        "units": "1",
                        "long_name": f"1 where the {c} sample is fitted (its residual RMS is over "
                        "these samples), else 0",
                    },
                )
        ds = xr.Dataset(
            data, coords={"time": ("time", np.asarray(self.series["time"]), {"units": "s"})}
        )
        ds.attrs["title"] = "rollerrig calibration: recorded against simulated channels"
        ds.attrs["provenance"] = json_text(provenance(what="calibration fit"))
        return ds
