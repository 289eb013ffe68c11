"""Figures of the filter study (Kayaalp, section 4.5.2.5-4.5.2.6, Figures 68-96 in spirit).

* :func:`filter_comparison_figure`: raw and filtered torque over the whole record, with zooms on
  a steady and a transient part underneath (the seed's layout);
* :func:`study_ranking_figure`: the ranked study as horizontal bars of the cost, split into its
  noise, peak and timing terms;
* :func:`savitzky_golay_grid_figure`: the Savitzky-Golay tuning table as an order × window map.

All return a matplotlib figure; save with :func:`rollerrig.output.save_figure`.
"""

from __future__ import annotations

import textwrap
from collections.abc import Mapping, Sequence

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.report.lines import envelope
from rollerrig.signal.scoring import ScoreWeights, Segmentation, StudyRow

__all__ = [
    "filter_comparison_figure",
    "savitzky_golay_grid_figure",
    "study_ranking_figure",
]

_TITLE_WIDTH = 80
"""Characters per line of the grid figure's red title at 9 pt: it fits over the axes."""


def _window_around(segments: list[tuple[int, int]], time: np.ndarray, pick: str):
    if not segments:
        return None
    a, b = max(segments, key=lambda s: s[1] - s[0]) if pick == "longest" else segments[0]
    return float(time[a]), float(time[b - 1])


