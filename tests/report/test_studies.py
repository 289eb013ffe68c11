"""Figures of a study: one kind per design, units on the axes, failed points marked (never
dropped), categorical parameters by their categories, a clear error for an unknown metric.

The figures are inspected as matplotlib objects (labels, scales, artists with the
``MISSING_GID``), not as pixels. The studies are synthetic Datasets in the form the study
store writes (plan11.md).
"""

from __future__ import annotations

import json

import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr

from rollerrig._validation import ParameterError
from rollerrig.report.studies import MISSING_GID, display_unit, study_figures
from rollerrig.studies.sensitivity import sobol_indices

PARAMS = {  # key -> (units, long_name), as the store writes them
    "stiffness.roller_shaft": ("N.m/rad", "roller-shaft stiffness k56"),
    "induction_motor.response_lag_clp": ("1/s", "AM response rate 1/τ"),
    "speed": ("m/s", "roller speed"),
    "load": ("N", "normal load"),
    "friction": ("", "friction"),
}
METRIC = "release_overshoot"


def _study(design: str, params: dict, y, status=None, labels=None, **attrs) -> xr.Dataset:
    """A study Dataset: ``params`` key -> values per point (units from PARAMS)."""
    y = np.asarray(y, dtype=float)
    n = y.size
    status = np.array(["ok"] * n if status is None else status, dtype=object)
    y = np.where(status == "ok", y, np.nan)
    data = {}
    for key, values in params.items():
        unit, name = PARAMS[key]
        a = {"units": unit, "long_name": name} if unit else {"long_name": name}
        data[key] = ("point", np.asarray(values), a)
    reasons = {"solver failed": "the fast solver failed at t = 2.31 s: step size below 1e-12 s",
               "invalid parameters": "stiffness.roller_shaft must be > 0 [N.m/rad]"}  # fmt: skip
    data |= {
        "label": ("point", labels or [f"point {i}" for i in range(n)]),
        "status": ("point", status.astype(str)),
        "reason": ("point", [reasons.get(s, "") for s in status]),
        METRIC: ("point", y, {"units": "1", "long_name": "release overshoot of T56/r_r",
                              "nan_meaning": "no release"}),
    }  # fmt: skip
    base = {"study": f"synthetic-{design}", "design": design,
            "parameters": json.dumps(list(params)), "metrics": json.dumps([METRIC])}  # fmt: skip
    return xr.Dataset(data, attrs=base | {k: json.dumps(v) for k, v in attrs.items()})


def grid_study(axes: dict, scales=None, failed=(), pending=()) -> xr.Dataset:
    """A C-order grid over ``axes`` (key -> levels, SI) with an overshoot that falls with the
    stiffness and rises with the lag; ``failed``/``pending``: point indices."""
    levels = [np.asarray(v) for v in axes.values()]
    mesh = [m.ravel() for m in np.meshgrid(*levels, indexing="ij")]
    n = mesh[0].size
    y = np.full(n, 0.2)
    for key, m in zip(axes, mesh, strict=True):
        if key == "stiffness.roller_shaft":
            y = y + 0.3 * (43.5e3 / m.astype(float))
        elif key == "friction":
            y = y + 0.05 * (m == "wet")
        else:
            y = y + 0.1 * m.astype(float) / m.astype(float).max()
    status = np.array(["ok"] * n, dtype=object)
    status[list(failed)] = "solver failed"
    status[list(pending)] = "pending"
    return _study("grid", dict(zip(axes, mesh, strict=True)), y, status,
                  grid_shape=[len(v) for v in levels],
                  grid_scales=scales or ["list"] * len(levels))  # fmt: skip


def grid1():
    k = 43.5e3 * np.logspace(0, 1, 6)
    return grid_study({"stiffness.roller_shaft": k}, ["log"], failed=[4])


def grid2():
    return grid_study(
        {
            "stiffness.roller_shaft": [43.5e3, 83.5e3, 143.5e3],
            "induction_motor.response_lag_clp": [2.75, 10000.0],
        },
        failed=[1],
        pending=[5],
    )


