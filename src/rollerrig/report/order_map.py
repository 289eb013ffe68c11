"""The order map: spectral peaks versus speed with the order lines, a Campbell diagram when the
twin's coupled modes are given (the modes with frequency and damping ratio, and the speeds where
an order line crosses one: :func:`resonance_speeds`).
"""

from __future__ import annotations

import textwrap
from collections.abc import Sequence
from dataclasses import dataclass

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np

from rollerrig.report.labels import spread
from rollerrig.report.spectrum_axes import (
    _COLOURS,
    _hidden_note,
    _plain_log_ticks,
    log_frequency_axis,
    source_name,
)
from rollerrig.signal.attribution import SOURCE_KINDS
from rollerrig.signal.spectra import OrderMap

__all__ = ["Resonance", "order_map_figure", "resonance_speeds"]


def _inferred_lines(omap: OrderMap) -> list:
    """Order lines for the attributed peaks that no line of ``omap`` passes through.

    A peak attributed to, e.g., the wheel's second order when only the first is drawn: its
    order k is the peak frequency over the order-1 frequency of its source at its speed
    (known from any drawn line of that source), accepted within 3 %.
    """
    from rollerrig.signal.ordermap import OrderLine

    unit = {}  # source -> frequency of order 1 on the speed grid [Hz]
    for line in omap.lines:
        if line.order > 0:
            unit.setdefault(line.source, line.frequency / line.order)
    drawn = {(line.source, line.order) for line in omap.lines}
    extra = []
    for speed, freq, kind in zip(omap.speed, omap.frequency, omap.source, strict=True):
        if kind not in unit:
            continue
        base = float(np.interp(speed, omap.speed_grid, unit[kind]))
        k = round(float(freq) / base) if base > 0 else 0
        if k < 1 or (kind, k) in drawn or abs(freq - k * base) > 0.03 * freq:
            continue
        drawn.add((kind, k))
        extra.append(OrderLine(kind, k, f"{SOURCE_KINDS.get(kind, kind)} ×{k}", k * unit[kind]))
    return extra


@dataclass(frozen=True)
class Resonance:
    """A speed at which an order line of an order map crosses a coupled mode of the twin.

    Attributes
    ----------
    line : str
        The order line's label, e.g. ``"AM electrical ×1"``.
    source : str
        Its source kind (:data:`rollerrig.signal.attribution.SOURCE_KINDS`).
    order : int
        Its harmonic number.
    mode_frequency : float
        The mode's damped frequency [Hz] (median over the operating points given).
    damping_ratio : tuple of float
        The mode's damping ratio ζ, lowest and highest over the operating points [-].
    speed : float
        Roller angular speed at the crossing [rad/s]: ``mode_frequency / slope`` with
        ``slope = k p / 2π`` [Hz per rad/s] of the line (AM: p = 5 pole pairs on the roller).
    """

    line: str
    source: str
    order: int
    mode_frequency: float
    damping_ratio: tuple[float, float]
    speed: float


@dataclass(frozen=True)
class _ModeLine:
    """A ringing mode matched over operating points: frequency and ζ ranges [Hz], [-]."""

    frequency: float
    frequencies: tuple[float, float]
    damping_ratio: tuple[float, float]

    @property
    def label(self) -> str:
        lo, hi = self.frequencies
        f = f"{self.frequency:.2f} Hz" if hi - lo <= 0.005 * hi else f"{lo:.2f}-{hi:.2f} Hz"
        za, zb = self.damping_ratio
        zeta = f"{za:.2g}" if f"{za:.2g}" == f"{zb:.2g}" else f"{za:.2g}-{zb:.2g}"
        return f"mode {f}, ζ {zeta}"


def _mode_lines(modes) -> list[_ModeLine]:
    """The ringing modes of one or several :class:`CoupledModes` (one per operating point),
    matched by frequency (within 5 %) across the points."""
    sets = [modes] if hasattr(modes, "ringing") else [m for m in modes if m is not None]
    groups: list[list] = []
    for cm in sets:
        for md in cm.ringing:
            for g in groups:
                if abs(md.frequency - g[0].frequency) <= 0.05 * g[0].frequency:
                    g.append(md)
                    break
            else:
                groups.append([md])
    out = []
    for g in groups:
        f = [md.frequency for md in g]
        z = [md.damping_ratio for md in g]
        out.append(_ModeLine(float(np.median(f)), (min(f), max(f)), (min(z), max(z))))
    return sorted(out, key=lambda m: m.frequency)


