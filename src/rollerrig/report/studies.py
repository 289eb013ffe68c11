"""Figures of a study: each metric against the study's parameters, failed points marked.

:func:`study_figures` draws, per metric, what fits the design of the study Dataset
(:mod:`rollerrig.studies.summary` describes its form):

- a **grid** of one axis: the metric against it (a log axis when the grid is log-spaced);
- a grid of two axes: a heat map over both, and one line per level of the second axis;
- a grid of more axes: a heat map over the first two, averaged over the others (the title
  says which), and a main-effect plot: the metric averaged over all other axes against each
  axis, one panel each (a shared y-axis, so that the panels compare);
- **cases**: a horizontal bar per case;
- a **sample**: the metric against each parameter (a scatter panel each), Spearman's rank
  correlation of each parameter, and for a Sobol design the indices S1 and ST with their
  confidence intervals.

A point without a value (failed, pending, or the metric undefined there) is never dropped
silently: on a line or scatter it is a cross at the bottom of the axes, in a heat map a
hatched cell, in a bar chart a cross at zero with its status, and the legend counts them by
status. A categorical parameter (friction, drive) is shown by its categories. Values are
shown in the units an engineer reads (:func:`display_unit`: kN·m/rad, km/h, kN); the
figures are returned, saving them (:func:`rollerrig.output.save_figure`) is the caller's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, Rectangle

from rollerrig._validation import ParameterError
from rollerrig.studies.summary import (
    STATUS_OK,
    check_metric,
    design_kind,
    grid_shape,
    is_numeric,
    json_attribute,
    metric_names,
    missing_counts,
    study_name,
    text_values,
    varied_parameters,
)
from rollerrig.units import apply_factor, si_factor

__all__ = ["MISSING_GID", "display_unit", "study_figures"]

MISSING_GID = "study-missing"
"""``gid`` of the artists that mark points without a value (crosses, hatched cells)."""

_DISPLAY = {"N.m/rad": "kN.m/rad", "N": "kN", "m/s": "km/h"}
"""SI unit -> the unit the figures show (the others are shown in SI)."""

_MISSING_COLOUR = "crimson"
_ANNOTATE_CELLS = 100  # annotate the values of heat maps with at most this many cells
_MAX_TICKS = 16  # at most this many tick labels on a categorical or grid axis


def display_unit(si_unit: str) -> tuple[str, float]:
    """The unit a figure shows for an SI unit, and the factor from SI to it.

    Parameters
    ----------
    si_unit : str
        SI unit as the study stores it, e.g. ``"N.m/rad"``; ``"1"`` or ``""`` for a
        dimensionless quantity.

    Returns
    -------
    (str, float)
        The unit as shown (``·`` for the product, ``-`` for dimensionless) and the factor:
        ``shown = value_SI * factor``.

    Examples
    --------
    >>> display_unit("N.m/rad"), display_unit("m/s")[0], display_unit("1")
    (('kN·m/rad', 0.001), 'km/h', ('-', 1.0))
    """
    if si_unit in ("", "1", "-"):
        return "-", 1.0
    shown = _DISPLAY.get(si_unit, si_unit)
    try:
        factor = 1.0 / si_factor(shown, si_unit)
    except ParameterError:  # not in the unit registry: shown as stored
        shown, factor = si_unit, 1.0
    return shown.replace(".", "·"), factor


@dataclass(frozen=True)
class _Quantity:
    """A parameter or metric as a figure shows it."""

    key: str
    name: str
    unit: str  # shown; "" for a categorical parameter
    values: np.ndarray  # per point: float in the shown unit, or str

    @property
    def numeric(self) -> bool:
        return is_numeric(self.values)

    @property
    def label(self) -> str:
        return f"{self.name} [{self.unit}]" if self.unit else self.name


def _quantity(ds, key: str) -> _Quantity:
    var = ds[key]
    raw = np.asarray(var.values).ravel()
    name = str(var.attrs.get("long_name", "") or key)
    if not is_numeric(raw):
        return _Quantity(key, name, "", np.asarray([str(v) for v in raw], dtype=object))
    unit, factor = display_unit(str(var.attrs.get("units", "")))
    values = np.asarray(raw, dtype=float)
    if factor != 1.0:
        values = apply_factor(values, factor)
    return _Quantity(key, name, unit, values)


def _fmt(value) -> str:
    """A value for a tick or a cell: 4 significant digits, no exponent from 0.001 to 1e6."""
    if isinstance(value, str):
        return value
    v = float(value)
    if not math.isfinite(v):
        return "–"
    if v == 0.0 or 1e-3 <= abs(v) < 1e6:
        return np.format_float_positional(v, precision=4, fractional=False, trim="-")
    return f"{v:.3g}"


def _counts_text(ds, y: np.ndarray) -> str:
    """The points of ``y`` without a value, by status: ``solver failed 2, pending 1``."""
    counts = missing_counts(ds, y)
    return ", ".join(f"{s} {n}" for s, n in sorted(counts.items()))


def _missing_text(ds, y: np.ndarray) -> str:
    """The points of ``y`` without a value: ``no value: solver failed 2, pending 1``."""
    return "no value: " + _counts_text(ds, y)


def _mark_missing(ax, x, colour=_MISSING_COLOUR, label=None) -> None:
    """Crosses at the bottom of ``ax`` at the x positions of points without a value."""
    x = np.asarray(x)
    if x.size == 0:
        return
    ax.plot(x, np.full(x.size, 0.03), ls="none", marker="x", ms=8, mew=2, color=colour,
            transform=ax.get_xaxis_transform(), clip_on=False, zorder=6, gid=MISSING_GID,
            label=label)  # fmt: skip


def _missing_handle(text: str, where: str = "× at the bottom") -> Line2D:
    colour = _MISSING_COLOUR if where == "× at the bottom" else "0.3"
    return Line2D([], [], ls="none", marker="x", ms=8, mew=2, color=colour,
                  label=f"{text}\n({where})")  # fmt: skip


def _room_for_missing(ax, lower: bool = True) -> None:
    """Lower the y-axis (``lower``; once for axes that share it) so that the crosses of
    :func:`_mark_missing` lie below every value, in a lightly shaded band."""
    if lower:
        lo, hi = ax.get_ylim()
        ax.set_ylim(lo - 0.12 * (hi - lo), hi)
    band = Rectangle((0.0, 0.0), 1.0, 0.065, transform=ax.transAxes, facecolor=_MISSING_COLOUR,
                     alpha=0.07, edgecolor="none", zorder=0)  # fmt: skip
    ax.add_patch(band)


def _level_ticks(axis, n: int, labels: list[str], which: str = "x", fontsize=None) -> None:
    """Ticks at 0..n-1 labelled by ``labels`` (at most :data:`_MAX_TICKS` of them)."""
    step = max(1, math.ceil(n / _MAX_TICKS))
    pos = np.arange(0, n, step)
    setter = axis.set_xticks if which == "x" else axis.set_yticks
    setter(pos, [labels[i] for i in pos], fontsize=fontsize)
    if which == "x" and max((len(s) for s in labels), default=0) > 8:
        plt.setp(axis.get_xticklabels(), rotation=30, ha="right")


def _log_x(ax, levels) -> None:
    """A log x-axis with plain numbers: ticks at the grid's ``levels`` when there are at most
    12 of them (None: matplotlib's decades)."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter, NullLocator

    ax.set_xscale("log")
    if levels is not None and len(levels) <= 12:
        ax.set_xticks(levels, [_fmt(v) for v in levels])
        ax.xaxis.set_minor_locator(NullLocator())
    else:  # 1, 2, 5 per decade, as plain numbers
        ax.xaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
        ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: _fmt(v)))
        ax.xaxis.set_minor_formatter(NullFormatter())


