"""One spectrum workflow for every output: CLI ``spectrum``, ``analyze``, the demo and the report.

:func:`explain_recording` takes one channel of a recording (in memory, or a chunked source that
streams from disk) and the rig, and returns an :class:`ExplainedSpectrum` that carries
everything it decided:

1. the operating point: mean roller and wheel speeds (speed channels, else the mean speed from
   the first and last encoder counts), the mean normal load (``normal_load`` channel, else the
   air-spring pressure times the rig's effective area, else the seed's test load 4.3 kN), each
   with its source stated;
2. the damped modes of the coupled, linearised twin at that operating point
   (:func:`rollerrig.rig.linear.coupled_modes`); only those that can ring label peaks;
3. the spectral settings, chosen from the signal unless given (:func:`choose_settings`: the
   segment length from the wanted resolution, set by the closest spacing of the first-order
   rotation lines, versus the record length; at least 8 averages where the record allows);
4. the Welch spectrum (and the coherence with a second channel, from the same segments) in one
   streaming pass (:mod:`rollerrig.signal.welch`), peaks (:mod:`rollerrig.signal.peaks`) and
   their attribution (:mod:`rollerrig.signal.attribution`).

:func:`explain_recordings` runs it on several recordings, finds the lines that stay put at every
speed and attributes the peaks again with them (no second pass over the data). Every output
states the settings (:meth:`ExplainedSpectrum.summary`, :meth:`ExplainedSpectrum.caption`), and
nothing in a summary is NaN or inf (None with a reason instead).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from rollerrig._validation import ParameterError, require_positive
from rollerrig.signal.attribution import (
    PeakAttribution,
    _finite,
    _rotation_frequency,
    attribute_peaks,
    speed_independent_lines,
)
from rollerrig.signal.peaks import SpectralPeak, find_spectral_peaks
from rollerrig.signal.welch import (
    CoherenceSpectrum,
    Spectrum,
    array_chunks,
    cross_spectra_stream,
    power_spectrum,
    power_unit,
    welch_stream,
)

__all__ = [
    "ExplainedSpectrum",
    "OperatingPoint",
    "SpectraSet",
    "SpectrumSettings",
    "choose_settings",
    "coherence_at",
    "explain_recording",
    "explain_recordings",
    "explain_spectrum",
    "line_spacing",
    "operating_point",
    "segment_count",
]

MIN_AVERAGES = 8  # Welch segments wanted (noise floor within ~±1.5 dB; coherence bias ≤ 1/8)
BINS_PER_SPACING = 6  # wanted: the closest first-order lines 6 bins apart (Hann lobe: 4 bins)
BINS_NEEDED = 3  # needed: the closest lines 3 bins apart (still separated by a dip)
FEW_SEGMENTS_SNR = 15.0  # [dB] peak threshold with 1-2 segments (periodogram-like statistics)
DEFAULT_CHUNK = 1 << 20  # samples per chunk when streaming [samples]


# --------------------------------------------------------------------------------------------
# Settings
# --------------------------------------------------------------------------------------------


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
        ε of the attribution tolerance rule [1].
    damping_threshold : float
        ζ below which a twin mode may label a peak [1].
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
        """Welch segments in a record of ``n_samples`` [1]."""
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

    def describe(self, sample_rate: float, n_samples: int) -> str:
        """One line: ``"Welch, hann window, 683-sample segments (Δf 0.366 Hz), ..."``."""
        overlap = 100.0 * self.noverlap / self.nperseg
        k = self.segments(n_samples)
        band = f"{self.min_frequency:.3g}–" + (
            f"{self.max_frequency:.4g} Hz" if self.max_frequency is not None else "Nyquist"
        )
        return (
            f"Welch, {self.window} window, {self.nperseg}-sample segments "
            f"(Δf {self.resolution(sample_rate):.4g} Hz), {overlap:.0f} % overlap, "
            f"{k} segment{'s' if k != 1 else ''}, {self.detrend or 'no'} detrend; peaks "
            f">= {self.min_prominence:g} dB prominence and >= {self.min_snr:g} dB above the "
            f"noise floor in {band}; twin modes with zeta < {self.damping_threshold:g} as sources"
        )


def segment_count(n_samples: int, nperseg: int, noverlap: int) -> int:
    """Welch segments ``(n − noverlap) // (nperseg − noverlap)`` in ``n_samples`` (0 if short)."""
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
    spacing = [float(roller_frequency)]
    if wheel_frequency is not None:
        spacing.append(float(wheel_frequency))
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
    spacing: float,
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
        Samples in the record [1].
    sample_rate : float
        Sampling rate [Hz].
    spacing : float
        Closest spacing of the lines to resolve [Hz] (:func:`line_spacing`).
    min_averages : int
        Segments wanted [1]; fewer are stated in ``reason``.
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
    fs = float(require_positive("sample_rate", sample_rate, "Hz"))
    gap = float(require_positive("spacing", spacing, "Hz"))
    if n < 16:
        raise ParameterError(f"a spectrum needs at least 16 samples, got {n}")
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
    seg = max(16, seg)
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


