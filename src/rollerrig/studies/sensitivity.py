"""Which parameter matters most: Sobol indices, rank correlations and grid main effects.

Three measures over a study Dataset (:mod:`rollerrig.studies.summary` describes its form),
one per kind of design:

- :func:`sobol_indices` — variance-based global sensitivity (first-order S1, total ST and,
  when sampled for it, second-order S2) of a ``[sample]`` study with ``method = "sobol"``,
  by SALib [1]_: Saltelli's sampling scheme [2]_ with the estimators of Saltelli et al.
  (2010) [3]_ for S1 and ST (Jansen's for ST) and of Saltelli (2002) [2]_ for S2, and
  bootstrap confidence intervals;
- :func:`rank_correlations` — Spearman's rank correlation of the metric with each parameter
  and its p-value, for any sampled design (random, lhs, sobol): monotone influence, cheap,
  tolerant of failed points;
- :func:`main_effects` — for a full-factorial grid, each axis's share of the variance of the
  metric over the grid (ANOVA main effects).

References
----------
.. [1] J. Herman and W. Usher, "SALib: An open-source Python library for Sensitivity
   Analysis", Journal of Open Source Software 2(9), 97, 2017.
.. [2] A. Saltelli, "Making best use of model evaluations to compute sensitivity indices",
   Computer Physics Communications 145(2), 280-297, 2002.
.. [3] A. Saltelli, P. Annoni, I. Azzini, F. Campolongo, M. Ratto and S. Tarantola,
   "Variance based sensitivity analysis of model output. Design and estimator for the total
   sensitivity index", Computer Physics Communications 181(2), 259-270, 2010.
.. [4] A. Saltelli et al., Global Sensitivity Analysis: The Primer, Wiley, 2008.
.. [5] D. C. Montgomery, Design and Analysis of Experiments, 8th ed., Wiley, 2013, ch. 5
   (sums of squares of a balanced factorial design).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rollerrig._optional import require
from rollerrig._validation import ParameterError
from rollerrig.studies.summary import (
    _describe_missing,
    _metric_values,
    _python,
    _unit,
    design_kind,
    grid_shape,
    is_numeric,
    json_attribute,
    missing_counts,
    study_name,
    varied_parameters,
)

__all__ = [
    "MainEffects",
    "RankCorrelations",
    "SobolIndices",
    "main_effects",
    "rank_correlations",
    "sobol_indices",
]


# --------------------------------------------------------------------------------------------
# Sobol indices (SALib)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class SobolIndices:
    """Sobol sensitivity indices of one metric of a study.

    Attributes
    ----------
    metric : str
        The metric analysed.
    unit : str
        Its unit (the indices themselves are fractions of its variance [-]).
    names : tuple of str
        The parameters, in design order.
    S1, S1_conf : ndarray, shape (D,)
        First-order indices [-] and the half-width of their confidence interval [-].
    ST, ST_conf : ndarray, shape (D,)
        Total-order indices [-] and the half-widths [-].
    S2, S2_conf : ndarray, shape (D, D), or None
        Second-order indices of each pair (upper triangle; NaN elsewhere) and half-widths [-];
        None when the study was not sampled for them (``second_order = false``).
    n_base : int
        Base sample size N of Saltelli's scheme (the study ran N (2D + 2) points with second
        order, N (D + 2) without).
    conf_level : float
        Confidence level of the intervals (bootstrap over the N base rows) [-].
    """

    metric: str
    unit: str
    names: tuple[str, ...]
    S1: np.ndarray
    S1_conf: np.ndarray
    ST: np.ndarray
    ST_conf: np.ndarray
    S2: np.ndarray | None
    S2_conf: np.ndarray | None
    n_base: int
    conf_level: float

    def rows(self) -> list[dict]:
        """One dict per parameter: ``parameter``, ``S1``, ``S1_conf``, ``ST``, ``ST_conf`` [-]
        (None, never NaN, where SALib gave no number)."""
        return [
            {
                "parameter": name,
                "S1": _python(self.S1[i]),
                "S1_conf": _python(self.S1_conf[i]),
                "ST": _python(self.ST[i]),
                "ST_conf": _python(self.ST_conf[i]),
            }
            for i, name in enumerate(self.names)
        ]

    def pair_rows(self) -> list[dict]:
        """One dict per pair of parameters: ``parameters``, ``S2``, ``S2_conf`` [-]; empty
        without second-order indices."""
        if self.S2 is None or self.S2_conf is None:
            return []
        d = len(self.names)
        return [
            {
                "parameters": f"{self.names[i]} × {self.names[j]}",
                "S2": _python(self.S2[i, j]),
                "S2_conf": _python(self.S2_conf[i, j]),
            }
            for i in range(d)
            for j in range(i + 1, d)
        ]


def _sample_spec(ds) -> dict:
    if design_kind(ds) != "sample":
        raise ParameterError(
            f"study {study_name(ds)!r} has design {ds.attrs.get('design')!r}, not a [sample] "
            "design: Sobol indices and rank correlations need sampled points; for a grid use "
            "main_effects"
        )
    spec = json_attribute(ds, "sample")
    if not isinstance(spec, dict):
        raise ParameterError(f"study {study_name(ds)!r}: attribute 'sample' must be a table")
    return spec


def _columns(ds, keys: list[str]) -> list[np.ndarray]:
    """Values of each parameter per point: float [SI], or text for a ``choice``."""
    out = []
    for k in keys:
        values = np.asarray(ds[k].values).ravel()
        out.append(values.astype(float) if is_numeric(values) else values.astype(str))
    return out


def _saltelli_blocks(ds, spec: dict, keys: list[str]) -> tuple[int, int, bool]:
    """(N, block length, second order) of a Sobol design, after checking its point order.

    Saltelli's scheme [2]_ stacks, for each of the N base rows, the blocks A, AB_1..AB_D,
    (BA_1..BA_D,) B, where AB_i is A with column i taken from B (BA_i: B with column i from
    A). A store whose points are not in this order (resorted, or a partial design) would give
    wrong indices without any error from SALib, so the structure is checked on the
    parameter values themselves (each column is mapped through its own inverse CDF, which
    keeps equal values equal; a ``choice`` parameter is compared as text).
    """
    d = len(keys)
    n_base = int(spec.get("n", 0))
    second = bool(spec.get("second_order", True))
    step = 2 * d + 2 if second else d + 2
    n = int(ds.sizes["point"])
    if d < 1 or n_base < 1 or n != n_base * step:
        raise ParameterError(
            f"study {study_name(ds)!r}: a Sobol design with N = {n_base} and D = {d} "
            f"parameters ({'with' if second else 'without'} second order) has N × "
            f"{step} = {n_base * step} points, the store has {n}; Sobol indices need the "
            "complete design in SALib's Saltelli order"
        )
    # Column c of block AB_i is column c of A, except for c == i (of B); BA_i the other way.
    good = True
    for c, values in enumerate(_columns(ds, keys)):
        x = values.reshape(n_base, step)
        a, b = x[:, :1], x[:, -1:]
        other = np.arange(d) == c
        ab = np.where(other, b, a)
        want = np.concatenate([ab, np.where(other, a, b)], axis=1) if second else ab
        got = x[:, 1 : 1 + want.shape[1]]
        if got.dtype.kind == "f":
            good = good and np.allclose(got, want, rtol=1e-12, atol=0.0)
        else:
            good = good and bool(np.all(got == want))
    if not good:
        raise ParameterError(
            f"study {study_name(ds)!r}: the points are not in SALib's Saltelli order "
            "(A, AB_1..AB_D, [BA_1..BA_D], B for each base row); Sobol indices need the "
            "store's points in design order"
        )
    return n_base, step, second


def sobol_indices(
    ds,
    metric: str,
    *,
    num_resamples: int = 100,
    conf_level: float = 0.95,
    seed: int | None = None,
) -> SobolIndices:
    """Sobol indices of a metric of a ``[sample]`` study with ``method = "sobol"``.

    The study's points are SALib's Saltelli sample on the unit cube (each column then mapped
    through its parameter's inverse CDF); the indices are those of the metric as a function
    of the parameters with their sampled distributions, by
    :func:`SALib.analyze.sobol.analyze` [1]_ on the problem
    ``{"num_vars": D, "names": keys, "bounds": [[0, 1]] * D}``: S1 by the estimator of
    Saltelli et al. (2010) [3]_ (Table 2 (b)), ST by Jansen's (ibid., (f)), S2 by Saltelli
    (2002) [2]_; confidence intervals by bootstrap over the N base rows.

    Parameters
    ----------
    ds : xarray.Dataset
        A study with ``design = "sample"`` and attrs ``sample`` = ``{"method": "sobol",
        "n": N, "second_order": bool, ...}``, its points in Saltelli order.
    metric : str
        One of the study's metrics.
    num_resamples : int
        Bootstrap resamples for the confidence intervals.
    conf_level : float
        Confidence level of the intervals, in (0, 1) [-].
    seed : int, optional
        Seed of the bootstrap; default the study's sampling seed (reproducible intervals).

    Returns
    -------
    SobolIndices

    Raises
    ------
    ParameterError
        The study is not a complete Sobol design in Saltelli order, has no such metric, or
        some points have no value of the metric (failed, pending, or the metric undefined
        there: the estimators need every point). The message counts them by status.

    Notes
    -----
    With N base rows the estimators' error falls as about N^(-1/2) (quasi-random: faster);
    the bootstrap half-widths say how far the indices may be off. S1 near zero may come out
    slightly negative, and S1 may exceed ST by the estimation error.

    Examples
    --------
    See ``tests/studies/test_sensitivity.py``: the Ishigami function's indices against
    their closed form (Saltelli et al. 2008 [4]_, sect. 4.7).
    """
    spec = _sample_spec(ds)
    method = str(spec.get("method", ""))
    if method != "sobol":
        raise ParameterError(
            f"study {study_name(ds)!r} was sampled with method {method!r}: Sobol indices need "
            "[sample] method = 'sobol' (Saltelli's scheme); for this study use "
            "rank_correlations"
        )
    keys = varied_parameters(ds)
    y = _metric_values(ds, metric)
    n_base, _, second = _saltelli_blocks(ds, spec, keys)
    bad = ~np.isfinite(y)
    if bad.any():
        raise ParameterError(
            f"study {study_name(ds)!r}: Sobol indices of {metric!r} need a value at every "
            f"point, but {int(bad.sum())} of {y.size} points have none "
            f"({_describe_missing(missing_counts(ds, y))}); finish pending points by running "
            "the study again (it resumes), narrow the ranges where points fail, or use "
            "rank_correlations, which ignores them"
        )
    if not 0.0 < conf_level < 1.0:
        raise ParameterError(f"conf_level must lie in (0, 1), got {conf_level!r}")
    analyze = require("SALib.analyze.sobol", purpose="Sobol indices of a study").analyze
    problem = {"num_vars": len(keys), "names": list(keys), "bounds": [[0.0, 1.0]] * len(keys)}
    res = analyze(
        problem,
        y,
        calc_second_order=second,
        num_resamples=int(num_resamples),
        conf_level=float(conf_level),
        print_to_console=False,
        seed=spec.get("seed") if seed is None else seed,
    )
    return SobolIndices(
        metric=metric,
        unit=_unit(ds, metric),
        names=tuple(keys),
        S1=np.asarray(res["S1"], dtype=float),
        S1_conf=np.asarray(res["S1_conf"], dtype=float),
        ST=np.asarray(res["ST"], dtype=float),
        ST_conf=np.asarray(res["ST_conf"], dtype=float),
        S2=np.asarray(res["S2"], dtype=float) if second else None,
        S2_conf=np.asarray(res["S2_conf"], dtype=float) if second else None,
        n_base=n_base,
        conf_level=float(conf_level),
    )


# --------------------------------------------------------------------------------------------
# Rank correlations (Spearman)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class RankCorrelations:
    """Spearman's rank correlation of a metric with each parameter of a sampled study.

    Attributes
    ----------
    metric : str
    names : tuple of str
        The parameters, in design order.
    rho : ndarray, shape (D,)
        Rank correlation coefficients, in [-1, 1] [-]; NaN where the parameter or the metric
        is constant over the points used, or the parameter is categorical (``choice``).
    pvalue : ndarray, shape (D,)
        Two-sided p-values of "no monotone association" [-] (scipy's t approximation).
    n_used : int
        Points used [points].
    n_ignored : int
        Points without a value of the metric, left out [points].
    ignored : dict
        Those points by why: status, or ``"metric undefined"`` (ran, but the metric has no
        value there) [points].
    note : str
        A sentence saying what was used and what was left out.
    """

    metric: str
    names: tuple[str, ...]
    rho: np.ndarray
    pvalue: np.ndarray
    n_used: int
    n_ignored: int
    ignored: dict
    note: str

    def rows(self) -> list[dict]:
        """One dict per parameter: ``parameter``, ``rho`` [-], ``p-value`` [-], ``points``
        (None, never NaN, where there is no coefficient)."""
        return [
            {
                "parameter": name,
                "rho": _python(self.rho[i]),
                "p-value": _python(self.pvalue[i]),
                "points": self.n_used,
            }
            for i, name in enumerate(self.names)
        ]


def rank_correlations(ds, metric: str) -> RankCorrelations:
    """Spearman's rank correlation of a metric with each sampled parameter.

    Measures monotone influence: +1 (-1) when the metric rises (falls) with the parameter
    at every point, whatever its shape. Points without a value of the metric (failed,
    pending, undefined) are left out and counted in the result.

    Parameters
    ----------
    ds : xarray.Dataset
        A study with ``design = "sample"`` (method random, lhs or sobol).
    metric : str
        One of the study's metrics.

    Returns
    -------
    RankCorrelations

    Raises
    ------
    ParameterError
        Not a sampled study, no such metric, or fewer than 3 points with a value.

    Notes
    -----
    For a Sobol design only the rows of the two independent base samples A and B (the first
    and last point of each Saltelli block) are used: the AB_i rows repeat their columns, and
    p-values assume independent points. Spearman's rho and its p-value are
    :func:`scipy.stats.spearmanr`'s.
    """
    from scipy import stats

    spec = _sample_spec(ds)
    keys = varied_parameters(ds)
    y = _metric_values(ds, metric)
    columns = _columns(ds, keys)
    numeric = np.array([c.dtype.kind == "f" for c in columns])
    x = np.column_stack([c if c.dtype.kind == "f" else np.zeros(c.size) for c in columns])
    use = np.ones(y.size, dtype=bool)
    where = ""
    if str(spec.get("method", "")) == "sobol":
        step = _saltelli_blocks(ds, spec, keys)[1]
        use[:] = False
        use[0::step] = True
        use[step - 1 :: step] = True
        where = f": the A and B rows of the Saltelli sample ({y.size} points in all)"
    counts = missing_counts(ds, np.where(use, y, 0.0))
    ok = use & np.isfinite(y)
    n_used, n_ignored = int(ok.sum()), int((use & ~np.isfinite(y)).sum())
    if n_used < 3:
        raise ParameterError(
            f"study {study_name(ds)!r}: rank correlations of {metric!r} need at least 3 points "
            f"with a value, it has {n_used}"
            + (f" ({_describe_missing(counts)} without)" if counts else "")
        )
    xs, ys = x[ok], y[ok]
    rho = np.full(len(keys), np.nan)
    pvalue = np.full(len(keys), np.nan)
    varied = numeric & (np.ptp(xs, axis=0) > 0.0)
    if np.ptp(ys) > 0.0 and varied.any():
        res = stats.spearmanr(np.column_stack([ys, xs[:, varied]]))
        r = np.atleast_2d(res.statistic)
        p = np.atleast_2d(res.pvalue)
        if r.shape == (1, 1):  # two columns: scipy returns scalars
            r = np.array([[1.0, float(res.statistic)]])
            p = np.array([[0.0, float(res.pvalue)]])
        rho[varied] = r[0, 1:]
        pvalue[varied] = p[0, 1:]
    note = f"{n_used} points used{where}"
    if not numeric.all():
        text = [k for k, num in zip(keys, numeric, strict=True) if not num]
        note += f"; {', '.join(text)}: categorical, no rank correlation"
    if n_ignored:
        note += f"; {n_ignored} without a value ignored ({_describe_missing(counts)})"
    return RankCorrelations(
        metric=metric,
        names=tuple(keys),
        rho=rho,
        pvalue=pvalue,
        n_used=n_used,
        n_ignored=n_ignored,
        ignored=counts,
        note=note,
    )


# --------------------------------------------------------------------------------------------
# Main effects of a full-factorial grid
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class MainEffects:
    """Main effects of the axes of a full-factorial grid on one metric.

    Attributes
    ----------
    metric : str
    unit : str
        The metric's unit.
    names : tuple of str
        The grid's axes, in design order.
    levels : tuple of tuple
        Values of each axis [SI, or text for a categorical axis].
    conditional_means : tuple of ndarray
        Mean of the metric at each level of each axis, over all the other axes [its unit].
    share : ndarray, shape (D,)
        Main-effect share of each axis: variance of its conditional means over the total
        variance [-]; NaN when the metric is constant over the grid.
    mean : float
        Grand mean over the grid [its unit].
    variance : float
        Total variance over the grid (equal weights, ``ddof = 0``) [its unit squared].
    """

    metric: str
    unit: str
    names: tuple[str, ...]
    levels: tuple[tuple, ...]
    conditional_means: tuple[np.ndarray, ...]
    share: np.ndarray
    mean: float
    variance: float

    @property
    def interaction_share(self) -> float:
        """What the main effects leave to interactions: ``1 - sum(share)`` [-] (NaN when the
        metric is constant)."""
        return float(1.0 - np.sum(self.share))

    def rows(self) -> list[dict]:
        """One dict per axis: ``parameter``, ``main-effect share [-]``, the smallest and
        largest conditional mean [the metric's unit] (None, never NaN)."""
        unit = f" [{self.unit}]" if self.unit and self.unit not in ("1", "-") else " [-]"
        return [
            {
                "parameter": name,
                "main-effect share [-]": _python(self.share[i]),
                f"lowest conditional mean{unit}": _python(self.conditional_means[i].min()),
                f"highest conditional mean{unit}": _python(self.conditional_means[i].max()),
            }
            for i, name in enumerate(self.names)
        ]


def _grid_levels(ds, keys: list[str], shape: tuple[int, ...]) -> tuple[tuple, ...]:
    """Values of each axis of a C-order grid, from the points [SI or text]."""
    levels = []
    for i, k in enumerate(keys):
        values = np.asarray(ds[k].values).reshape(shape)
        index = tuple(slice(None) if j == i else 0 for j in range(len(keys)))
        levels.append(tuple(_python(v) for v in values[index]))
    return tuple(levels)


def main_effects(ds, metric: str) -> MainEffects:
    """Main-effect share of each axis of a full-factorial grid in the variance of a metric.

    With the grid's points weighted equally, the share of axis i is

    .. math:: S_i = \\frac{\\operatorname{Var}_{x_i}\\left(E[Y \\mid x_i]\\right)}
                         {\\operatorname{Var}(Y)},

    the variance of the metric's conditional means over the levels of axis i (each mean over
    all the other axes) divided by its total variance over the grid (both ``ddof = 0``). For
    a full factorial this is the ANOVA main-effect sum of squares over the total sum of
    squares [5]_, and the first-order Sobol index of the metric when each axis is uniformly
    distributed on its levels [4]_. The shares sum to 1 for an additive metric; the rest,
    :attr:`MainEffects.interaction_share`, is the interactions'.

    Parameters
    ----------
    ds : xarray.Dataset
        A study with ``design = "grid"`` (attrs ``grid_shape``: points in C order over the
        axes).
    metric : str
        One of the study's metrics.

    Returns
    -------
    MainEffects

    Raises
    ------
    ParameterError
        Not a grid, no such metric, or points without a value (a conditional mean would then
        be over a different set of points at each level: the decomposition needs them all).

    Notes
    -----
    The shares describe the grid as designed: they depend on where its levels lie (a log
    axis weights its low decades as much as its high ones).
    """
    if design_kind(ds) != "grid":
        raise ParameterError(
            f"study {study_name(ds)!r} has design {ds.attrs.get('design')!r}: main effects "
            "need a full-factorial [grid]; for a [sample] study use sobol_indices or "
            "rank_correlations"
        )
    keys = varied_parameters(ds)
    shape = grid_shape(ds, keys)
    y = _metric_values(ds, metric)
    bad = ~np.isfinite(y)
    if bad.any():
        raise ParameterError(
            f"study {study_name(ds)!r}: main effects of {metric!r} need a value at every grid "
            f"point, but {int(bad.sum())} of {y.size} have none "
            f"({_describe_missing(missing_counts(ds, y))}); run the pending points (the "
            "study resumes) or leave the failing levels out of the grid"
        )
    grid = y.reshape(shape)
    mean = float(grid.mean())
    variance = float(np.mean((grid - mean) ** 2))
    d = len(keys)
    cond = tuple(grid.mean(axis=tuple(j for j in range(d) if j != i)) for i in range(d))
    between = np.array([np.mean((c - mean) ** 2) for c in cond])
    share = between / variance if variance > 0.0 else np.full(d, np.nan)
    return MainEffects(
        metric=metric,
        unit=_unit(ds, metric),
        names=tuple(keys),
        levels=_grid_levels(ds, keys, shape),
        conditional_means=cond,
        share=share,
        mean=mean,
        variance=variance,
    )
