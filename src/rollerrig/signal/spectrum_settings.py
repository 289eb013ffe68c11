"""How a spectrum is estimated and read, and how the workflow chooses it from the signal.

:class:`SpectrumSettings` holds the Welch settings (segment length, overlap, window, detrend,
scaling) and the peak and attribution thresholds; every output of the spectrum workflow
(:mod:`rollerrig.signal.workflow`) states them. :func:`choose_settings` chooses the segment length
from the wanted resolution, set by the closest spacing of the first-order rotation lines
(:func:`line_spacing`), against the record length: at least 8 averages where the record allows.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from rollerrig._validation import ParameterError, require_positive

__all__ = [
    "BINS_NEEDED",
    "BINS_PER_SPACING",
    "FEW_SEGMENTS_SNR",
    "MIN_AVERAGES",
    "SpectrumSettings",
    "choose_settings",
    "line_spacing",
    "segment_count",
]

MIN_AVERAGES = 8  # Welch segments wanted (noise floor within ~±1.5 dB; coherence bias ≤ 1/8)
BINS_PER_SPACING = 6  # wanted: the closest first-order lines 6 bins apart (Hann lobe: 4 bins)
BINS_NEEDED = 3  # needed: the closest lines 3 bins apart (still separated by a dip)
FEW_SEGMENTS_SNR = 15.0  # [dB] peak threshold with 1-2 segments (periodogram-like statistics)


@dataclass(frozen=True)
class SpectrumSettings:
    """How a spectrum is estimated and read; stated in every output.

    Attributes
    ----------
    nperseg : int
        Welch segment length [samples]; the resolution is ``f_s / nperseg``.
    noverlap : int
        Overlap of consecutive segments [samples].
    window : str
        Window (:func:`scipy.signal.get_window`).
    detrend : str or bool
        Trend removed from each segment.
    scaling : str
        ``"spectrum"`` [unit²] or ``"density"`` [unit²/Hz].
    min_frequency : float
        Lowest peak frequency searched [Hz].
    max_frequency : float or None
        Highest peak frequency searched [Hz] (None: Nyquist).
    min_prominence : float
        Least peak prominence [dB].
    min_snr : float
        Least height above the running-median noise floor [dB].
    max_peaks : int or None
        Most peaks kept (the most powerful).
    max_harmonic : int
        Highest harmonic / rotation order tried.
    relative_tolerance : float
        ε of the attribution tolerance rule [-].
    damping_threshold : float
        ζ below which a twin mode may label a peak [-].
    reason : str
        How the segment length was chosen.
    """

    nperseg: int
    noverlap: int
    window: str = "hann"
    detrend: str | bool = "linear"
    scaling: str = "spectrum"
    min_frequency: float = 0.1
    max_frequency: float | None = None
    min_prominence: float = 6.0
    min_snr: float = 10.0
    max_peaks: int | None = 20
    max_harmonic: int = 12
    relative_tolerance: float = 0.005
    damping_threshold: float = 0.3
    reason: str = "given"

    def resolution(self, sample_rate: float) -> float:
        """Bin spacing ``f_s / nperseg`` [Hz]."""
        return float(sample_rate) / self.nperseg

    def segments(self, n_samples: int) -> int:
        """Welch segments in a record of ``n_samples`` [-]."""
        return segment_count(n_samples, self.nperseg, self.noverlap)

    def as_dict(self, sample_rate: float | None = None, n_samples: int | None = None) -> dict:
        """JSON-ready settings with units in the keys (resolution and segments when known)."""
        out: dict[str, Any] = {
            "method": "welch",
            "window": self.window,
            "detrend": self.detrend,
            "scaling": self.scaling,
            "nperseg [samples]": self.nperseg,
            "noverlap [samples]": self.noverlap,
        }
        if sample_rate is not None:
            out["sample_rate [Hz]"] = float(sample_rate)
            out["resolution [Hz]"] = self.resolution(sample_rate)
            out["segment_duration [s]"] = self.nperseg / float(sample_rate)
        if n_samples is not None:
            out["samples"] = int(n_samples)
            out["segments"] = self.segments(n_samples)
        out.update(
            {
                "min_frequency [Hz]": self.min_frequency,
                "max_frequency [Hz]": self.max_frequency,
                "min_prominence [dB]": self.min_prominence,
                "min_snr [dB]": self.min_snr,
                "max_peaks": self.max_peaks,
                "max_harmonic": self.max_harmonic,
                "relative_tolerance [-]": self.relative_tolerance,
                "mode_damping_threshold [-]": self.damping_threshold,
                "chosen_by": self.reason,
            }
        )
        return out

    def band(self) -> str:
        """The band searched for peaks, e.g. ``"0.879–Nyquist"`` or ``"0.5–40 Hz"``."""
        top = f"{self.max_frequency:.4g} Hz" if self.max_frequency is not None else "Nyquist"
        return f"{self.min_frequency:.3g}–{top}"

    def describe(self, sample_rate: float, n_samples: int) -> str:
        """One line: ``"Welch, hann window, 683-sample segments (Δf 0.366 Hz), ..."``."""
        overlap = 100.0 * self.noverlap / self.nperseg
        k = self.segments(n_samples)
        band = self.band()
        return (
            f"Welch, {self.window} window, {self.nperseg}-sample segments "
            f"(Δf {self.resolution(sample_rate):.4g} Hz), {overlap:.0f} % overlap, "
            f"{k} segment{'s' if k != 1 else ''}, {self.detrend or 'no'} detrend; peaks "
            f">= {self.min_prominence:g} dB prominence and >= {self.min_snr:g} dB above the "
            f"noise floor in {band}; twin modes with zeta < {self.damping_threshold:g} as sources"
        )


def segment_count(n_samples: int, nperseg: int, noverlap: int) -> int:
    """Welch segments ``(n − noverlap) // (nperseg − noverlap)`` in ``n_samples`` (0 if short)."""
    if not (0 <= noverlap < nperseg):
        raise ParameterError(
            f"noverlap must lie in [0, nperseg) = [0, {nperseg}) [samples], got {noverlap!r}"
        )
    if n_samples < nperseg:
        return 0
    return (int(n_samples) - noverlap) // (nperseg - noverlap)