def grid3():
    return grid_study(
        {
            "stiffness.roller_shaft": [43.5e3, 83.5e3, 143.5e3, 203.5e3],
            "speed": [5 / 3.6, 10 / 3.6, 20 / 3.6, 30 / 3.6],
            "friction": ["dry", "wet"],
        },
        failed=[1, 3],  # k = 43.5, v = 5 km/h wet and v = 10 km/h wet: half of that cell
    )


def grid_categorical():
    return grid_study(
        {"friction": ["dry", "wet", "oil"], "stiffness.roller_shaft": [43.5e3, 143.5e3]},
        failed=[5],
    )


def cases_study():
    labels = ["AM V/f with lag (rig today)", "AM V/f, no lag",
              "AM V/f, no lag, k56 = 143.5 kN·m/rad", "speed servo, 5 Hz bandwidth",
              "speed servo, 20 Hz bandwidth", "ideal speed source"]  # fmt: skip
    y = [0.42, 0.25, 0.11, 0.08, 0.03, 0.0]
    status = ["ok", "ok", "ok", "solver failed", "ok", "ok"]
    drives = ["induction", "induction", "induction", "servo", "servo", "ideal_speed"]
    return _study("cases", {"friction": drives}, y, status, labels)


def sample_study(method: str = "random", n: int = 300, failed: int = 12):
    rng = np.random.default_rng(5)
    k = 43.5e3 + 100e3 * rng.random(n)
    lag = np.exp(np.log(1.0) + np.log(1e3) * rng.random(n))
    load = 4300.0 + 15e3 * rng.random(n)
    y = 0.3 * 43.5e3 / k + 0.02 * np.log(lag) + 0.01 * rng.standard_normal(n)
    status = np.array(["ok"] * n, dtype=object)
    status[rng.choice(n, failed, replace=False)] = "invalid parameters"
    dist = {"stiffness.roller_shaft": {"distribution": "uniform", "low": 43.5e3, "high": 143.5e3},
            "induction_motor.response_lag_clp": {"distribution": "loguniform", "low": 1.0,
                                                 "high": 1e3},
            "load": {"distribution": "uniform", "low": 4300.0, "high": 19300.0}}  # fmt: skip
    sample = {"method": method, "n": n, "seed": 5, "second_order": False, "parameters": dist}
    params = {"stiffness.roller_shaft": k, "induction_motor.response_lag_clp": lag, "load": load}
    return _study("sample", params, y, status, sample=sample)


def sobol_study(failed: int = 0):
    from SALib.sample import sobol as sobol_sample

    n = 256
    problem = {"num_vars": 2, "names": ["a", "b"], "bounds": [[0.0, 1.0]] * 2}
    u = sobol_sample.sample(problem, n, calc_second_order=True, seed=4)
    k = 43.5e3 + 100e3 * u[:, 0]
    speed = (5 + 25 * u[:, 1]) / 3.6
    y = 0.3 * 43.5e3 / k + 0.01 * speed
    status = np.array(["ok"] * y.size, dtype=object)
    status[:failed] = "solver failed"
    dist = {"stiffness.roller_shaft": {"distribution": "uniform", "low": 43.5e3, "high": 143.5e3},
            "speed": {"distribution": "uniform", "low": 5 / 3.6, "high": 30 / 3.6}}  # fmt: skip
    sample = {"method": "sobol", "n": n, "seed": 4, "second_order": True, "parameters": dist}
    return _study("sample", {"stiffness.roller_shaft": k, "speed": speed}, y, status,
                  sample=sample)  # fmt: skip


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _missing_artists(fig):
    return [a for ax in fig.axes for a in ax.get_children() if a.get_gid() == MISSING_GID]


def _hatched_cells(ax) -> set[tuple[int, int]]:
    """The heat-map cells ``(column, row)`` where a missing-value patch of ``ax`` shows: those
    it covers, and of a patch below the mesh (a background) only those the mesh leaves out."""
    mesh = ax.collections[0]
    values = mesh.get_array()  # rows first
    ny, nx = values.shape
    centres = np.array([(i, j) for i in range(nx) for j in range(ny)], dtype=float)
    holes = np.ma.getmaskarray(values).T.ravel()
    cells = set()
    for patch in [a for a in ax.patches if a.get_gid() == MISSING_GID]:
        path = patch.get_patch_transform().transform_path(patch.get_path())  # in data units
        shown = path.contains_points(centres)
        if patch.get_zorder() < mesh.get_zorder():
            shown &= holes
        cells |= {(int(i), int(j)) for i, j in centres[shown]}
    return cells


