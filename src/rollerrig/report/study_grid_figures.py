"""Figures of a grid study: the metric against one axis, a heat map and lines over two, a heat
map and main effects over more.

:func:`rollerrig.report.studies.study_figures` calls :func:`_grid_figures` for a study of design
``"grid"``. Heat-map cells without a value are hatched; a cell that averages fewer points than
the others (some without a value) is hatched lightly and says how many are missing.
"""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, PathPatch, Rectangle
from matplotlib.path import Path

from rollerrig.output.figures import crop_when_saved
from rollerrig.report.study_display import (
    _MISSING_COLOUR,
    MISSING_GID,
    _cell_status,
    _fmt,
    _footnote,
    _level_ticks,
    _log_x,
    _mark_missing,
    _missing_handle,
    _missing_text,
    _Quantity,
    _quantity,
    _room_for_missing,
    _say_no_values,
    _title,
    _x_positions,
)
from rollerrig.studies.summary import grid_shape, json_attribute, varied_parameters

__all__: list[str] = []

_ANNOTATE_CELLS = 100  # annotate the values of heat maps with at most this many cells


def _mean_over(grid: np.ndarray, keep: tuple[int, ...]) -> tuple[np.ndarray, np.ndarray, int]:
    """Mean over the finite values of all axes but ``keep``; (mean, points missing, total)."""
    drop = tuple(i for i in range(grid.ndim) if i not in keep)
    finite = np.isfinite(grid)
    total = int(np.prod([grid.shape[i] for i in drop])) if drop else 1
    s = np.where(finite, grid, 0.0).sum(axis=drop) if drop else np.where(finite, grid, 0.0)
    n = finite.sum(axis=drop) if drop else finite.astype(int)
    mean = np.divide(s, n, out=np.full(s.shape, np.nan), where=n > 0)
    return mean, total - n, total


def _grid_levels(q: _Quantity, shape, axis: int) -> list:
    values = q.values.reshape(shape)
    index = tuple(slice(None) if j == axis else 0 for j in range(len(shape)))
    return list(values[index])


def _line_figure(ds, metric: _Quantity, qx: _Quantity, shape, scale: str, y_lines, groups):
    """The metric against ``qx``: one line per row of ``y_lines`` (levels of ``qx`` along
    the last axis), labelled by ``groups`` (None: a single line)."""
    levels = _grid_levels(qx, shape, 0)
    x, categorical = _x_positions(qx, levels)
    fig, ax = plt.subplots(figsize=(9.0, 4.6))
    many = len(y_lines) > 1
    if len(y_lines) <= 10:
        colours = [plt.get_cmap("tab10")(i) for i in range(len(y_lines))]
    else:
        colours = [
            plt.get_cmap("viridis")(0.85 * i / (len(y_lines) - 1)) for i in range(len(y_lines))
        ]
    missing_any = False
    for i, y in enumerate(y_lines):
        colour = colours[i]
        label = groups[i] if groups is not None else None
        ax.plot(x, y, "o-", color=colour, ms=5, lw=1.5, label=label, zorder=3)
        bad = ~np.isfinite(y)
        if bad.any():
            missing_any = True
            _mark_missing(ax, x[bad], colour=colour if many else _MISSING_COLOUR)
    if categorical:
        _level_ticks(ax, len(levels), [str(v) for v in levels])
        ax.set_xlim(-0.5, len(levels) - 0.5)
    elif scale == "log" and np.all(x > 0):
        _log_x(ax, x)
    ax.set_xlabel(qx.label)
    ax.set_ylabel(metric.label)
    ax.grid(True, alpha=0.3)
    _say_no_values(ax, metric.values)
    handles = ax.get_legend_handles_labels()[0]
    if missing_any:
        _room_for_missing(ax)
        where = "× at the bottom, in its line's colour" if many else "× at the bottom"
        handles.append(_missing_handle(_missing_text(ds, metric.values), where))
    if handles:
        # Beside the axes: a legend inside could hide a point (a line broken by a failure).
        ax.legend(handles=handles, fontsize=8, title=groups.title if groups is not None
                  else None, title_fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0),
                  ncol=1 + len(handles) // 13, borderaxespad=0.0)  # fmt: skip
    return fig, ax