# --------------------------------------------------------------------------------------------
# Access to a recording, in memory or chunked
# --------------------------------------------------------------------------------------------


class _Access:
    """Uniform chunked access to a Recording or a chunked source (``iter_chunks``)."""

    def __init__(self, rec) -> None:
        self.rec = rec
        self.streaming = hasattr(rec, "iter_chunks") and not hasattr(rec, "channels")
        meta = getattr(rec, "metadata", {}) or {}
        self.metadata = meta
        self.source = str(meta.get("source", "") or meta.get("path", "") or "recording")
        if self.streaming:
            self.names = tuple(rec.names)
            self.units = dict(rec.units)
            self.sample_rate = float(rec.sample_rate)
            self.n_samples = int(rec.n_samples)
        else:
            self.names = tuple(rec.channels)
            self.units = dict(rec.units)
            self.sample_rate = float(rec.sample_rate)
            self.n_samples = int(rec.time.size)

    def __contains__(self, name: str) -> bool:
        return name in self.names

    def require(self, *names: str) -> None:
        missing = [n for n in names if n not in self.names]
        if missing:
            from rollerrig.measure.recording import RecordingError

            raise RecordingError(
                f"{self.source}: no channel {missing[0]!r} for the spectrum; it has "
                f"{sorted(self.names)} (map it in the channel map, or choose --channel)"
            )

    def chunks(self, names: Sequence[str], size: int = DEFAULT_CHUNK) -> Iterator[tuple]:
        if self.streaming:
            for chunk in self.rec.iter_chunks(names=tuple(names), chunk_samples=size):
                yield tuple(np.asarray(chunk[n], dtype=float) for n in names)
        else:
            arrays = [self.rec[n] for n in names]
            for start in range(0, self.n_samples, size):
                yield tuple(a[start : start + size] for a in arrays)

    def stats(self, names: Sequence[str]) -> dict[str, tuple[float, float, float]]:
        """(mean, first value, last value) of each channel, in one pass when streaming."""
        names = [n for n in dict.fromkeys(names) if n in self.names]
        if not names:
            return {}
        if not self.streaming:
            out = {}
            for n in names:
                x = self.rec[n]
                out[n] = (float(np.mean(x)), float(x[0]), float(x[-1]))
            return out
        total = dict.fromkeys(names, 0.0)
        first: dict[str, float] = {}
        last: dict[str, float] = {}
        count = 0
        for chunk in self.chunks(names):
            if not chunk[0].size:
                continue
            count += chunk[0].size
            for n, x in zip(names, chunk, strict=True):
                total[n] += float(np.sum(x))
                first.setdefault(n, float(x[0]))
                last[n] = float(x[-1])
        if count == 0:
            return {}
        return {n: (total[n] / count, first[n], last[n]) for n in names}

    @property
    def duration(self) -> float:
        """Time from the first to the last sample [s]."""
        if not self.streaming:
            return float(self.rec.time[-1] - self.rec.time[0])
        return float(getattr(self.rec, "duration", (self.n_samples - 1) / self.sample_rate))

    def fail(self, message: str):
        from rollerrig.measure.recording import RecordingError

        return RecordingError(f"{self.source}: {message}")