def filter_comparison_figure(
    time,
    raw,
    filtered: Mapping[str, np.ndarray],
    *,
    truth=None,
    segmentation: Segmentation | None = None,
    steady_window: tuple[float, float] | None = None,
    transient_window: tuple[float, float] | None = None,
    unit: str = "N·m",
    title: str = "",
):
    """Raw vs filtered signals with zooms on a steady and a transient part.

    Parameters
    ----------
    time : array_like, shape (n,)
        Sample times [s].
    raw : array_like, shape (n,)
        Raw signal [``unit``].
    filtered : mapping of str to array_like
        Filtered signals by legend label.
    truth : array_like, optional
        Noise-free signal, drawn dashed.
    segmentation : Segmentation, optional
        Picks the zoom windows (longest steady run, first transient run) when not given.
    steady_window, transient_window : (float, float), optional
        Zoom windows [s].
    unit : str
        Label of the signal unit.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    t = np.asarray(time, float)
    if segmentation is not None:
        steady_window = steady_window or _window_around(
            segmentation.steady_segments(), t, "longest"
        )
        transient_window = transient_window or _window_around(
            segmentation.transient_segments(), t, "first"
        )
    fig = plt.figure(figsize=(10, 6.5))
    grid = fig.add_gridspec(2, 2, height_ratios=[1.1, 1.0])
    top = fig.add_subplot(grid[0, :])
    zooms = [fig.add_subplot(grid[1, 0]), fig.add_subplot(grid[1, 1])]
    raw = np.asarray(raw, dtype=float)
    for ax, window in ((top, None), (zooms[0], steady_window), (zooms[1], transient_window)):
        # Each axis gets only what it shows, drawn as an envelope (bounded points per line).
        part = slice(None)
        if window is not None:
            i0, i1 = np.searchsorted(t, window)
            part = slice(max(int(i0) - 1, 0), int(i1) + 1)
        ax.plot(*envelope(t[part], raw[part]), color="0.7", lw=0.6, label="raw")
        if truth is not None:
            ax.plot(*envelope(t[part], np.asarray(truth)[part]), "k--", lw=0.9, label="truth")
        for label, y in filtered.items():
            ax.plot(*envelope(t[part], np.asarray(y)[part]), lw=1.2, label=label)
        ax.set_xlabel("time [s]")
        ax.set_ylabel(f"torque [{unit}]")
        ax.grid(alpha=0.3)
    for ax, window, name in zip(
        zooms, (steady_window, transient_window), ("steady part", "transient part"), strict=True
    ):
        ax.set_title(name, fontsize=9)
        if window is not None:
            ax.set_xlim(*window)
            keep = (t >= window[0]) & (t <= window[1])
            if keep.any():
                lo, hi = float(np.min(np.asarray(raw)[keep])), float(np.max(np.asarray(raw)[keep]))
                pad = 0.05 * (hi - lo or 1.0)
                ax.set_ylim(lo - pad, hi + pad)
            top.axvspan(*window, color="tab:orange" if "trans" in name else "tab:green", alpha=0.1)
    top.legend(fontsize=8, ncol=4, loc="upper left")
    if title:
        top.set_title(title)
    fig.tight_layout()
    return fig


def study_ranking_figure(
    rows: Sequence[StudyRow], *, top: int = 25, weights: ScoreWeights | None = None
):
    """Ranked filter study as stacked horizontal bars of the cost terms (best at the top).

    The legend stands right of the axes, clear of every bar.

    Parameters
    ----------
    rows : sequence of StudyRow
        Output of :func:`rollerrig.signal.scoring.filter_study`.
    top : int
        How many of the best rows to show.
    weights : ScoreWeights, optional
        The weights the study used (to split the cost into its terms).

    Returns
    -------
    matplotlib.figure.Figure
    """
    w = weights or ScoreWeights()
    shown = list(rows)[:top]
    labels = [f"{r.rank}. {r.label}" for r in shown]
    noise = np.array([w.noise * np.nan_to_num(r.score.noise_left) for r in shown])
    peak = np.array([w.peak * abs(1 - np.nan_to_num(r.score.peak_kept, nan=1.0)) for r in shown])
    timing = np.array(
        [
            w.timing
            * (abs(np.nan_to_num(r.score.lag)) + abs(np.nan_to_num(r.score.peak_time_error)))
            / w.time_scale
            for r in shown
        ]
    )
    y = np.arange(len(shown))[::-1]
    fig, ax = plt.subplots(figsize=(9.5, 0.28 * len(shown) + 1.2))
    ax.barh(y, noise, color="tab:blue", label="steady noise left")
    ax.barh(y, peak, left=noise, color="tab:red", label="peak lost")
    ax.barh(y, timing, left=noise + peak, color="tab:gray", label="lag + peak-time error")
    ax.set_yticks(y, labels, fontsize=8)
    ax.set_xlabel("cost [-] (lower is better)")
    rate = _analysis_rate(rows)
    if rate is not None:
        ax.set_title(f"windows w in samples at {rate:g} Hz", fontsize=8)
    # Outside the bars, right of the axes: it hides no part of any bar (the winner's included).
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    ax.grid(axis="x", alpha=0.3)
    fig.tight_layout()
    return fig


def savitzky_golay_grid_figure(
    table: Sequence[StudyRow], *, clip_percentile: float = 90.0, flat_tolerance: float = 0.05
):
    """Savitzky-Golay tuning table as a cost map over polynomial order × window.

    The window axis counts samples at the rate the tuning ran at (the table's
    ``basis.analysis_rate``, else the rows' ``sample_rate``), which is 250 Hz for a recording
    faster than 500 Hz, not the recording's own rate; the axis label says which.

    The colour scale is robust: it runs from the lowest cost to the ``clip_percentile``-th
    percentile of the costs, so a few very poor combinations (the shortest windows at high
    orders) do not flatten the cells near the optimum; costs above the clip take the colour of
    the bar's triangle. When the shown range spans a factor of 10 or more the scale is
    logarithmic. The colour bar's label says which scale and where it clips.

    The lowest cost is marked with a star, and the cells within ``flat_tolerance`` of it are
    outlined: a cost that differs by a few per cent is no evidence of a better filter (the
    score's own noise is not estimated), so the title says how many cells share the optimum
    rather than calling one cell the optimum. Grey cells were not computed (not tried, or not
    scored), white ones are above the colour scale's clip; the legend says so. An optimum on
    the edge of the grid (the smallest or
    largest window or order tried) is not known to be an optimum: it is circled and the figure
    says "optimum on the grid edge (...)", naming the edge and how to try a wider grid.

    Parameters
    ----------
    table : sequence of StudyRow
        Output table of :func:`rollerrig.signal.scoring.tune_savitzky_golay` (ranked: the
        first row has the lowest cost).
    clip_percentile : float
        Upper end of the colour scale, as a percentile of the finite costs [%], in (0, 100].
    flat_tolerance : float
        Relative cost above the lowest within which a cell counts as equally good [-], ≥ 0;
        default 0.05.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.colors import LogNorm, Normalize

    if not 0.0 < clip_percentile <= 100.0:
        raise ParameterError(f"clip_percentile must be in (0, 100] [%], got {clip_percentile!r}")
    if not (np.isfinite(flat_tolerance) and flat_tolerance >= 0.0):
        raise ParameterError(f"flat_tolerance must be >= 0 [-], got {flat_tolerance!r}")
    from matplotlib.patches import Patch

    orders = sorted({r.params["order"] for r in table})
    windows = sorted({r.params["window"] for r in table})
    grid = np.full((len(orders), len(windows)), np.nan)
    for r in table:
        grid[orders.index(r.params["order"]), windows.index(r.params["window"])] = r.score.cost
    finite = grid[np.isfinite(grid)]
    lo = float(finite.min()) if finite.size else 0.0
    hi = float(np.percentile(finite, clip_percentile)) if finite.size else 1.0
    hi = hi if hi > lo else lo + (abs(lo) or 1.0) * 1e-3
    clipped = bool(finite.size and finite.max() > hi)
    logarithmic = lo > 0.0 and hi / lo >= 10.0
    norm = LogNorm(vmin=lo, vmax=hi) if logarithmic else Normalize(vmin=lo, vmax=hi)
    # Dark: low cost, light: high cost; white beyond the clip (off the scale, continuing dark
    # -> light); grey: a combination not tried or not scored.
    cmap = plt.get_cmap("viridis").with_extremes(over="white", bad="0.55")
    fig, ax = plt.subplots(figsize=(8, 3.8))
    im = ax.imshow(grid, aspect="auto", origin="lower", cmap=cmap, norm=norm)
    ax.set_xticks(range(len(windows)), [str(w) for w in windows], fontsize=7, rotation=90)
    ax.set_yticks(range(len(orders)), [str(o) for o in orders])
    ax.set_xlabel(_window_axis(table))
    ax.set_ylabel("polynomial order")
    best = min(table, key=lambda r: r.rank).params
    col, row = windows.index(best["window"]), orders.index(best["order"])
    # The star on top of every other marker (the orange squares had hidden it, leaving a red
    # square where the legend shows a star), with a white edge to stand out on dark cells.
    ax.plot(col, row, "*", ms=14, mfc="red", mec="white", mew=0.8, zorder=5, label="lowest cost")
    lowest = f"lowest cost (red star): order {best['order']}, window {best['window']}"
    # Cells as good as the lowest within the tolerance: the optimum is a region, not a cell.
    near = np.isfinite(grid) & (grid <= lo + flat_tolerance * abs(lo))
    n_near = int(near.sum())
    if n_near > 1:
        others = near.copy()
        others[row, col] = False  # the lowest cell carries the star, not a square
        rows_near, cols_near = np.nonzero(others)
        ax.plot(
            cols_near, rows_near, "s", ms=9, mfc="none", mec="tab:orange", mew=1.2,
            label=f"within {100 * flat_tolerance:g} % of the lowest",
        )  # fmt: skip
        lowest += (
            f"; {n_near} cells within {100 * flat_tolerance:g} % of it (squares): a flat optimum"
        )
    edges = _grid_edges(best, orders, windows)
    if edges:
        ax.plot(col, row, "o", ms=20, mfc="none", mec="red", mew=1.5, label="on the grid edge")
        ax.text(0.5, 1.02, lowest, transform=ax.transAxes, ha="center", va="bottom", fontsize=8)
        # Wrapped: on one line the title ran past both sides of the figure.
        ax.set_title(
            textwrap.fill(
                "optimum on the grid edge (" + "; ".join(edges) + "): the true optimum may lie "
                "beyond; a wider grid: tune_savitzky_golay(orders=, windows=)",
                width=_TITLE_WIDTH,
            ),
            fontsize=9,
            color="tab:red",
            pad=16,
        )
    else:
        ax.set_title(lowest, fontsize=8)
    handles, _ = ax.get_legend_handles_labels()
    if np.isnan(grid).any():
        handles.append(Patch(facecolor="0.55", label="not computed"))
    if clipped:
        handles.append(Patch(facecolor="white", edgecolor="0.3", label="above the clip"))
    ax.legend(
        handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(0.0, -0.28), ncol=4,
        frameon=False,
    )  # fmt: skip
    scale = "log scale" if logarithmic else "linear scale"
    clip = f"\nclipped at the {clip_percentile:g}th percentile, {hi:.3g}"
    fig.colorbar(
        im,
        ax=ax,
        extend="max" if clipped else "neither",
        label=f"cost [-], {scale}" + (clip if clipped else ""),
    )
    fig.tight_layout()
    return fig


def _grid_edges(best: Mapping, orders: Sequence[int], windows: Sequence[int]) -> list[str]:
    """Which edges of the order × window grid the optimum ``best`` lies on, in words."""
    edges = []
    for key, values, what in (("window", windows, "window"), ("order", orders, "order")):
        v = best[key]
        if v == values[-1]:
            edges.append(f"{what} {v} is the largest tried")
        elif v == values[0]:
            edges.append(f"{what} {v} is the smallest tried")
    return edges


def _analysis_rate(rows) -> float | None:
    """Rate [Hz] the windows of a study table count samples at, if known."""
    basis = getattr(rows, "basis", None)
    if basis is not None:
        return float(basis.analysis_rate)
    rates = {r.sample_rate for r in rows if getattr(r, "sample_rate", None) is not None}
    return float(rates.pop()) if len(rates) == 1 else None


def _window_axis(rows) -> str:
    rate = _analysis_rate(rows)
    if rate is None:
        return "window [samples]"
    basis = getattr(rows, "basis", None)
    where = ""
    if basis is not None and basis.decimation is not None:
        where = f", the recording's {basis.source_rate:g} Hz decimated"
    return f"window [samples at {rate:g} Hz{where}]"