def line_spacing(roller_frequency: float, wheel_frequency: float | None = None) -> float:
    """Closest spacing of the first-order lines [Hz]: ``f_r``, ``f_w`` and ``|f_w − f_r|``.

    Roller and wheel orders ``k f_r`` and ``j f_w`` lie ``|f_w − f_r|`` apart at order one
    (0.3 f_r on Kayaalp's rig, r_r/r_w = 1.30). A difference below 5 % of ``f_r`` (radii alike)
    cannot be resolved usefully and is ignored.

    Examples
    --------
    >>> round(line_spacing(2.934, 3.811), 3)   # 30 km/h on the seed's rig
    0.877
    """
    spacing = [require_positive("roller_frequency", roller_frequency, "Hz", single=True)]
    if wheel_frequency is not None:
        spacing.append(require_positive("wheel_frequency", wheel_frequency, "Hz", single=True))
        gap = abs(float(wheel_frequency) - float(roller_frequency))
        if gap >= 0.05 * float(roller_frequency):
            spacing.append(gap)
    return min(spacing)


def _largest_nperseg(n: int, averages: int) -> int:
    """Largest segment length giving at least ``averages`` segments at 50 % overlap."""
    seg = max(16, (2 * n) // (averages + 1))
    while seg > 16 and segment_count(n, seg, seg // 2) < averages:
        seg -= 1
    return seg


def choose_settings(
    n_samples: int,
    sample_rate: float,
    spacing: float | None,
    *,
    min_averages: int = MIN_AVERAGES,
    **overrides: Any,
) -> SpectrumSettings:
    """Welch settings chosen from the signal: the wanted resolution versus the record length.

    With ``s`` the closest spacing of the lines to tell apart (:func:`line_spacing`: the roller
    and wheel rotation frequencies and their difference), the wanted resolution is
    ``Δf = s / 6`` (neighbouring first-order lines 6 bins apart, beyond the 4-bin main lobe of
    the Hann window) and the needed one ``s / 3`` (still separated by a dip). Segments overlap
    by 50 %:

    * the wanted resolution when the record gives at least ``min_averages`` segments at it
      (longer records give more averages at the same resolution);
    * else exactly ``min_averages`` segments at the finest resolution that allows, when that
      meets the needed resolution (averages keep noise peaks out and make a coherence
      meaningful: its value for unrelated channels is about 1/segments);
    * else the whole record as one segment: the finest resolution it allows (a windowed
      periodogram; no coherence can be estimated from it).

    With one or two segments (periodogram statistics) a peak must stand 15 dB above the noise
    floor instead of 10 dB. Peaks are searched from 2.5 bins up (below lie the DC lobe and the
    trend residue).

    Parameters
    ----------
    n_samples : int
        Samples in the record [-].
    sample_rate : float
        Sampling rate [Hz].
    spacing : float or None
        Closest spacing of the lines to resolve [Hz] (:func:`line_spacing`); None when there
        are no lines to resolve (a roller at rest): ``min_averages`` segments at the finest
        resolution the record allows.
    min_averages : int
        Segments wanted [-]; fewer are stated in ``reason``.
    **overrides
        Any other :class:`SpectrumSettings` field (e.g. ``min_snr``).

    Returns
    -------
    SpectrumSettings
        With ``reason`` stating the choice.

    Examples
    --------
    One hour at 19.2 kHz, roller at 5 km/h on the seed's rig (f_r = 0.489 Hz, f_w = 0.635 Hz):

    >>> s = choose_settings(3600 * 19200, 19200.0, line_spacing(0.489, 0.635))
    >>> s.nperseg, round(s.resolution(19200.0), 4), s.segments(3600 * 19200)
    (789042, 0.0243, 174)

    20 s at 600 Hz at 30 km/h (spacing 0.877 Hz): 8 averages at Δf = 0.225 Hz.

    >>> s = choose_settings(12_000, 600.0, 0.877)
    >>> s.nperseg, s.segments(12_000)
    (2666, 8)
    """
    n = int(n_samples)
    fs = require_positive("sample_rate", sample_rate, "Hz", single=True)
    if n < 16:
        raise ParameterError(f"a spectrum needs at least 16 samples, got {n}")
    if spacing is None:
        seg = max(16, _largest_nperseg(n, min_averages))
        return _settings(
            n,
            fs,
            seg,
            f"no rotation lines to resolve (roller at rest): {min_averages} averages at the "
            "finest resolution the record allows",
            overrides,
        )
    gap = require_positive("spacing", spacing, "Hz", single=True)
    want = int(np.ceil(fs * BINS_PER_SPACING / gap))
    need = int(np.ceil(fs * BINS_NEEDED / gap))
    by_averages = _largest_nperseg(n, min_averages)
    if want <= by_averages:
        seg = want
        reason = (
            f"resolution spacing/{BINS_PER_SPACING} (closest line spacing {gap:.4g} Hz) with "
            f">= {min_averages} averages"
        )
    elif need <= by_averages:
        seg = by_averages
        reason = (
            f"{min_averages} averages at the finest resolution the record allows, between "
            f"spacing/{BINS_PER_SPACING} and spacing/{BINS_NEEDED} (closest line spacing "
            f"{gap:.4g} Hz)"
        )
    else:
        seg = n
        reason = (
            f"short record: {min_averages} averages would not resolve lines {gap:.4g} Hz apart "
            f"(spacing/{BINS_NEEDED} needs {need}-sample segments); the whole record as one "
            "segment, the finest resolution it allows"
        )
    return _settings(n, fs, max(16, seg), reason, overrides)


def _settings(n: int, fs: float, seg: int, reason: str, overrides) -> SpectrumSettings:
    """Settings with ``seg``-sample segments, 50 % overlap and the peak search's lower end."""
    values: dict[str, Any] = {
        "nperseg": seg,
        "noverlap": seg // 2,
        "min_frequency": 2.5 * fs / seg,
        "reason": reason,
    }
    if segment_count(n, seg, seg // 2) < 3:
        values["min_snr"] = FEW_SEGMENTS_SNR
    values.update(overrides)
    return SpectrumSettings(**values)