# --------------------------------------------------------------------------------------------
# Operating point
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class OperatingPoint:
    """Mean speeds and load of a recording, with where each came from.

    Attributes
    ----------
    roller_speed : float
        Mean roller angular speed [rad/s] (> 0).
    wheel_speed : float or None
        Mean wheel angular speed [rad/s] (None: unknown; wheel and PMSM sources skipped).
    normal_load : float
        Normal load used for the twin's modes [N].
    speed_source, wheel_source, load_source : str
        Where each value came from.
    roller_radius : float
        Roller rolling radius [m] (for the surface speed).
    """

    roller_speed: float
    wheel_speed: float | None
    normal_load: float
    speed_source: str
    wheel_source: str
    load_source: str
    roller_radius: float

    @property
    def surface_speed(self) -> float:
        """Roller surface speed ``ω_r r_r`` [m/s]."""
        return self.roller_speed * self.roller_radius

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready (units in the keys)."""
        return {
            "roller_speed [rad/s]": self.roller_speed,
            "roller_speed [km/h]": self.surface_speed * 3.6,
            "roller_speed_source": self.speed_source,
            "wheel_speed [rad/s]": self.wheel_speed,
            "wheel_speed_source": self.wheel_source,
            "normal_load [N]": self.normal_load,
            "normal_load_source": self.load_source,
        }


def _mean_speed(access: _Access, stats, which: str, rig, given: float | None):
    name, counts = f"{which}_speed", f"{which}_encoder_counts"
    if given is not None:
        return float(require_positive(f"{which}_speed", abs(given), "rad/s")), "given"
    if name in stats:
        if not np.isfinite(stats[name][0]):
            raise access.fail(f"channel {name!r} has non-finite values; fill or cut them first")
        return abs(stats[name][0]), f"mean of the {name} channel"
    if counts in stats and rig is not None:
        cpr = rig.sensors.encoder_pulses_per_revolution * rig.sensors.encoder_quadrature_factor
        _, first, last = stats[counts]
        duration = access.duration
        if duration > 0:
            return (
                abs(last - first) / duration * 2.0 * np.pi / cpr,
                f"mean from the first and last {counts} ({cpr:g} counts per revolution)",
            )
    return None, f"no {name} or {counts} channel"


def operating_point(
    recording, rig, roller_speed: float | None = None, wheel_speed: float | None = None
) -> OperatingPoint:
    """Mean speeds and normal load of a recording (see the module docstring).

    Parameters
    ----------
    recording : Recording or chunked source
        The recording.
    rig : RigParameters
        Radii, encoder resolution, air-spring area.
    roller_speed, wheel_speed : float, optional
        Given mean angular speeds [rad/s] instead of the recording's.

    Returns
    -------
    OperatingPoint

    Raises
    ------
    RecordingError
        No roller speed (channel, encoder counts or given), or a roller at rest.
    """
    from rollerrig.rig.linear import DEFAULT_NORMAL_LOAD

    access = recording if isinstance(recording, _Access) else _Access(recording)
    wanted = []
    for which, given in (("roller", roller_speed), ("wheel", wheel_speed)):
        if given is None:
            speed = f"{which}_speed"
            wanted.append(speed if speed in access else f"{which}_encoder_counts")
    wanted.append("normal_load" if "normal_load" in access else "air_spring_pressure")
    stats = access.stats(wanted)
    w_r, r_source = _mean_speed(access, stats, "roller", rig, roller_speed)
    if w_r is None:
        raise access.fail(
            "the spectrum's sources need the roller speed: map a roller_speed or "
            "roller_encoder_counts channel (or give the speed)"
        )
    if not w_r > 1e-3:
        raise access.fail(
            f"the roller is at rest (mean speed {w_r:.3g} rad/s, {r_source}): speed-proportional "
            "lines cannot be attributed; record at speed"
        )
    w_w, w_source = _mean_speed(access, stats, "wheel", rig, wheel_speed)
    if w_w is not None and not w_w > 1e-3:
        w_w, w_source = None, f"wheel at rest ({w_source})"
    if "normal_load" in stats:
        load, l_source = stats["normal_load"][0], "mean of the normal_load channel"
    elif "air_spring_pressure" in stats:
        area = rig.sensors.air_spring_effective_area
        load = stats["air_spring_pressure"][0] * area
        l_source = f"mean air_spring_pressure × effective area {area:g} m² (rig)"
    else:
        load, l_source = DEFAULT_NORMAL_LOAD, "no load channel: the seed's test load 4.3 kN"
    if not (np.isfinite(load) and load > 0.0):
        raise access.fail(
            f"the mean normal load is {load:.4g} N ({l_source}); check the channel's unit, "
            "scale and offset in the channel map"
        )
    return OperatingPoint(
        float(w_r),
        None if w_w is None else float(w_w),
        float(load),
        r_source,
        w_source,
        l_source,
        float(rig.geometry.roller_radius_x),
    )


# --------------------------------------------------------------------------------------------
# The explained spectrum
# --------------------------------------------------------------------------------------------


def coherence_at(coh: CoherenceSpectrum, frequencies) -> np.ndarray:
    """Coherence at given frequencies: the largest γ² within ±1 bin of each.

    Parameters
    ----------
    coh : CoherenceSpectrum
        From :func:`rollerrig.signal.welch.coherence`.
    frequencies : array_like
        Frequencies [Hz] (e.g. peak frequencies of one channel).

    Returns
    -------
    ndarray
        γ² at each frequency (NaN outside the band; summaries write None).

    Examples
    --------
    >>> c = CoherenceSpectrum(np.arange(5.0), np.array([0.1, 0.2, 0.9, 0.3, 0.1]), 10)
    >>> coherence_at(c, [2.2, 7.0]).tolist()
    [0.9, nan]
    """
    from rollerrig._validation import require_finite

    fq = np.atleast_1d(require_finite("frequencies", frequencies, "Hz"))
    f, c = coh.frequency, coh.coherence
    df = float(f[1] - f[0])
    out = np.full(fq.shape, np.nan)
    for i, fi in enumerate(fq):
        lo = int(np.searchsorted(f, fi - df * (1.0 + 1e-9), side="left"))
        hi = int(np.searchsorted(f, fi + df * (1.0 + 1e-9), side="right"))
        if hi > lo:
            out[i] = float(np.max(c[lo:hi]))
    return out


@dataclass(frozen=True)
class ExplainedSpectrum:
    """A channel's spectrum with its peaks, their sources and the settings that produced it.

    Attributes
    ----------
    channel : str
        Channel name.
    unit : str
        SI unit of the channel.
    spectrum : Spectrum
        The power spectrum.
    peaks : tuple of SpectralPeak
        Peaks found (may be empty).
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
    settings : SpectrumSettings or None
        The settings (None for the lower-level :func:`explain_spectrum`).
    operating_point : OperatingPoint or None
        Speeds and load with their sources.
    modes : CoupledModes or None
        The coupled twin's modes at the operating point.
    coherence : CoherenceSpectrum or None
        Coherence with ``coherence_with`` from the same segments.
    coherence_with : str or None
        The second channel.
    speed_independent : tuple of float
        Speed-independent lines used as sources [Hz].
    source : str
        The recording (file) the spectrum came from.
    notes : tuple of str
        What the workflow decided or could not do.
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
    settings: SpectrumSettings | None = None
    operating_point: OperatingPoint | None = None
    modes: Any = None
    coherence: CoherenceSpectrum | None = None
    coherence_with: str | None = None
    speed_independent: tuple[float, ...] = ()
    source: str = ""
    notes: tuple[str, ...] = field(default_factory=tuple)

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

    @property
    def n_samples(self) -> int:
        """Samples the spectrum was estimated from [1]."""
        s = self.spectrum
        return int((s.n_segments - 1) * (s.nperseg - s.noverlap) + s.nperseg)

    @property
    def coherence_note(self) -> str | None:
        """What the coherence can say with its number of segments (None without coherence)."""
        if self.coherence is None:
            return None
        k = self.coherence.n_segments
        if k < 2:
            return (
                "one segment: the coherence is identically 1 and says nothing (record a longer "
                "signal for at least 8 segments); not reported"
            )
        return f"from {k} segments: two unrelated channels read about {1.0 / k:.2g}"

    def coherence_at_peaks(self) -> list[float | None]:
        """γ² with :attr:`coherence_with` at each peak (None without a usable coherence)."""
        if self.coherence is None or self.coherence.n_segments < 2 or not self.rows:
            return [None] * len(self.rows)
        values = coherence_at(self.coherence, [r.frequency for r in self.rows])
        return [_finite(v) for v in values]

    def table(self) -> list[dict[str, Any]]:
        """Tidy rows, one per peak (:meth:`PeakAttribution.as_row`), with the coherence.

        Every number is finite or None.
        """
        rows = [r.as_row() for r in self.rows]
        if self.coherence_with is not None:
            for row, g in zip(rows, self.coherence_at_peaks(), strict=True):
                row[f"coherence with {self.coherence_with} [-]"] = g
        return rows

    @property
    def empty_message(self) -> str:
        """The sentence for a spectrum without peaks."""
        s = self.settings
        if s is None:
            return "no peak above the thresholds"
        band = f"{s.min_frequency:.3g}–" + (
            f"{s.max_frequency:.4g} Hz" if s.max_frequency is not None else "Nyquist"
        )
        return (
            f"no peak above the thresholds ({s.min_prominence:g} dB prominence, {s.min_snr:g} dB "
            f"above the noise floor, {band}): nothing to explain"
        )

    def caption(self) -> str:
        """The settings and operating point in one paragraph (tables, figures, reports)."""
        parts = []
        if self.settings is not None:
            parts.append(self.settings.describe(self.spectrum.sample_rate, self.n_samples))
        else:
            s = self.spectrum
            parts.append(
                f"{s.method}, {s.window} window, {s.nperseg}-sample segments "
                f"(Δf {s.resolution:.4g} Hz), {s.n_segments} segments"
            )
        op = self.operating_point
        if op is not None:
            wheel = "unknown" if op.wheel_speed is None else f"{op.wheel_speed:.4g} rad/s"
            parts.append(
                f"roller {op.roller_speed:.4g} rad/s ({op.surface_speed * 3.6:.1f} km/h, "
                f"{op.speed_source}), wheel {wheel}, N = {op.normal_load / 1e3:.3g} kN "
                f"({op.load_source})"
            )
        if self.modes is not None:
            ring = ", ".join(
                f"{md.frequency:.2f} Hz (ζ {md.damping_ratio:.2g})" for md in self.modes.ringing
            )
            parts.append(f"twin modes that can ring: {ring or 'none'}")
        return "; ".join(parts)

    def format_table(self) -> str:
        """The rows as aligned text under the caption; a sentence when there is no peak."""
        unit = power_unit(self.unit, self.spectrum.scaling)
        lines = [f"{self.channel}: {self.caption()}"]
        if not self.rows:
            lines.append(self.empty_message)
            return "\n".join(lines)
        coh = self.coherence_with is not None
        head = f"{'f [Hz]':>9}  {'power [' + unit + ']':>16}  {'Δf [Hz]':>8}"
        lines.append(head + (f"  {'γ² [-]':>6}" if coh else "") + "  source")
        for r, g in zip(self.rows, self.coherence_at_peaks(), strict=True):
            df = "–" if r.delta_f is None else f"{r.delta_f:.3f}"
            power = "–" if r.power is None else f"{r.power:.4g}"
            gamma = ("–" if g is None else f"{g:.2f}") if coh else None
            label = r.label if r.explained else f"unexplained: {r.reason}"
            lines.append(
                f"{r.frequency:9.3f}  {power:>16}  {df:>8}"
                + (f"  {gamma:>6}" if coh else "")
                + f"  {label}"
            )
        return "\n".join(lines)

    def summary(self) -> dict[str, Any]:
        """JSON-ready summary: settings, operating point, twin modes, peaks, notes.

        Every number is finite or None (``json.dumps(..., allow_nan=False)`` succeeds).
        """
        s = self.spectrum
        out: dict[str, Any] = {
            "channel": self.channel,
            "unit": self.unit,
            "source": self.source or None,
            "settings": (
                self.settings.as_dict(s.sample_rate, self.n_samples)
                if self.settings is not None
                else {
                    "method": s.method,
                    "window": s.window,
                    "nperseg [samples]": s.nperseg,
                    "segments": s.n_segments,
                    "resolution [Hz]": s.resolution,
                }
            ),
            "roller_speed [rad/s]": self.roller_speed,
            "wheel_speed [rad/s]": self.wheel_speed,
            "operating_point": None
            if self.operating_point is None
            else self.operating_point.as_dict(),
            "twin_modes": None if self.modes is None else self.modes.as_dict(),
            "speed_independent_lines [Hz]": [float(f) for f in self.speed_independent],
            "coherence_with": self.coherence_with,
            "coherence_note": self.coherence_note,
            "peaks": self.table(),
            "message": None if self.rows else self.empty_message,
            "notes": list(self.notes),
        }
        return out

    def with_speed_independent(self, lines) -> ExplainedSpectrum:
        """The same spectrum with its peaks attributed again, now with speed-independent lines."""
        fixed = tuple(float(f) for f in np.atleast_1d(np.asarray(lines, dtype=float)))
        s = self.settings or SpectrumSettings(self.spectrum.nperseg, self.spectrum.noverlap)
        rows = attribute_peaks(
            self.peaks,
            self.roller_speed,
            self.wheel_speed,
            self.am_pole_pairs,
            self.pmsm_pole_pairs,
            s.max_harmonic,
            None,
            fixed,
            relative_tolerance=s.relative_tolerance,
            am_slip=self.am_slip,
            rig_modes=() if self.modes is None else self.modes.modes,
        )
        return replace(self, rows=tuple(rows), speed_independent=fixed)