def _texts(fig) -> str:
    out = [fig._suptitle.get_text() if fig._suptitle else ""]
    for ax in fig.axes:
        out += [ax.get_title(), ax.get_xlabel(), ax.get_ylabel()]
        out += [t.get_text() for t in ax.texts]
        legend = ax.get_legend()
        if legend:
            out += [t.get_text() for t in legend.get_texts()]
    for legend in fig.legends:
        out += [t.get_text() for t in legend.get_texts()]
    return "\n".join(out)


def test_display_units():
    assert display_unit("N.m/rad") == ("kN·m/rad", 1e-3)
    unit, factor = display_unit("m/s")
    assert unit == "km/h" and factor == pytest.approx(3.6)
    assert display_unit("N") == ("kN", 1e-3)
    assert display_unit("1/s") == ("1/s", 1.0) and display_unit("N.m") == ("N·m", 1.0)
    assert display_unit("furlong") == ("furlong", 1.0)  # unknown: shown as stored


def test_grid_of_one_axis_is_a_line_on_a_log_axis():
    figs = study_figures(grid1())
    assert list(figs) == [f"{METRIC}-line"]
    ax = figs[f"{METRIC}-line"].axes[0]
    assert ax.get_xscale() == "log"
    assert ax.get_xlabel() == "roller-shaft stiffness k56 [kN·m/rad]"
    assert ax.get_ylabel() == "release overshoot of T56/r_r [-]"
    line = ax.get_lines()[0]
    np.testing.assert_allclose(line.get_xdata()[0], 43.5)  # kN·m/rad
    assert [t.get_text() for t in ax.get_xticklabels()][:2] == ["43.5", "68.94"]  # the levels
    (cross,) = _missing_artists(figs[f"{METRIC}-line"])
    np.testing.assert_allclose(cross.get_xdata(), [43.5 * 10**0.8])  # the failed point
    # The cross lies below every value: no value can be mistaken for it.
    data = ax.transAxes.inverted().transform(ax.transData.transform(line.get_xydata()))
    finite = np.isfinite(data).all(axis=1)
    assert data[finite, 1].min() > 0.08 > cross.get_ydata()[0]
    assert "no value: solver failed 1" in _texts(figs[f"{METRIC}-line"])


def test_grid_of_two_axes_is_a_heat_map_and_lines():
    figs = study_figures(grid2(), METRIC)
    assert set(figs) == {f"{METRIC}-heatmap", f"{METRIC}-lines"}
    heat = figs[f"{METRIC}-heatmap"]
    ax, cbar = heat.axes
    assert ax.get_xlabel() == "roller-shaft stiffness k56 [kN·m/rad]"
    assert ax.get_ylabel() == "AM response rate 1/τ [1/s]"
    assert cbar.get_ylabel() == "release overshoot of T56/r_r [-]"
    assert [t.get_text() for t in ax.get_xticklabels()] == ["43.5", "83.5", "143.5"]
    assert [t.get_text() for t in ax.get_yticklabels()] == ["2.75", "10000"]
    assert _hatched_cells(ax) == {(0, 1), (2, 1)}  # the failed and the pending point
    texts = _texts(heat)
    assert "solver failed" in texts and "pending" in texts
    assert "2 of 6 points without a value" in texts
    # Small grid: every value annotated.
    assert sum(t.get_text().replace(".", "").isdigit() for t in ax.texts) == 4
    lines = figs[f"{METRIC}-lines"]
    lax = lines.axes[0]
    assert len([ln for ln in lax.get_lines() if ln.get_gid() != MISSING_GID]) == 2
    assert lax.get_legend().get_title().get_text() == "AM response rate 1/τ [1/s]"
    crosses = _missing_artists(lines)
    assert sum(c.get_xdata().size for c in crosses) == 2
    assert "no value: pending 1, solver failed 1" in _texts(lines)


