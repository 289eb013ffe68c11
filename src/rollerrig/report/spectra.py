"""Figures of the spectral analysis: labelled spectra, coherence, order map.

Each function takes the data objects of :mod:`rollerrig.signal.spectra` and returns a matplotlib
figure (save it with :func:`rollerrig.output.save_figure`). Speeds are converted to km/h only
here, at the edge, when a roller radius is given.
"""

from __future__ import annotations

import textwrap
from collections.abc import Sequence

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np

from rollerrig.report.labels import separate_labels
from rollerrig.signal.spectra import CoherenceSpectrum, ExplainedSpectrum, OrderMap
from rollerrig.signal.welch import power_unit

__all__ = ["coherence_figure", "order_map_figure", "spectrum_figure"]

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


def spectrum_figure(
    explained: ExplainedSpectrum,
    max_frequency: float | None = None,
    max_labels: int = 12,
    title: str | None = None,
):
    """Power spectrum on a log axis with every attributed peak marked and labelled.

    Parameters
    ----------
    explained : ExplainedSpectrum
        From :func:`rollerrig.signal.workflow.explain_recording`.
    max_frequency : float, optional
        Upper end of the frequency axis [Hz]; default just above the highest peak (at least
        a tenth of the Nyquist frequency), or the Nyquist frequency without peaks.
    max_labels : int
        Label at most this many peaks, the most powerful; the others keep their marker.
    title : str, optional
        Figure title; default names the channel and the mean roller speed.

    Returns
    -------
    matplotlib.figure.Figure
    """
    spec = explained.spectrum
    f, p = spec.frequency, spec.power
    fig, ax = plt.subplots(figsize=(9.0, 4.8))
    ax.semilogy(f[1:], p[1:], color="0.3", lw=0.8)
    rows = list(explained.rows)
    if max_frequency is None:
        nyquist = spec.sample_rate / 2.0
        fmax = max((r.frequency for r in rows), default=nyquist)
        max_frequency = min(nyquist, max(1.15 * fmax, 0.1 * nyquist)) if rows else nyquist
    ax.set_xlim(0.0, max_frequency)
    labelled = sorted(rows, key=lambda r: r.power, reverse=True)[: int(max_labels)]
    labels = []  # most powerful first: they keep the top row
    seen: set[str] = set()
    for r in sorted(rows, key=lambda r: r.frequency):
        colour = _COLOURS.get(r.source, "k")
        legend = r.source if r.source not in seen else None
        seen.add(r.source)
        ax.plot(r.frequency, r.power, "v", color=colour, ms=6, label=legend)
    for rank, r in enumerate(x for x in labelled if x.frequency <= max_frequency):
        colour = _COLOURS.get(r.source, "k")
        # Labels hang from the top, each with a leader line to its peak; moved apart below.
        text = f"{r.frequency:.3f} Hz\n{r.label.split(' (')[0]}"
        labels.append(_peak_label(ax, text, (r.frequency, r.power), colour, rank))
    shown = [r.power for r in rows if r.frequency <= max_frequency]
    top = max(shown, default=float(np.max(p)))
    visible = p[(f > 0) & (f <= max_frequency)]
    floor = float(np.percentile(visible, 5)) if visible.size else top * 1e-6
    ax.set_ylim(bottom=floor / 3.0, top=top * 10.0 ** (0.45 * np.log10(top / floor) + 1.0))
    modes = getattr(explained, "modes", None)
    for md in () if modes is None else modes.ringing:
        if md.frequency <= max_frequency:
            ax.axvline(md.frequency, color=_COLOURS["rig_mode"], ls=":", lw=0.8, alpha=0.7)
            ax.annotate(
                f"mode {md.frequency:.2f} Hz",
                (md.frequency, 0.02),
                xycoords=("data", "axes fraction"),
                rotation=90,
                fontsize=6,
                color=_COLOURS["rig_mode"],
                ha="right",
                va="bottom",
            )
    if not rows:
        message = getattr(explained, "empty_message", "no peak above the thresholds")
        ax.text(0.5, 0.5, message, transform=ax.transAxes, ha="center", va="center", fontsize=8)
    ax.text(
        0.01,
        -0.16,
        textwrap.fill(_settings_line(explained), 120),
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
            f"{explained.channel}: {spec.method} spectrum, roller {speed:.2f} rad/s "
            f"(f_r = {explained.roller_frequency:.3f} Hz, f_AM = {explained.am_frequency:.3f} Hz)"
        ),
        fontsize=9,
    )
    if rows:
        # Bottom right: the peak labels hang from the top, the noise floor is low and flat.
        ax.legend(fontsize=7, loc="lower right", framealpha=0.9)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    separate_labels(ax, labels)
    return fig