_LOWEST_CROSSING = 0.05
"""Crossings below this fraction of the map's largest speed are not listed [-]: every order line
starts at zero, so a low mode meets the fast lines near standstill (0.81 Hz and PMSM ×6 at
0.3 km/h), where the rig does not dwell; listing them crowded out the ones that matter."""


def resonance_speeds(omap: OrderMap, modes) -> tuple[Resonance, ...]:
    """Speeds where the order lines of ``omap`` cross the twin's ringing modes (Campbell).

    A speed-proportional line ``f = s ω_r`` (``s = k p / 2π`` for an AM harmonic, ``k / 2π``
    for a roller order, ``k p ω_w / (2π ω_r)`` for the wheel side) meets a mode at
    ``f_mode`` at ``ω_r = f_mode / s``; crossings within the map's speed grid (above
    :data:`_LOWEST_CROSSING` of it) are returned, by mode frequency, then speed. A rotating
    excitation at that speed drives the mode at resonance (the Campbell diagram's reading:
    Ewins, *Modal Testing*, 2000, section 6.11; Kayaalp, section 4.5.2.4).

    Parameters
    ----------
    omap : OrderMap
        From :func:`rollerrig.signal.spectra.order_map` (its lines, and the attributed orders
        :func:`order_map_figure` draws besides them).
    modes : CoupledModes or sequence of CoupledModes
        The twin's modes (:func:`rollerrig.rig.linear.coupled_modes`), e.g. one per recording
        (``ExplainedSpectrum.modes``); the ringing ones are used, matched across points.

    Returns
    -------
    tuple of Resonance

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> from rollerrig.signal.ordermap import order_map
    >>> omap = order_map([(18.44, [14.67])], roller_orders=(), am_harmonics=(1,))
    >>> mode = NS(frequency=13.78, damping_ratio=0.0039)
    >>> [(r.line, round(r.speed, 2)) for r in resonance_speeds(omap, NS(ringing=(mode,)))]
    [('AM electrical ×1', 17.32)]
    """
    grid = omap.speed_grid
    end = float(grid[-1])
    out = []
    for line in [*omap.lines, *_inferred_lines(omap)]:
        slope = float(line.frequency[-1]) / end if end > 0 else 0.0
        if line.order <= 0 or slope <= 0:
            continue
        for md in _mode_lines(modes):
            speed = md.frequency / slope
            if _LOWEST_CROSSING * end <= speed <= end:
                out.append(
                    Resonance(
                        line.label, line.source, line.order, md.frequency, md.damping_ratio, speed
                    )
                )
    return tuple(sorted(out, key=lambda r: (r.mode_frequency, r.speed)))


def _resonance_text(found: Sequence[Resonance], scale: float, unit: str) -> str:
    """The resonance speeds in words, grouped by mode, for the figure's small print."""
    parts = []
    for f in dict.fromkeys(r.mode_frequency for r in found):
        mine = [f"{r.line} {r.speed * scale:.1f}" for r in found if r.mode_frequency == f]
        parts.append(f"{f:.2f} Hz: " + ", ".join(mine))
    text = f"resonance speeds [{unit}] (order line crosses a mode, open circles): "
    return textwrap.fill(text + "; ".join(parts), 120)


