"""JCGM 101 (GUM Supplement 1) Monte Carlo of the corrected CoA and its validation of the LPU.

:func:`monte_carlo` draws every input of the measurement model of
:mod:`rollerrig.estimation.uncertainty` from its PDF (rectangular, normal, the release ring's
arcsine; the calibrated parameters jointly normal with their covariance) and passes the draws
through the full, non-linearised model: adaptive (§7.9) or with a fixed number of draws (§7.2).
:func:`jcgm101_validation` is the comparison of §8: the law of propagation's interval
y ± 1.96 u against the Monte Carlo's probabilistically symmetric 95 % interval, within the
numerical tolerance δ of u (:func:`numerical_tolerance`, §7.9.2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from rollerrig._validation import (
    ParameterError,
    require_finite,
    require_in_range,
    require_nonnegative,
    require_whole,
)

if TYPE_CHECKING:
    from rollerrig.estimation.coa_uncertainty import CoaUncertainty

__all__ = [
    "K95",
    "MonteCarloResult",
    "jcgm101_validation",
    "monte_carlo",
    "numerical_tolerance",
]

K95 = 1.959963984540054
"""Coverage factor of a 95 % interval of a normal output (JCGM 101 §8 compares with it)."""

_MC_BLOCK = 10_000  # JCGM 101 §7.9.4: M = max(100/(1 - p), 10^4) per run
_MC_MAX_RUNS = 100


def numerical_tolerance(u, ndig: int = 2):
    """JCGM 101 §7.9.2: δ = ½·10^l for u written as c·10^l with ``ndig`` significant digits.

    Parameters
    ----------
    u : array_like
        Standard uncertainties [unit of the output], finite and >= 0 (δ of u = 0 is 0).
    ndig : int
        Significant digits of u, >= 1.

    Examples
    --------
    JCGM 101 §7.9.2: u = 0.0123 is 12 × 10⁻³ to two digits, so δ = ½ × 10⁻³.

    >>> float(numerical_tolerance(0.0123))
    0.0005
    >>> numerical_tolerance(float("nan"))
    Traceback (most recent call last):
    ...
    rollerrig._validation.ParameterError: u must be finite, got nan
    """
    return _tolerance(require_nonnegative("u", u), _check_ndig(ndig))


def _check_ndig(ndig) -> int:
    return require_whole("ndig", ndig, minimum=1, unit="significant digits")


def _tolerance(u: np.ndarray, ndig: int):
    """:func:`numerical_tolerance` of checked ``u`` (NaN where a draw's u is NaN)."""
    safe = np.where(u > 0, u, 1.0)
    exponent = np.floor(np.log10(safe)) - (ndig - 1)
    return np.where(u > 0, 0.5 * 10.0**exponent, 0.0)


def _coa(t56, d_t, e_t, alpha, e_a, p, d_p, e_p, area, radius, j5, k_b, f_g, r_b, w_r, th,
         kappa=0.0, w_d=0.0):  # fmt: skip
    """μ_corr of the measurement model (:mod:`rollerrig.estimation.uncertainty`) [-]; arrays
    broadcast. ``kappa`` [-], ``w_d`` [N]: the swinging arm's σ h/l and dead weight."""
    load = (p + d_p + e_p) * area
    b = k_b * f_g * r_b * th
    force = (t56 + d_t + e_t + j5 * (alpha + e_a) + b * (w_r + load + w_d)) / (radius - kappa * b)
    return force / (load + w_d + kappa * force)


@dataclass
class MonteCarloResult:
    """JCGM 101 Monte Carlo at chosen samples.

    Attributes
    ----------
    index : ndarray
        The samples [-].
    mean, u : ndarray
        Mean and standard deviation of the draws [-].
    low, high : ndarray
        Probabilistically symmetric 95 % coverage interval [-].
    draws : int
        Draws per sample (runs × block).
    runs, block : int
    converged : bool
        The adaptive stopping rule (§7.9.4) was met before the cap of runs (False for a
        fixed number of draws).
    seed : int
    adaptive : bool
        Adaptive (§7.9) or a fixed number of draws (§7.2).
    """

    index: np.ndarray
    mean: np.ndarray
    u: np.ndarray
    low: np.ndarray
    high: np.ndarray
    draws: int
    runs: int
    block: int
    converged: bool
    seed: int
    adaptive: bool = True

    def as_dict(self) -> dict:
        method = (
            "JCGM 101 adaptive Monte Carlo (§7.9): runs of M draws until 2 s of the run "
            "values of y, u and the interval ends <= delta"
            if self.adaptive
            else "JCGM 101 Monte Carlo with a fixed number of draws (§7.2)"
        )
        out = {
            "method": method,
            "M per run": self.block,
            "runs": self.runs,
            "draws per point": self.draws,
            "adaptive": self.adaptive,
            "converged": self.converged if self.adaptive else None,
            "seed": self.seed,
            "coverage probability": 0.95,
            "interval": "probabilistically symmetric",
        }
        if not self.adaptive:
            out["converged_null_because"] = "a fixed number of draws, no stopping rule"
        return out


def _draw(unc: CoaUncertainty, index: np.ndarray, size: int, rng) -> np.ndarray:
    """``size`` draws of μ_corr at the samples ``index``: shape (size, len(index))."""
    m, terms = unc._model, unc.terms
    p = m["params"]
    u_sys, dist = m["u_sys"], m["dist"]
    shape = (size, 1)

    def systematic(name, estimate):
        if name not in u_sys or name in m["calibrated"]:
            return np.full(shape, estimate)
        u = u_sys[name]
        if dist[name] == "rectangular":
            a = u * math.sqrt(3.0)
            return estimate + rng.uniform(-a, a, shape)
        return estimate + u * rng.standard_normal(shape)

    drawn = {
        "area": systematic("air_spring_area", p["area"]),
        "radius": systematic("roller_radius", p["radius"]),
        "j5": systematic("roller_inertia", p["j5"]),
        "f_g": np.full(shape, p["f_g"]),
        "r_b": np.full(shape, p["r_b"]),
        "w_r": np.full(shape, p["w_r"]),
    }
    k_b = systematic("bearing_loss", 1.0) if "bearing_loss" in u_sys else np.ones(shape)
    if "h" in p:  # the swinging arm (rig files before it have none)
        h = systematic("arm_pivot_height", p["h"])
        arm_l = systematic("arm_length", p["l"])
        kappa, w_d = p["sign"] * h / arm_l, systematic("arm_dead_weight", p["w_d"])
    else:
        kappa, w_d = 0.0, 0.0
    names = m["calibrated"]
    if names:  # multivariate normal with the calibration's covariance
        est = {
            "air_spring_area": p["area"],
            "roller_radius": p["radius"],
            "roller_inertia": p["j5"],
            "bearing_friction": p["f_g"],
            "bearing_radius": p["r_b"],
            "roller_weight": p["w_r"],
        }
        vals, vecs = np.linalg.eigh(m["covariance"])
        root = vecs * np.sqrt(np.clip(vals, 0.0, None))
        z = rng.standard_normal((size, len(names))) @ root.T
        slot = {
            "air_spring_area": "area",
            "roller_radius": "radius",
            "roller_inertia": "j5",
            "bearing_friction": "f_g",
            "bearing_radius": "r_b",
            "roller_weight": "w_r",
        }
        for j, name in enumerate(names):
            drawn[slot[name]] = est[name] + z[:, j : j + 1]
    d_t = systematic("torque_class", 0.0)
    d_p = systematic("pressure_class", 0.0)
    k = index.size
    e_t = m["u_torque_noise"][index] * rng.standard_normal((size, k))
    e_a = m["u_accel_noise"][index] * rng.standard_normal((size, k))
    e_p = m["sigma_pressure"] * rng.standard_normal((size, k))
    res = np.hypot(unc.contributions["residual_steady"][index], m["u_release_fast"][index])
    res = res * rng.standard_normal((size, k))
    # The ring: an oscillation of unknown phase, arcsine PDF of amplitude √2 u.
    res = res + math.sqrt(2.0) * m["u_release_ring"][index] * np.sin(
        2.0 * math.pi * rng.random((size, k))
    )
    mu = _coa(
        terms.torque[index], d_t, e_t, terms.acceleration[index], e_a, m["pressure"][index],
        d_p, e_p, drawn["area"], drawn["radius"], drawn["j5"], k_b, drawn["f_g"], drawn["r_b"],
        drawn["w_r"], m["th"][index], kappa, w_d,
    )  # fmt: skip
    return mu + res


def monte_carlo(
    unc: CoaUncertainty,
    index,
    *,
    seed: int = 0,
    adaptive: bool = True,
    block: int = _MC_BLOCK,
    max_runs: int = _MC_MAX_RUNS,
    ndig: int = 2,
) -> MonteCarloResult:
    """JCGM 101 Monte Carlo of μ_corr at the samples ``index``.

    Every input is drawn from its PDF (rectangular or normal; the calibrated parameters
    jointly normal with their covariance) and passed through the full, non-linearised model.
    Adaptive (§7.9.4): runs of ``block`` draws until twice the standard deviation of the run
    values of the mean, u and both 95 % interval ends is at most the numerical tolerance δ of u
    (``ndig`` significant digits, §7.9.2) at every point, or ``max_runs``; ``adaptive=False``
    makes exactly ``max_runs`` runs.

    Parameters
    ----------
    unc : CoaUncertainty
        The law of propagation's result whose model is drawn.
    index : int or array_like of int, shape (k,)
        The samples [-]: at least one, each in ``[0, n)`` for the ``n`` samples of ``unc``
        (a negative index is refused, not counted from the end).
    seed : int
        Seed of the random generator, >= 0 (recorded for reproducibility).
    adaptive : bool
        Adaptive (§7.9) or exactly ``max_runs`` runs (§7.2).
    block : int
        Draws per run M, >= 2 (u is a standard deviation of the draws).
    max_runs : int
        Most runs, >= 1.
    ndig : int
        Significant digits of u for the numerical tolerance, >= 1.

    Returns
    -------
    MonteCarloResult
    """
    idx = _check_index(index, np.size(unc.value))
    # A float had failed deep in numpy, 0 runs in np.concatenate, a seed of -1 in SeedSequence;
    # block >= 2: u is the standard deviation of a run's draws.
    seed = require_whole("seed", seed, minimum=0)
    block = require_whole("block", block, minimum=2, unit="draws")
    max_runs = require_whole("max_runs", max_runs, minimum=1, unit="runs")
    ndig = _check_ndig(ndig)
    if not isinstance(adaptive, bool | np.bool_):
        raise ParameterError(f"adaptive must be True or False, got {adaptive!r}")
    rng = np.random.default_rng(seed)
    runs: list[np.ndarray] = []
    pooled: list[np.ndarray] = []
    converged = False
    for h in range(1, max_runs + 1):
        mu = _draw(unc, idx, block, rng)
        pooled.append(mu)
        if not adaptive:
            continue
        lo, hi = np.quantile(mu, [0.025, 0.975], axis=0)
        runs.append(np.stack([mu.mean(axis=0), mu.std(axis=0, ddof=1), lo, hi]))
        if h >= 2:
            r = np.stack(runs)  # (h, 4, points)
            spread = 2.0 * r.std(axis=0, ddof=1) / math.sqrt(h)
            delta = _tolerance(r[:, 1].mean(axis=0), ndig)
            if np.all(spread <= delta[None, :]):
                converged = True
                break
    draws = np.concatenate(pooled, axis=0)
    lo, hi = np.quantile(draws, [0.025, 0.975], axis=0)
    return MonteCarloResult(
        index=idx,
        mean=draws.mean(axis=0),
        u=draws.std(axis=0, ddof=1),
        low=lo,
        high=hi,
        draws=draws.shape[0],
        runs=len(pooled),
        block=block,
        converged=converged,
        seed=seed,
        adaptive=adaptive,
    )


def _check_index(index, n: int) -> np.ndarray:
    """The samples ``index`` as a 1-D int array in ``[0, n)``, or ParameterError: a negative
    index had silently picked a sample counted from the end, 1.5 sample 1, a mask the
    samples 0 and 1."""
    arr = np.asarray(index)
    if arr.dtype == bool:
        raise ParameterError(
            "index must be sample numbers [-], got a boolean mask; use np.flatnonzero(mask)"
        )
    values = require_finite("index", arr, "-")
    values = np.atleast_1d(values)
    if values.ndim != 1 or values.size == 0:
        raise ParameterError(
            f"index must be one sample number or a 1-D array of at least one [-], got shape "
            f"{np.shape(index)}"
        )
    negative = np.flatnonzero(values < 0)
    if negative.size:
        k = int(negative[0])
        raise ParameterError(
            f"index must be >= 0 [-] (sample numbers, not counted from the end), got "
            f"index[{k}] = {values[k]:g}"
        )
    require_in_range("index", values, 0, n, "-", low_inclusive=True)
    idx = values.astype(int)
    if np.any(idx != values):
        k = int(np.flatnonzero(idx != values)[0])
        raise ParameterError(
            f"index must be whole sample numbers [-], got index[{k}] = {values[k]:g}"
        )
    return idx


def jcgm101_validation(unc: CoaUncertainty, mc: MonteCarloResult, ndig: int = 2) -> dict:
    """JCGM 101 §8: is the LPU interval y ± U validated by the Monte Carlo at each point?

    d_low = |y − U − y_low|, d_high = |y + U − y_high| against δ (``ndig`` digits of u); and,
    separately, whether u itself agrees (|u_LPU − u_MC| ≤ δ: the model is near linear there;
    the interval can still differ where a rectangular input makes the output non-normal).

    Returns
    -------
    dict
        Arrays per point: ``delta``, ``d_low``, ``d_high``, ``interval_validated``,
        ``u_agrees``, ``u_relative_difference``.
    """
    i = mc.index
    y, u = unc.value[i], unc.u[i]
    big_u = K95 * u  # the GUM interval for p = 0.95 (normal output)
    delta = _tolerance(u, _check_ndig(ndig))
    d_low = np.abs(y - big_u - mc.low)
    d_high = np.abs(y + big_u - mc.high)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(u > 0, (mc.u - u) / u, 0.0)
    return {
        "delta": delta,
        "d_low": d_low,
        "d_high": d_high,
        "interval_validated": (d_low <= delta) & (d_high <= delta),
        "u_agrees": np.abs(mc.u - u) <= np.maximum(delta, 0.0),
        "u_relative_difference": rel,
    }
