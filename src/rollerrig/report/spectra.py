"""Figures of the spectral analysis: labelled spectra, coherence, order map.

Each function takes the data objects of :mod:`rollerrig.signal.spectra` and returns a matplotlib
figure (save it with :func:`rollerrig.output.save_figure`). Speeds are converted to km/h only
here, at the edge, when a roller radius is given.

One policy for the frequency axis of every figure here: by default it shows every listed peak
(:func:`frequency_limit`: up to 1.1 times the highest, capped at the Nyquist frequency), on a
log scale when the peaks span a factor of :data:`LOG_SPAN` or more (:func:`log_frequency_axis`).
Peak labels stand in a row above the data (:func:`rollerrig.report.labels.label_peaks`), legends
and line names outside the axes: nothing written covers a peak, a marker or the curve. Source
kinds are named in words (:func:`source_name`).
"""

from __future__ import annotations

import textwrap
from collections.abc import Sequence

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

from rollerrig.report.labels import PeakLabel, label_peaks, spread
from rollerrig.signal.attribution import SOURCE_KINDS
from rollerrig.signal.spectra import CoherenceSpectrum, ExplainedSpectrum, OrderMap
from rollerrig.signal.welch import power_unit

__all__ = [
    "coherence_figure",
    "frequency_limit",
    "log_frequency_axis",
    "order_map_figure",
    "source_name",
    "spectrum_figure",
]

_MARKER = 6.0  # size of the peak markers [pt]

_COLOURS = {
    "am_electrical": "tab:red",
    "roller_order": "tab:blue",
    "pmsm_electrical": "tab:purple",
    "wheel_order": "tab:green",
    "speed_independent": "tab:orange",
    "rig_mode": "tab:brown",
    "unexplained": "tab:gray",
    "": "k",
}


def _power_unit(explained: ExplainedSpectrum) -> str:
    return power_unit(explained.unit, explained.spectrum.scaling)


def _settings_line(explained: ExplainedSpectrum) -> str:
    """The estimation settings in one short line (stated on every spectrum figure)."""
    s = explained.spectrum
    text = (
        f"{s.method}, {s.window} window, {s.nperseg}-sample segments (Δf {s.resolution:.4g} Hz), "
        f"{s.n_segments} segment{'s' if s.n_segments != 1 else ''}"
    )
    settings = getattr(explained, "settings", None)
    if settings is not None:
        text += (
            f"; peaks >= {settings.min_prominence:g} dB prominence, >= {settings.min_snr:g} dB "
            f"above the floor, from {settings.min_frequency:.3g} Hz"
        )
    op = getattr(explained, "operating_point", None)
    if op is not None:
        text += f"; N = {op.normal_load / 1e3:.3g} kN ({op.load_source})"
    return text


def frequency_limit(peaks: Sequence[float], nyquist: float) -> float:
    """Upper end of a frequency axis that shows every listed peak [Hz].

    1.1 times the highest peak, at least a tenth of the Nyquist frequency (a spectrum whose
    peaks all sit low still shows some floor), at most the Nyquist frequency; the Nyquist
    frequency when there is no peak. The one policy of the spectrum, coherence and order-map
    figures (:func:`spectrum_figure`, :func:`coherence_figure`, :func:`order_map_figure`).

    Parameters
    ----------
    peaks : sequence of float
        Frequencies of the peaks listed with the figure [Hz].
    nyquist : float
        Nyquist frequency [Hz].

    Returns
    -------
    float
        [Hz]

    Examples
    --------
    >>> frequency_limit([2.93, 14.67, 83.81], 300.0)  # doctest: +ELLIPSIS
    92.19...
    >>> frequency_limit([167.48], 150.0), frequency_limit([], 300.0)
    (150.0, 300.0)
    """
    finite = [float(f) for f in peaks if np.isfinite(f)]
    if not finite:
        return float(nyquist)
    return float(min(nyquist, max(1.1 * max(finite), 0.1 * nyquist)))


LOG_SPAN = 50.0
"""Ratio of the highest to the lowest listed peak from which a frequency axis is logarithmic
by default [1]: on a linear axis the low orders of a slow rotation (0.5-1.3 Hz at 5 km/h) would
sit within a marker's width of each other next to a motor line at 80-170 Hz."""


