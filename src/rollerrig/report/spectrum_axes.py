"""The frequency axis and the words of the spectral figures (:mod:`rollerrig.report.spectra`,
:mod:`rollerrig.report.order_map`): how far it runs, when it is logarithmic, the colours and
names of the source kinds.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

from rollerrig.signal.attribution import SOURCE_KINDS

__all__ = ["LOG_SPAN", "frequency_limit", "log_frequency_axis", "source_name"]

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
by default [-]: on a linear axis the low orders of a slow rotation (0.5-1.3 Hz at 5 km/h) would
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