class _Groups(list):
    """Legend labels of the lines, with the legend's title."""

    def __init__(self, labels, title: str):
        super().__init__(labels)
        self.title = title


def _heatmap(fig, ax, qx, qy, levels_x, levels_y, z, missing, total, metric, status=None):
    """Cells over the levels of ``qx`` (columns) and ``qy`` (rows); ``z`` shape (nx, ny).

    ``missing``: points of a cell without a value (of ``total``); a cell with none of its
    points is hatched grey, one that averages fewer than all of them hatched lightly.
    ``status``: the status of each cell's point (a cell of one point), written in it.
    """
    nx, ny = z.shape
    finite = np.isfinite(z)
    empty = missing >= total
    partial = (missing > 0) & ~empty
    lo, hi = (float(z[finite].min()), float(z[finite].max())) if finite.any() else (0.0, 1.0)
    if hi == lo:
        lo, hi = lo - 0.5 * (abs(lo) or 1.0), hi + 0.5 * (abs(hi) or 1.0)
    # The cells without a value are holes in the mesh over one hatched background, and the
    # cells of fewer points one hatched path: a patch per cell made an interrupted 1000 x 1000
    # study take minutes to draw (a million artists); the background costs the same for any
    # number of cells.
    if empty.any():
        ax.add_patch(Rectangle((-0.5, -0.5), nx, ny, facecolor="0.9", edgecolor=_MISSING_COLOUR,
                               hatch="xx", lw=0, zorder=0.5, gid=MISSING_GID))  # fmt: skip
    mesh = ax.pcolormesh(np.arange(nx + 1) - 0.5, np.arange(ny + 1) - 0.5,
                         np.ma.masked_where((~finite | empty).T, z.T), cmap="viridis", vmin=lo,
                         vmax=hi, shading="flat")  # fmt: skip
    cbar = fig.colorbar(mesh, ax=ax, pad=0.02)
    cbar.set_label(metric.label)
    if partial.any():
        ax.add_patch(PathPatch(_cells_path(partial), facecolor="none", edgecolor="w",
                               hatch="//", lw=0, gid=MISSING_GID))  # fmt: skip
    if nx * ny <= _ANNOTATE_CELLS:
        colours = mesh.cmap(mesh.norm(np.where(finite, z, lo)))
        light = colours[..., :3] @ np.array([0.299, 0.587, 0.114]) > 0.5
        size = 8 if nx * ny <= 36 else 6
        for i in range(nx):
            for j in range(ny):
                if empty[i, j]:
                    text = status[i, j] if status is not None else "no value"
                    ax.text(i, j, text, ha="center", va="center", fontsize=size,
                            color=_MISSING_COLOUR, fontweight="bold",
                            bbox={"fc": "w", "ec": "none", "alpha": 0.8, "pad": 1})  # fmt: skip
                    continue
                text = _fmt(z[i, j])
                if partial[i, j]:
                    text += f"\n({int(missing[i, j])} of {total} missing)"
                    ax.text(i, j, text, ha="center", va="center", fontsize=size, color="k",
                            bbox={"fc": "w", "ec": "none", "alpha": 0.8, "pad": 1})  # fmt: skip
                    continue
                ax.text(i, j, text, ha="center", va="center", fontsize=size,
                        color="k" if light[i, j] else "w")  # fmt: skip
    _level_ticks(ax, nx, [_fmt(v) for v in levels_x], "x", fontsize=8)
    _level_ticks(ax, ny, [_fmt(v) for v in levels_y], "y", fontsize=8)
    ax.set_xlabel(qx.label)
    ax.set_ylabel(qy.label)
    handles = []
    if empty.any():
        what = "no value" if status is None else _missing_text_cells(status[empty])
        handles.append(Patch(facecolor="0.9", edgecolor=_MISSING_COLOUR, hatch="xx", label=what))
    if partial.any():
        handles.append(Patch(facecolor="0.6", edgecolor="w", hatch="//",
                             label="average over fewer points (some without a value)"))  # fmt: skip
    if handles:
        ax.legend(handles=handles, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.16),
                  ncol=len(handles), frameon=False)  # fmt: skip
    return mesh