def _x_positions(q: _Quantity, levels) -> tuple[np.ndarray, bool]:
    """Where the levels of ``q`` sit on an x-axis: their values, or 0..n-1 if categorical."""
    if q.numeric:
        return np.asarray(levels, dtype=float), False
    return np.arange(len(levels), dtype=float), True


def _say_no_values(ax, y: np.ndarray) -> None:
    """When no point has a value: say so in the axes (and drop the meaningless y ticks)."""
    if np.isfinite(y).any():
        return
    ax.text(0.5, 0.5, "no point has a value of this metric", transform=ax.transAxes,
            ha="center", va="center", color=_MISSING_COLOUR, fontsize=10)  # fmt: skip
    ax.set_yticks([])


def _title(ds, what: str, width: int = 80) -> str:
    """``study: what``, each line wrapped at ``width`` characters."""
    import textwrap

    lines = f"{study_name(ds)}: {what}".split("\n")
    return "\n".join("\n".join(textwrap.wrap(line, width)) for line in lines)


def _footnote(ds, y: np.ndarray) -> str:
    bad = ~np.isfinite(y)
    if not bad.any():
        return f"all {y.size} points have a value"
    return f"{int(bad.sum())} of {y.size} points without a value ({_counts_text(ds, y)})"


# --------------------------------------------------------------------------------------------
# Grids
# --------------------------------------------------------------------------------------------


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
    lo, hi = (float(z[finite].min()), float(z[finite].max())) if finite.any() else (0.0, 1.0)
    if hi == lo:
        lo, hi = lo - 0.5 * (abs(lo) or 1.0), hi + 0.5 * (abs(hi) or 1.0)
    mesh = ax.pcolormesh(np.arange(nx + 1) - 0.5, np.arange(ny + 1) - 0.5,
                         np.ma.masked_invalid(z.T), cmap="viridis", vmin=lo, vmax=hi,
                         shading="flat")  # fmt: skip
    cbar = fig.colorbar(mesh, ax=ax, pad=0.02)
    cbar.set_label(metric.label)
    empty = missing >= total
    partial = (missing > 0) & ~empty
    for i, j in zip(*np.nonzero(empty), strict=True):
        ax.add_patch(Rectangle((i - 0.5, j - 0.5), 1, 1, facecolor="0.9", edgecolor=_MISSING_COLOUR,
                               hatch="xx", lw=0, gid=MISSING_GID))  # fmt: skip
    for i, j in zip(*np.nonzero(partial), strict=True):
        ax.add_patch(Rectangle((i - 0.5, j - 0.5), 1, 1, facecolor="none", edgecolor="w",
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


def _missing_text_cells(status: np.ndarray) -> str:
    counts: dict[str, int] = {}
    for s in status:
        counts[str(s)] = counts.get(str(s), 0) + 1
    return "no value: " + ", ".join(f"{s} {n}" for s, n in sorted(counts.items()))


def _cell_status(ds, y: np.ndarray) -> np.ndarray:
    """Status per point, "metric undefined" where it ran but the metric has no value."""
    status = text_values(ds, "status").astype(object)
    undefined = (status == STATUS_OK) & ~np.isfinite(y)
    status[undefined] = "metric undefined"
    return status


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


# --------------------------------------------------------------------------------------------
# Cases
# --------------------------------------------------------------------------------------------


def _cases_figure(ds, metric: _Quantity):
    y = metric.values
    n = y.size
    labels = list(text_values(ds, "label"))
    labels = [lab or f"case {i}" for i, lab in enumerate(labels)]
    status, reason = _cell_status(ds, y), text_values(ds, "reason")
    fig, ax = plt.subplots(figsize=(8.5, max(2.6, 0.38 * n + 1.4)))
    pos = np.arange(n)
    ok = np.isfinite(y)
    ax.barh(pos[ok], y[ok], height=0.6, color="tab:blue", zorder=3)
    span = float(np.max(np.abs(y[ok]))) if ok.any() else 1.0
    for i in pos[ok]:
        ax.text(y[i] + 0.01 * span * np.sign(y[i] or 1.0), i, _fmt(y[i]), va="center",
                ha="left" if y[i] >= 0 else "right", fontsize=8)  # fmt: skip
    if (~ok).any():
        ax.plot(np.zeros((~ok).sum()), pos[~ok], ls="none", marker="x", ms=9, mew=2,
                color=_MISSING_COLOUR, zorder=5, gid=MISSING_GID)  # fmt: skip
        for i in pos[~ok]:
            why = f"{status[i]}: {reason[i]}" if reason[i] else str(status[i])
            why = why if len(why) <= 70 else why[:69] + "…"
            ax.text(0.02 * span, i, why, va="center", ha="left", fontsize=8,
                    color=_MISSING_COLOUR, style="italic")  # fmt: skip
    ax.set_yticks(pos, labels, fontsize=8)
    ax.set_ylim(n - 0.5, -0.5)  # the first case on top
    ax.axvline(0.0, color="k", lw=0.6)
    lo = min(0.0, float(y[ok].min()) if ok.any() else 0.0)
    hi = max(0.0, float(y[ok].max()) if ok.any() else 1.0)
    pad = 0.15 * (hi - lo or 1.0)
    ax.set_xlim(lo - (pad if lo < 0 else 0.0), hi + pad)
    ax.set_xlabel(metric.label)
    ax.grid(True, axis="x", alpha=0.3)
    if (~ok).any():
        ax.legend(handles=[Line2D([], [], ls="none", marker="x", ms=9, mew=2,
                                  color=_MISSING_COLOUR, label=_missing_text(ds, y))],
                  fontsize=8, loc="lower right")  # fmt: skip
    ax.set_title(_title(ds, f"{metric.name} per case\n{_footnote(ds, y)}"), fontsize=10)
    fig.tight_layout()
    return fig


# --------------------------------------------------------------------------------------------
# Samples
# --------------------------------------------------------------------------------------------


def _scatter_figure(ds, metric: _Quantity, qs, spec: dict):
    y = metric.values
    ok = np.isfinite(y)
    d = len(qs)
    ncols = min(d, 3)
    nrows = math.ceil(d / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(4.2 * ncols, 3.6 * nrows), sharey=True,
                             squeeze=False)  # fmt: skip
    dists = spec.get("parameters", {}) if isinstance(spec.get("parameters"), dict) else {}
    ms = 4.0 if y.size <= 500 else 2.0
    alpha = 0.8 if y.size <= 2000 else 0.35
    for i, (q, ax) in enumerate(zip(qs, axes.flat, strict=False)):
        dist = dists.get(q.key, {}) if isinstance(dists.get(q.key), dict) else {}
        if q.numeric:
            x = q.values
        else:  # a choice: its categories side by side, spread sideways to show how many
            cats = [str(c) for c in dist.get("values", [])]
            cats += [c for c in dict.fromkeys(q.values) if c not in cats]
            x = np.array([cats.index(v) for v in q.values], dtype=float)
            x += 0.3 * ((np.arange(x.size) * 0.6180339887) % 1.0 - 0.5)  # golden-ratio jitter
            _level_ticks(ax, len(cats), cats)
            ax.set_xlim(-0.5, len(cats) - 0.5)
        ax.plot(x[ok], y[ok], ".", ms=ms, alpha=alpha, color="tab:blue", zorder=3)
        if (~ok).any():
            _mark_missing(ax, x[~ok])
            _room_for_missing(ax, lower=False)
        if str(dist.get("distribution", "")) == "loguniform" and q.numeric and np.all(x > 0):
            _log_x(ax, None)
        ax.set_xlabel(q.label, fontsize=9)
        ax.grid(True, alpha=0.3)
        if i == 0:  # one label for the shared y-axis: one per row would overlap the next
            ax.set_ylabel(metric.label, fontsize=9)
    for ax in list(axes.flat)[d:]:
        ax.set_visible(False)
    if (~ok).any():  # the y-axis is shared: lowered once
        lo, hi = axes.flat[0].get_ylim()
        axes.flat[0].set_ylim(lo - 0.12 * (hi - lo), hi)
    for ax in list(axes.flat)[:d]:
        _say_no_values(ax, y)
    handles = [Line2D([], [], ls="none", marker=".", ms=8, color="tab:blue",
                      label="point with a value")]  # fmt: skip
    if (~ok).any():
        handles.append(_missing_handle(_missing_text(ds, y)))
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=8, frameon=False)
    method = spec.get("method", "?")
    fig.suptitle(_title(ds, f"{metric.name} against each parameter ({method} sample)\n"
                            f"{_footnote(ds, y)}", 40 * ncols), fontsize=10)  # fmt: skip
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    return fig


def _message_figure(ds, title: str, message: str):
    fig, ax = plt.subplots(figsize=(7.5, 2.4))
    ax.axis("off")
    ax.text(0.5, 0.5, message, ha="center", va="center", wrap=True, fontsize=9,
            color=_MISSING_COLOUR, transform=ax.transAxes, gid=MISSING_GID)  # fmt: skip
    ax.set_title(_title(ds, title), fontsize=10)
    fig.tight_layout()
    return fig


def _short_names(qs) -> list[str]:
    return [q.name if len(q.name) <= 28 else q.key for q in qs]


def _sobol_figure(ds, metric: _Quantity, qs):
    from rollerrig.studies.sensitivity import sobol_indices

    try:
        r = sobol_indices(ds, metric.key)
    except ParameterError as exc:
        return _message_figure(ds, f"Sobol indices of {metric.name}: not computed",
                               _wrap(str(exc)))  # fmt: skip
    d = len(r.names)
    fig, ax = plt.subplots(figsize=(max(6.0, 1.3 * d + 2.5), 4.4))
    x = np.arange(d)
    w = 0.38
    err = {"capsize": 4, "error_kw": {"lw": 1.2}}
    ax.bar(x - w / 2, r.S1, w, yerr=r.S1_conf, color="tab:blue", label="first order S1", **err)
    ax.bar(x + w / 2, r.ST, w, yerr=r.ST_conf, color="tab:orange", label="total ST", **err)
    ax.axhline(0.0, color="k", lw=0.6)
    top = float(np.nanmax(np.concatenate([r.S1 + r.S1_conf, r.ST + r.ST_conf, [1.0]])))
    bottom = float(np.nanmin(np.concatenate([r.S1 - r.S1_conf, [0.0]])))
    ax.set_ylim(min(bottom, 0.0) - 0.03, top + 0.05)
    names = _short_names(qs)
    ax.set_xticks(x, names, fontsize=8)
    if max(len(s) for s in names) > 12:
        plt.setp(ax.get_xticklabels(), rotation=20, ha="right")
    ax.set_ylabel("share of the variance [-]")
    ax.grid(True, axis="y", alpha=0.3)
    ax.legend(fontsize=8, title=f"error bars: {100 * r.conf_level:g} % bootstrap interval",
              title_fontsize=8, loc="upper right")  # fmt: skip
    for xs, values, conf in ((x - w / 2, r.S1, r.S1_conf), (x + w / 2, r.ST, r.ST_conf)):
        for xi, v, c in zip(xs, values, conf, strict=True):
            if np.isfinite(v):  # above the error bar
                top = v + (c if np.isfinite(c) else 0.0)
                ax.text(xi, max(top, 0.0) + 0.01, f"{v:.2f}", ha="center", va="bottom",
                        fontsize=8, zorder=5)  # fmt: skip
    what = (
        f"Sobol indices of {metric.name}\nN = {r.n_base} base rows, {metric.values.size} "
        "points (SALib, Saltelli 2010 estimators)"
    )
    ax.set_title(_title(ds, what), fontsize=10)
    fig.tight_layout()
    return fig


def _rank_figure(ds, metric: _Quantity, qs):
    from rollerrig.studies.sensitivity import rank_correlations

    try:
        r = rank_correlations(ds, metric.key)
    except ParameterError as exc:
        return _message_figure(ds, f"rank correlations of {metric.name}: not computed",
                               _wrap(str(exc)))  # fmt: skip
    d = len(r.names)
    fig, ax = plt.subplots(figsize=(7.5, max(2.4, 0.45 * d + 1.5)))
    pos = np.arange(d)
    rho = np.nan_to_num(r.rho)
    ax.barh(pos, rho, height=0.6, color="tab:blue", zorder=3)
    for i in range(d):
        if np.isfinite(r.rho[i]):
            text = f"ρ = {r.rho[i]:+.2f}, p = {r.pvalue[i]:.2g}"
        elif not qs[i].numeric:
            text = "categorical: no rank correlation"
        else:
            text = "undefined (constant)"
        ax.text(0.02 if rho[i] < 0 else -0.02, i, text, va="center",
                ha="left" if rho[i] < 0 else "right", fontsize=8)  # fmt: skip
    ax.set_yticks(pos, _short_names(qs), fontsize=8)
    ax.set_ylim(d - 0.5, -0.5)
    ax.set_xlim(-1.05, 1.05)
    ax.axvline(0.0, color="k", lw=0.6)
    ax.set_xlabel(f"Spearman rank correlation ρ with {metric.name} [-]")
    ax.grid(True, axis="x", alpha=0.3)
    ax.set_title(_title(ds, f"rank correlation with {metric.name}\n{r.note}"), fontsize=10)
    fig.tight_layout()
    return fig


def _wrap(text: str, width: int = 90) -> str:
    import textwrap

    return "\n".join(textwrap.wrap(text, width))


def _sample_figures(ds, metric: _Quantity) -> dict:
    keys = varied_parameters(ds)
    qs = [_quantity(ds, k) for k in keys]
    spec = json_attribute(ds, "sample", {})
    spec = spec if isinstance(spec, dict) else {}
    figs = {f"{metric.key}-scatter": _scatter_figure(ds, metric, qs, spec)}
    figs[f"{metric.key}-rank-correlation"] = _rank_figure(ds, metric, qs)
    if spec.get("method") == "sobol":
        figs[f"{metric.key}-sobol"] = _sobol_figure(ds, metric, qs)
    return figs


# --------------------------------------------------------------------------------------------


def study_figures(ds, metrics=None) -> dict:
    """The figures of a study, per metric, for its design.

    Parameters
    ----------
    ds : xarray.Dataset
        A study (:func:`rollerrig.studies.store.open_study`).
    metrics : str or sequence of str, optional
        The metrics to draw; default every metric of the study.

    Returns
    -------
    dict of str -> matplotlib.figure.Figure
        Keyed ``"<metric>-<kind>"`` (a file stem): for a grid ``-line`` (one axis),
        ``-heatmap`` and ``-lines`` (two axes), ``-heatmap`` and ``-main-effects`` (more);
        for cases ``-cases``; for a sample ``-scatter``, ``-rank-correlation`` and, for a
        Sobol design, ``-sobol`` (a figure saying why when the indices cannot be computed,
        e.g. failed points). The caller saves and closes them.

    Raises
    ------
    ParameterError
        A metric the study does not have (the message lists those it has), or a Dataset
        without the attributes of a study.

    Examples
    --------
    >>> import json, numpy as np, xarray as xr
    >>> ds = xr.Dataset(
    ...     {"speed": ("point", [5.0, 10.0, 15.0], {"units": "m/s", "long_name": "speed"}),
    ...      "status": ("point", ["ok", "solver failed", "ok"]),
    ...      "peak_coa": ("point", [0.31, np.nan, 0.35], {"units": "1"})},
    ...     attrs={"study": "demo", "design": "grid", "parameters": '["speed"]',
    ...            "metrics": '["peak_coa"]', "grid_shape": "[3]", "grid_scales": '["linear"]'})
    >>> figs = study_figures(ds)
    >>> list(figs), figs["peak_coa-line"].axes[0].get_xlabel()
    (['peak_coa-line'], 'speed [km/h]')
    >>> plt.close("all")
    """
    names = metric_names(ds) if metrics is None else (
        [metrics] if isinstance(metrics, str) else [str(m) for m in metrics])  # fmt: skip
    design = design_kind(ds)
    for m in names:
        check_metric(ds, m)
    figs: dict = {}
    for m in names:
        metric = _quantity(ds, m)
        if design == "grid":
            figs.update(_grid_figures(ds, metric))
        elif design == "cases":
            figs[f"{m}-cases"] = _cases_figure(ds, metric)
        else:
            figs.update(_sample_figures(ds, metric))
    return figs
