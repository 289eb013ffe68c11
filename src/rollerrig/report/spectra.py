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
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np

from rollerrig.output.figures import crop_when_saved
from rollerrig.report.labels import PeakLabel, label_peaks
from rollerrig.report.order_map import Resonance, order_map_figure, resonance_speeds
from rollerrig.report.spectrum_axes import (
    _COLOURS,
    LOG_SPAN,
    _hidden_note,
    _plain_log_ticks,
    frequency_limit,
    log_frequency_axis,
    source_name,
)
from rollerrig.signal.spectra import CoherenceSpectrum, ExplainedSpectrum
from rollerrig.signal.welch import power_unit

__all__ = [
    "LOG_SPAN",
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
    # The twin's ringing modes inside the spectrum's band are drawn too: the axis spans them
    # (a 0.81 Hz and a 110.8 Hz mode had been left off a figure that ended at 90 Hz).
    modes = getattr(explained, "modes", None)
    nyquist = spec.sample_rate / 2.0
    drawn = listed + [
        md.frequency
        for md in (() if modes is None else modes.ringing)
        if float(f[1]) <= md.frequency <= nyquist
    ]
    if max_frequency is None:
        max_frequency = frequency_limit(drawn, nyquist)
    low = _frequency_axis(ax, drawn, float(f[1]), max_frequency, log_frequency)
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
    crop_when_saved(fig)  # the title holds the recording's name, of any length
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
        f"coherence of {names[0]} and {names[1]}\n({count}{seg}, Δf {df:.4g} Hz)",
        fontsize=9,
    )
    hidden = _hidden_note([float(m) for m in marks if m > fmax], fmax)
    if hidden:
        ax.text(0.0, -0.14, hidden, transform=ax.transAxes, fontsize=6.5, color="0.3", va="top")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    label_peaks(ax, labels, data_top=1.0, marker_size=_MARKER)  # above γ² = 1, the most it can be
    crop_when_saved(fig)  # the title holds the recordings' names, of any length
    return fig
