"""Figures of the filter study (Kayaalp, section 4.5.2.5-4.5.2.6, Figures 68-96 in spirit).

* :func:`filter_comparison_figure`: raw and filtered torque over the whole record, with zooms on
  a steady and a transient part underneath (the seed's layout);
* :func:`study_ranking_figure`: the ranked study as horizontal bars of the cost, split into its
  noise, peak and timing terms;
* :func:`savitzky_golay_grid_figure`: the Savitzky-Golay tuning table as an order × window map.

All return a matplotlib figure; save with :func:`rollerrig.report._io.save_figure`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np

from rollerrig.signal.scoring import ScoreWeights, Segmentation, StudyRow

__all__ = ["filter_comparison_figure", "savitzky_golay_grid_figure", "study_ranking_figure"]


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
    for ax in (top, *zooms):
        ax.plot(t, raw, color="0.7", lw=0.6, label="raw")
        if truth is not None:
            ax.plot(t, truth, "k--", lw=0.9, label="truth")
        for label, y in filtered.items():
            ax.plot(t, y, lw=1.2, label=label)
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
    fig, ax = plt.subplots(figsize=(8, 0.28 * len(shown) + 1.2))
    ax.barh(y, noise, color="tab:blue", label="steady noise left")
    ax.barh(y, peak, left=noise, color="tab:red", label="peak lost")
    ax.barh(y, timing, left=noise + peak, color="tab:gray", label="lag + peak-time error")
    ax.set_yticks(y, labels, fontsize=8)
    ax.set_xlabel("cost [1] (lower is better)")
    ax.legend(fontsize=8, loc="best")
    ax.grid(axis="x", alpha=0.3)
    fig.tight_layout()
    return fig


def savitzky_golay_grid_figure(table: Sequence[StudyRow]):
    """Savitzky-Golay tuning table as a cost map over polynomial order × window.

    Parameters
    ----------
    table : sequence of StudyRow
        Output table of :func:`rollerrig.signal.scoring.tune_savitzky_golay`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    orders = sorted({r.params["order"] for r in table})
    windows = sorted({r.params["window"] for r in table})
    grid = np.full((len(orders), len(windows)), np.nan)
    for r in table:
        grid[orders.index(r.params["order"]), windows.index(r.params["window"])] = r.score.cost
    fig, ax = plt.subplots(figsize=(8, 3.5))
    im = ax.imshow(grid, aspect="auto", origin="lower", cmap="viridis_r")
    ax.set_xticks(range(len(windows)), [str(w) for w in windows], fontsize=7, rotation=90)
    ax.set_yticks(range(len(orders)), [str(o) for o in orders])
    ax.set_xlabel("window [samples]")
    ax.set_ylabel("polynomial order")
    best = table[0].params
    ax.plot(windows.index(best["window"]), orders.index(best["order"]), "r*", ms=12)
    fig.colorbar(im, ax=ax, label="cost [1]")
    fig.tight_layout()
    return fig
