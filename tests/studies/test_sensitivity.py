"""Sensitivity of a study's metric: Sobol indices against the Ishigami function's closed form,
grid main effects against exact variance shares, rank correlations of monotone functions.

The studies are synthetic Datasets in the form the study store writes (issue 11, plan11.md):
dimension ``point``, one variable per parameter, ``label``/``status``/``reason``, one variable
per metric, JSON attributes ``parameters``, ``metrics``, ``design`` and ``sample`` or
``grid_shape``/``grid_scales``.
"""

from __future__ import annotations

import json
import sys

import numpy as np
import pytest
import xarray as xr

from rollerrig._optional import MissingExtraError
from rollerrig._validation import ParameterError
from rollerrig.studies.sensitivity import main_effects, rank_correlations, sobol_indices

PI = np.pi


def _study(params: dict, metrics: dict, design: str, status=None, **attrs) -> xr.Dataset:
    """A study Dataset: ``params`` key -> (values, unit), ``metrics`` name -> values."""
    n = len(next(iter(metrics.values())))
    status = ["ok"] * n if status is None else list(status)
    data = {
        k: ("point", np.asarray(v), {"units": u, "long_name": k}) for k, (v, u) in params.items()
    }
    data |= {
        "label": ("point", [f"point {i}" for i in range(n)]),
        "status": ("point", status),
        "reason": ("point", ["" if s == "ok" else f"because {s}" for s in status]),
    }
    data |= {
        m: ("point", np.asarray(v, dtype=float), {"units": "1", "nan_meaning": "no value"})
        for m, v in metrics.items()
    }
    base = {
        "study": "synthetic",
        "design": design,
        "parameters": json.dumps(list(params)),
        "metrics": json.dumps(list(metrics)),
    }
    return xr.Dataset(data, attrs=base | {k: json.dumps(v) for k, v in attrs.items()})


def _sobol_study(fn, n: int, d: int = 3, second: bool = True, seed: int = 1, lo=-PI, hi=PI):
    """SALib's Saltelli sample of the unit cube, mapped to U(lo, hi) per column, and fn(x)."""
    from SALib.sample import sobol as sobol_sample

    keys = [f"x{i + 1}" for i in range(d)]
    problem = {"num_vars": d, "names": keys, "bounds": [[0.0, 1.0]] * d}
    u = sobol_sample.sample(problem, n, calc_second_order=second, seed=seed)
    x = lo + (hi - lo) * u  # inverse CDF of U(lo, hi)
    dist = {k: {"distribution": "uniform", "low": lo, "high": hi} for k in keys}
    sample = {"method": "sobol", "n": n, "seed": seed, "second_order": second, "parameters": dist}
    return _study({k: (x[:, i], "1") for i, k in enumerate(keys)}, {"y": fn(x)}, "sample",
                  sample=sample)  # fmt: skip


A_ISH, B_ISH = 7.0, 0.1  # Ishigami & Homma (1990); Saltelli et al. (2008), sect. 4.7


def _ishigami(x: np.ndarray) -> np.ndarray:
    return np.sin(x[:, 0]) + A_ISH * np.sin(x[:, 1]) ** 2 + B_ISH * x[:, 2] ** 4 * np.sin(x[:, 0])


def _ishigami_exact():
    """Closed form (Saltelli et al. 2008, The Primer, sect. 4.7; Ishigami & Homma 1990)."""
    a, b = A_ISH, B_ISH
    v = a**2 / 8 + b * PI**4 / 5 + b**2 * PI**8 / 18 + 0.5
    v1 = 0.5 * (1 + b * PI**4 / 5) ** 2
    v2 = a**2 / 8
    v13 = b**2 * PI**8 * (1 / 18 - 1 / 50)
    return np.array([v1, v2, 0.0]) / v, np.array([v1 + v13, v2, v13]) / v, v13 / v


N_ISH = 4096  # base rows: 4096 x (2*3 + 2) = 32768 evaluations


