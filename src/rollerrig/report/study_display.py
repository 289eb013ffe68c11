"""How a study's values appear in its figures: display units, quantities as shown, points
without a value marked.

The pieces every figure of :mod:`rollerrig.report.studies` shares: :func:`display_unit` (the
unit an engineer reads, kN·m/rad, km/h, kN), a parameter or metric as shown (values in that
unit, or categories), numbers on ticks and in cells, and the marks of points without a value
(crosses at the bottom of the axes, a shaded band, a legend entry counting them by status, the
``gid`` :data:`MISSING_GID` that finds them), titles and footnotes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.lines import Line2D
from matplotlib.patches import Rectangle

from rollerrig._validation import ParameterError
from rollerrig.studies.summary import (
    STATUS_OK,
    is_numeric,
    missing_counts,
    study_name,
    text_values,
    warned_points,
)
from rollerrig.units import apply_factor, si_factor

__all__ = ["MISSING_GID", "display_unit"]

MISSING_GID = "study-missing"
"""``gid`` of the artists that mark points without a value (crosses, hatched cells)."""

_DISPLAY = {"N.m/rad": "kN.m/rad", "N": "kN", "m/s": "km/h"}
"""SI unit -> the unit the figures show (the others are shown in SI)."""

_MISSING_COLOUR = "crimson"
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
        text = f"all {y.size} points have a value"
    else:
        text = f"{int(bad.sum())} of {y.size} points without a value ({_counts_text(ds, y)})"
    warned = len(warned_points(ds))
    if warned:  # their values stand, but the twin was used outside its domain there
        text += f"; {warned} with a domain warning (the CSV's reason)"
    return text


def _cell_status(ds, y: np.ndarray) -> np.ndarray:
    """Status per point, "metric undefined" where it ran but the metric has no value."""
    status = text_values(ds, "status").astype(object)
    undefined = (status == STATUS_OK) & ~np.isfinite(y)
    status[undefined] = "metric undefined"
    return status