def order_map_figure(
    omap: OrderMap,
    roller_radius: float | None = None,
    max_frequency: float | None = None,
    log_frequency: bool | None = None,
    modes=None,
    title: str | None = None,
):
    """Peak frequency versus speed with the order lines overlaid; a Campbell diagram when the
    twin's modes are given.

    Besides the lines of ``omap``, a line is drawn for every attributed order that has none
    (e.g. the wheel's second order, the PMSM's sixth). Each line is named outside the axes,
    on the right where it leaves the speed range (above the axes where it leaves through the
    top), so the names cover no point. With ``modes``, each ringing mode of the coupled twin
    is a horizontal brown line named with its frequency and damping ratio ζ, and every speed
    where an order line crosses a mode (:func:`resonance_speeds`) is circled and listed under
    the axes: there a rotating excitation drives the mode at resonance.

    Parameters
    ----------
    omap : OrderMap
        From :func:`rollerrig.signal.spectra.order_map`.
    roller_radius : float, optional
        Roller rolling radius [m]; when given the speed axis is the surface speed in km/h
        (Kayaalp: 0.452 m), else the roller angular speed in rad/s.
    max_frequency : float, optional
        Upper end of the frequency axis [Hz]; default 1.1 times the highest peak (every peak
        shown, as :func:`frequency_limit`). Peaks above a smaller given limit are named under
        the axes.
    log_frequency : bool, optional
        A logarithmic frequency axis (from just below the lowest peak); default
        :func:`log_frequency_axis` of the peaks (the low orders of a slow rotation stay apart
        next to the motor lines).
    modes : CoupledModes or sequence of CoupledModes, optional
        The coupled twin's modes (:func:`rollerrig.rig.linear.coupled_modes`), e.g. those of
        each recording's operating point (``[e.modes for e in spectra_set.spectra]``): the
        ringing ones are drawn (frequency and ζ ranges over the points in the label). Modes
        outside the frequency range shown are named in the small print.
    title : str, optional
        Figure title; default says what the map shows (and the recordings' count).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from rollerrig.rig.linear import coupled_modes
    >>> from rollerrig.rig.parameters import default_rig
    >>> from rollerrig.signal.ordermap import order_map
    >>> omap = order_map([(3.07, [2.45]), (18.44, [14.67, 1.333])])
    >>> fig = order_map_figure(omap, 0.452, modes=coupled_modes(default_rig(), 8.33, 4.3e3))
    >>> "Campbell" in fig.axes[0].get_title()
    True
    """
    scale = 3.6 * roller_radius if roller_radius is not None else 1.0
    unit = "km/h" if roller_radius is not None else "rad/s"
    fig, ax = plt.subplots(figsize=(8.5, 5.6))
    styles = {
        "am_electrical": "-",
        "roller_order": "--",
        "pmsm_electrical": "-",
        "wheel_order": ":",
    }
    peaks = omap.frequency[np.isfinite(omap.frequency) & (omap.frequency > 0)]
    top = max_frequency or (1.1 * float(peaks.max()) if peaks.size else 10.0)
    if log_frequency is None:
        log_frequency = log_frequency_axis(peaks.tolist())
    bottom = float(peaks.min()) / 1.5 if log_frequency and peaks.size else 0.0
    if log_frequency:
        ax.set_yscale("log")
        _plain_log_ticks(ax.yaxis)
    x_end = float(omap.speed_grid[-1]) * scale
    ax.set_xlim(0.0, x_end)
    ax.set_ylim(bottom if log_frequency else 0.0, top)
    lines = [*omap.lines, *_inferred_lines(omap)]
    for line in lines:
        ax.plot(
            omap.speed_grid * scale,
            line.frequency,
            styles.get(line.source, "-."),
            color=_COLOURS.get(line.source, "k"),
            lw=0.9,
            alpha=0.7,
            gid="order-line",
        )
    from rollerrig.signal.ordermap import OrderLine

    mode_lines, outside, found = [], [], ()
    if modes is not None:
        low = bottom if log_frequency else 0.0
        for md in _mode_lines(modes):
            if not low < md.frequency <= top:
                outside.append(md)
                continue
            mode_lines.append(
                OrderLine("rig_mode", 0, md.label, np.full(omap.speed_grid.shape, md.frequency))
            )
            ax.axhline(md.frequency, color=_COLOURS["rig_mode"], lw=1.6, alpha=0.8, gid="mode")
        drawn = {round(m.frequency[0], 9) for m in mode_lines}
        found = tuple(
            r for r in resonance_speeds(omap, modes) if round(r.mode_frequency, 9) in drawn
        )
        if found:
            ax.plot(
                [r.speed * scale for r in found],
                [r.mode_frequency for r in found],
                "o",
                ms=8,
                mfc="none",
                mec="k",
                mew=1.0,
                zorder=5,
                gid="resonance",
            )
        # Legend entries of what a Campbell diagram adds (drawn nowhere: proxies).
        ax.plot([], [], color=_COLOURS["rig_mode"], lw=1.6, label="twin mode (ζ: damping ratio)")
        if found:
            ax.plot([], [], "o", ms=8, mfc="none", mec="k", label="order line crosses a mode")
    for kind in dict.fromkeys(omap.source.tolist()):
        sel = omap.source == kind
        ax.plot(
            omap.speed[sel] * scale,
            omap.frequency[sel],
            "o",
            color=_COLOURS.get(kind, "k"),
            ms=5,
            zorder=4,
            label=source_name(kind),
        )
    ax.set_xlabel("speed [km/h]" if roller_radius is not None else "roller speed [rad/s]")
    ax.set_ylabel("frequency [Hz]" if modes is not None else "peak frequency [Hz]")
    notes = [_hidden_note([float(f) for f in omap.frequency if f > top], top)]
    if outside:
        notes.append(
            "twin modes outside the range shown: "
            + ", ".join(m.label.removeprefix("mode ") for m in outside)
        )
    if found:
        notes.append(_resonance_text(found, scale, unit))
    small_print = "\n".join(n for n in notes if n)
    handles, _ = ax.get_legend_handles_labels()
    if handles or small_print:  # below the axes: it hides no point and no line
        ax.legend(
            fontsize=7,
            loc="upper center",
            bbox_to_anchor=(0.5, -0.11),
            ncol=max(1, min(len(handles), 4)),
            title=small_print or None,  # what a given limit leaves out; the resonance speeds
            title_fontsize=6.5,
            alignment="left",
        )
    ax.grid(True, which="both" if log_frequency else "major", alpha=0.3)
    names = _line_names(ax, [*lines, *mode_lines], omap.speed_grid * scale)
    n_rec = len(set(omap.recording.tolist()))
    what = (
        "Campbell diagram: peaks, order lines and the twin's coupled modes versus speed"
        if modes is not None
        else "order map: spectral peaks versus speed"
    )
    default = f"{what} ({n_rec} recording{'s' if n_rec != 1 else ''})"
    ax.set_title(textwrap.fill(title or default, 90), fontsize=10, pad=6 + (14 if names else 0))
    fig.tight_layout()
    _place_line_names(ax, names)
    return fig


