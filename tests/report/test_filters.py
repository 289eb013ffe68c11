"""Filter-study figures: they say at which rate their windows count samples, draw long signals
as their envelope (bounded points, every excursion kept), and the Savitzky-Golay grid keeps its
colour scale for the cells near the optimum (robust, clipped; log over decades) and flags an
optimum on the edge of the grid. Figures are inspected as matplotlib objects, not pixels."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.colors import LogNorm

from rollerrig._validation import ParameterError
from rollerrig.report.analysis_sections import _params_at
from rollerrig.report.filters import (
    filter_comparison_figure,
    savitzky_golay_grid_figure,
    study_ranking_figure,
)
from rollerrig.signal.scoring import (
    FilterScore,
    StudyRow,
    StudyTable,
    prepare_study_signal,
    seed_like_torque,
)

ORDERS = (2, 3, 4, 5, 6, 7)
WINDOWS = tuple(range(11, 202, 10))  # the default tuning grid at 250 Hz: 6 x 20 cells


def _grid_table(cost) -> StudyTable:
    """A ranked SG tuning table with ``cost(order, window)`` [1], windows at 250 Hz."""
    rows = [(o, w, float(cost(o, w))) for o in ORDERS for w in WINDOWS]
    rows.sort(key=lambda r: r[2])
    return StudyTable(
        StudyRow(
            rank=i + 1,
            method="savitzky_golay",
            params={"order": o, "window": w},
            label=f"SG order {o} w{w}",
            score=FilterScore(0.1, 1.0, 0.0, 0.0, c),
            sample_rate=250.0,
        )
        for i, (o, w, c) in enumerate(rows)
    )


def _interior(o, w):
    """Smooth bowl with its minimum at order 3, window 51, plus three huge outliers (as the
    shortest window at the highest orders gives)."""
    c = 1.0 + 0.1 * (o - 3) ** 2 + 1e-5 * (w - 51) ** 2
    return 60.0 if (w == 11 and o >= 5) else c


def _texts(fig) -> str:
    ax = fig.axes[0]
    return " | ".join([ax.get_title(), *(t.get_text() for t in ax.texts)])


def test_figures_of_a_decimated_study_say_the_rate_of_their_windows():
    sig = seed_like_torque(sample_rate=2000.0, duration=20.0)
    study = prepare_study_signal(sig.time, sig.raw)  # 2 kHz -> 250 Hz
    _, _, grid = study.tune_savitzky_golay(orders=[2, 4], windows=[33, 111])
    fig = savitzky_golay_grid_figure(grid)
    assert fig.axes[0].get_xlabel() == (
        "window [samples at 250 Hz, the recording's 2000 Hz decimated]"
    )
    plt.close(fig)
    rows = study.filter_study([("moving_average", {"window": 33})])
    fig = study_ranking_figure(rows)
    assert "samples at 250 Hz" in fig.axes[0].get_title()
    plt.close(fig)
    # A study row's window at 250 Hz is the same span at the signal's 2 kHz (made odd).
    assert _params_at(rows[0], 2000.0)["window"] == 257
    assert _params_at(rows[0], 250.0)["window"] == 33


def test_comparison_figure_of_a_long_signal_draws_bounded_points():
    t = np.arange(600_000) / 1000.0
    raw = np.sin(t) + 0.1 * np.cos(50 * t)
    fig = filter_comparison_figure(
        t, raw, {"smooth": np.sin(t)}, steady_window=(10.0, 12.0), transient_window=(300, 301)
    )
    counts = [line.get_xdata().size for ax in fig.axes for line in ax.get_lines()]
    assert max(counts) <= 20_004
    zoom = fig.axes[1].get_lines()[0].get_xdata()
    assert zoom.min() >= 9.99 and zoom.max() <= 12.01  # a zoom holds only its window
    plt.close(fig)


def test_comparison_figure_axes_labels_and_legend():
    t = np.arange(5000) / 250.0
    raw = np.sin(t) + 0.1 * np.cos(50 * t)
    fig = filter_comparison_figure(
        t, raw, {"SG": np.sin(t), "MA": np.sin(t) * 0.9}, truth=np.sin(t), unit="N·m",
        steady_window=(2.0, 4.0), transient_window=(10.0, 12.0), title="torque",
    )  # fmt: skip
    top, steady, transient = fig.axes
    assert [t.get_text() for t in top.get_legend().get_texts()] == ["raw", "truth", "SG", "MA"]
    assert all(len(ax.get_lines()) == 4 for ax in fig.axes)
    assert all(ax.get_ylabel() == "torque [N·m]" and ax.get_xlabel() == "time [s]"
               for ax in fig.axes)  # fmt: skip
    assert (steady.get_title(), transient.get_title()) == ("steady part", "transient part")
    assert steady.get_xlim() == (2.0, 4.0) and top.get_title() == "torque"
    assert len(top.patches) == 2  # the two zoom windows shaded on the whole record
    plt.close(fig)


def test_ranking_figure_stacks_the_three_cost_terms_per_row():
    table = _grid_table(_interior)
    fig = study_ranking_figure(table, top=5)
    ax = fig.axes[0]
    assert len(ax.patches) == 3 * 5
    assert [t.get_text() for t in ax.get_legend().get_texts()] == [
        "steady noise left", "peak lost", "lag + peak-time error"
    ]  # fmt: skip
    assert ax.get_xlabel() == "cost [-] (lower is better)"
    top = max(ax.get_yticklabels(), key=lambda t: t.get_position()[1])
    assert top.get_text() == "1. SG order 3 w51"  # the best on top
    assert ax.get_title() == "windows w in samples at 250 Hz"
    plt.close(fig)


def test_grid_colour_scale_is_robust_against_outliers_and_says_so():
    table = _grid_table(_interior)
    fig = savitzky_golay_grid_figure(table)
    ax, bar = fig.axes
    norm = ax.images[0].norm
    costs = np.array([r.score.cost for r in table])
    # A linear scale up to 60 would give every cell near the optimum the same colour (1.0 and
    # 1.1 would be 0.2 % of the scale apart).
    assert norm.vmin == costs.min() and norm.vmax < 0.1 * costs.max()
    assert norm(1.1) - norm(1.0) > 0.05
    assert norm.vmax == pytest.approx(np.percentile(costs, 90))
    label = bar.get_ylabel()
    assert label.startswith("cost [-], linear scale") and "clipped at the 90th percentile" in label
    # The clipped cells are drawn in the over colour, shown as the colour bar's triangle.
    over = ax.images[0].to_rgba(np.array([[costs.max()]]))[0, 0]
    assert tuple(over) == (1.0, 1.0, 1.0, 1.0)  # white: beyond the scale's (light) end
    # The optimum is interior: starred, not flagged.
    star = [ln for ln in ax.get_lines() if ln.get_label() == "lowest cost"]
    assert star and (star[0].get_xdata()[0], star[0].get_ydata()[0]) == (4, 1)  # w51, order 3
    assert "grid edge" not in _texts(fig)
    assert "lowest cost (red star): order 3, window 51" in _texts(fig)
    plt.close(fig)


def test_grid_over_decades_uses_a_log_scale():
    fig = savitzky_golay_grid_figure(_grid_table(lambda o, w: 0.01 * 2.0 ** (o + w / 10)))
    ax, bar = fig.axes
    assert isinstance(ax.images[0].norm, LogNorm)
    assert bar.get_ylabel().startswith("cost [-], log scale")
    plt.close(fig)


@pytest.mark.parametrize(
    ("best", "edge"),
    [
        ((3, 201), "window 201 is the largest tried"),
        ((2, 51), "order 2 is the smallest tried"),
        ((7, 11), "window 11 is the smallest tried; order 7 is the largest tried"),
    ],
)
def test_an_optimum_on_the_grid_edge_is_flagged(best, edge):
    o0, w0 = best
    table = _grid_table(lambda o, w: 1.0 + 0.1 * abs(o - o0) + 1e-3 * abs(w - w0))
    assert table[0].params == {"order": o0, "window": w0}
    fig = savitzky_golay_grid_figure(table)
    ax = fig.axes[0]
    title = " ".join(ax.get_title().split())  # wrapped to fit the figure
    assert title.startswith(f"optimum on the grid edge ({edge}): the true optimum")
    fig.canvas.draw()  # as a viewer sees it: the red title lies inside the figure (it was cut
    box = ax.title.get_window_extent(fig.canvas.get_renderer())  # off on both sides)
    assert fig.bbox.x0 <= box.x0 and box.x1 <= fig.bbox.x1 and box.y1 <= fig.bbox.y1
    ring = [ln for ln in ax.get_lines() if ln.get_label() == "on the grid edge"]
    assert len(ring) == 1
    assert (ring[0].get_xdata()[0], ring[0].get_ydata()[0]) == (
        WINDOWS.index(w0), ORDERS.index(o0)
    )  # fmt: skip
    plt.close(fig)


def test_grid_refuses_a_percentile_out_of_range():
    with pytest.raises(ParameterError, match=r"clip_percentile must be in \(0, 100\] \[%\]"):
        savitzky_golay_grid_figure(_grid_table(_interior), clip_percentile=0.0)


def _study_rows(n: int = 8) -> StudyTable:
    """A ranked study whose best row has the longest bar part in the upper right, where a
    legend inside the axes would sit."""
    rows = []
    for i in range(n):
        score = FilterScore(0.45 + 0.04 * i, 0.85 + 0.01 * i, 0.0, 0.0, 0.77 + 0.01 * i)
        rows.append(
            StudyRow(rank=i + 1, method="moving_average", params={"window": 11 + 10 * i},
                     label=f"MA w{11 + 10 * i}", score=score, sample_rate=250.0)
        )  # fmt: skip
    return StudyTable(rows)


def test_ranking_legend_hides_no_bar():
    fig = study_ranking_figure(_study_rows())
    ax = fig.axes[0]
    fig.canvas.draw()  # as a viewer sees it
    renderer = fig.canvas.get_renderer()
    legend = ax.get_legend().get_window_extent(renderer)
    bars = [p.get_window_extent(renderer) for p in ax.patches]
    assert len(bars) == 3 * 8
    assert not any(legend.overlaps(b) for b in bars)
    assert legend.x0 >= ax.get_window_extent(renderer).x1  # right of the axes
    assert fig.bbox.contains(legend.x1 - 1, legend.y0 + 1)  # and inside the figure
    plt.close(fig)


def test_a_flat_optimum_is_called_flat_and_its_cells_outlined():
    # Costs within 5 % of the lowest: order 3, windows 41, 51, 61 (1.00, 1.04 and 1.04).
    table = _grid_table(lambda o, w: 1.0 + 0.5 * abs(o - 3) + 4e-3 * abs(w - 51))
    fig = savitzky_golay_grid_figure(table)
    ax = fig.axes[0]
    squares = [ln for ln in ax.get_lines() if ln.get_label().startswith("within 5 %")]
    assert len(squares) == 1
    # The lowest cell carries the star, drawn above the squares: a square over it had hidden
    # the star the legend shows.
    assert sorted(zip(squares[0].get_xdata(), squares[0].get_ydata(), strict=True)) == [
        (3, 1), (5, 1)
    ]  # fmt: skip
    star = next(ln for ln in ax.get_lines() if ln.get_label() == "lowest cost")
    assert star.get_marker() == "*" and star.get_zorder() > squares[0].get_zorder()
    assert (star.get_xdata()[0], star.get_ydata()[0]) == (4, 1)
    assert "3 cells within 5 % of it" in ax.get_title() and "flat optimum" in ax.get_title()
    plt.close(fig)
    # A sharp optimum: one cell, no squares, no word "flat".
    fig = savitzky_golay_grid_figure(table, flat_tolerance=0.01)
    ax = fig.axes[0]
    assert not [ln for ln in ax.get_lines() if ln.get_label().startswith("within")]
    assert "flat" not in ax.get_title()
    plt.close(fig)


def test_cells_not_computed_and_clipped_cells_are_named_in_the_legend():
    table = StudyTable(
        [r for r in _grid_table(_interior) if r.params != {"order": 4, "window": 101}]
    )
    fig = savitzky_golay_grid_figure(table)
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert "not computed" in labels and "above the clip" in labels
    plt.close(fig)
    fig = savitzky_golay_grid_figure(_grid_table(_interior), clip_percentile=100.0)
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert "not computed" not in labels and "above the clip" not in labels
    plt.close(fig)


def test_grid_refuses_a_negative_flat_tolerance():
    with pytest.raises(ParameterError, match=r"flat_tolerance must be >= 0 \[-\]"):
        savitzky_golay_grid_figure(_grid_table(_interior), flat_tolerance=-0.1)
