"""The result of a fit of the modified FASTSIM: values, covariance, honesty diagnostics.

:class:`ModifiedFastsimFit` is what :func:`rollerrig.fit.modified_fastsim.fit_modified_fastsim`
returns: the fitted :class:`~rollerrig.contact.laws.FastsimParameters`, their standard errors,
covariance and correlation, the residuals, the A/B coverage and the residual structure; its
fitted curve, its distance from a known set and its JSON summary.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import stats

from rollerrig._validation import require_finite
from rollerrig.contact.ellipse_grid import FastsimGrid
from rollerrig.contact.laws import FastsimParameters
from rollerrig.fit.diagnostics import ResidualStructure, SlipVelocityCoverage, distance_row
from rollerrig.fit.modified_fastsim_model import (
    MODIFIED_FASTSIM_PARAMETER_NAMES,
    _theta,
    modified_fastsim_coa,
)

__all__ = ["ModifiedFastsimFit"]


@dataclass(frozen=True)
class ModifiedFastsimFit:
    """Result of :func:`fit_modified_fastsim`.

    Attributes
    ----------
    parameters : FastsimParameters
        The fitted set.
    stderr : dict of str to float
        Standard errors by :data:`MODIFIED_FASTSIM_PARAMETER_NAMES` (inf where J^T J is
        singular) [units of the parameter].
    covariance, correlation : ndarray, shape (6, 6)
        Of (k0, α∞, β, μ0, A, B).
    residuals : ndarray
        Model minus measured CoA at each fitted point [-].
    rmse : float
        [-].
    dof : int
        n − 6.
    at_bound : tuple of str
        Parameters at a bound of the search.
    identifiable : bool
        False when a :class:`ModifiedFastsimFitWarning` was issued.
    problems : tuple of str
        Why not, one sentence each.
    success : bool
        Optimiser convergence.
    message : str
        Optimiser message.
    creep, slip_velocity, normal_load, coa : ndarray
        The fitted data (ξ [-], w [m/s], N [N], CoA [-]).
    semi_axis_x, semi_axis_y, shear_modulus, poisson, reference_load : float
        The contact the law was evaluated on (a, b [m] at N_ref [N]; G [Pa]; ν [-]).
    points_available : int
        Points given before thinning.
    residual_structure : ResidualStructure or None
    coverage : SlipVelocityCoverage or None
    grid : FastsimGrid
    """

    parameters: FastsimParameters
    stderr: dict
    covariance: np.ndarray
    correlation: np.ndarray
    residuals: np.ndarray
    rmse: float
    dof: int
    at_bound: tuple[str, ...]
    identifiable: bool
    problems: tuple[str, ...]
    success: bool
    message: str
    creep: np.ndarray = field(repr=False)
    slip_velocity: np.ndarray = field(repr=False)
    normal_load: np.ndarray = field(repr=False)
    coa: np.ndarray = field(repr=False)
    semi_axis_x: float = 0.0
    semi_axis_y: float = 0.0
    shear_modulus: float = 0.0
    poisson: float = 0.0
    reference_load: float = 0.0
    points_available: int = 0
    residual_structure: ResidualStructure | None = None
    coverage: SlipVelocityCoverage | None = None
    grid: FastsimGrid | None = field(default=None, repr=False)

    @property
    def values(self) -> dict[str, float]:
        """Fitted values by :data:`MODIFIED_FASTSIM_PARAMETER_NAMES`."""
        return dict(
            zip(MODIFIED_FASTSIM_PARAMETER_NAMES, _theta(self.parameters).tolist(), strict=True)
        )

    def confidence_interval(self, level: float = 0.95) -> dict[str, tuple[float, float]]:
        """Symmetric asymptotic interval of each parameter (t-distribution, ``dof``)."""
        q = float(stats.t.ppf(0.5 + 0.5 * level, max(self.dof, 1)))
        return {k: (v - q * self.stderr[k], v + q * self.stderr[k]) for k, v in self.values.items()}

    def curve(self, creep, slip_velocity=None, rolling_speed=None, normal_load=None):
        """Fitted CoA at Kalker creepages ``creep`` [-] on the fitted contact.

        ``slip_velocity`` [m/s] defaults to creep × ``rolling_speed`` [m/s] (default the
        median |w/ξ| of the data); ``normal_load`` [N] to the reference load.
        """
        s = require_finite("creep", creep, "-")
        if slip_velocity is None:
            if rolling_speed is None:
                ok = np.abs(self.creep) > 1e-6
                rolling_speed = float(np.median(np.abs(self.slip_velocity[ok] / self.creep[ok])))
            slip_velocity = s * rolling_speed
        q = self.reference_load if normal_load is None else normal_load
        return modified_fastsim_coa(
            s, slip_velocity, q, self.semi_axis_x, self.semi_axis_y, self.shear_modulus,
            self.poisson, self.parameters, reference_load=self.reference_load, grid=self.grid,
        )  # fmt: skip

    def truth_distance(self, truth: FastsimParameters, warn_sigma: float = 3.0) -> dict:
        """Distance of each fitted parameter from a known set, in standard errors [-]."""
        true = dict(zip(MODIFIED_FASTSIM_PARAMETER_NAMES, _theta(truth).tolist(), strict=True))
        return {
            k: distance_row(true[k], v, float(self.stderr[k]), k in self.at_bound, warn_sigma)
            for k, v in self.values.items()
        }

    def summary(self) -> dict:
        """JSON-ready: values, standard errors (None with the reason when not finite), the
        correlation matrix, the honesty diagnostics."""
        stderr = {k: (float(v) if np.isfinite(v) else None) for k, v in self.stderr.items()}
        corr = np.where(np.isfinite(self.correlation), self.correlation, np.nan)
        out = {
            "law": "modified-fastsim",
            "parameters": {
                "k0 [-]": self.parameters.k0,
                "alpha_inf [-]": self.parameters.alpha_inf,
                "beta [-]": self.parameters.beta,
                "mu0 [-]": self.parameters.static_friction,
                "A [-]": self.parameters.limit_ratio,
                "B [s/m]": self.parameters.friction_decay,
            },
            "stderr": stderr,
            "correlation": {
                "order": list(MODIFIED_FASTSIM_PARAMETER_NAMES),
                "matrix": [[None if not np.isfinite(x) else float(x) for x in row] for row in corr],
            },
            "rmse [-]": self.rmse,
            "dof": self.dof,
            "points": int(self.creep.size),
            "points_available": self.points_available,
            "at_bound": list(self.at_bound),
            "identifiable": self.identifiable,
            "problems": list(self.problems),
            "contact": {
                "semi_axis_x [m]": self.semi_axis_x,
                "semi_axis_y [m]": self.semi_axis_y,
                "shear_modulus [Pa]": self.shear_modulus,
                "poisson [-]": self.poisson,
                "reference_load [N]": self.reference_load,
            },
            "residual_structure": None
            if self.residual_structure is None
            else self.residual_structure.as_dict(),
            "slip_velocity_coverage": None if self.coverage is None else self.coverage.as_dict(),
            "success": self.success,
        }
        if any(v is None for v in stderr.values()):
            out["stderr_null_because"] = "J^T J singular: not determined by the data"
        return out