def _line_names(ax, lines, speeds: np.ndarray) -> list:
    """Name texts of the order lines, outside the axes: (text, side, where [data]) each.

    A line inside the frequency range at the right end is named on the right, at its
    frequency there; one that leaves through the top is named above the axes, at the speed
    where it leaves. Positions are spread apart by :func:`_place_line_names`.
    """
    lo, hi = ax.get_ylim()
    names = []
    for line in lines:
        f = np.asarray(line.frequency, dtype=float)
        end = float(f[-1])
        if lo < end <= hi:  # on the right, tied to the line's end by a short leader
            side, where, coords, xy, xytext, align = (
                "right", end, ("axes fraction", "data"), (1.0, end), (1.02, end), ("left", "center")
            )  # fmt: skip
        elif end > hi and f[0] <= hi:  # above the axes, where the line leaves through the top
            rising = bool(np.all(np.diff(f) >= 0))
            where = float(np.interp(hi, f, speeds)) if rising else float(speeds[-1])
            side, coords, xy, xytext, align = (
                "top", ("data", "axes fraction"), (where, 1.0), (where, 1.01), ("center", "bottom")
            )  # fmt: skip
        else:
            continue
        colour = _COLOURS.get(line.source, "k")
        leader = {"arrowstyle": "-", "color": colour, "lw": 0.5, "shrinkA": 1, "shrinkB": 0}
        text = ax.annotate(
            line.label,
            xy,
            xycoords=coords,
            xytext=xytext,
            textcoords=coords,
            fontsize=6,
            color=colour,
            ha=align[0],
            va=align[1],
            annotation_clip=False,
            arrowprops=leader if side == "right" else None,
        )
        names.append((text, side, where))
    return names


def _place_line_names(ax, names) -> None:
    """Spread the line names apart (on the right: vertically; on top: sideways)."""
    renderer = ax.figure.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    to_axes = ax.transAxes.inverted()
    for side in ("right", "top"):
        mine = [(t, where) for t, s, where in names if s == side]
        if not mine:
            continue
        boxes = [t.get_window_extent(renderer) for t, _ in mine]
        if side == "right":
            want = [ax.transData.transform((0.0, w))[1] for _, w in mine]
            ys = spread(want, [b.height for b in boxes], frame.y0, frame.y1, 1.0)
            for (t, _), y in zip(mine, ys, strict=True):
                t.set_position((1.02, float(to_axes.transform((frame.x1, y))[1])))
                t.set_anncoords("axes fraction")
        else:
            want = [ax.transData.transform((w, 1.0))[0] for _, w in mine]
            xs = spread(want, [b.width for b in boxes], frame.x0, frame.x1, 4.0)
            for (t, _), x in zip(mine, xs, strict=True):
                t.set_position((float(to_axes.transform((x, frame.y1))[0]), 1.01))
                t.set_anncoords("axes fraction")
