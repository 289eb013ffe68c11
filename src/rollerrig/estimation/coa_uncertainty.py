"""The corrected CoA's uncertainty per sample (:class:`CoaUncertainty`), the type the law of
propagation (:mod:`rollerrig.estimation.uncertainty`) makes and the Monte Carlo
(:mod:`rollerrig.estimation.montecarlo`) draws from."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rollerrig.measure.correction import CorrectionTerms

__all__ = ["COVERAGE_FACTOR", "CoaUncertainty"]

COVERAGE_FACTOR = 2.0
"""Coverage factor k of the expanded uncertainty U = k u (about 95 % for a normal output)."""


@dataclass
class CoaUncertainty:
    """The corrected CoA with its uncertainty per sample, and what it was made of.

    Attributes
    ----------
    time : ndarray
        [s].
    value : ndarray
        μ_corr [-] (the analysis's corrected CoA).
    u : ndarray
        Combined standard uncertainty (LPU) [-].
    contributions : dict
        Input name -> |c_i| u(x_i) per sample [-] (the budget).
    correlation : ndarray
        Signed variance of the calibrated parameters' covariances per sample [-²] (0 without).
    inputs : list of InputQuantity
    terms : CorrectionTerms
    notes : list of str
    """

    time: np.ndarray
    value: np.ndarray
    u: np.ndarray
    contributions: dict
    correlation: np.ndarray
    inputs: list
    terms: CorrectionTerms
    notes: list = field(default_factory=list)
    coverage_factor: float = COVERAGE_FACTOR
    # the model's estimates and per-sample input uncertainties (for the Monte Carlo)
    _model: dict = field(default_factory=dict, repr=False)
    _filters: dict = field(default_factory=dict, repr=False)

    @property
    def expanded(self) -> np.ndarray:
        """U = k u [-]."""
        return self.coverage_factor * self.u

    def dominant(self, index=None) -> str:
        """The input with the largest RMS contribution over ``index`` (all samples)."""
        sel = slice(None) if index is None else index
        rms = {k: float(np.sqrt(np.mean(v[sel] ** 2))) for k, v in self.contributions.items()}
        return max(rms, key=rms.get)

    def systematic_errors(self, index) -> dict[str, np.ndarray]:
        """The change of μ_corr at the samples ``index`` for a one-standard-uncertainty error
        of each systematic input [-], signed: what every sample shares (a fit through these
        samples moves with it; :meth:`rollerrig.fit.polach.PolachFit.with_systematic`).

        Independent inputs by name; the calibrated parameters, correlated through the
        calibration's covariance C, as independent combinations ``calibrated (k)``: C's
        eigenvectors v_k scaled by √λ_k, so that their outer products sum to the block's
        covariance (JCGM 100 §5.2).
        """
        m = self._model
        sens = m["sensitivity"]
        calibrated = list(m["calibrated"])
        out = {
            inp.name: sens[inp.name][index] * m["u_sys"][inp.name]
            for inp in self.inputs
            if inp.kind == "systematic" and inp.name not in calibrated
        }
        if calibrated:
            lam, vec = np.linalg.eigh(m["covariance"])
            c = np.stack([sens[k][index] for k in calibrated])  # (inputs, samples)
            for k in np.flatnonzero(lam > 0.0):
                out[f"calibrated ({k + 1})"] = (vec[:, k] * math.sqrt(lam[k])) @ c
        return out

    def phase_mean(self, start: int, stop: int) -> tuple[float, float, dict]:
        """The mean of μ_corr over samples [start, stop), its u [-] and budget {input: u_i}.

        Systematic inputs: the mean sensitivity times u(x) (the same error in every sample).
        Filtered noise: the phase's mean filter weights. Pressure noise: independent samples.
        Residual: correlated over one correction window (its variance divided by the number
        of windows in the phase, at least 1).
        """
        m = self._model
        sl = slice(start, stop)
        n = stop - start
        budget, cov_term = {}, 0.0
        sens = m["sensitivity"]
        for inp in self.inputs:
            name = inp.name
            if inp.kind == "systematic":
                budget[name] = abs(float(np.mean(sens[name][sl]))) * m["u_sys"][name]
            elif name == "torque_noise":
                gain = self._filters["smooth"].mean_norm2(start, stop)
                budget[name] = (
                    abs(float(np.mean(sens[name][sl]))) * m["sigma_torque"] * math.sqrt(gain)
                )
            elif name == "encoder_quantisation":
                gain = self._filters["acceleration"].mean_norm2(start, stop)
                budget[name] = (
                    abs(float(np.mean(sens[name][sl]))) * m["sigma_counts"] * math.sqrt(gain)
                )
            elif name == "pressure_noise":
                budget[name] = float(
                    np.sqrt(np.mean((sens[name][sl] * m["sigma_pressure"]) ** 2) / n)
                )
            else:  # residual
                windows = max(1.0, n / max(m["window"], 1))
                budget[name] = float(np.sqrt(np.mean(self.contributions[name][sl] ** 2) / windows))
        names = m["calibrated"]
        if names:
            c = np.array([np.mean(sens[k][sl]) for k in names])
            full = float(c @ m["covariance"] @ c)
            cov_term = full - float(np.sum(c**2 * np.diag(m["covariance"])))
        u2 = sum(v**2 for v in budget.values()) + cov_term
        return float(np.mean(self.value[sl])), math.sqrt(max(u2, 0.0)), budget