@pytest.fixture(scope="module")
def ishigami():
    return sobol_indices(_sobol_study(_ishigami, N_ISH), "y")


def test_ishigami_closed_form_is_the_primers():
    """The closed form reproduces the Primer's table (Saltelli et al. 2008, sect. 4.7:
    S1 = 0.3139, 0.4424, 0; ST = 0.5576, 0.4424, 0.2437)."""
    s1, st, s13 = _ishigami_exact()
    np.testing.assert_allclose(s1, [0.3139, 0.4424, 0.0], atol=5e-5)
    np.testing.assert_allclose(st, [0.5576, 0.4424, 0.2437], atol=5e-5)
    assert s13 == pytest.approx(0.2437, abs=5e-5)


def test_ishigami_sobol_indices_match_the_closed_form(ishigami):
    """S1, ST and S2(x1, x3) of the Ishigami function within 0.02 at N = 4096.

    Tolerance from N: the bootstrap 95 % half-widths at N = 4096 are 0.02-0.05 (a standard
    error of 0.01-0.025, falling as N^-1/2; scrambled Sobol points do better), and over ten
    scrambling seeds the largest error of S1 was 0.007, of ST 0.002. The closed form must also
    lie inside the reported confidence intervals.
    """
    s1, st, s13 = _ishigami_exact()
    r = ishigami
    assert r.names == ("x1", "x2", "x3") and r.n_base == N_ISH and r.metric == "y"
    np.testing.assert_allclose(r.S1, s1, atol=0.02)
    np.testing.assert_allclose(r.ST, st, atol=0.02)
    assert np.all(np.abs(r.S1 - s1) <= r.S1_conf)
    assert np.all(np.abs(r.ST - st) <= r.ST_conf)
    # Second order: only x1-x3 interact (V13 = b^2 pi^8 (1/18 - 1/50)); Saltelli 2002's S2
    # estimator is noisier, so 0.05.
    assert r.S2 is not None and r.S2[0, 2] == pytest.approx(s13, abs=0.05)
    assert abs(r.S2[0, 1]) < 0.05 and abs(r.S2[1, 2]) < 0.05
    # The most influential parameter in total is x1, the least x3.
    assert np.argmax(r.ST) == 0 and np.argmin(r.ST) == 2


def test_sobol_rows_have_no_nan(ishigami):
    rows = ishigami.rows()
    assert [row["parameter"] for row in rows] == ["x1", "x2", "x3"]
    pairs = ishigami.pair_rows()
    assert [p["parameters"] for p in pairs] == ["x1 × x2", "x1 × x3", "x2 × x3"]
    for row in rows + pairs:
        assert all(v is None or isinstance(v, str) or np.isfinite(v) for v in row.values())
    json.dumps(rows + pairs, allow_nan=False)


def test_sobol_without_second_order():
    """N (D + 2) points; an additive function y = x1 + 2 x2 on U(0, 1): S1 = ST = 1/5, 4/5
    (variances 1/12 and 4/12 of the two terms, closed form)."""
    ds = _sobol_study(lambda x: x[:, 0] + 2 * x[:, 1], 1024, d=2, second=False, lo=0.0, hi=1.0)
    assert ds.sizes["point"] == 1024 * 4
    r = sobol_indices(ds, "y")
    assert r.S2 is None and r.pair_rows() == []
    np.testing.assert_allclose(r.S1, [0.2, 0.8], atol=0.02)
    np.testing.assert_allclose(r.ST, [0.2, 0.8], atol=0.02)


