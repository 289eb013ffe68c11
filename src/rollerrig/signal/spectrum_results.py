"""The results of the spectral estimators: a power spectrum, a coherence spectrum, the auto and
cross spectra of two channels, and the unit of a power spectrum.

Made by :mod:`rollerrig.signal.streamed_welch` (Welch averaging of streamed chunks) and
:mod:`rollerrig.signal.welch` (arrays in memory, the periodogram); read by the peak finder, the
attribution and the reports.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, fields

import numpy as np

__all__ = ["CoherenceSpectrum", "CrossSpectra", "Spectrum", "power_unit"]


class _FrequencyPair:
    """Unpacks as its first two fields, ``frequency, values = spectrum`` (spectra dataclasses)."""

    def __iter__(self) -> Iterator[np.ndarray]:
        return (getattr(self, f.name) for f in fields(self)[:2])


@dataclass(frozen=True)
class Spectrum(_FrequencyPair):
    """A one-sided power spectrum.

    Unpacks as ``frequency, power = spectrum``.

    Attributes
    ----------
    frequency : ndarray
        Bin frequencies [Hz].
    power : ndarray
        Power per bin [unit²] (``scaling="spectrum"``) or power spectral density [unit²/Hz]
        (``scaling="density"``).
    scaling : str
        ``"spectrum"`` or ``"density"``.
    method : str
        ``"welch"`` or ``"periodogram"``.
    sample_rate : float
        Sampling rate [Hz].
    nperseg : int
        Samples per segment (the whole record for the periodogram).
    n_segments : int
        Number of averaged segments (1 for the periodogram).
    window : str
        Window name.
    enbw : float
        Equivalent noise bandwidth of the window [Hz] (1.5 bins for Hann).
    noverlap : int
        Overlap of consecutive segments [samples] (0 for the periodogram).
    detrend : str or bool
        Trend removed from each segment: ``"linear"``, ``"constant"`` or False.
    """

    frequency: np.ndarray
    power: np.ndarray
    scaling: str
    method: str
    sample_rate: float
    nperseg: int
    n_segments: int
    window: str
    enbw: float
    noverlap: int = 0
    detrend: str | bool = "linear"

    @property
    def resolution(self) -> float:
        """Bin spacing Δf [Hz]."""
        return float(self.frequency[1] - self.frequency[0])


@dataclass(frozen=True)
class CoherenceSpectrum(_FrequencyPair):
    """Magnitude-squared coherence γ²(f) of two channels; unpacks as ``frequency, coherence``.

    Attributes
    ----------
    frequency : ndarray
        Bin frequencies [Hz].
    coherence : ndarray
        γ² in [0, 1].
    n_segments : int
        Averaged segments (the bias of γ² is about ``(1 - γ²)² / n_segments``).
    nperseg : int
        Samples per segment (0 when unknown).
    noverlap : int
        Overlap [samples].
    window : str
        Window name.
    detrend : str or bool
        Trend removed from each segment.
    """

    frequency: np.ndarray
    coherence: np.ndarray
    n_segments: int
    nperseg: int = 0
    noverlap: int = 0
    window: str = "hann"
    detrend: str | bool = "linear"


@dataclass(frozen=True)
class CrossSpectra:
    """Auto and cross spectra of two channels from one Welch pass.

    Attributes
    ----------
    x, y : Spectrum
        Power spectra of the two channels.
    cross : ndarray of complex
        Cross spectrum ``conj(X)·Y`` averaged over segments, in the scaling of ``x`` and ``y``
        [unit_x·unit_y] or [unit_x·unit_y/Hz].
    """

    x: Spectrum
    y: Spectrum
    cross: np.ndarray

    @property
    def coherence(self) -> CoherenceSpectrum:
        """Magnitude-squared coherence ``|S_xy|² / (S_xx S_yy)`` (0 where a channel is empty)."""
        den = self.x.power * self.y.power
        gamma = np.divide(np.abs(self.cross) ** 2, den, out=np.zeros_like(den), where=den > 0.0)
        s = self.x
        return CoherenceSpectrum(
            s.frequency,
            np.clip(gamma, 0.0, 1.0),
            s.n_segments,
            s.nperseg,
            s.noverlap,
            s.window,
            s.detrend,
        )


def power_unit(unit: str | None, scaling: str = "spectrum") -> str:
    """Unit of a power spectrum of a signal in ``unit``: squared as a whole, per Hz for a density.

    Examples
    --------
    >>> power_unit("N.m"), power_unit("m", "density"), power_unit(None)
    ('(N.m)²', 'm²/Hz', '1²')
    """
    u = unit or "1"
    # (N.m)², not N.m², which reads as newton square metre.
    squared = f"({u})²" if any(c in u for c in "./*· ") else f"{u}²"
    return f"{squared}/Hz" if scaling == "density" else squared