def explain_recording(
    recording,
    channel: str = "torque",
    rig=None,
    *,
    coherence_with: str | None = None,
    settings: SpectrumSettings | None = None,
    speed_independent=(),
    roller_speed: float | None = None,
    wheel_speed: float | None = None,
    drives=None,
    friction: str = "dry",
    chunk_samples: int = DEFAULT_CHUNK,
) -> ExplainedSpectrum:
    """The spectrum workflow: one channel of a recording, explained (module docstring).

    Parameters
    ----------
    recording : Recording or chunked source
        In memory (:class:`rollerrig.measure.recording.Recording`), or an object with
        ``iter_chunks(names=, chunk_samples=)``, ``names``, ``units``, ``sample_rate``,
        ``n_samples`` and ``metadata`` (streamed from disk: bounded memory).
    channel : str
        Channel analysed, e.g. ``"torque"``.
    rig : RigParameters, optional
        The rig (radii, pole pairs, encoders, air spring, the twin); default the bundled rig.
    coherence_with : str, optional
        Second channel: its coherence with ``channel`` from the same segments.
    settings : SpectrumSettings, optional
        Fixed settings; default :func:`choose_settings` from the record length and the closest
        spacing of the roller and wheel rotation lines (:func:`line_spacing`).
    speed_independent : array_like of float
        Speed-independent lines [Hz] to use as sources.
    roller_speed, wheel_speed : float, optional
        Mean angular speeds [rad/s] instead of the recording's.
    drives : DriveConfig, optional
        Drive models of the twin (default: the rig's PMSM and induction motor with lag).
    friction : str
        Friction condition of the twin's contact (Polach set).
    chunk_samples : int
        Samples per chunk when streaming.

    Returns
    -------
    ExplainedSpectrum
        With its settings, operating point, twin modes, coherence and notes.

    Raises
    ------
    RecordingError
        Missing channel or roller speed, a constant, non-finite or absurd channel (named),
        a record shorter than one segment.

    Examples
    --------
    >>> from rollerrig.measure.recording import Recording
    >>> fs, w_r = 250.0, 30 / 3.6 / 0.452
    >>> t = np.arange(30_000) / fs
    >>> rng = np.random.default_rng(0)
    >>> T = 5.0 * np.sin(2 * np.pi * 5 * w_r / (2 * np.pi) * t) + rng.standard_normal(t.size)
    >>> rec = Recording(t, {"torque": T, "roller_speed": np.full(t.size, w_r)},
    ...                 {"torque": "N.m", "roller_speed": "rad/s"})
    >>> e = explain_recording(rec)
    >>> [r.label for r in e.rows]
    ['AM electrical ×1 (14.67 Hz)']
    >>> e.settings.segments(t.size) >= 8
    True
    """
    from rollerrig.rig.linear import coupled_modes
    from rollerrig.rig.parameters import default_rig

    rig = default_rig() if rig is None else rig
    access = _Access(recording)
    names = [channel] if coherence_with is None else [channel, coherence_with]
    access.require(*names)
    op = operating_point(access, rig, roller_speed, wheel_speed)
    notes: list[str] = []
    if op.load_source.startswith("no load channel"):
        notes.append(f"twin modes at the default load 4.3 kN ({op.load_source})")
    threshold = settings.damping_threshold if settings is not None else 0.3
    modes = None
    try:
        modes = coupled_modes(
            rig,
            op.surface_speed,
            op.normal_load,
            drives=drives,
            friction=friction,
            damping_threshold=threshold,
            load_source=op.load_source,
        )
    except (ParameterError, ValueError, ArithmeticError) as exc:
        notes.append(f"twin not linearised at this operating point ({exc}); no mode labels")
    if settings is None:
        f_w = None if op.wheel_speed is None else op.wheel_speed / (2 * np.pi)
        spacing = line_spacing(op.roller_speed / (2 * np.pi), f_w)
        try:
            settings = choose_settings(access.n_samples, access.sample_rate, spacing)
        except ParameterError as exc:
            raise access.fail(f"channel {channel!r}: {exc}") from None
    try:
        if coherence_with is None:
            spec = welch_stream(
                (c[0] for c in access.chunks(names, chunk_samples)),
                access.sample_rate,
                settings.nperseg,
                settings.noverlap,
                settings.window,
                settings.detrend,
                settings.scaling,
                name=f"channel {channel!r}",
            )
            coh = None
        else:
            cs = cross_spectra_stream(
                access.chunks(names, chunk_samples),
                access.sample_rate,
                settings.nperseg,
                settings.noverlap,
                settings.window,
                settings.detrend,
                settings.scaling,
                names=(f"channel {channel!r}", f"channel {coherence_with!r}"),
            )
            spec, coh = cs.x, cs.coherence
        peaks = find_spectral_peaks(
            spec,
            min_prominence=settings.min_prominence,
            max_peaks=settings.max_peaks,
            min_frequency=settings.min_frequency,
            max_frequency=settings.max_frequency,
            min_snr=settings.min_snr,
        )
    except ParameterError as exc:
        raise access.fail(str(exc)) from None
    am_pp = int(rig.induction_motor.pole_pairs)
    pmsm_pp = int(rig.pmsm.pole_pairs)
    fixed = tuple(float(f) for f in np.atleast_1d(np.asarray(speed_independent, dtype=float)))
    rows = attribute_peaks(
        peaks,
        op.roller_speed,
        op.wheel_speed,
        am_pp,
        pmsm_pp,
        settings.max_harmonic,
        None,
        fixed,
        relative_tolerance=settings.relative_tolerance,
        rig_modes=() if modes is None else modes.modes,
    )
    if op.wheel_speed is None:
        notes.append(f"wheel speed unknown ({op.wheel_source}): wheel and PMSM lines not tried")
    return ExplainedSpectrum(
        channel=channel,
        unit=access.units.get(channel, ""),
        spectrum=spec,
        peaks=tuple(peaks),
        rows=tuple(rows),
        roller_speed=op.roller_speed,
        wheel_speed=op.wheel_speed,
        am_pole_pairs=am_pp,
        pmsm_pole_pairs=pmsm_pp,
        am_slip=0.0,
        settings=settings,
        operating_point=op,
        modes=modes,
        coherence=coh,
        coherence_with=coherence_with,
        speed_independent=fixed,
        source=access.source,
        notes=tuple(notes),
    )