def test_sobol_with_a_categorical_parameter():
    """y = x1 + [friction == wet], x1 ~ U(0, 1), friction a fair choice of dry/wet: S1 = ST =
    (1/12) / (1/12 + 1/4) = 0.25 and 0.75 (variances of the two terms, closed form)."""
    from SALib.sample import sobol as sobol_sample

    problem = {"num_vars": 2, "names": ["x1", "friction"], "bounds": [[0.0, 1.0]] * 2}
    u = sobol_sample.sample(problem, 1024, calc_second_order=False, seed=2)
    friction = np.where(u[:, 1] < 0.5, "dry", "wet")  # inverse CDF of the choice
    y = u[:, 0] + (friction == "wet")
    dist = {"x1": {"distribution": "uniform", "low": 0.0, "high": 1.0},
            "friction": {"distribution": "choice", "values": ["dry", "wet"]}}  # fmt: skip
    sample = {"method": "sobol", "n": 1024, "seed": 2, "second_order": False, "parameters": dist}
    ds = _study({"x1": (u[:, 0], "1"), "friction": (friction, "")}, {"y": y}, "sample",
                sample=sample)  # fmt: skip
    r = sobol_indices(ds, "y")
    np.testing.assert_allclose(r.S1, [0.25, 0.75], atol=0.02)
    np.testing.assert_allclose(r.ST, [0.25, 0.75], atol=0.02)
    rank = rank_correlations(ds, "y")
    assert np.isnan(rank.rho[1]) and "friction: categorical" in rank.note
    assert rank.rows()[1]["rho"] is None


def test_sobol_bootstrap_is_reproducible():
    ds = _sobol_study(_ishigami, 256)
    a, b = sobol_indices(ds, "y"), sobol_indices(ds, "y")
    np.testing.assert_array_equal(a.S1_conf, b.S1_conf)


def test_sobol_with_failed_points_says_how_many_and_why():
    ds = _sobol_study(_ishigami, 64)
    status = np.array(["ok"] * ds.sizes["point"], dtype=object)
    status[[3, 10, 11]] = "solver failed"
    status[-2:] = "pending"
    y = ds["y"].values.copy()
    y[status != "ok"] = np.nan
    y[20] = np.nan  # ran, metric undefined
    ds = ds.assign(status=("point", status.astype(str)), y=("point", y, ds["y"].attrs))
    with pytest.raises(ParameterError) as err:
        sobol_indices(ds, "y")
    msg = str(err.value)
    assert "6 of 512 points" in msg
    assert "solver failed: 3" in msg and "pending: 2" in msg and "metric undefined: 1" in msg
    assert "rank_correlations" in msg


def test_sobol_refuses_other_designs():
    ds = _sobol_study(_ishigami, 64)
    lhs = ds.assign_attrs(sample=json.dumps({"method": "lhs", "n": 64}))
    with pytest.raises(ParameterError, match=r"method 'lhs'.*rank_correlations"):
        sobol_indices(lhs, "y")
    grid = _study({"k": ([1.0, 2.0], "N.m/rad")}, {"y": [1.0, 2.0]}, "grid", grid_shape=[2])
    with pytest.raises(ParameterError, match=r"not a \[sample\] design.*main_effects"):
        sobol_indices(grid, "y")
    partial = ds.isel(point=slice(0, 500))
    with pytest.raises(ParameterError, match=r"= 512 points, the store has 500"):
        sobol_indices(partial, "y")
    shuffled = ds.isel(point=np.random.default_rng(0).permutation(ds.sizes["point"]))
    with pytest.raises(ParameterError, match=r"not in SALib's Saltelli order"):
        sobol_indices(shuffled, "y")


def test_unknown_metric_names_the_metrics():
    ds = _sobol_study(_ishigami, 16)
    with pytest.raises(ParameterError, match=r"no metric 'yy' \(did you mean 'y'\?\).*'y'"):
        sobol_indices(ds, "yy")
    with pytest.raises(ParameterError, match=r"no metric 'z'"):
        rank_correlations(ds, "z")


def test_missing_salib_names_the_package(monkeypatch):
    ds = _sobol_study(_ishigami, 16)
    monkeypatch.setitem(sys.modules, "SALib.analyze.sobol", None)  # import fails
    want = r"Sobol indices of a study needs SALib: pip install 'rollerrig\[studies\]'"
    with pytest.raises(MissingExtraError, match=want):
        sobol_indices(ds, "y")


