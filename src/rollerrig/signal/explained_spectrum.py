"""The spectrum workflow's results and how they are stated: tables, captions, JSON summaries.

:class:`ExplainedSpectrum` is one channel's spectrum with its peaks, the source of each peak and
everything the workflow decided (settings, operating point, twin modes, coherence, notes);
:class:`SpectraSet` holds the spectra of several recordings with the lines that stay put at every
speed. Both state their settings (:meth:`ExplainedSpectrum.summary`,
:meth:`ExplainedSpectrum.caption`, :meth:`ExplainedSpectrum.format_table`), and nothing in a
summary is NaN or inf (None with a reason instead).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from rollerrig._validation import require_finite
from rollerrig.signal._numeric import finite_or_none
from rollerrig.signal.attribution import PeakAttribution, _rotation_frequency, attribute_peaks
from rollerrig.signal.operating_point import OperatingPoint
from rollerrig.signal.peaks import SpectralPeak
from rollerrig.signal.spectrum_settings import SpectrumSettings
from rollerrig.signal.welch import CoherenceSpectrum, Spectrum, power_unit

__all__ = ["ExplainedSpectrum", "SpectraSet", "coherence_at", "line_frequencies"]


def line_frequencies(lines) -> tuple[float, ...]:
    """Speed-independent line frequencies as a tuple of floats [Hz] (a scalar gives one line).

    Examples
    --------
    >>> line_frequencies(1.333), line_frequencies([1.5, 2])
    ((1.333,), (1.5, 2.0))
    """
    return tuple(float(f) for f in np.atleast_1d(np.asarray(lines, dtype=float)))


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
    roller_speed : float or None
        Mean roller angular speed used [rad/s] (None: the roller is at rest; roller and AM
        sources skipped, the notes say so).
    wheel_speed : float or None
        Mean wheel angular speed used [rad/s] (None: wheel and PMSM sources skipped).
    am_pole_pairs, pmsm_pole_pairs : int
        Pole pairs used.
    am_slip : float
        AM slip used [-].
    settings : SpectrumSettings or None
        The settings (None for the lower-level
        :func:`rollerrig.signal.workflow.explain_spectrum`).
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
    roller_speed: float | None
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
    def roller_frequency(self) -> float | None:
        """Roller rotation frequency f_r [Hz] (None with the roller at rest)."""
        return None if self.roller_speed is None else _rotation_frequency(self.roller_speed)

    @property
    def wheel_frequency(self) -> float | None:
        """Wheel rotation frequency f_w [Hz] (None without a wheel speed)."""
        return None if self.wheel_speed is None else _rotation_frequency(self.wheel_speed)

    @property
    def am_frequency(self) -> float | None:
        """AM electrical frequency ``p_AM f_r / (1 - s)`` [Hz] (None with the roller at rest)."""
        fr = self.roller_frequency
        return None if fr is None else self.am_pole_pairs * fr / (1.0 - self.am_slip)

    @property
    def pmsm_frequency(self) -> float | None:
        """PMSM electrical frequency ``p_PMSM f_w`` [Hz] (None without a wheel speed)."""
        fw = self.wheel_frequency
        return None if fw is None else self.pmsm_pole_pairs * fw

    @property
    def n_samples(self) -> int:
        """Samples the spectrum was estimated from [-]."""
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
        return [finite_or_none(v) for v in values]

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
        return (
            f"no peak above the thresholds ({s.min_prominence:g} dB prominence, {s.min_snr:g} dB "
            f"above the noise floor, {s.band()}): nothing to explain"
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
            roller = (
                op.speed_source
                if op.at_rest
                else f"roller {op.roller_speed:.4g} rad/s ({op.surface_speed * 3.6:.1f} km/h, "
                f"{op.speed_source})"
            )
            parts.append(
                f"{roller}, wheel {wheel}, N = {op.normal_load / 1e3:.3g} kN ({op.load_source})"
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
        """The same spectrum with its peaks attributed (again) with these speed-independent lines.

        The attribution uses the spectrum's speeds, pole pairs, AM slip, settings (highest
        harmonic, relative tolerance) and twin modes; ``lines`` [Hz] may be empty.
        """
        fixed = line_frequencies(lines)
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
