"""The six-panel twin figure shows the truth above what the rig measures, and says which is
which; the sweep figure draws one series per legend entry. The figures are inspected as
matplotlib objects (axes, labels, legends, lines, z-order), not as pixels."""

from __future__ import annotations

import json
import re

import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr
from matplotlib.colors import to_rgb

from rollerrig.report.twin import MEASURED_STYLE, experiment_figure, sweep_figure

RW, RR = 0.348, 0.452  # wheel and roller rolling radii [m]


def _twin_dataset(n: int = 2000) -> xr.Dataset:
    """What ``Simulation.run`` returns, in the variables the figure reads (truth and measured)."""
    t = np.linspace(0.0, 8.0, n)
    ramp = np.clip((t - 1.0) / 3.0, 0.0, 1.0) * (t < 5.0)
    w_r = np.full(n, 30 / 3.6 / RR)
    creep = 0.03 * ramp
    w_w = w_r * RR * (1 + creep) / RW
    step_w, step_r = 0.05, 0.04  # encoder quantisation [rad/s]
    force = 2000.0 * ramp
    data = {
        "torque_request": 720.0 * ramp,
        "pmsm_torque": 720.0 * ramp,
        "creep": creep,
        "coa": force / 4300.0,
        "wheel_speed": w_w,
        "roller_speed": w_r,
        "roller_speed_setpoint": w_r * RR,
        "slip_velocity": w_w * RW - w_r * RR,
        "contact_force": force,
        "measured_wheel_speed": np.round(w_w / step_w) * step_w,
        "measured_roller_speed": np.round(w_r / step_r) * step_r,
        "measured_creep": creep + 0.002 * np.sin(40 * t),
        "measured_coa": force / 4300.0 + 0.01 * np.sin(30 * t),
        "measured_force": force + 100.0 * np.sin(30 * t),
    }
    m = data
    m["measured_slip_velocity"] = m["measured_wheel_speed"] * RW - m["measured_roller_speed"] * RR
    prov = {"rig": {"geometry": {"wheel_radius_x": RW, "roller_radius_x": RR}}}
    return xr.Dataset(
        {k: ("time", v) for k, v in data.items()},
        coords={"time": t},
        attrs={"provenance": json.dumps(prov), "title": "twin test"},
    )


@pytest.fixture(scope="module")
def figure():
    fig = experiment_figure(_twin_dataset())
    yield fig
    plt.close(fig)


def _legend(ax) -> list[str]:
    return [t.get_text() for t in ax.get_legend().get_texts()]


def _lines(ax, prefix: str):
    return [ln for ln in ax.get_lines() if ln.get_label().startswith(prefix)]


def test_with_pyplot_imported_the_figure_is_pyplots(figure):
    """So that plt.show(), a notebook and sphinx-gallery (which collects pyplot's figures: the
    gallery's seed experiment lost its figure without this) see it; without pyplot the
    command line draws it on a canvas of its own (tests/cli/test_lazy.py)."""
    assert figure.number in plt.get_fignums()


def test_six_panels_with_units_in_brackets(figure):
    axes = figure.axes
    assert len(axes) == 6
    titles = [ax.get_title() for ax in axes]
    assert [t[:3] for t in titles] == ["(a)", "(b)", "(c)", "(d)", "(e)", "(f)"]
    assert titles[3] == "(d) slip velocity"  # the title says what the axis says
    ylabels = [ax.get_ylabel() for ax in axes]
    assert ylabels == [
        "wheel torque [N·m]",
        "CoA [-]",
        "wheel peripheral speed [km/h]",
        "slip velocity [m/s]",
        "roller peripheral speed [km/h]",
        "force [N]",
    ]
    xlabels = [ax.get_xlabel() for ax in axes]
    assert xlabels[1] == "creep [%]" and all(
        x == "time [s]" for i, x in enumerate(xlabels) if i != 1
    )
    assert all(re.search(r"\[[^\]]+\]$", label) for label in ylabels + xlabels)
    assert figure.texts[0].get_text() == "twin test"  # the suptitle