def log_frequency_axis(peaks: Sequence[float]) -> bool:
    """Whether a frequency axis showing ``peaks`` [Hz] is logarithmic by default.

    Yes when the highest peak is :data:`LOG_SPAN` times the lowest or more.

    Examples
    --------
    >>> log_frequency_axis([0.49, 2.44, 83.6]), log_frequency_axis([2.93, 14.67, 83.8])
    (True, False)
    """
    positive = [float(f) for f in peaks if np.isfinite(f) and f > 0]
    return bool(positive) and max(positive) >= LOG_SPAN * min(positive)


def _frequency_axis(ax, peaks: Sequence[float], low: float, high: float, log: bool | None):
    """Set the frequency axis: linear from 0, or logarithmic from below the lowest peak."""
    positive = [float(f) for f in peaks if np.isfinite(f) and 0 < f <= high]
    if log is None:
        log = log_frequency_axis(positive)
    if log and positive:
        ax.set_xscale("log")
        ax.set_xlim(max(low, min(positive) / 1.6), high)
        _plain_log_ticks(ax.xaxis)
    else:
        ax.set_xlim(0.0, high)
    return ax.get_xlim()[0]


def _plain_log_ticks(axis) -> None:
    """Ticks of a log frequency axis as plain numbers at 1-2-5 steps (0.5, 1, 2, 5, 10 Hz)."""
    axis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
    axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(NullFormatter())


def source_name(kind: str) -> str:
    """A source kind in words, for legends: ``"am_electrical"`` -> ``"AM electrical"``.

    Examples
    --------
    >>> source_name("roller_order"), source_name("speed_independent"), source_name("")
    ('roller order', 'speed-independent line', 'peak')
    """
    return SOURCE_KINDS.get(kind, kind.replace("_", " ")) or "peak"


def _hidden_note(hidden: Sequence[float], limit: float) -> str:
    """What an explicit frequency limit leaves out, for the figure's small print."""
    if not hidden:
        return ""
    listed = ", ".join(f"{f:.2f}" for f in sorted(hidden))
    n = len(hidden)
    return f"{n} listed peak{'s' if n != 1 else ''} above the {limit:.4g} Hz shown: {listed} Hz"