@dataclass(frozen=True)
class SpectraSet:
    """Explained spectra of several recordings and the lines that stay put at every speed.

    Attributes
    ----------
    spectra : tuple of ExplainedSpectrum
        One per recording, attributed with the speed-independent lines.
    speed_independent : ndarray
        Speed-independent lines [Hz] (empty with a single recording).
    """

    spectra: tuple[ExplainedSpectrum, ...]
    speed_independent: np.ndarray

    def order_map(self, **kwargs):
        """:func:`rollerrig.signal.ordermap.order_map` of the spectra."""
        from rollerrig.signal.ordermap import order_map

        return order_map(list(self.spectra), speed_independent=self.speed_independent, **kwargs)

    def summary(self) -> dict[str, Any]:
        """JSON-ready: one summary per recording and the speed-independent lines."""
        return {
            "recordings": [e.summary() for e in self.spectra],
            "speed_independent_lines [Hz]": [float(f) for f in self.speed_independent],
        }


def explain_recordings(recordings: Sequence, channel: str = "torque", rig=None, **kwargs):
    """:func:`explain_recording` on each recording, then the speed-independent lines.

    With two or more recordings, :func:`rollerrig.signal.attribution.speed_independent_lines`
    finds the lines that stay put across speeds and every spectrum's peaks are attributed again
    with them (the data are read once).

    Parameters
    ----------
    recordings : sequence of Recording or chunked source
        The recordings.
    channel : str
        Channel analysed.
    rig : RigParameters, optional
        The rig.
    **kwargs
        Passed to :func:`explain_recording` (``coherence_with``, ``settings``, ...).

    Returns
    -------
    SpectraSet
    """
    from rollerrig.rig.parameters import default_rig

    rig = default_rig() if rig is None else rig
    spectra = [explain_recording(r, channel, rig, **kwargs) for r in recordings]
    fixed = np.array([])
    if len(spectra) > 1:
        fixed = speed_independent_lines(spectra)
        if fixed.size:
            spectra = [e.with_speed_independent(fixed) for e in spectra]
    return SpectraSet(tuple(spectra), fixed)