def test_truth_is_drawn_above_the_measured_traces_and_legends_say_which(figure):
    for ax in figure.axes[1:]:  # every panel with both a truth and a measurement
        true, measured = _lines(ax, "true:"), _lines(ax, "measured:")
        assert true and measured, ax.get_title()
        assert min(t.get_zorder() for t in true) > max(m.get_zorder() for m in measured)
        for t in true:
            for m in measured:
                assert to_rgb(t.get_color()) != to_rgb(m.get_color())  # distinguishable
                if m.get_linestyle() != "None":  # lines (not the scatter of panel b)
                    assert m.get_linewidth() < t.get_linewidth()
        entries = _legend(ax)
        assert any(e.startswith("true:") for e in entries)
        assert any(e.startswith("measured:") for e in entries)
    # The measured traces are light grey, the quantised encoder staircase in particular.
    c, d = figure.axes[2], figure.axes[3]
    assert to_rgb(_lines(c, "measured:")[0].get_color()) == to_rgb(MEASURED_STYLE["color"])
    assert "quantised" in _lines(c, "measured:")[0].get_label()
    assert "encoders" in _lines(d, "measured:")[0].get_label()


def test_the_panels_draw_the_datasets_values(figure):
    ds = _twin_dataset()
    c = figure.axes[2]
    truth = _lines(c, "true:")[0]
    np.testing.assert_allclose(truth.get_ydata(), ds.wheel_speed.values * RW * 3.6)
    staircase = _lines(c, "measured:")[0]
    np.testing.assert_allclose(staircase.get_ydata(), ds.measured_wheel_speed.values * RW * 3.6)
    e = figure.axes[4]
    assert "set point" in _legend(e)


LONG_TITLE = (
    "rollerrig simulation: seed-30kmh-dry on Pardubice tram roller rig; variant: wheel drive "
    "ideal_torque, roller drive induction_linear, roller lag 0.05 s, flexible frame, law "
    "modified-fastsim, solver reference, rig file soft-shaft.toml"
)


@pytest.mark.parametrize(("scale", "title"), [(1.0, None), (-6.0, None), (1.0, LONG_TITLE)])
def test_the_fixed_layout_clips_nothing_and_nothing_overlaps(scale, title):
    """The experiment figure is laid out once, with fixed margins (no tight bounding box when
    saved): every panel with its tick labels, axis labels, title and legend lies inside the
    figure, apart from the other panels and from the figure's title; also with tick labels of
    five characters (forces and torques of -12000)."""
    ds = _twin_dataset()
    for name in ("torque_request", "pmsm_torque", "contact_force", "measured_force"):
        ds[name] = ds[name] * scale
    fig = experiment_figure(ds, title=title)
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        whole = fig.bbox
        boxes = [ax.get_tightbbox(renderer) for ax in fig.axes]
        heading = fig.texts[0].get_window_extent(renderer)
        assert whole.x0 <= heading.x0 and heading.x1 <= whole.x1  # a variant's title fits too
        assert fig.texts[0].get_text() == (title or "twin test")
        for ax, box in zip(fig.axes, [*boxes], strict=True):
            assert whole.x0 <= box.x0 and box.x1 <= whole.x1, ax.get_title()
            assert whole.y0 <= box.y0 and box.y1 <= whole.y1, ax.get_title()
            assert not box.overlaps(heading), ax.get_title()
        for i, box in enumerate(boxes):
            for other in boxes[i + 1 :]:
                assert not box.overlaps(other), (fig.axes[i].get_title(), box, other)
        assert fig.get_layout_engine() is None  # nothing to compute again when saved
    finally:
        plt.close(fig)


@pytest.mark.parametrize("values", [[1e5, 3e5, 1e6], ["pmsm + induction", "ideal drives"]])
def test_sweep_figure_draws_one_series_per_legend_entry(values):
    amplitudes = {"measured": [0.1] * len(values), "true": [0.05] * len(values)}
    fig = sweep_figure(values, amplitudes, "shaft stiffness [N·m/rad]", "overshoot")
    ax = fig.axes[0]
    assert _legend(ax) == ["measured", "true"]
    if isinstance(values[0], float):
        assert len(ax.get_lines()) == 2
        assert ax.get_xlabel() == "shaft stiffness [N·m/rad]"
        np.testing.assert_allclose(ax.get_lines()[0].get_ydata(), 10.0)  # [%]
        assert ax.get_ylabel() == "overshoot below zero [%]"
    else:
        assert len(ax.patches) == 2 * len(values)  # one bar per series and value
        assert [t.get_text() for t in ax.get_yticklabels()] == values
        assert ax.get_xlabel().endswith("[% of the force before release]")
    plt.close(fig)