def _cells_path(mask: np.ndarray) -> Path:
    """The cells where ``mask`` (shape (nx, ny)) is true, as one compound path of rectangles.

    Cell ``(i, j)`` spans ``i ± 0.5``, ``j ± 0.5``. Runs of cells along a column are one
    rectangle, and equal runs of neighbouring columns one too: a block of cells (the points
    an interrupted study has not run yet) is two or three rectangles.
    """
    if not mask.any():
        return Path(np.zeros((0, 2)))
    padded = np.zeros((mask.shape[0], mask.shape[1] + 2), dtype=np.int8)
    padded[:, 1:-1] = mask
    step = np.diff(padded, axis=1)
    # Starts and ends of the runs, both in C order: the k-th start and end are one run.
    col, lo = np.nonzero(step == 1)
    hi = np.nonzero(step == -1)[1]
    order = np.lexsort((col, hi, lo))  # by run (lo, hi), then column
    col, lo, hi = col[order], lo[order], hi[order]
    new = np.ones(col.size, dtype=bool)
    new[1:] = (lo[1:] != lo[:-1]) | (hi[1:] != hi[:-1]) | (col[1:] != col[:-1] + 1)
    first = np.flatnonzero(new)
    last = np.append(first[1:], col.size) - 1
    x0, x1 = col[first] - 0.5, col[last] + 0.5
    y0, y1 = lo[first] - 0.5, hi[first] - 0.5
    vertices = np.stack([np.column_stack(v) for v in
                         ((x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0))], axis=1)  # fmt: skip
    codes = np.tile([Path.MOVETO, Path.LINETO, Path.LINETO, Path.LINETO, Path.CLOSEPOLY],
                    first.size)  # fmt: skip
    return Path(vertices.reshape(-1, 2), codes)


def _missing_text_cells(status: np.ndarray) -> str:
    counts: dict[str, int] = {}
    for s in status:
        counts[str(s)] = counts.get(str(s), 0) + 1
    return "no value: " + ", ".join(f"{s} {n}" for s, n in sorted(counts.items()))


def _grid_figures(ds, metric: _Quantity) -> dict:
    keys = varied_parameters(ds)
    shape = grid_shape(ds, keys)
    scales = [str(s) for s in json_attribute(ds, "grid_scales", ["list"] * len(keys))]
    qs = [_quantity(ds, k) for k in keys]
    y = metric.values
    grid = y.reshape(shape)
    figs = {}
    name = metric.name
    foot = _footnote(ds, y)
    if len(keys) == 1:
        fig, ax = _line_figure(ds, metric, qs[0], shape, scales[0], [grid], None)
        ax.set_title(_title(ds, f"{name} against {qs[0].name}\n{foot}"), fontsize=10)
        fig.tight_layout()
        crop_when_saved(fig)  # the legend beside the axes narrows them; the title can overhang
        figs[f"{metric.key}-line"] = fig
        return figs

    lx, ly = _grid_levels(qs[0], shape, 0), _grid_levels(qs[1], shape, 1)
    if len(keys) == 2:
        z, missing, total = grid, (~np.isfinite(grid)).astype(int), 1
        status = _cell_status(ds, y).reshape(shape)
        what = f"{name}\n{foot}"
    else:
        z, missing, total = _mean_over(grid, (0, 1))
        status = None
        others = ", ".join(q.name for q in qs[2:])
        what = f"{name}, averaged over {others}\n{foot}"
    fig, ax = plt.subplots(figsize=(8.0, 5.4))
    _heatmap(fig, ax, qs[0], qs[1], lx, ly, z, missing, total, metric, status)
    ax.set_title(_title(ds, what), fontsize=10)
    fig.tight_layout()
    figs[f"{metric.key}-heatmap"] = fig

    if len(keys) == 2:
        groups = _Groups([f"{_fmt(v)} {qs[1].unit}".strip() for v in ly], qs[1].label)
        fig, ax = _line_figure(ds, metric, qs[0], shape, scales[0], list(grid.T), groups)
        ax.set_title(_title(ds, f"{name} against {qs[0].name}, one line per "
                                f"{qs[1].name}\n{foot}"), fontsize=10)  # fmt: skip
        fig.tight_layout()
        crop_when_saved(fig)  # the legend beside the axes narrows them; the title can overhang
        figs[f"{metric.key}-lines"] = fig
    else:
        figs[f"{metric.key}-main-effects"] = _main_effect_figure(ds, metric, qs, shape, scales)
    return figs