# --------------------------------------------------------------------------------------------
# Rank correlations
# --------------------------------------------------------------------------------------------


def _random_study(n: int = 200, method: str = "random"):
    rng = np.random.default_rng(3)
    x = rng.uniform(size=(n, 3))
    # exp(5 x1) rises with x1, -x2^3 falls with x2: both strictly monotone; x3 does nothing.
    y = np.exp(5 * x[:, 0]) - x[:, 1] ** 3
    y_mono = {"up": np.exp(3 * x[:, 0]), "down": -(x[:, 1] ** 3)}
    sample = {"method": method, "n": n, "seed": 3, "second_order": False, "parameters": {}}
    return _study({f"x{i + 1}": (x[:, i], "1") for i in range(3)}, {"y": y} | y_mono,
                  "sample", sample=sample)  # fmt: skip


def test_rank_correlation_of_a_monotone_function_is_one():
    """Spearman's rho is +1 (-1) for a strictly increasing (decreasing) function of one
    parameter, whatever its shape (definition of the rank correlation)."""
    ds = _random_study()
    up = rank_correlations(ds, "up")
    assert up.rho[0] == pytest.approx(1.0, abs=1e-12)
    assert up.pvalue[0] < 1e-12
    down = rank_correlations(ds, "down")
    assert down.rho[1] == pytest.approx(-1.0, abs=1e-12)
    # Independent parameters: |rho| within 3 standard errors (1 / sqrt(n - 1)) of 0.
    assert abs(up.rho[1]) < 3 / np.sqrt(199) and abs(up.rho[2]) < 3 / np.sqrt(199)
    both = rank_correlations(ds, "y")
    assert both.rho[0] > 0.5 and both.rho[1] < 0 and both.n_ignored == 0
    assert "200 points used" in both.note


def test_rank_correlations_ignore_failed_points_and_say_so():
    ds = _random_study(method="lhs")
    status = np.array(["ok"] * 200, dtype=object)
    status[:7] = "invalid parameters"
    up = ds["up"].values.copy()
    up[:7] = np.nan
    ds = ds.assign(status=("point", status.astype(str)), up=("point", up, ds["up"].attrs))
    r = rank_correlations(ds, "up")
    assert r.n_used == 193 and r.n_ignored == 7
    assert r.ignored == {"invalid parameters": 7}
    assert "7 without a value ignored (invalid parameters: 7)" in r.note
    assert r.rho[0] == pytest.approx(1.0, abs=1e-12)
    rows = r.rows()
    assert rows[0] == {"parameter": "x1", "rho": r.rho[0], "p-value": r.pvalue[0], "points": 193}


def test_rank_correlations_of_a_constant_are_none():
    ds = _random_study()
    ds = ds.assign(up=("point", np.ones(200), ds["up"].attrs))
    r = rank_correlations(ds, "up")
    assert np.isnan(r.rho).all()
    assert all(row["rho"] is None and row["p-value"] is None for row in r.rows())


def test_rank_correlations_on_a_sobol_design_use_the_base_samples():
    ds = _sobol_study(lambda x: np.exp(x[:, 2]), 128)
    r = rank_correlations(ds, "y")
    assert r.n_used == 256
    assert r.rho[2] == pytest.approx(1.0, abs=1e-12)
    assert "A and B rows" in r.note


def test_rank_correlations_refuse_a_grid():
    grid = _study({"k": ([1.0, 2.0, 3.0], "1")}, {"y": [1.0, 2.0, 3.0]}, "grid", grid_shape=[3])
    with pytest.raises(ParameterError, match=r"design 'grid'"):
        rank_correlations(grid, "y")


# --------------------------------------------------------------------------------------------
# Main effects of a grid
# --------------------------------------------------------------------------------------------


