"""The result of a roller-to-track transfer: both curves, the factor, their bands, and every
stated assumption, as columns for a table and as a JSON-ready summary.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rollerrig.analysis.measured_curve import MeasuredCurve
from rollerrig.analysis.transfer_geometry import ContactGeometry, RailGeometry

__all__ = ["TransferResult"]


@dataclass
class TransferResult:
    """What :func:`transfer_curve` predicts, with the band and every stated assumption.

    Attributes
    ----------
    law : str
        The creep law.
    creepage : ndarray
        Kalker's ξ of the output grid [-].
    creep : ndarray
        The same creepage referred to the roller (rig) or rail (track) speed, s [-].
    slip_velocity : ndarray
        w = s·V [m/s].
    roller, roller_low, roller_high : ndarray
        The fitted curve on the roller and its 95 % band [-].
    track, track_low, track_high : ndarray
        The predicted curve on the rail and its 95 % band [-].
    factor, factor_low, factor_high : ndarray
        F_track/F_roller at equal creepage and its 95 % band [-].
    normal_load, rolling_speed : float
        N [N] and V [m/s] of both curves (V also the rail's speed).
    rolling_speed_is : str
        What V is ("the median roller speed of the points fitted", "as given"): the one speed
        every output states (:meth:`speed_text`).
    geometry : ContactGeometry
    rail : RailGeometry
    elastic : dict
        The elastic part on each side (semi-axes, a/b, C_ij, creep stiffness), and ratios.
    surface : dict
        The surface parameters carried over, with standard errors.
    fit : PolachFit or ModifiedFastsimFit
    peaks : dict
        Peak creepage and CoA on each side with their 95 % intervals.
    band : dict
        How the band was made: its construction ("model" or "measured points") and why,
        method, draws, inputs, what is not in it.
    assumptions, notes : list of str
    measured : MeasuredCurve
    """

    law: str
    creepage: np.ndarray
    creep: np.ndarray
    slip_velocity: np.ndarray
    roller: np.ndarray
    roller_low: np.ndarray
    roller_high: np.ndarray
    track: np.ndarray
    track_low: np.ndarray
    track_high: np.ndarray
    factor: np.ndarray
    factor_low: np.ndarray
    factor_high: np.ndarray
    normal_load: float
    rolling_speed: float
    geometry: ContactGeometry
    rail: RailGeometry
    elastic: dict
    surface: dict
    fit: object
    peaks: dict
    band: dict
    assumptions: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    measured: MeasuredCurve | None = None
    rolling_speed_is: str = "as given"

    def speed_text(self) -> str:
        """The one speed of the transfer, said the same way everywhere (console, figure, files):
        ``V = 31.4 km/h (the median roller speed of the points fitted)``."""
        return f"V = {self.rolling_speed * 3.6:.3g} km/h ({self.rolling_speed_is})"

    @property
    def stiffness_ratio(self) -> float:
        """G·a·b·C11 on the rail over that on the roller [-] (the factor at ξ → 0)."""
        return self.elastic["ratio_track_over_roller"]["creep_stiffness"]

    def factor_at(self, creepage: float) -> float:
        """F_track/F_roller at Kalker creepage ``creepage`` [-] (linear interpolation)."""
        return float(np.interp(creepage, self.creepage, self.factor))

    def _by_law(self, name: str) -> bool:
        return "located_by" in self.peaks[name]

    def peak_creepage_text(self, name: str) -> str:
        """The peak creepage of side ``name`` ("roller", "track") for a table, in %: with its
        95 % interval, "≥" the largest creepage where there is no peak in the range, and
        "law's shape" where the law's fitted shape places it (not the curve written)."""
        p = self.peaks[name]
        x = 100 * p["creepage [-]"]
        if not p.get("inside_measured_range", True):
            return f"≥ {x:.2f} (" + ("law's shape " if self._by_law(name) else "") + "still rising)"
        lo, hi = p["creepage_95 [-]"]
        text = f"{x:.2f} ({100 * lo:.2f}-{100 * hi:.2f})"
        return text + (", law's shape" if self._by_law(name) else "")

    def peak_coa_text(self, name: str) -> str:
        """The peak CoA of side ``name`` for a table, with its 95 % interval ("≥" where there is
        no peak in the range: the curve's largest CoA)."""
        p = self.peaks[name]
        text = f"{p['coa [-]']:.3f} ({p['coa_95 [-]'][0]:.3f}-{p['coa_95 [-]'][1]:.3f})"
        return text if p.get("inside_measured_range", True) else f"≥ {text}"

    def curve_maximum_text(self, name: str) -> str | None:
        """Where the curve written (the CSV's column) has its largest CoA inside the range, when
        that is not the peak stated (the law's shape placed the peak elsewhere or found none):
        "0.460 at 3.38 %"; None otherwise."""
        p = self.peaks[name]
        m = p.get("curve_maximum")
        if m is None or not m["inside_measured_range"]:
            return None
        same = p.get("inside_measured_range", True) and m["creepage [-]"] == p["creepage [-]"]
        return None if same else f"{m['coa [-]']:.3f} at {100 * m['creepage [-]']:.2f} %"

    def factor_text(self) -> str:
        """The transfer factor at small creepage, at the roller's peak (or, where there is none
        in the range, at the roller curve's largest CoA) and at the largest creepage."""
        lo, hi = self.elastic["ratio_track_over_roller"]["creep_stiffness_95"]
        p = self.peaks["roller"]
        text = f"factor F_rail/F_roller at small creepage {self.stiffness_ratio:.3f} "
        text += f"(95 %: {lo:.3f}-{hi:.3f}), "
        if p.get("inside_measured_range", True):
            shape = " (law's shape)" if self._by_law("roller") else ""
            text += f"at the roller's peak{shape} {self.factor_at(p['creepage [-]']):.3f}, "
        else:
            text += "no roller peak in the range"
            m = p.get("curve_maximum")
            if m is not None and m["inside_measured_range"]:
                text += (
                    f", at the roller curve's largest CoA (ξ {100 * m['creepage [-]']:.2f} %) "
                    f"{self.factor_at(m['creepage [-]']):.3f}"
                )
            text += ", "
        return text + f"at the largest creepage {self.factor[-1]:.3f}"

    def columns(self) -> dict:
        """The curves as columns for :func:`rollerrig.output.write_table` (name -> values,
        unit, long name)."""
        ref = "roller (rig) or rail (track) speed, Kayaalp eq. 4.21"
        measured = (self.band or {}).get("construction") == "measured points"
        level = "the measured level (the law's fit plus its residuals)" if measured else (
            f"the {self.law} law fitted"
        )  # fmt: skip
        edge = "edge of the 95 % band (draws' quantile, widened to hold the central curve and "
        edge += "by the law's factor error where included)"
        return {
            "creepage_kalker": (self.creepage, "1", "creepage referred to the mean rolling speed"),
            "creep": (self.creep, "1", f"creep referred to the {ref}"),
            "slip_velocity": (self.slip_velocity, "m/s", f"w = s V, {self.speed_text()}"),
            "coa_roller": (self.roller, "1", f"CoA on the roller: {level}"),
            "coa_roller_low95": (self.roller_low, "1", f"lower {edge}: roller CoA"),
            "coa_roller_high95": (self.roller_high, "1", f"upper {edge}: roller CoA"),
            "coa_track": (self.track, "1", "CoA predicted on the rail: the roller's times factor"),
            "coa_track_low95": (self.track_low, "1", f"lower {edge}: rail CoA"),
            "coa_track_high95": (self.track_high, "1", f"upper {edge}: rail CoA"),
            "factor": (self.factor, "1", "F_track / F_roller at equal creepage"),
            "factor_low95": (self.factor_low, "1", f"lower {edge}: factor"),
            "factor_high95": (self.factor_high, "1", f"upper {edge}: factor"),
        }

    def summary(self) -> dict:
        """JSON-ready: conditions, the elastic part, the surface part, factors, peaks, band,
        assumptions, the fit; units in the keys."""
        xi = self.creepage
        probes = [x for x in (0.001, 0.002, 0.005, 0.01, 0.02, 0.05) if x <= xi[-1]]
        fit = self.fit
        fit_summary = fit.summary() if hasattr(fit, "summary") else polach_fit_summary(fit)
        return {
            "law": self.law,
            "source": None if self.measured is None else self.measured.source,
            "creepage": {
                "rig": "s = (omega_w r_w - omega_r r_r)/(omega_r r_r), referred to the roller "
                "speed (Kayaalp eq. 4.21); on track referred to the rail (vehicle) speed V",
                "kalker": "xi = w / ((v_wheel + v_roller)/2), referred to the mean rolling speed "
                "(Kalker); the laws are evaluated in xi",
                "conversion": "xi = 2 s/(2 + s), s = 2 xi/(2 - xi); w = s V",
                "compared_at": "equal creepage and equal speed, hence equal slip velocity",
            },
            "conditions": {
                "normal_load [N]": self.normal_load,
                "rolling_speed [m/s]": self.rolling_speed,
                "rolling_speed [km/h]": self.rolling_speed * 3.6,
                "rolling_speed_is": self.rolling_speed_is,
                "rail": self.rail.describe(self.geometry.roller_radius_y),
            },
            "geometry": self.geometry.to_dict(),
            "transferred_by_contact_mechanics": self.elastic,
            "carried_over_as_measured": self.surface,
            "transfer_factor": {
                "small_creepage (= creep stiffness ratio) [-]": self.stiffness_ratio,
                "at_creepage [-]": {f"{x:g}": self.factor_at(x) for x in probes},
                "at_roller_peak [-]": self.factor_at(self.peaks["roller"]["creepage [-]"])
                if self.peaks["roller"].get("inside_measured_range", True)
                else None,
                "at_roller_curve_maximum [-]": self.factor_at(
                    self.peaks["roller"].get("curve_maximum", self.peaks["roller"])["creepage [-]"]
                ),
                "largest_creepage [-]": float(xi[-1]),
                "factor_at_largest_creepage [-]": float(self.factor[-1]),
            },
            "peaks": self.peaks,
            "band": self.band,
            "assumptions": self.assumptions,
            "notes": self.notes,
            "fit": fit_summary,
            "analysis_polach_fit": None if self.measured is None else self.measured.analysis_fit,
        }


def polach_fit_summary(fit) -> dict:
    stderr = {k: (float(v) if np.isfinite(v) else None) for k, v in fit.stderr.items()}
    p = fit.parameters
    out = {
        "law": "polach",
        "parameters": {
            "mu0 [-]": p.static_friction,
            "A [-]": p.limit_ratio,
            "B [s/m]": p.friction_decay,
            "kA [-]": p.k_adhesion,
            "kS [-]": p.k_slip,
        },
        "stderr": stderr,
        "rmse [-]": float(fit.rmse),
        "dof": int(fit.dof),
        "points": int(fit.creep.size),
        "identifiable": bool(fit.identifiable),
        "at_bound": list(fit.at_bound),
        "residual_structure": None
        if fit.residual_structure is None
        else fit.residual_structure.as_dict(),
        "slip_velocity_coverage": None if fit.coverage is None else fit.coverage.as_dict(),
    }
    if any(v is None for v in stderr.values()):
        out["stderr_null_because"] = "J^T J singular: not determined by the data"
    return out


# --------------------------------------------------------------------------------------------
# The transfer
# --------------------------------------------------------------------------------------------