def spectrum_figure(
    explained: ExplainedSpectrum,
    max_frequency: float | None = None,
    max_labels: int = 12,
    title: str | None = None,
    log_frequency: bool | None = None,
):
    """Power spectrum on a log axis with every attributed peak marked and labelled.

    The labels stand in one row above the spectrum (:func:`rollerrig.report.labels.label_peaks`):
    none covers a peak marker or the curve. The coupled twin's ringing modes are drawn as
    dotted lines, labelled in the same row.

    Parameters
    ----------
    explained : ExplainedSpectrum
        From :func:`rollerrig.signal.workflow.explain_recording`.
    max_frequency : float, optional
        Upper end of the frequency axis [Hz]; default :func:`frequency_limit` of the listed
        peaks (every listed peak shown). Peaks above a smaller given limit are named in the
        figure's small print.
    max_labels : int
        Label at most this many peaks, the most powerful; the others keep their marker.
    title : str, optional
        Figure title; default names the channel and the mean roller speed.
    log_frequency : bool, optional
        A logarithmic frequency axis (from just below the lowest listed peak); default
        :func:`log_frequency_axis` of the listed peaks.

    Returns
    -------
    matplotlib.figure.Figure
    """
    spec = explained.spectrum
    f, p = spec.frequency, spec.power
    fig, ax = plt.subplots(figsize=(10.0, 5.2))
    ax.semilogy(f[1:], p[1:], color="0.3", lw=0.8, zorder=2)
    rows = list(explained.rows)
    listed = [r.frequency for r in rows]
    if max_frequency is None:
        max_frequency = frequency_limit(listed, spec.sample_rate / 2.0)
    low = _frequency_axis(ax, listed, float(f[1]), max_frequency, log_frequency)
    shown = [r for r in rows if low <= r.frequency <= max_frequency]
    for kind in dict.fromkeys(r.source for r in shown):  # one legend entry per kind shown
        mine = [r for r in shown if r.source == kind]
        ax.plot(
            [r.frequency for r in mine],
            [r.power for r in mine],
            "v",
            ls="none",
            color=_COLOURS.get(kind, "k"),
            ms=_MARKER,
            zorder=6,  # above the labels' boxes and leaders
            label=source_name(kind),
        )
    visible = p[(f > 0) & (f >= low) & (f <= max_frequency)]
    heights = [r.power for r in shown] + ([float(np.max(visible))] if visible.size else [])
    top = max(heights, default=float(np.max(p)))
    floor = float(np.percentile(visible, 5)) if visible.size else top * 1e-6
    ax.set_ylim(bottom=floor / 3.0, top=top * 10.0)
    labelled = sorted(shown, key=lambda r: r.power, reverse=True)[: int(max_labels)]
    labels = [
        PeakLabel(
            r.frequency,
            r.power,
            f"{r.frequency:.3f} Hz\n{r.label.split(' (')[0]}",
            _COLOURS.get(r.source, "k"),
        )
        for r in labelled
    ]
    modes = getattr(explained, "modes", None)
    for md in () if modes is None else modes.ringing:
        if low <= md.frequency <= max_frequency:  # a dotted line from the label to the axis
            labels.append(
                PeakLabel(
                    md.frequency, None, f"mode {md.frequency:.2f} Hz", _COLOURS["rig_mode"], ":"
                )
            )
    if not rows:
        message = getattr(explained, "empty_message", "no peak above the thresholds")
        ax.text(0.5, 0.5, message, transform=ax.transAxes, ha="center", va="center", fontsize=8)
    hidden = _hidden_note([r.frequency for r in rows if r.frequency > max_frequency], max_frequency)
    small_print = "; ".join(x for x in (_settings_line(explained), hidden) if x)
    ax.text(
        0.0,
        -0.14,
        textwrap.fill(small_print, 130),
        transform=ax.transAxes,
        fontsize=6.5,
        color="0.3",
        va="top",
    )
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel(f"power [{_power_unit(explained)}]")
    speed = explained.roller_speed
    ax.set_title(
        title
        or (
            f"{explained.channel}: {spec.method} spectrum, roller at rest (orders unattributed)"
            if speed is None
            else f"{explained.channel}: {spec.method} spectrum, roller {speed:.2f} rad/s "
            f"(f_r = {explained.roller_frequency:.3f} Hz, f_AM = {explained.am_frequency:.3f} Hz)"
        ),
        fontsize=9,
    )
    if shown:
        # Outside the axes, on the right: it hides no peak and no label.
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    label_peaks(ax, labels, data_top=top, marker_size=_MARKER)
    return fig