def _grid_study(fn, axes: dict, status=None):
    """A C-order full-factorial grid over ``axes`` (key -> (levels, unit)) and fn(*mesh)."""
    levels = [np.asarray(v) for v, _ in axes.values()]
    mesh = np.meshgrid(*levels, indexing="ij")
    params = {k: (m.ravel(), u) for (k, (_, u)), m in zip(axes.items(), mesh, strict=True)}
    y = fn(*mesh).ravel()
    shape = [len(v) for v in levels]
    return _study(params, {"y": y}, "grid", status=status, grid_shape=shape,
                  grid_scales=["list"] * len(shape))  # fmt: skip


def test_main_effects_of_an_additive_grid_are_the_exact_shares():
    """y = 2 k + s^2 + c(friction) on a 3 x 4 x 2 grid: the shares are each term's variance
    over its levels divided by their sum (additive: no interaction). Exact, by hand:
    Var(2 k) on k = 0, 1, 2 is 8/3; Var(s^2) on s = -1, 0, 1, 2 (s^2 = 1, 0, 1, 4) is 9/4;
    Var(c) on c = 0, 1 is 1/4."""
    effect = {"dry": 0.0, "wet": 1.0}
    ds = _grid_study(
        lambda k, s, f: 2 * k + s**2 + np.vectorize(effect.get)(f),
        {
            "stiffness.roller_shaft": ([0.0, 1.0, 2.0], "N.m/rad"),
            "speed": ([-1.0, 0.0, 1.0, 2.0], "m/s"),
            "friction": (["dry", "wet"], ""),
        },
    )
    r = main_effects(ds, "y")
    var = np.array([8 / 3, 9 / 4, 1 / 4])
    np.testing.assert_allclose(r.share, var / var.sum(), rtol=1e-12)
    assert r.interaction_share == pytest.approx(0.0, abs=1e-12)
    assert r.variance == pytest.approx(var.sum(), rel=1e-12)
    assert r.levels[2] == ("dry", "wet") and r.levels[1] == (-1.0, 0.0, 1.0, 2.0)
    np.testing.assert_allclose(r.conditional_means[2], r.mean + np.array([-0.5, 0.5]))
    rows = r.rows()
    assert rows[0]["parameter"] == "stiffness.roller_shaft"
    assert rows[0]["main-effect share [-]"] == pytest.approx(var[0] / var.sum())


def test_main_effects_of_a_pure_interaction_are_zero():
    """y = a b on centred levels: both conditional means are 0, all variance is interaction."""
    ds = _grid_study(lambda a, b: a * b, {"a": ([-1.0, 1.0], "1"), "b": ([-2.0, 0.0, 2.0], "1")})
    r = main_effects(ds, "y")
    np.testing.assert_allclose(r.share, 0.0, atol=1e-15)
    assert r.interaction_share == pytest.approx(1.0)


def test_main_effects_of_a_constant_are_none():
    ds = _grid_study(lambda a, b: 0 * a + 1.0, {"a": ([1.0, 2.0], "1"), "b": ([1.0, 2.0], "1")})
    r = main_effects(ds, "y")
    assert all(row["main-effect share [-]"] is None for row in r.rows())


def test_main_effects_refuse_failed_points_and_samples():
    status = ["ok", "solver failed", "ok", "pending"]
    ds = _grid_study(lambda a, b: a + b, {"a": ([1.0, 2.0], "1"), "b": ([1.0, 2.0], "1")},
                     status=status)  # fmt: skip
    ds["y"].values[[1, 3]] = np.nan
    with pytest.raises(ParameterError, match=r"2 of 4 have none \(pending: 1, solver failed: 1\)"):
        main_effects(ds, "y")
    with pytest.raises(ParameterError, match=r"need a full-factorial \[grid\]"):
        main_effects(_random_study(20), "y")
    bad = ds.assign_attrs(grid_shape="[3, 2]")
    with pytest.raises(ParameterError, match=r"grid_shape \[3, 2\] does not fit"):
        main_effects(bad, "y")
