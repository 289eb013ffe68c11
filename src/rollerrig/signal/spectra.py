"""Spectra that explain themselves: power spectra, peak finding and attribution of every peak.

Kayaalp (the seed dissertation, sections 4.5.2.3-4.5.2.4, Tables 3-4) reads the spectra of the
roller-shaft torque (250 Hz) and of the laser displacement sensors (600 Hz) of the wheel-roller
rig by hand: the displacement peaks at the roller rotation frequency (0.484 Hz at 5 km/h ...
2.99 Hz at 30 km/h), the torque at the electrical frequency of the roller's induction motor
(AM, 5 pole pairs: 2.433 Hz at 5 km/h) and its harmonics, plus a line at 1.333 Hz that stays put
at every speed. This module does that reading automatically:

* :func:`power_spectrum` / :func:`amplitude_spectrum` -- Welch or periodogram estimates, with an
  amplitude calibration (a sine of amplitude ``A`` at a bin centre shows as ``A**2/2`` in
  ``"spectrum"`` scaling, as ``A`` in the amplitude spectrum).
* :func:`find_spectral_peaks` -- peaks on the log power, their frequency refined by parabolic
  interpolation of the log power over the three bins around the maximum.
* :func:`attribute_peaks` -- names the source of each peak: AM electrical frequency and its
  harmonics, roller and wheel rotation orders, PMSM electrical frequency and harmonics,
  speed-independent lines, or "unexplained".
* :func:`speed_independent_lines` -- lines that stay put across recordings at different speeds.
* :func:`coherence` / :func:`coherence_at` -- magnitude-squared coherence between two channels.
* :func:`order_map` -- peak frequency versus speed with the order lines, for a Campbell-like plot.
* :func:`explain_spectrum` -- all of the above for one channel of a
  :class:`~rollerrig.measure.recording.Recording`.

Frequencies of the candidate sources
------------------------------------
With the mean angular speeds ``ω_r`` (roller) and ``ω_w`` (wheel) [rad/s] of the recording,
``f_r = ω_r / 2π`` and ``f_w = ω_w / 2π`` are the rotation frequencies and

* AM electrical frequency ``f_AM = p_AM f_r / (1 - s_AM)`` (``p_AM = 5``; Kayaalp takes the slip
  ``s_AM = 0``: "the mechanical frequency of the AM rotor is 0.487 Hz which corresponds to
  2.433 Hz for the electrical frequency", section 4.5.2.4), harmonics ``k f_AM``;
* roller rotation orders ``k f_r`` (out-of-roundness, shaft eccentricity, section 4.5.2.3);
* wheel rotation orders ``k f_w``;
* PMSM electrical frequency ``f_PMSM = p_PMSM f_w`` (``p_PMSM = 22``, synchronous), harmonics
  ``k f_PMSM``.

Tolerance rule
--------------
A peak at ``f`` matches a speed-proportional candidate at ``f_c`` when
``|f - f_c| <= tol(f_c)`` with ``tol(f_c) = 1.5 Δf + ε f_c`` where ``Δf`` is the bin spacing of
the spectrum (1.5 bins: the half-width of the main lobe of the Hann window is 2 bins and the
interpolated peak frequency is within a small fraction of a bin) and ``ε`` is the
``relative_tolerance`` (default 0.5 %: the mean speed of a recording and the speed drift during it
are not known better; Kayaalp's Table 3 harmonics scatter by up to 0.5 % about ``k f_AM``). A
speed-independent line matches within ``1.5 Δf``. A ``tolerance_hz`` given by the caller replaces
the rule by that fixed tolerance [Hz]. When several candidates match, all are reported, the best
first: smallest ``|f - f_c|``, then lowest order (candidates with the same predicted frequency,
such as AM electrical ×1 and roller order ×5, are ranked by order, then AM electrical, roller,
PMSM electrical, wheel, speed-independent).

References
----------
Kayaalp (dissertation, the seed), sections 4.5.2.3-4.5.2.4, Tables 3-4.
P. D. Welch, "The use of fast Fourier transform for the estimation of power spectra", IEEE Trans.
Audio Electroacoust. 15 (1967) 70-73.
G. Heinzel, A. Rüdiger, R. Schilling, "Spectrum and spectral density estimation by the Discrete
Fourier transform (DFT)", Max-Planck-Institut für Gravitationsphysik, 2002 (sections 9-10:
"spectrum" vs "density" normalisation, equivalent noise bandwidth).
J. O. Smith, *Spectral Audio Signal Processing*, W3K, 2011, "Quadratic Interpolation of Spectral
Peaks" (parabolic interpolation on the log magnitude).
J. S. Bendat, A. G. Piersol, *Random Data*, 4th ed., Wiley, 2010, section 6.1.4 (coherence of a
linear system with uncorrelated output noise, eq. 6.37).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy import ndimage
from scipy import signal as sps

from rollerrig._validation import ParameterError, require_finite, require_positive

__all__ = [
    "SOURCE_KINDS",
    "CoherenceSpectrum",
    "ExplainedSpectrum",
    "OrderLine",
    "OrderMap",
    "PeakAttribution",
    "SourceMatch",
    "SpectralPeak",
    "Spectrum",
    "amplitude_spectrum",
    "attribute_peaks",
    "coherence",
    "coherence_at",
    "explain_spectrum",
    "find_spectral_peaks",
    "order_map",
    "power_spectrum",
    "speed_independent_lines",
]

SOURCE_KINDS: dict[str, str] = {
    "am_electrical": "AM electrical",
    "roller_order": "roller order",
    "pmsm_electrical": "PMSM electrical",
    "wheel_order": "wheel order",
    "speed_independent": "speed-independent line",
    "rig_mode": "rig torsional mode",
    "unexplained": "unexplained",
}
"""Source kind -> label prefix, in the order used to break ties between coincident candidates."""

_KIND_RANK = {k: i for i, k in enumerate(SOURCE_KINDS)}
_BIN_TOLERANCE = 1.5  # bins; see the module docstring
_TWO_PI = 2.0 * np.pi


# --------------------------------------------------------------------------------------------
# Spectra
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Spectrum:
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

    @property
    def resolution(self) -> float:
        """Bin spacing Δf [Hz]."""
        return float(self.frequency[1] - self.frequency[0])

    def __iter__(self) -> Iterator[np.ndarray]:
        return iter((self.frequency, self.power))


def _as_signal(name: str, x) -> np.ndarray:
    arr = require_finite(name, x)
    if arr.ndim != 1 or arr.size < 8:
        raise ParameterError(f"{name} must be a 1-D array of at least 8 samples, got {arr.shape}")
    return arr


def _choice(name: str, value: str, allowed: Sequence[str]) -> str:
    if value not in allowed:
        raise ParameterError(f"{name} must be one of {list(allowed)}, got {value!r}")
    return value


def _segment_length(n: int, nperseg: int | None) -> int:
    if nperseg is None:
        return min(n, max(256, n // 4))
    if int(nperseg) != nperseg or nperseg < 8:
        raise ParameterError(f"nperseg must be an integer >= 8 [samples], got {nperseg!r}")
    return min(int(nperseg), n)


def power_spectrum(
    x,
    sample_rate: float,
    method: str = "welch",
    nperseg: int | None = None,
    window: str = "hann",
    detrend: str | bool = "linear",
    scaling: str = "spectrum",
    noverlap: int | None = None,
) -> Spectrum:
    """One-sided power spectrum by Welch's method or the (windowed) periodogram.

    Thin validated wrapper of :func:`scipy.signal.welch` / :func:`scipy.signal.periodogram`.

    Parameters
    ----------
    x : array_like, shape (n,)
        Signal [unit], uniformly sampled, finite.
    sample_rate : float
        Sampling rate f_s [Hz].
    method : {"welch", "periodogram"}
        Welch's average of overlapping windowed segments (Welch 1967) or a single windowed
        periodogram of the whole record (finest resolution, no averaging).
    nperseg : int, optional
        Welch segment length [samples]; default ``min(n, max(256, n // 4))`` (about 7 averages
        with 50 % overlap). The bin spacing is ``f_s / nperseg``. Ignored by the periodogram.
    window : str
        Window name understood by :func:`scipy.signal.get_window`.
    detrend : {"linear", "constant", False}
        Trend removed from each segment before the transform.
    scaling : {"spectrum", "density"}
        ``"spectrum"``: power per bin [unit²], amplitude-calibrated so that a sine of amplitude
        ``A`` at a bin centre shows a peak of ``A**2/2`` (its mean square). ``"density"``: power
        spectral density [unit²/Hz], whose integral is the variance (Heinzel et al. 2002).
    noverlap : int, optional
        Welch overlap [samples]; default ``nperseg // 2``.

    Returns
    -------
    Spectrum
        Frequencies [Hz] and power; unpacks as ``f, p``.

    Examples
    --------
    >>> fs = 250.0
    >>> t = np.arange(25_000) / fs
    >>> s = power_spectrum(2.0 * np.sin(2 * np.pi * 10.0 * t), fs, nperseg=2500)
    >>> f, p = s
    >>> round(float(f[np.argmax(p)]), 3), round(float(p.max()), 3)   # A**2/2 = 2
    (10.0, 2.0)
    """
    x = _as_signal("x", x)
    fs = float(require_positive("sample_rate", sample_rate, "Hz"))
    method = _choice("method", method, ("welch", "periodogram"))
    scaling = _choice("scaling", scaling, ("spectrum", "density"))
    if detrend not in ("linear", "constant", False):
        raise ParameterError(
            f"detrend must be one of ['linear', 'constant', False], got {detrend!r}"
        )
    n = x.size
    if method == "welch":
        seg = _segment_length(n, nperseg)
        overlap = seg // 2 if noverlap is None else int(noverlap)
        if not 0 <= overlap < seg:
            raise ParameterError(f"noverlap must lie in [0, {seg}) [samples], got {noverlap!r}")
        f, p = sps.welch(
            x, fs, window=window, nperseg=seg, noverlap=overlap, detrend=detrend, scaling=scaling
        )
        n_segments = 1 + (n - seg) // (seg - overlap)
    else:
        seg = n
        f, p = sps.periodogram(x, fs, window=window, detrend=detrend, scaling=scaling)
        n_segments = 1
    w = sps.get_window(window, seg)
    enbw = fs * float(np.sum(w**2)) / float(np.sum(w)) ** 2
    return Spectrum(f, p, scaling, method, fs, seg, n_segments, str(window), enbw)


def amplitude_spectrum(x, sample_rate: float, **kwargs: Any) -> tuple[np.ndarray, np.ndarray]:
    """Peak-amplitude spectrum: a sine of amplitude ``A`` at a bin centre shows as ``A``.

    ``A_k = sqrt(2 P_k)`` with ``P_k`` the ``"spectrum"``-scaled power of
    :func:`power_spectrum` (the DC bin is not amplitude-calibrated).

    Parameters
    ----------
    x : array_like, shape (n,)
        Signal [unit].
    sample_rate : float
        Sampling rate [Hz].
    **kwargs
        Passed to :func:`power_spectrum` (``method``, ``nperseg``, ``window``, ``detrend``);
        ``scaling`` is fixed to ``"spectrum"``.

    Returns
    -------
    frequency : ndarray
        Bin frequencies [Hz].
    amplitude : ndarray
        Peak amplitude per bin [unit].

    Examples
    --------
    >>> t = np.arange(6000) / 600.0
    >>> f, a = amplitude_spectrum(0.15e-3 * np.sin(2 * np.pi * 3.0 * t), 600.0, nperseg=2000)
    >>> round(float(a.max()) * 1e3, 4)   # [mm]
    0.15
    """
    if "scaling" in kwargs:
        raise ParameterError("amplitude_spectrum fixes scaling='spectrum'; do not pass scaling")
    s = power_spectrum(x, sample_rate, scaling="spectrum", **kwargs)
    return s.frequency, np.sqrt(2.0 * s.power)


# --------------------------------------------------------------------------------------------
# Peaks
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class SpectralPeak:
    """A spectral peak.

    Attributes
    ----------
    frequency : float
        Peak frequency [Hz], refined by parabolic interpolation of the log power.
    power : float
        Interpolated peak power [unit²] or [unit²/Hz], in the scaling of the spectrum.
    prominence : float
        Prominence of the peak in the log power [dB] (:func:`scipy.signal.find_peaks`).
    snr : float
        Height of the peak above the running-median noise floor [dB].
    index : int
        Index of the maximum bin.
    resolution : float
        Bin spacing Δf of the spectrum [Hz].
    """

    frequency: float
    power: float
    prominence: float
    snr: float
    index: int
    resolution: float


def _parabolic_vertex(left, centre, right):
    """Offset [bins] and height of the parabola through three equally spaced points."""
    denom = left - 2.0 * centre + right
    safe = np.where(denom < 0.0, denom, -1.0)
    delta = np.where(denom < 0.0, 0.5 * (left - right) / safe, 0.0)
    delta = np.clip(delta, -0.5, 0.5)
    return delta, centre - 0.25 * (left - right) * delta


_LEAK_OVERSAMPLE = 16
_LEAK_BINS = 64


def _leakage_envelope(w: np.ndarray) -> np.ndarray:
    """Upper envelope of the window's power response |W(d)|² / |W(0)|² over d ± 0.5 bin.

    Sampled every 1/16 bin from 0 to 64 bins.
    """
    n = w.size * _LEAK_OVERSAMPLE
    response = np.abs(np.fft.rfft(w, n=n)[: _LEAK_BINS * _LEAK_OVERSAMPLE + 1]) ** 2
    response /= float(np.sum(w)) ** 2
    return ndimage.maximum_filter1d(response, size=_LEAK_OVERSAMPLE + 1, mode="nearest")


def _leakage(position: np.ndarray, height: np.ndarray, envelope: np.ndarray) -> np.ndarray:
    """Peaks that are leakage (window sidelobes) of a stronger kept peak.

    A peak at ``position`` [bins] with level ``height`` [dB] is leakage when a stronger peak
    lies 1 to 64 bins away and the weaker one is no more than 3 dB above the stronger one's
    sidelobe envelope at that distance.
    """
    leak = np.zeros(position.size, dtype=bool)
    kept: list[int] = []
    for j in np.argsort(height)[::-1]:
        for i in kept:
            d = abs(position[j] - position[i])
            if 1.0 <= d <= _LEAK_BINS:
                env = envelope[round(d * _LEAK_OVERSAMPLE)]
                if height[j] <= height[i] + 10.0 * np.log10(2.0 * max(env, 1e-300)):
                    leak[j] = True
                    break
        if not leak[j]:
            kept.append(int(j))
    return leak


def find_spectral_peaks(
    frequency,
    power=None,
    min_prominence: float = 6.0,
    max_peaks: int | None = None,
    min_frequency: float = 0.0,
    max_frequency: float | None = None,
    min_snr: float = 10.0,
    floor_bins: int | None = None,
    dynamic_range: float = 150.0,
) -> list[SpectralPeak]:
    """Peaks of a power spectrum, with interpolated frequency and power.

    A bin is a peak when it is a local maximum of ``L = 10 log10(P)`` with a prominence of at
    least ``min_prominence`` dB (:func:`scipy.signal.find_peaks`) and stands at least ``min_snr``
    dB above the noise floor, the running median of ``L`` over ``floor_bins`` bins. Its frequency
    and power are refined by fitting a parabola to ``L`` at the maximum bin and its two
    neighbours (quadratic interpolation of the log spectrum, Smith 2011): with ``α, β, γ`` the
    three values, the vertex lies ``δ = (α - γ) / (2(α - 2β + γ))`` bins from the maximum and
    has height ``β - (α - γ) δ / 4``. For a Hann window the frequency error of a sine is below
    0.02 bin; for a bin-centred sine ``δ = 0`` and the power is the bin value.

    The peak power is the vertex height when bare arrays are given (for a Hann window it
    overestimates a sine by up to 0.33 dB, at half-bin offset). When a :class:`Spectrum` is
    given, the window is known and the power is the bin value divided by the window's
    normalised response ``|W(δ)|² = |Σ w_n exp(-2πiδn/N)|² / (Σ w_n)²`` at the interpolated
    offset (scalloping-loss correction, Heinzel et al. 2002): a sine of amplitude ``A`` reads
    ``A**2/2`` in ``"spectrum"`` scaling wherever it falls between bins (for Hann within about
    1.5 %, the effect of the residual frequency error). With a :class:`Spectrum` the window's
    sidelobes are also rejected: a peak 1 to 64 bins from a stronger one and no more than 3 dB
    above the window's sidelobe envelope at that distance is leakage, not a line.

    Parameters
    ----------
    frequency : array_like, shape (m,), or Spectrum
        Equally spaced bin frequencies [Hz], or a :class:`Spectrum` (then ``power`` is omitted).
    power : array_like, shape (m,)
        Power or power spectral density, >= 0.
    min_prominence : float
        Least prominence of a peak in the log power [dB].
    max_peaks : int, optional
        Keep only this many peaks, the most powerful.
    min_frequency, max_frequency : float, optional
        Frequency band searched [Hz].
    min_snr : float
        Least height above the running-median noise floor [dB]. With Welch averaging (>= 6
        segments) noise rarely rises 6 dB above the floor; a raw periodogram (exponentially
        distributed bins) needs about 15 dB to keep false peaks out.
    floor_bins : int, optional
        Width of the running median [bins]; default the larger of 31 and 2 % of the bins.
    dynamic_range : float
        Ignore peaks more than this many dB below the strongest bin (double-precision
        round-off of a noise-free signal lies near -300 dB).

    Returns
    -------
    list of SpectralPeak
        Sorted by frequency.

    Examples
    --------
    >>> fs = 250.0
    >>> t = np.arange(50_000) / fs
    >>> x = np.sin(2 * np.pi * 14.6713 * t) + 0.3 * np.sin(2 * np.pi * 1.333 * t)
    >>> peaks = find_spectral_peaks(power_spectrum(x, fs, nperseg=8192), min_frequency=0.5)
    >>> [(round(p.frequency, 2), round(float(np.sqrt(2 * p.power)), 1)) for p in peaks]  # A
    [(1.33, 0.3), (14.67, 1.0)]
    """
    spectrum = frequency if isinstance(frequency, Spectrum) else None
    if spectrum is not None:
        if power is not None:
            raise ParameterError("pass either a Spectrum or frequency and power, not both")
        frequency, power = spectrum.frequency, spectrum.power
    elif power is None:
        raise ParameterError("find_spectral_peaks needs power (or a Spectrum as first argument)")
    f = require_finite("frequency", frequency)
    p = require_finite("power", power)
    if f.ndim != 1 or f.shape != p.shape or f.size < 3:
        raise ParameterError(
            f"frequency and power must be 1-D arrays of the same length >= 3, "
            f"got {f.shape} and {p.shape}"
        )
    df = float(f[1] - f[0])
    if df <= 0.0 or not np.allclose(np.diff(f), df, rtol=1e-6, atol=0.0):
        raise ParameterError("frequency must be equally spaced and increasing [Hz]")
    if np.any(p < 0.0):
        raise ParameterError("power must be >= 0")
    if max_peaks is not None and (int(max_peaks) != max_peaks or max_peaks < 1):
        raise ParameterError(f"max_peaks must be a positive integer, got {max_peaks!r}")
    tiny = np.finfo(float).tiny
    level = 10.0 * np.log10(np.maximum(p, max(float(p.max()), tiny) * 1e-30))
    width = floor_bins if floor_bins is not None else max(31, int(0.02 * f.size))
    width = min(int(width) | 1, (f.size - 1) | 1)
    floor = ndimage.median_filter(level, size=width, mode="nearest")
    idx, props = sps.find_peaks(level, prominence=float(min_prominence))
    prominence = props["prominences"]
    snr = level[idx] - floor[idx]
    keep = (snr >= min_snr) & (f[idx] >= min_frequency)
    keep &= level[idx] >= float(np.max(level)) - float(dynamic_range)
    if max_frequency is not None:
        keep &= f[idx] <= max_frequency
    idx, prominence, snr = idx[keep], prominence[keep], snr[keep]
    delta, height = _parabolic_vertex(level[idx - 1], level[idx], level[idx + 1])
    if spectrum is not None:
        w = sps.get_window(spectrum.window, spectrum.nperseg)
        # nfft = nperseg, so one bin is 1/N cycles per sample.
        phase = np.exp(-2j * np.pi * np.outer(delta, np.arange(w.size)) / w.size)
        response = np.abs(phase @ w) ** 2 / float(np.sum(w)) ** 2
        height = 10.0 * np.log10(p[idx] / response)
        leak = _leakage(idx + delta, height, _leakage_envelope(w))
        idx, delta, height, prominence, snr = (
            a[~leak] for a in (idx, delta, height, prominence, snr)
        )
    if max_peaks is not None and idx.size > max_peaks:
        top = np.sort(np.argsort(height)[::-1][: int(max_peaks)])
        idx, delta, height, prominence, snr = (
            a[top] for a in (idx, delta, height, prominence, snr)
        )
    return [
        SpectralPeak(
            frequency=float(f[i] + d * df),
            power=float(10.0 ** (h / 10.0)),
            prominence=float(pr),
            snr=float(s),
            index=int(i),
            resolution=df,
        )
        for i, d, h, pr, s in zip(idx, delta, height, prominence, snr, strict=True)
    ]


# --------------------------------------------------------------------------------------------
# Attribution
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class SourceMatch:
    """One candidate source that explains a peak.

    Attributes
    ----------
    source : str
        Source kind, a key of :data:`SOURCE_KINDS`.
    order : int
        Harmonic number k of the source (0 for speed-independent lines).
    predicted_frequency : float
        Frequency the source predicts [Hz].
    delta_f : float
        Peak frequency minus predicted frequency [Hz].
    tolerance : float
        Tolerance the match was accepted with [Hz].
    label : str
        e.g. ``"AM electrical ×2 (4.89 Hz)"``.
    """

    source: str
    order: int
    predicted_frequency: float
    delta_f: float
    tolerance: float
    label: str


@dataclass(frozen=True)
class PeakAttribution:
    """A peak with its best explanation and every other matching source.

    Attributes
    ----------
    frequency : float
        Peak frequency [Hz].
    power : float
        Peak power (scaling of the spectrum; NaN when the peak was given as a bare frequency).
    label : str
        Label of the best match, ``"unexplained"`` when none matches.
    order : int
        Harmonic number of the best match (0 when unexplained or speed-independent).
    source : str
        Source kind of the best match, a key of :data:`SOURCE_KINDS`.
    delta_f : float
        Peak minus predicted frequency of the best match [Hz] (NaN when unexplained).
    matches : tuple of SourceMatch
        Every matching source, the best first.
    """

    frequency: float
    power: float
    label: str
    order: int
    source: str
    delta_f: float
    matches: tuple[SourceMatch, ...] = field(default_factory=tuple)

    def as_row(self) -> dict[str, Any]:
        """The attribution as a flat table row (``also`` lists the other matches' labels)."""
        return {
            "frequency_hz": self.frequency,
            "power": self.power,
            "label": self.label,
            "order": self.order,
            "source": self.source,
            "delta_f_hz": self.delta_f,
            "also": "; ".join(m.label for m in self.matches[1:]),
        }


def _label(kind: str, order: int, frequency: float) -> str:
    if kind in ("speed_independent", "rig_mode"):
        return f"{SOURCE_KINDS[kind]} ({frequency:.3f} Hz)"
    return f"{SOURCE_KINDS[kind]} ×{order} ({frequency:.2f} Hz)"


def _rotation_frequency(omega: float) -> float:
    return abs(float(omega)) / _TWO_PI


def _speed_sources(
    roller_speed: float | None,
    wheel_speed: float | None,
    am_pole_pairs: int,
    pmsm_pole_pairs: int,
    max_harmonic: int,
    am_slip: float,
) -> list[tuple[str, int, float]]:
    """(kind, order, predicted frequency [Hz]) of every speed-proportional candidate."""
    out: list[tuple[str, int, float]] = []
    k = np.arange(1, max_harmonic + 1)
    if roller_speed is not None:
        f_r = _rotation_frequency(roller_speed)
        f_am = am_pole_pairs * f_r / (1.0 - am_slip)
        out += [("am_electrical", int(i), float(i * f_am)) for i in k]
        out += [("roller_order", int(i), float(i * f_r)) for i in k]
    if wheel_speed is not None:
        f_w = _rotation_frequency(wheel_speed)
        out += [("pmsm_electrical", int(i), float(i * pmsm_pole_pairs * f_w)) for i in k]
        out += [("wheel_order", int(i), float(i * f_w)) for i in k]
    return out


def _match(
    f: float,
    sources: list[tuple[str, int, float]],
    fixed: np.ndarray,
    bin_tol: float,
    relative_tolerance: float,
    tolerance_hz: float | None,
    modes=(),
) -> list[SourceMatch]:
    found: list[SourceMatch] = []
    for kind, order, fc in sources:
        tol = tolerance_hz if tolerance_hz is not None else bin_tol + relative_tolerance * fc
        if abs(f - fc) <= tol:
            found.append(SourceMatch(kind, order, fc, f - fc, tol, _label(kind, order, fc)))
    for fc in fixed:
        tol = tolerance_hz if tolerance_hz is not None else bin_tol
        if abs(f - fc) <= tol:
            kind = "speed_independent"
            found.append(SourceMatch(kind, 0, float(fc), f - fc, tol, _label(kind, 0, fc)))
    for fc in modes:
        # A natural frequency of the chain is known only as well as the model: allow 2 %.
        tol = tolerance_hz if tolerance_hz is not None else bin_tol + 0.02 * fc
        if abs(f - fc) <= tol:
            label = _label("rig_mode", 0, fc)
            found.append(SourceMatch("rig_mode", 0, float(fc), f - fc, tol, label))

    # Coincident predictions (AM ×k and roller ×5k) differ only by rounding: compare |Δf| on a
    # grid far finer than any spectral resolution, then order, then kind.
    def key(m: SourceMatch):
        return (round(abs(m.delta_f), 9), m.order, _KIND_RANK[m.source])

    return sorted(found, key=key)


def _peak_values(peaks) -> tuple[np.ndarray, np.ndarray, float | None]:
    """Frequencies, powers and the coarsest resolution of SpectralPeaks or bare frequencies."""
    items = list(peaks)
    if all(isinstance(p, SpectralPeak) for p in items):
        f = np.array([p.frequency for p in items], dtype=float)
        pw = np.array([p.power for p in items], dtype=float)
        res = max((p.resolution for p in items), default=None)
        return f, pw, res
    f = require_finite("peaks", items)
    if f.ndim != 1:
        raise ParameterError(f"peaks must be SpectralPeaks or a 1-D array of [Hz], got {f.shape}")
    return f, np.full(f.shape, np.nan), None


def _check_attribution_options(
    am_pole_pairs, pmsm_pole_pairs, max_harmonic, tolerance_hz, relative_tolerance, am_slip
) -> None:
    for name, value in (
        ("am_pole_pairs", am_pole_pairs),
        ("pmsm_pole_pairs", pmsm_pole_pairs),
        ("max_harmonic", max_harmonic),
    ):
        if int(value) != value or value < 1:
            raise ParameterError(f"{name} must be a positive integer [1], got {value!r}")
    if tolerance_hz is not None:
        require_positive("tolerance_hz", tolerance_hz, "Hz")
    if not 0.0 <= relative_tolerance < 0.5:
        raise ParameterError(
            f"relative_tolerance must lie in [0, 0.5) [1], got {relative_tolerance}"
        )
    if not -1.0 < am_slip < 1.0:
        raise ParameterError(f"am_slip must lie in (-1, 1) [1], got {am_slip}")


def attribute_peaks(
    peaks,
    roller_speed: float | None,
    wheel_speed: float | None = None,
    am_pole_pairs: int = 5,
    pmsm_pole_pairs: int = 22,
    max_harmonic: int = 12,
    tolerance_hz: float | None = None,
    speed_independent=(),
    resolution: float | None = None,
    relative_tolerance: float = 0.005,
    am_slip: float = 0.0,
    rig_modes=(),
) -> list[PeakAttribution]:
    """Name the source of each spectral peak.

    Candidates (module docstring): AM electrical frequency ``p_AM f_r / (1 - s_AM)`` and its
    harmonics, roller rotation orders ``k f_r``, PMSM electrical frequency ``p_PMSM f_w`` and its
    harmonics, wheel rotation orders ``k f_w`` (``k = 1 .. max_harmonic``), and the
    speed-independent lines given; a peak that matches none is "unexplained". Tolerance rule:
    ``1.5 Δf + relative_tolerance · f_c`` for speed-proportional candidates, ``1.5 Δf`` for
    speed-independent lines, or ``tolerance_hz`` for all when given.

    Parameters
    ----------
    peaks : sequence of SpectralPeak or array_like of float
        Peaks (:func:`find_spectral_peaks`) or bare peak frequencies [Hz].
    roller_speed : float or None
        Mean roller angular speed ω_r of the recording [rad/s]; None skips the roller and AM
        sources.
    wheel_speed : float, optional
        Mean wheel angular speed ω_w [rad/s]; None skips the wheel and PMSM sources.
    am_pole_pairs : int
        Pole pairs of the roller's induction motor (Kayaalp Table 2: 10 poles).
    pmsm_pole_pairs : int
        Pole pairs of the wheel's PMSM (Kayaalp Table 1: 44 poles).
    max_harmonic : int
        Highest harmonic number / rotation order tried for each source.
    tolerance_hz : float, optional
        Fixed matching tolerance [Hz], replacing the rule above.
    speed_independent : array_like of float
        Frequencies of speed-independent lines [Hz] (e.g. from
        :func:`speed_independent_lines`; Kayaalp's 1.333 Hz).
    resolution : float, optional
        Bin spacing Δf [Hz]; taken from the peaks when they are SpectralPeaks. Needed with bare
        frequencies unless ``tolerance_hz`` is given.
    relative_tolerance : float
        ε of the tolerance rule [1] (uncertainty of the mean speed).
    am_slip : float
        Slip of the induction motor [1] (Kayaalp: 0).
    rig_modes : array_like of float
        Natural frequencies of the rig's torsional chain [Hz] (e.g. the roller-shaft mode
        of :func:`rollerrig.rig.chain.modal_table`); matched within the bin tolerance plus 2 %.

    Returns
    -------
    list of PeakAttribution
        One row per peak, in the order of ``peaks``.

    Examples
    --------
    Kayaalp's 30 km/h torque spectrum: roller speed (30/3.6) / 0.452 = 18.44 rad/s.

    >>> rows = attribute_peaks([14.67, 11.74, 1.333], 18.437, tolerance_hz=0.05,
    ...                        speed_independent=[1.333])
    >>> for r in rows:
    ...     print(r.label)
    AM electrical ×1 (14.67 Hz)
    roller order ×4 (11.74 Hz)
    speed-independent line (1.333 Hz)
    """
    _check_attribution_options(
        am_pole_pairs, pmsm_pole_pairs, max_harmonic, tolerance_hz, relative_tolerance, am_slip
    )
    if roller_speed is not None:
        roller_speed = float(require_positive("roller_speed", abs(roller_speed), "rad/s"))
    if wheel_speed is not None:
        wheel_speed = float(require_positive("wheel_speed", abs(wheel_speed), "rad/s"))
    f, pw, res = _peak_values(peaks)
    if resolution is not None:
        res = float(require_positive("resolution", resolution, "Hz"))
    if tolerance_hz is None and res is None:
        raise ParameterError(
            "attribute_peaks needs the spectral resolution [Hz] to set the tolerance: pass "
            "SpectralPeaks, resolution= or tolerance_hz="
        )
    fixed = np.atleast_1d(require_finite("speed_independent", speed_independent, "Hz"))
    modes = np.atleast_1d(require_finite("rig_modes", rig_modes, "Hz"))
    sources = _speed_sources(
        roller_speed,
        wheel_speed,
        int(am_pole_pairs),
        int(pmsm_pole_pairs),
        int(max_harmonic),
        float(am_slip),
    )
    bin_tol = _BIN_TOLERANCE * res if res is not None else 0.0
    rows = []
    for fi, pi in zip(f, pw, strict=True):
        matches = _match(
            float(fi), sources, fixed, bin_tol, relative_tolerance, tolerance_hz, modes
        )
        if matches:
            best = matches[0]
            rows.append(
                PeakAttribution(
                    float(fi),
                    float(pi),
                    best.label,
                    best.order,
                    best.source,
                    best.delta_f,
                    tuple(matches),
                )
            )
        else:
            rows.append(
                PeakAttribution(
                    float(fi), float(pi), "unexplained", 0, "unexplained", float("nan"), ()
                )
            )
    return rows


def _entry(item) -> tuple[float, float | None, list, float | None]:
    """(roller speed, wheel speed, peaks, resolution) of an ExplainedSpectrum or a tuple."""
    if isinstance(item, ExplainedSpectrum):
        return item.roller_speed, item.wheel_speed, list(item.peaks), item.spectrum.resolution
    item = tuple(item)
    if len(item) == 2:
        roller, peaks = item
        wheel = None
    elif len(item) == 3:
        roller, wheel, peaks = item
    else:
        raise ParameterError(
            "each entry must be an ExplainedSpectrum, (roller_speed, peaks) or "
            "(roller_speed, wheel_speed, peaks)"
        )
    f, _, res = _peak_values(peaks)
    peaks = list(peaks) if res is not None else list(f)
    return float(roller), (None if wheel is None else float(wheel)), peaks, res


def speed_independent_lines(
    spectra,
    tolerance_hz: float | None = None,
    min_speed_ratio: float = 1.2,
    am_pole_pairs: int = 5,
    pmsm_pole_pairs: int = 22,
    max_harmonic: int = 12,
    relative_tolerance: float = 0.005,
    am_slip: float = 0.0,
) -> np.ndarray:
    """Lines that stay put across recordings at different speeds.

    Peaks that a speed-proportional source (AM, roller, PMSM, wheel; :func:`attribute_peaks`)
    explains in their own recording are set aside. The remaining peaks of all recordings are
    grouped by single linkage: sorted by frequency, a gap larger than ``tolerance_hz`` starts a
    new group. A group is a speed-independent line when it holds peaks of at least two
    recordings whose roller speeds differ by more than ``min_speed_ratio`` (fastest / slowest
    > 1.2: "differ by more than 20 %"); its frequency is the mean of one peak per recording
    (the one nearest the group median).

    Parameters
    ----------
    spectra : sequence
        One entry per recording: an :class:`ExplainedSpectrum`, or ``(roller_speed, peaks)`` or
        ``(roller_speed, wheel_speed, peaks)`` with speeds in [rad/s] and peaks as
        :class:`SpectralPeak` or bare frequencies [Hz].
    tolerance_hz : float, optional
        Grouping tolerance [Hz]; default 1.5 times the coarsest bin spacing of the peaks. Needed
        when the peaks are bare frequencies.
    min_speed_ratio : float
        Least ratio of the fastest to the slowest roller speed in a group [1].
    am_pole_pairs, pmsm_pole_pairs, max_harmonic, relative_tolerance, am_slip
        As in :func:`attribute_peaks` (to set explained peaks aside).

    Returns
    -------
    ndarray
        Frequencies of the speed-independent lines [Hz], increasing.

    Examples
    --------
    Kayaalp's 1.333 Hz line at 10, 20 and 30 km/h (roller radius 0.452 m):

    >>> w = [v / 3.6 / 0.452 for v in (10.0, 20.0, 30.0)]
    >>> speed_independent_lines([(w[0], [4.87, 1.333]), (w[1], [1.334, 8.97]),
    ...                          (w[2], [1.332, 14.67])], tolerance_hz=0.02)
    array([1.333])
    """
    _check_attribution_options(
        am_pole_pairs, pmsm_pole_pairs, max_harmonic, tolerance_hz, relative_tolerance, am_slip
    )
    if not min_speed_ratio >= 1.0:
        raise ParameterError(f"min_speed_ratio must be >= 1 [1], got {min_speed_ratio}")
    entries = [_entry(item) for item in spectra]
    resolutions = [e[3] for e in entries if e[3] is not None]
    if tolerance_hz is None:
        if len(resolutions) < len(entries):
            raise ParameterError(
                "speed_independent_lines needs tolerance_hz [Hz] when peaks are bare frequencies"
            )
        tol = _BIN_TOLERANCE * max(resolutions, default=0.0)
    else:
        tol = float(tolerance_hz)
    pool: list[tuple[float, int, float]] = []  # (frequency, recording, |roller speed|)
    for i, (roller, wheel, peaks, res) in enumerate(entries):
        rows = attribute_peaks(
            peaks,
            roller,
            wheel,
            am_pole_pairs,
            pmsm_pole_pairs,
            max_harmonic,
            tolerance_hz=tolerance_hz,
            resolution=res if res is not None else tol,
            relative_tolerance=relative_tolerance,
            am_slip=am_slip,
        )
        pool += [(r.frequency, i, abs(roller)) for r in rows if r.source == "unexplained"]
    pool.sort()
    groups: list[list[tuple[float, int, float]]] = []
    for item in pool:
        if groups and item[0] - groups[-1][-1][0] <= tol:
            groups[-1].append(item)
        else:
            groups.append([item])
    lines = []
    for g in groups:
        speeds = {rec: speed for _, rec, speed in g}
        if len(speeds) < 2 or max(speeds.values()) <= min_speed_ratio * min(speeds.values()):
            continue
        centre = float(np.median([fr for fr, _, _ in g]))
        one_each = {}
        for fr, rec, _ in g:
            if rec not in one_each or abs(fr - centre) < abs(one_each[rec] - centre):
                one_each[rec] = fr
        lines.append(float(np.mean(list(one_each.values()))))
    return np.array(sorted(lines))


# --------------------------------------------------------------------------------------------
# Coherence
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class CoherenceSpectrum:
    """Magnitude-squared coherence γ²(f) of two channels.

    Attributes
    ----------
    frequency : ndarray
        Bin frequencies [Hz].
    coherence : ndarray
        γ² in [0, 1].
    n_segments : int
        Averaged segments (the bias of γ² is about ``(1 - γ²)² / n_segments``).
    """

    frequency: np.ndarray
    coherence: np.ndarray
    n_segments: int

    def __iter__(self) -> Iterator[np.ndarray]:
        return iter((self.frequency, self.coherence))


def coherence(
    x,
    y,
    sample_rate: float,
    nperseg: int | None = None,
    window: str = "hann",
    detrend: str | bool = "linear",
) -> CoherenceSpectrum:
    """Magnitude-squared coherence ``γ² = |S_xy|² / (S_xx S_yy)`` by Welch averaging.

    Validated wrapper of :func:`scipy.signal.coherence` (50 % overlap). For ``y = h * x + n``
    with noise ``n`` uncorrelated with ``x``, ``γ² = |H|² S_xx / (|H|² S_xx + S_nn)`` (Bendat &
    Piersol 2010, eq. 6.37): a line present in both channels with γ² near 1 comes from one
    source.

    Parameters
    ----------
    x, y : array_like, shape (n,)
        The two channels [any unit], sampled together.
    sample_rate : float
        Sampling rate [Hz].
    nperseg : int, optional
        Segment length [samples]; default ``min(n, max(256, n // 8))``. Coherence needs many
        segments: with one segment it is identically 1.
    window : str
        Window name.
    detrend : {"linear", "constant", False}
        Trend removed from each segment.

    Returns
    -------
    CoherenceSpectrum
        Unpacks as ``f, gamma2``.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> x = rng.standard_normal(20_000)
    >>> f, g = coherence(x, 2.0 * x + 0.1 * rng.standard_normal(x.size), 250.0, nperseg=256)
    >>> bool(g.min() > 0.99)
    True
    """
    x = _as_signal("x", x)
    y = _as_signal("y", y)
    if x.shape != y.shape:
        raise ParameterError(f"x and y must have the same length, got {x.size} and {y.size}")
    fs = float(require_positive("sample_rate", sample_rate, "Hz"))
    seg = (
        min(x.size, max(256, x.size // 8)) if nperseg is None else _segment_length(x.size, nperseg)
    )
    f, c = sps.coherence(x, y, fs, window=window, nperseg=seg, noverlap=seg // 2, detrend=detrend)
    n_segments = 1 + (x.size - seg) // (seg - seg // 2)
    return CoherenceSpectrum(f, c, n_segments)


def coherence_at(coh: CoherenceSpectrum, frequencies) -> np.ndarray:
    """Coherence at given frequencies: the largest γ² within ±1 bin of each.

    Parameters
    ----------
    coh : CoherenceSpectrum
        From :func:`coherence`.
    frequencies : array_like
        Frequencies [Hz] (e.g. peak frequencies of one channel).

    Returns
    -------
    ndarray
        γ² at each frequency (NaN outside the band).

    Examples
    --------
    >>> c = CoherenceSpectrum(np.arange(5.0), np.array([0.1, 0.2, 0.9, 0.3, 0.1]), 10)
    >>> coherence_at(c, [2.2, 7.0]).tolist()
    [0.9, nan]
    """
    fq = np.atleast_1d(require_finite("frequencies", frequencies, "Hz"))
    f, c = coh.frequency, coh.coherence
    df = float(f[1] - f[0])
    out = np.full(fq.shape, np.nan)
    for i, fi in enumerate(fq):
        near = np.abs(f - fi) <= df * (1.0 + 1e-9)
        if np.any(near):
            out[i] = float(np.max(c[near]))
    return out


# --------------------------------------------------------------------------------------------
# Explained spectrum of a recording
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ExplainedSpectrum:
    """A channel's spectrum with its peaks and their sources.

    Attributes
    ----------
    channel : str
        Channel name.
    unit : str
        SI unit of the channel.
    spectrum : Spectrum
        The power spectrum.
    peaks : tuple of SpectralPeak
        Peaks found.
    rows : tuple of PeakAttribution
        One attribution per peak.
    roller_speed : float
        Mean roller angular speed used [rad/s].
    wheel_speed : float or None
        Mean wheel angular speed used [rad/s] (None: wheel and PMSM sources skipped).
    am_pole_pairs, pmsm_pole_pairs : int
        Pole pairs used.
    am_slip : float
        AM slip used [1].
    """

    channel: str
    unit: str
    spectrum: Spectrum
    peaks: tuple[SpectralPeak, ...]
    rows: tuple[PeakAttribution, ...]
    roller_speed: float
    wheel_speed: float | None
    am_pole_pairs: int = 5
    pmsm_pole_pairs: int = 22
    am_slip: float = 0.0

    @property
    def roller_frequency(self) -> float:
        """Roller rotation frequency f_r [Hz]."""
        return _rotation_frequency(self.roller_speed)

    @property
    def wheel_frequency(self) -> float | None:
        """Wheel rotation frequency f_w [Hz] (None without a wheel speed)."""
        return None if self.wheel_speed is None else _rotation_frequency(self.wheel_speed)

    @property
    def am_frequency(self) -> float:
        """AM electrical frequency ``p_AM f_r / (1 - s)`` [Hz]."""
        return self.am_pole_pairs * self.roller_frequency / (1.0 - self.am_slip)

    @property
    def pmsm_frequency(self) -> float | None:
        """PMSM electrical frequency ``p_PMSM f_w`` [Hz] (None without a wheel speed)."""
        fw = self.wheel_frequency
        return None if fw is None else self.pmsm_pole_pairs * fw

    def table(self) -> list[dict[str, Any]]:
        """Tidy rows: one dict per peak (see :meth:`PeakAttribution.as_row`)."""
        return [r.as_row() for r in self.rows]

    def format_table(self) -> str:
        """The rows as aligned text."""
        unit = f"{self.unit}²" + ("/Hz" if self.spectrum.scaling == "density" else "")
        lines = [f"{'f [Hz]':>9}  {'power [' + unit + ']':>16}  {'Δf [Hz]':>8}  source"]
        for r in self.rows:
            lines.append(f"{r.frequency:9.3f}  {r.power:16.4g}  {r.delta_f:8.3f}  {r.label}")
        return "\n".join(lines)


def _mean_speed(recording, name: str, given: float | None, required: bool) -> float | None:
    if given is not None:
        return float(require_positive(name, abs(given), "rad/s"))
    if name not in recording:
        if required:
            recording.require(name)
        return None
    return float(
        require_positive(f"mean {name} of the recording", abs(np.mean(recording[name])), "rad/s")
    )


def explain_spectrum(
    recording,
    channel: str = "torque",
    roller_speed: float | None = None,
    wheel_speed: float | None = None,
    method: str = "welch",
    nperseg: int | None = None,
    window: str = "hann",
    scaling: str = "spectrum",
    min_prominence: float = 6.0,
    min_snr: float = 10.0,
    max_peaks: int | None = 20,
    min_frequency: float = 0.1,
    max_frequency: float | None = None,
    am_pole_pairs: int = 5,
    pmsm_pole_pairs: int = 22,
    max_harmonic: int = 12,
    tolerance_hz: float | None = None,
    speed_independent=(),
    relative_tolerance: float = 0.005,
    am_slip: float = 0.0,
    rig_modes=(),
) -> ExplainedSpectrum:
    """Spectrum of one channel of a recording, its peaks and their sources.

    :func:`power_spectrum` (linear detrend), :func:`find_spectral_peaks` and
    :func:`attribute_peaks` in one call; the mean roller and wheel angular speeds come from the
    recording's ``roller_speed`` / ``wheel_speed`` channels unless given (a missing wheel speed
    skips the wheel and PMSM sources).

    Parameters
    ----------
    recording : Recording
        The recording (:class:`rollerrig.measure.recording.Recording`).
    channel : str
        Channel analysed, e.g. ``"torque"`` or ``"displacement_front_bearing"``.
    roller_speed, wheel_speed : float, optional
        Mean angular speeds [rad/s]; default the means of the recording's channels.
    method, nperseg, window, scaling
        As in :func:`power_spectrum`.
    min_prominence, min_snr, max_peaks, min_frequency, max_frequency
        As in :func:`find_spectral_peaks` (dB, dB, count, Hz, Hz).
    am_pole_pairs, pmsm_pole_pairs, max_harmonic, tolerance_hz, speed_independent, \
relative_tolerance, am_slip
        As in :func:`attribute_peaks`.

    Returns
    -------
    ExplainedSpectrum

    Examples
    --------
    >>> from rollerrig.measure.recording import Recording
    >>> fs, w_r = 250.0, 30 / 3.6 / 0.452
    >>> t = np.arange(30_000) / fs
    >>> T = 5.0 * np.sin(2 * np.pi * 5 * w_r / (2 * np.pi) * t)
    >>> rec = Recording(t, {"torque": T, "roller_speed": np.full(t.size, w_r)},
    ...                 {"torque": "N.m", "roller_speed": "rad/s"})
    >>> [r.label for r in explain_spectrum(rec).rows]
    ['AM electrical ×1 (14.67 Hz)']
    """
    recording.require(channel)
    w_r = _mean_speed(recording, "roller_speed", roller_speed, required=True)
    w_w = _mean_speed(recording, "wheel_speed", wheel_speed, required=False)
    spec = power_spectrum(
        recording[channel],
        recording.sample_rate,
        method=method,
        nperseg=nperseg,
        window=window,
        scaling=scaling,
    )
    peaks = find_spectral_peaks(
        spec,
        min_prominence=min_prominence,
        max_peaks=max_peaks,
        min_frequency=min_frequency,
        max_frequency=max_frequency,
        min_snr=min_snr,
    )
    rows = attribute_peaks(
        peaks,
        w_r,
        w_w,
        am_pole_pairs,
        pmsm_pole_pairs,
        max_harmonic,
        tolerance_hz,
        speed_independent,
        relative_tolerance=relative_tolerance,
        am_slip=am_slip,
        rig_modes=rig_modes,
    )
    return ExplainedSpectrum(
        channel,
        recording.units.get(channel, ""),
        spec,
        tuple(peaks),
        tuple(rows),
        w_r,
        w_w,
        int(am_pole_pairs),
        int(pmsm_pole_pairs),
        float(am_slip),
    )


# --------------------------------------------------------------------------------------------
# Order map
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class OrderLine:
    """A speed-proportional (or fixed) line of an order map.

    Attributes
    ----------
    source : str
        Source kind (:data:`SOURCE_KINDS`).
    order : int
        Harmonic number (0 for a speed-independent line).
    label : str
        Legend label, e.g. ``"AM electrical ×2"``.
    frequency : ndarray
        Frequency of the line [Hz] on :attr:`OrderMap.speed_grid`.
    """

    source: str
    order: int
    label: str
    frequency: np.ndarray


@dataclass(frozen=True)
class OrderMap:
    """Peak frequency versus roller speed with the order lines overlaid.

    Attributes
    ----------
    speed : ndarray
        Roller angular speed of each peak's recording [rad/s].
    frequency : ndarray
        Peak frequencies [Hz].
    power : ndarray
        Peak powers (NaN when unknown).
    source : ndarray of str
        Source kind of each peak's best attribution ("" when the entry carried none).
    recording : ndarray of int
        Index of each peak's entry.
    speed_grid : ndarray
        Roller speeds the lines are drawn on [rad/s].
    lines : tuple of OrderLine
        AM electrical harmonics, roller orders, and (when the wheel-to-roller speed ratio is
        known) wheel orders and the PMSM electrical frequency, plus the speed-independent lines.
    wheel_to_roller : float or None
        Median ω_w / ω_r of the entries (about r_roller / r_wheel = 1.30 on Kayaalp's rig).
    """

    speed: np.ndarray
    frequency: np.ndarray
    power: np.ndarray
    source: np.ndarray
    recording: np.ndarray
    speed_grid: np.ndarray
    lines: tuple[OrderLine, ...]
    wheel_to_roller: float | None


def order_map(
    entries,
    am_harmonics: Sequence[int] = (1, 2, 3),
    roller_orders: Sequence[int] = (1, 2, 3, 4),
    wheel_orders: Sequence[int] = (1,),
    pmsm_harmonics: Sequence[int] = (1,),
    speed_independent=(),
    am_pole_pairs: int = 5,
    pmsm_pole_pairs: int = 22,
    wheel_to_roller: float | None = None,
    n_grid: int = 101,
) -> OrderMap:
    """Data for a plot of peak frequency versus speed with the order lines overlaid.

    A speed-proportional source is a straight line through the origin,
    ``f = k p ω_r / 2π`` (roller side) or ``f = k p (ω_w/ω_r) ω_r / 2π`` (wheel side); a
    speed-independent line is horizontal. Peaks that sit on a line share its source.

    Parameters
    ----------
    entries : sequence
        One per recording: an :class:`ExplainedSpectrum`, or ``(roller_speed, peaks)`` or
        ``(roller_speed, wheel_speed, peaks)`` with speeds [rad/s] and peaks as
        :class:`SpectralPeak` or frequencies [Hz].
    am_harmonics, roller_orders, wheel_orders, pmsm_harmonics : sequence of int
        Harmonic numbers of the lines drawn.
    speed_independent : array_like of float
        Horizontal lines [Hz].
    am_pole_pairs, pmsm_pole_pairs : int
        Pole pairs.
    wheel_to_roller : float, optional
        ω_w / ω_r for the wheel-side lines; default the median over entries with a wheel speed
        (no wheel-side lines when none has one).
    n_grid : int
        Points of the speed grid, from 0 to 1.1 times the largest speed.

    Returns
    -------
    OrderMap

    Examples
    --------
    >>> m = order_map([(3.07, [2.45]), (18.44, [14.67, 1.333])], speed_independent=[1.333])
    >>> m.frequency.tolist(), [line.label for line in m.lines][:2]
    ([2.45, 14.67, 1.333], ['AM electrical ×1', 'AM electrical ×2'])
    """
    speed, freq, power, source, rec = [], [], [], [], []
    ratios = []
    for i, item in enumerate(entries):
        roller, wheel, peaks, _ = _entry(item)
        if wheel is not None:
            ratios.append(abs(wheel) / abs(roller))
        if isinstance(item, ExplainedSpectrum):
            kinds = [r.source for r in item.rows]
        else:
            kinds = [""] * len(peaks)
        f, pw, _ = _peak_values(peaks) if peaks else (np.array([]), np.array([]), None)
        speed += [abs(roller)] * f.size
        freq += f.tolist()
        power += pw.tolist()
        source += kinds
        rec += [i] * f.size
    speed_arr = np.array(speed, dtype=float)
    ratio = wheel_to_roller
    if ratio is None and ratios:
        ratio = float(np.median(ratios))
    top = 1.1 * float(speed_arr.max()) if speed_arr.size else 1.0
    grid = np.linspace(0.0, top, int(n_grid))
    fr = grid / _TWO_PI
    lines = [
        OrderLine("am_electrical", k, f"AM electrical ×{k}", k * am_pole_pairs * fr)
        for k in am_harmonics
    ]
    lines += [OrderLine("roller_order", k, f"roller order ×{k}", k * fr) for k in roller_orders]
    if ratio is not None:
        fw = ratio * fr
        lines += [
            OrderLine("pmsm_electrical", k, f"PMSM electrical ×{k}", k * pmsm_pole_pairs * fw)
            for k in pmsm_harmonics
        ]
        lines += [OrderLine("wheel_order", k, f"wheel order ×{k}", k * fw) for k in wheel_orders]
    for fc in np.atleast_1d(require_finite("speed_independent", speed_independent, "Hz")):
        lines.append(
            OrderLine(
                "speed_independent",
                0,
                _label("speed_independent", 0, fc),
                np.full(grid.shape, float(fc)),
            )
        )
    return OrderMap(
        speed_arr,
        np.array(freq, dtype=float),
        np.array(power, dtype=float),
        np.array(source, dtype=object),
        np.array(rec, dtype=int),
        grid,
        tuple(lines),
        ratio,
    )