# --------------------------------------------------------------------------------------------
# Lower level: explicit settings, no twin (kept for existing callers)
# --------------------------------------------------------------------------------------------


def _given_mean_speed(recording, name: str, given: float | None, required: bool) -> float | None:
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
    """Spectrum of one channel with explicit settings and sources (lower level).

    :func:`power_spectrum`, :func:`find_spectral_peaks` and :func:`attribute_peaks` in one
    call, without the twin and without choosing settings: use :func:`explain_recording` for
    recordings (it chooses and states the settings and labels with the twin's damped modes).

    Parameters
    ----------
    recording : Recording
        The recording.
    channel : str
        Channel analysed.
    roller_speed, wheel_speed : float, optional
        Mean angular speeds [rad/s]; default the means of the recording's channels.
    method, nperseg, window, scaling
        As in :func:`rollerrig.signal.welch.power_spectrum`.
    min_prominence, min_snr, max_peaks, min_frequency, max_frequency
        As in :func:`find_spectral_peaks` (dB, dB, count, Hz, Hz).
    am_pole_pairs, pmsm_pole_pairs, max_harmonic, tolerance_hz, speed_independent, \
relative_tolerance, am_slip, rig_modes
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
    w_r = _given_mean_speed(recording, "roller_speed", roller_speed, required=True)
    w_w = _given_mean_speed(recording, "wheel_speed", wheel_speed, required=False)
    from rollerrig.measure.recording import RecordingError

    try:
        if method == "welch":  # streamed over the array, errors naming the channel
            x = recording[channel]
            seg = min(x.size, max(256, x.size // 4)) if nperseg is None else min(nperseg, x.size)
            spec = welch_stream(
                array_chunks(x),
                recording.sample_rate,
                seg,
                None,
                window,
                "linear",
                scaling,
                name=f"channel {channel!r}",
            )
        else:
            spec = power_spectrum(
                recording[channel], recording.sample_rate, method=method, window=window,
                scaling=scaling,
            )  # fmt: skip
    except RecordingError:
        raise
    except ParameterError as exc:
        source = recording.metadata.get("source", "recording")
        raise RecordingError(f"{source}: {exc}") from None
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
        speed_independent=tuple(
            float(f) for f in np.atleast_1d(np.asarray(speed_independent, dtype=float))
        ),
    )