def test_grid_of_three_axes_averages_and_shows_main_effects():
    figs = study_figures(grid3())
    assert set(figs) == {f"{METRIC}-heatmap", f"{METRIC}-main-effects"}
    heat = figs[f"{METRIC}-heatmap"]
    assert "averaged over friction" in heat.axes[0].get_title()
    assert heat.axes[0].get_ylabel() == "roller speed [km/h]"
    assert [t.get_text() for t in heat.axes[0].get_yticklabels()] == ["5", "10", "20", "30"]
    # Two cells average one point of two: hatched lightly, annotated.
    assert _hatched_cells(heat.axes[0]) == {(0, 0), (0, 1)}
    assert "(1 of 2 missing)" in _texts(heat)
    main = figs[f"{METRIC}-main-effects"]
    axes = [ax for ax in main.axes if ax.get_visible()]
    assert [ax.get_xlabel() for ax in axes] == [
        "roller-shaft stiffness k56 [kN·m/rad]", "roller speed [km/h]", "friction"]  # fmt: skip
    assert [t.get_text() for t in axes[2].get_xticklabels()] == ["dry", "wet"]
    assert axes[0].get_shared_y_axes().joined(axes[0], axes[1])
    assert len(_missing_artists(main)) == 3  # one level of each axis misses points
    assert "mean over fewer points" in _texts(main)


def test_heat_map_draws_missing_cells_as_one_layer_whatever_their_number():
    # An interrupted study (the last 40 % pending) with scattered failures: a patch per cell
    # made a 1000 x 1000 grid take minutes; one patch per kind of cell costs the same for any.
    nx, ny = 40, 30
    rng = np.random.default_rng(3)
    failed = rng.choice(int(0.6 * nx * ny), 50, replace=False)
    pending = np.arange(int(0.6 * nx * ny), nx * ny)
    axes = {"stiffness.roller_shaft": 43.5e3 * np.linspace(1.0, 3.0, nx),
            "induction_motor.response_lag_clp": np.linspace(1.0, 100.0, ny)}  # fmt: skip
    heat = study_figures(grid_study(axes, failed=failed, pending=pending))[f"{METRIC}-heatmap"]
    ax = heat.axes[0]
    assert len(_missing_artists(heat)) == 1  # one hatched background behind the mesh
    assert len(ax.patches) <= 2 and len(ax.get_children()) < 30
    missing = np.zeros(nx * ny, dtype=bool)
    missing[failed] = missing[pending] = True
    assert _hatched_cells(ax) == {(int(i), int(j)) for i, j in zip(
        *np.nonzero(missing.reshape(nx, ny)), strict=True)}  # fmt: skip
    assert "no value: pending 480, solver failed 50" in _texts(heat)


def test_categorical_axis_shows_its_categories():
    figs = study_figures(grid_categorical())
    heat = figs[f"{METRIC}-heatmap"].axes[0]
    assert [t.get_text() for t in heat.get_xticklabels()] == ["dry", "wet", "oil"]
    assert heat.get_xlabel() == "friction"
    lines = figs[f"{METRIC}-lines"].axes[0]
    assert [t.get_text() for t in lines.get_xticklabels()] == ["dry", "wet", "oil"]
    assert len(_missing_artists(figs[f"{METRIC}-lines"])) == 1


def test_cases_are_bars_with_the_failed_case_marked():
    figs = study_figures(cases_study())
    fig = figs[f"{METRIC}-cases"]
    ax = fig.axes[0]
    assert ax.get_xlabel() == "release overshoot of T56/r_r [-]"
    assert ax.get_yticklabels()[0].get_text() == "AM V/f with lag (rig today)"
    assert len(ax.patches) == 5  # bars of the cases with a value
    (cross,) = _missing_artists(fig)
    np.testing.assert_array_equal(cross.get_ydata(), [3])
    assert "solver failed: the fast solver failed at t = 2.31 s" in _texts(fig)


def test_sample_scatter_and_rank_correlations():
    ds = sample_study("lhs")
    figs = study_figures(ds)
    assert set(figs) == {f"{METRIC}-scatter", f"{METRIC}-rank-correlation"}
    fig = figs[f"{METRIC}-scatter"]
    axes = [ax for ax in fig.axes if ax.get_visible()]
    assert [ax.get_xlabel() for ax in axes] == [
        "roller-shaft stiffness k56 [kN·m/rad]", "AM response rate 1/τ [1/s]",
        "normal load [kN]"]  # fmt: skip
    assert axes[1].get_xscale() == "log"  # loguniform
    crosses = _missing_artists(fig)
    assert len(crosses) == 3 and all(c.get_xdata().size == 12 for c in crosses)
    assert "no value: invalid parameters 12" in _texts(fig)
    points = axes[2].get_lines()[0]
    assert points.get_xdata().max() <= 19.3  # kN
    rank = figs[f"{METRIC}-rank-correlation"]
    assert "12 without a value ignored" in _texts(rank)
    assert rank.axes[0].get_xlim() == (-1.05, 1.05)