def _main_effect_figure(ds, metric: _Quantity, qs, shape, scales):
    """The metric averaged over all other axes, against each axis (one panel each)."""
    grid = metric.values.reshape(shape)
    d = len(qs)
    ncols = min(d, 3)
    nrows = math.ceil(d / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(4.2 * ncols, 3.6 * nrows), sharey=True,
                             squeeze=False)  # fmt: skip
    partial_any = empty_any = False
    for i, (q, ax) in enumerate(zip(qs, axes.flat, strict=False)):
        mean, missing, total = _mean_over(grid, (i,))
        levels = _grid_levels(q, shape, i)
        x, categorical = _x_positions(q, levels)
        ax.plot(x, mean, "o-", color="tab:blue", ms=5, zorder=3)
        partial = (missing > 0) & (missing < total)
        if partial.any():
            partial_any = True
            ax.plot(x[partial], mean[partial], "o", ms=10, mfc="none", mec=_MISSING_COLOUR,
                    mew=1.5, zorder=4, gid=MISSING_GID)  # fmt: skip
        empty = missing >= total
        if empty.any():
            empty_any = True
            _mark_missing(ax, x[empty])
            _room_for_missing(ax, lower=False)
        if categorical:
            _level_ticks(ax, len(levels), [str(v) for v in levels])
            ax.set_xlim(-0.5, len(levels) - 0.5)
        elif scales[i] == "log" and np.all(x > 0):
            _log_x(ax, x)
        ax.set_xlabel(q.label, fontsize=9)
        ax.grid(True, alpha=0.3)
        if i == 0:  # one label for the shared y-axis: one per row would overlap the next
            ax.set_ylabel(f"mean {metric.label}", fontsize=9)
    for ax in list(axes.flat)[d:]:
        ax.set_visible(False)
    if empty_any:  # the y-axis is shared: lowered once
        lo, hi = axes.flat[0].get_ylim()
        axes.flat[0].set_ylim(lo - 0.12 * (hi - lo), hi)
    handles = [Line2D([], [], marker="o", color="tab:blue", label="mean over the other axes")]
    if partial_any:
        handles.append(Line2D([], [], ls="none", marker="o", ms=10, mfc="none",
                              mec=_MISSING_COLOUR, mew=1.5,
                              label="mean over fewer points (some without a value)"))  # fmt: skip
    if empty_any:
        handles.append(_missing_handle("no point of the level has a value"))
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=8, frameon=False)
    fig.suptitle(_title(ds, f"main effects on {metric.name}: each axis, averaged over the "
                            f"others\n{_footnote(ds, metric.values)}", 40 * ncols),
                 fontsize=10)  # fmt: skip
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    return fig
