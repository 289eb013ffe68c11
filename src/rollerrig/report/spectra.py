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

The spectra of one set (several recordings of one command or report, shown side by side) share
one axis convention: :func:`shared_log_frequency` decides linear or logarithmic once over every
spectrum's listed peaks, so 5 and 30 km/h are not drawn on different scales. The order map is
a Campbell diagram when the twin's coupled modes are given (:func:`order_map_figure`): the
modes as horizontal lines with frequency and damping ratio, and the speeds where an order line
crosses a mode (:func:`resonance_speeds`).
"""

from __future__ import annotations

import textwrap
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

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
    "Resonance",
    "coherence_figure",
    "frequency_limit",
    "log_frequency_axis",
    "order_map_figure",
    "resonance_speeds",
    "shared_log_frequency",
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


def shared_log_frequency(spectra: Sequence[ExplainedSpectrum]) -> bool:
    """One frequency-axis convention for a set of spectra shown side by side [bool].

    :func:`log_frequency_axis` of the listed peaks of every spectrum together: when any
    spectrum of the set needs a log axis to keep its lines apart, all are drawn on one, so a
    reader comparing 5 km/h with 30 km/h compares like with like. Pass the answer as
    ``log_frequency`` to :func:`spectrum_figure` and :func:`coherence_figure` of the set.

    Parameters
    ----------
    spectra : sequence of ExplainedSpectrum
        The spectra of one command or report (e.g. ``SpectraSet.spectra``).

    Returns
    -------
    bool
        True: logarithmic frequency axes for the whole set.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> slow = NS(rows=[NS(frequency=f) for f in (0.49, 2.44, 83.6)])
    >>> fast = NS(rows=[NS(frequency=f) for f in (2.93, 14.67, 83.8)])
    >>> log_frequency_axis([r.frequency for r in fast.rows]), shared_log_frequency([slow, fast])
    (False, True)
    """
    return log_frequency_axis([r.frequency for e in spectra for r in e.rows])


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
        Figure title; default names the recording (``explained.source``, when known), the
        channel and the mean roller speed.
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
    source = getattr(explained, "source", "")
    where = f"{Path(source).name}, " if source else ""  # the recording, when known
    ax.set_title(
        title
        or (
            f"{where}{explained.channel}: {spec.method} spectrum, roller at rest "
            "(orders unattributed)"
            if speed is None
            else f"{where}{explained.channel}: {spec.method} spectrum, roller {speed:.2f} rad/s "
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
        The mode's damping ratio ζ, lowest and highest over the operating points [1].
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
    """A ringing mode matched over operating points: frequency and ζ ranges [Hz], [1]."""

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


def resonance_speeds(omap: OrderMap, modes) -> tuple[Resonance, ...]:
    """Speeds where the order lines of ``omap`` cross the twin's ringing modes (Campbell).

    A speed-proportional line ``f = s ω_r`` (``s = k p / 2π`` for an AM harmonic, ``k / 2π``
    for a roller order, ``k p ω_w / (2π ω_r)`` for the wheel side) meets a mode at
    ``f_mode`` at ``ω_r = f_mode / s``; crossings within the map's speed grid are returned,
    by speed. A rotating excitation at that speed drives the mode at resonance (the Campbell
    diagram's reading: Ewins, *Modal Testing*, 2000, section 6.11; Kayaalp, section 4.5.2.4).

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
            if 0.0 < speed <= end:
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