def _peak_label(ax, text: str, peak: tuple[float, float], colour: str, rank: int, top=0.97):
    """A peak label hung from the top of the axes with a leader line to ``peak`` (data)."""
    return ax.annotate(
        text,
        peak,
        xytext=(peak[0], top),
        textcoords=("data", "axes fraction"),
        ha="center",
        va="top",
        fontsize=7,
        color=colour,
        # Later (lower) labels above earlier leader lines, on a light box that hides them.
        zorder=5 + 0.01 * rank,
        bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.75},
        arrowprops={"arrowstyle": "-", "color": colour, "lw": 0.4, "alpha": 0.6},
    )


def coherence_figure(
    coh: CoherenceSpectrum,
    mark_frequencies: Sequence[float] = (),
    mark_labels: Sequence[str] | None = None,
    names: tuple[str, str] = ("x", "y"),
    max_frequency: float | None = None,
):
    """Magnitude-squared coherence with optional markers at given frequencies.

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
        Upper end of the frequency axis [Hz].

    Returns
    -------
    matplotlib.figure.Figure
    """
    from rollerrig.signal.spectra import coherence_at

    fig, ax = plt.subplots(figsize=(9.0, 4.6))
    ax.plot(coh.frequency, coh.coherence, color="tab:blue", lw=0.9)
    marks = np.asarray(mark_frequencies, dtype=float)
    fmax = max_frequency or float(coh.frequency[-1])
    labels = []
    if marks.size:
        values = coherence_at(coh, marks)
        texts = list(mark_labels) if mark_labels is not None else [""] * marks.size
        # The most coherent marks keep the top row of labels.
        order = np.argsort(-np.nan_to_num(values, nan=-1.0), kind="stable")
        for rank, k in enumerate(order):
            fm, g, lab = marks[k], values[k], texts[k].split(" (")[0]
            if fm > fmax:
                continue
            ax.plot(fm, g, "v", color="tab:red", ms=5)
            peak = (fm, g if np.isfinite(g) else 0.0)
            labels.append(_peak_label(ax, f"{lab}\nγ² = {g:.2f}", peak, "tab:red", rank))
    ax.set_ylim(0.0, 1.6 if marks.size else 1.05)
    ax.set_yticks([0.0, 0.25, 0.5, 0.75, 1.0])
    ax.set_xlim(0.0, fmax)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("coherence γ² [-]")
    df = float(coh.frequency[1] - coh.frequency[0])
    seg = f", {coh.nperseg}-sample segments" if coh.nperseg else ""
    ax.set_title(
        f"coherence of {names[0]} and {names[1]} ({coh.n_segments} segments{seg}, Δf {df:.4g} Hz)",
        fontsize=9,
    )
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    separate_labels(ax, labels)
    return fig


def order_map_figure(
    omap: OrderMap,
    roller_radius: float | None = None,
    max_frequency: float | None = None,
):
    """Peak frequency versus speed with the order lines overlaid (a Campbell-like map).

    Parameters
    ----------
    omap : OrderMap
        From :func:`rollerrig.signal.spectra.order_map`.
    roller_radius : float, optional
        Roller rolling radius [m]; when given the speed axis is the surface speed in km/h
        (Kayaalp: 0.452 m), else the roller angular speed in rad/s.
    max_frequency : float, optional
        Upper end of the frequency axis [Hz]; default 1.1 times the highest peak.

    Returns
    -------
    matplotlib.figure.Figure
    """
    scale = 3.6 * roller_radius if roller_radius is not None else 1.0
    fig, ax = plt.subplots(figsize=(7.5, 5.0))
    styles = {
        "am_electrical": "-",
        "roller_order": "--",
        "pmsm_electrical": "-",
        "wheel_order": ":",
    }
    for line in omap.lines:
        ax.plot(
            omap.speed_grid * scale,
            line.frequency,
            styles.get(line.source, "-."),
            color=_COLOURS.get(line.source, "k"),
            lw=0.9,
            alpha=0.7,
        )
        ax.annotate(
            line.label,
            (omap.speed_grid[-1] * scale, line.frequency[-1]),
            fontsize=6,
            color=_COLOURS.get(line.source, "k"),
            ha="right",
            va="bottom",
        )
    for kind in dict.fromkeys(omap.source.tolist()):
        sel = omap.source == kind
        ax.plot(
            omap.speed[sel] * scale,
            omap.frequency[sel],
            "o",
            color=_COLOURS.get(kind, "k"),
            ms=5,
            label=kind or "peak",
        )
    top = max_frequency or (1.1 * float(omap.frequency.max()) if omap.frequency.size else 10.0)
    ax.set_ylim(0.0, top)
    ax.set_xlim(0.0, float(omap.speed_grid[-1]) * scale)
    ax.set_xlabel("speed [km/h]" if roller_radius is not None else "roller speed [rad/s]")
    ax.set_ylabel("peak frequency [Hz]")
    ax.set_title("order map: spectral peaks versus speed")
    if omap.frequency.size:
        ax.legend(fontsize=7, loc="upper left")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    return fig