def coherence_figure(
    coh: CoherenceSpectrum,
    mark_frequencies: Sequence[float] = (),
    mark_labels: Sequence[str] | None = None,
    names: tuple[str, str] = ("x", "y"),
    max_frequency: float | None = None,
    log_frequency: bool | None = None,
):
    """Magnitude-squared coherence with optional markers at given frequencies.

    The marks' labels stand in one row above γ² = 1 (:func:`rollerrig.report.labels.label_peaks`):
    none covers a marker or the curve.

    Parameters
    ----------
    coh : CoherenceSpectrum
        From :func:`rollerrig.signal.spectra.coherence`.
    mark_frequencies : sequence of float
        Frequencies to mark [Hz] (e.g. the peaks of one channel).
    mark_labels : sequence of str, optional
        One label per marked frequency.
    names : tuple of str
        Names of the two channels for the title.
    max_frequency : float, optional
        Upper end of the frequency axis [Hz]; default :func:`frequency_limit` of the marked
        frequencies (every mark shown). Marks above a smaller given limit are named in the
        figure's small print.
    log_frequency : bool, optional
        A logarithmic frequency axis; default :func:`log_frequency_axis` of the marks.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from rollerrig.signal.spectra import coherence_at

    fig, ax = plt.subplots(figsize=(10.0, 4.8))
    # One segment: γ² = 1 at every frequency, whatever the signals: withheld, as the console
    # and the tables withhold it (ExplainedSpectrum.coherence_at_peaks).
    withheld = coh.n_segments < 2
    if not withheld:
        ax.plot(coh.frequency, coh.coherence, color="tab:blue", lw=0.9, zorder=2)
    marks = np.asarray(mark_frequencies, dtype=float)
    fmax = max_frequency or frequency_limit(marks.tolist(), float(coh.frequency[-1]))
    low = _frequency_axis(ax, marks.tolist(), float(coh.frequency[1]), fmax, log_frequency)
    labels = []
    if withheld:
        ax.text(
            0.5, 0.5,
            "γ² not estimated: one segment (with one segment γ² = 1 at every frequency, "
            "whatever the signals;\nit needs at least two averaged segments: a longer "
            "recording or shorter segments)",
            transform=ax.transAxes, ha="center", va="center", fontsize=9, color="0.25",
        )  # fmt: skip
    elif marks.size:
        values = coherence_at(coh, marks)
        texts = list(mark_labels) if mark_labels is not None else [""] * marks.size
        # The most coherent marks are labelled first (kept if the row is too long).
        order = np.argsort(-np.nan_to_num(values, nan=-1.0), kind="stable")
        for k in order:
            fm, g, lab = marks[k], values[k], texts[k].split(" (")[0]
            if not low <= fm <= fmax:
                continue
            height = g if np.isfinite(g) else 0.0
            ax.plot(fm, height, "v", color="tab:red", ms=_MARKER, zorder=6)
            text = f"{lab}\nγ² = {g:.2f}" if lab else f"{fm:.3f} Hz\nγ² = {g:.2f}"
            labels.append(PeakLabel(float(fm), float(height), text, "tab:red"))
    ax.set_ylim(0.0, 1.05)
    ax.set_yticks([0.0, 0.25, 0.5, 0.75, 1.0])
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("coherence γ² [-]")
    df = float(coh.frequency[1] - coh.frequency[0])
    seg = f", {coh.nperseg}-sample segments" if coh.nperseg else ""
    count = "1 segment: γ² not estimated" if withheld else f"{coh.n_segments} segments"
    ax.set_title(
        f"coherence of {names[0]} and {names[1]} ({count}{seg}, Δf {df:.4g} Hz)",
        fontsize=9,
    )
    hidden = _hidden_note([float(m) for m in marks if m > fmax], fmax)
    if hidden:
        ax.text(0.0, -0.14, hidden, transform=ax.transAxes, fontsize=6.5, color="0.3", va="top")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    label_peaks(ax, labels, data_top=1.0, marker_size=_MARKER)  # above γ² = 1, the most it can be
    return fig


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


def order_map_figure(
    omap: OrderMap,
    roller_radius: float | None = None,
    max_frequency: float | None = None,
    log_frequency: bool | None = None,
):
    """Peak frequency versus speed with the order lines overlaid (a Campbell-like map).

    Besides the lines of ``omap``, a line is drawn for every attributed order that has none
    (e.g. the wheel's second order, the PMSM's sixth). Each line is named outside the axes,
    on the right where it leaves the speed range (above the axes where it leaves through the
    top), so the names cover no point.

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

    Returns
    -------
    matplotlib.figure.Figure
    """
    scale = 3.6 * roller_radius if roller_radius is not None else 1.0
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
    ax.set_ylabel("peak frequency [Hz]")
    if omap.frequency.size:  # below the axes: it hides no point and no line
        kinds = len(set(omap.source.tolist()))
        hidden = _hidden_note([float(f) for f in omap.frequency if f > top], top)
        ax.legend(
            fontsize=7,
            loc="upper center",
            bbox_to_anchor=(0.5, -0.11),
            ncol=kinds,
            title=hidden or None,  # what a given frequency limit leaves out
            title_fontsize=6.5,
        )
    ax.grid(True, which="both" if log_frequency else "major", alpha=0.3)
    names = _line_names(ax, lines, omap.speed_grid * scale)
    ax.set_title("order map: spectral peaks versus speed", pad=6 + (14 if names else 0))
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