def test_sobol_sample_has_its_indices():
    ds = sobol_study()
    figs = study_figures(ds)
    assert set(figs) == {f"{METRIC}-scatter", f"{METRIC}-rank-correlation", f"{METRIC}-sobol"}
    ax = figs[f"{METRIC}-sobol"].axes[0]
    r = sobol_indices(ds, METRIC)
    heights = [p.get_height() for p in ax.patches]
    np.testing.assert_allclose(heights, np.concatenate([r.S1, r.ST]))
    assert ax.get_ylabel() == "share of the variance [-]"
    assert "N = 256" in ax.get_title()


def test_sobol_with_failed_points_says_why_in_the_figure():
    figs = study_figures(sobol_study(failed=3))
    fig = figs[f"{METRIC}-sobol"]
    assert len(_missing_artists(fig)) == 1
    text = _texts(fig)
    assert "not computed" in text and "3 of 1536 points" in text and "solver failed: 3" in text


def test_unknown_metric_is_a_clear_error():
    with pytest.raises(ParameterError, match=r"no metric 'overshoot'.*'release_overshoot'"):
        study_figures(grid2(), ["overshoot"])


def test_metric_without_any_value_still_draws():
    ds = grid2()
    ds[METRIC].values[:] = np.nan
    figs = study_figures(ds)
    assert len(_hatched_cells(figs[f"{METRIC}-heatmap"].axes[0])) == 6


def test_sample_with_a_choice_shows_its_categories():
    rng = np.random.default_rng(1)
    n = 60
    friction = np.where(rng.random(n) < 0.5, "wet", "dry")
    k = 43.5e3 + 100e3 * rng.random(n)
    dist = {"stiffness.roller_shaft": {"distribution": "uniform", "low": 43.5e3, "high": 143.5e3},
            "friction": {"distribution": "choice", "values": ["dry", "wet"]}}  # fmt: skip
    sample = {"method": "random", "n": n, "seed": 1, "second_order": False, "parameters": dist}
    ds = _study("sample", {"stiffness.roller_shaft": k, "friction": friction},
                0.2 + 0.1 * (friction == "wet"), sample=sample)  # fmt: skip
    figs = study_figures(ds)
    ax = figs[f"{METRIC}-scatter"].axes[1]
    assert [t.get_text() for t in ax.get_xticklabels()] == ["dry", "wet"]  # the design's order
    x = ax.get_lines()[0].get_xdata()
    np.testing.assert_array_equal(np.round(x), (friction == "wet").astype(float))
    assert "categorical" in _texts(figs[f"{METRIC}-rank-correlation"])


def test_drive_dynamics_figure_marks_the_line_and_the_seed_lag():
    from rollerrig.report.drive_dynamics import LINE_HZ, drive_dynamics_figure

    row = {"drive": "dq", "speed [km/h]": 5.0, "normal_load [kN]": 4.3,
           "modes below 20 Hz": [{"frequency [Hz]": 1.4, "damping_ratio [-]": 0.1}]}  # fmt: skip
    study = {
        "thevenin": [], "dq": [row], "seed_lag [s]": 0.3635,
        "lag_held_speed": [{"speed [km/h]": 5.0, "tau [s]": 0.06}],
        "lag_in_rig": [{"speed [km/h]": 10.0, "tau [s]": 0.04}],
    }  # fmt: skip
    fig = drive_dynamics_figure(study)
    ax, lag = fig.axes[:2]
    assert any(abs(line.get_xdata()[0] - LINE_HZ) < 1e-12 for line in ax.get_lines()[-2:])
    assert lag.get_ylabel() == "first-order lag τ [ms]"
    assert any(np.allclose(line.get_ydata(), 363.5) for line in lag.get_lines())
