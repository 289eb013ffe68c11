"""The smoother's innovations judged: their log-likelihood and whiteness (the model's
consistency), and the chain's drive noise by maximum likelihood in :data:`DRIVE_NOISE_RANGE`
(``drive_noise="ml"`` of :func:`rollerrig.estimation.smoother.smooth_contact_torque`).
"""

from __future__ import annotations

import math

import numpy as np

from rollerrig.estimation.smoother_model import _Smoother

__all__ = ["DRIVE_NOISE_RANGE"]


DRIVE_NOISE_RANGE = (1e1, 1e8)
"""Range of the chain's drive noise [N².m²/s] searched by maximum likelihood
(``drive_noise="ml"``): from a tenth of
:data:`~rollerrig.estimation.smoother.DEFAULT_DRIVE_NOISE` to where the drive model says
nothing any more (the drive torque then follows the torque sensor alone)."""


def _most_likely_drive_noise(log_likelihood) -> float:
    """The drive noise [N².m²/s] in :data:`DRIVE_NOISE_RANGE` that maximises the innovations'
    log-likelihood per sample (``log_likelihood(q)`` returns the innovations' dict): a bounded
    scalar search on log10 q to 0.2 decade (the likelihood is smooth and single-peaked in it
    on every recording tried, the twin's own, the dq drive's and the arm's)."""
    from scipy.optimize import minimize_scalar

    lo, hi = (math.log10(v) for v in DRIVE_NOISE_RANGE)
    res = minimize_scalar(
        lambda z: -log_likelihood(10.0**z)["log_likelihood_per_sample"],
        bounds=(lo, hi),
        method="bounded",
        options={"xatol": 0.2},
    )
    return float(10.0**res.x)


_MIN_INNOVATIONS = 30  # steady-state innovations below which none are judged


def _innovation_whiteness(sd: _Smoother, e: np.ndarray, judge: bool = True) -> dict:
    """The innovations' log-likelihood per sample (Gaussian, steady-state covariance
    S = H P⁻ Hᵀ + R in the scaled measurements) and, per measurement (``angle``, ``torque``),
    the whiteness (:func:`rollerrig.fit.whiteness.whiteness`) and ``variance`` of each
    innovation divided by its predicted standard deviation: for the right model, white with
    unit variance (the consistency test of Bar-Shalom, Li and Kirubarajan 2001, §5.4). The
    filter's transient is left out; empty (a likelihood of 0) below
    :data:`_MIN_INNOVATIONS` samples after it."""
    from rollerrig.fit.whiteness import whiteness

    skip = sd.gains.shape[0]
    if e.shape[0] - skip < _MIN_INNOVATIONS:
        return {"log_likelihood_per_sample": 0.0}  # too short to judge
    e = e[skip:]
    sd_pred = np.sqrt(np.diag(sd.H @ sd.P_prior @ sd.H.T) + 1.0)
    S = sd.H @ sd.P_prior @ sd.H.T + np.eye(e.shape[1])
    out = {
        "log_likelihood_per_sample": float(
            -0.5 * np.mean(np.sum(e * np.linalg.solve(S, e.T).T, axis=1))
            - 0.5 * np.log(np.linalg.det(S))
        )
    }
    if not judge:  # the likelihood alone (the drive noise's search)
        return out
    for j, name in enumerate(("angle", "torque")[: e.shape[1]]):
        x = e[:, j] / sd_pred[j]
        w = whiteness(x)
        w["variance"] = float(np.mean(x**2))
        out[name] = w
    return out
