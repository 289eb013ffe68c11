"""Spectra that explain themselves: power spectra, peak finding and attribution of every peak.

Kayaalp (the seed dissertation, sections 4.5.2.3-4.5.2.4, Tables 3-4) reads the spectra of the
roller-shaft torque (250 Hz) and of the laser displacement sensors (600 Hz) of the wheel-roller
rig by hand: the displacement peaks at the roller rotation frequency (0.484 Hz at 5 km/h ...
2.99 Hz at 30 km/h), the torque at the electrical frequency of the roller's induction motor
(AM, 5 pole pairs: 2.433 Hz at 5 km/h) and its harmonics, plus a line at 1.333 Hz that stays put
at every speed. The toolkit does that reading automatically. This module gathers the public API,
which lives in modules by concern:

* :mod:`rollerrig.signal.welch` -- :func:`power_spectrum`, :func:`amplitude_spectrum`,
  :func:`coherence`, and the streaming estimators :func:`welch_stream`,
  :func:`cross_spectra_stream`, :func:`coherence_stream` (bounded memory; equal to scipy's
  ``welch`` / ``csd`` / ``coherence`` on the concatenated signal).
* :mod:`rollerrig.signal.peaks` -- :func:`find_spectral_peaks` (memory independent of the number
  of candidate peaks).
* :mod:`rollerrig.signal.attribution` -- :func:`attribute_peaks`,
  :func:`speed_independent_lines`, the tolerance rule; unexplained peaks stated with a reason.
* :mod:`rollerrig.signal.ordermap` -- :func:`order_map`.
* :mod:`rollerrig.signal.workflow` -- the one spectrum workflow, :func:`explain_recording` /
  :func:`explain_recordings`, with settings chosen from the signal (:func:`choose_settings` in
  :mod:`rollerrig.signal.spectrum_settings`), the operating point
  (:mod:`rollerrig.signal.operating_point`) and the damped modes of the coupled twin
  (:mod:`rollerrig.rig.linear`) as sources; the lower-level :func:`explain_spectrum` with explicit
  settings. Its results, :class:`ExplainedSpectrum` and :class:`SpectraSet`, and their tables and
  summaries are in :mod:`rollerrig.signal.explained_spectrum`.

References
----------
Kayaalp (dissertation, the seed), sections 4.5.2.3-4.5.2.4, Tables 3-4.
P. D. Welch, "The use of fast Fourier transform for the estimation of power spectra", IEEE Trans.
Audio Electroacoust. 15 (1967) 70-73.
G. Heinzel, A. Rüdiger, R. Schilling, "Spectrum and spectral density estimation by the Discrete
Fourier transform (DFT)", Max-Planck-Institut für Gravitationsphysik, 2002.
J. O. Smith, *Spectral Audio Signal Processing*, W3K, 2011, "Quadratic Interpolation of Spectral
Peaks".
J. S. Bendat, A. G. Piersol, *Random Data*, 4th ed., Wiley, 2010, section 6.1.4.
"""

from __future__ import annotations

from rollerrig.signal.attribution import (
    SOURCE_KINDS,
    PeakAttribution,
    SourceMatch,
    attribute_peaks,
    speed_independent_lines,
)
from rollerrig.signal.explained_spectrum import ExplainedSpectrum, SpectraSet, coherence_at
from rollerrig.signal.operating_point import OperatingPoint
from rollerrig.signal.ordermap import OrderLine, OrderMap, order_map
from rollerrig.signal.peaks import SpectralPeak, find_spectral_peaks
from rollerrig.signal.spectrum_settings import SpectrumSettings, choose_settings
from rollerrig.signal.welch import (
    CoherenceSpectrum,
    CrossSpectra,
    Spectrum,
    amplitude_spectrum,
    coherence,
    coherence_stream,
    cross_spectra_stream,
    power_spectrum,
    welch_stream,
)
from rollerrig.signal.workflow import explain_recording, explain_recordings, explain_spectrum

__all__ = [
    "SOURCE_KINDS",
    "CoherenceSpectrum",
    "CrossSpectra",
    "ExplainedSpectrum",
    "OperatingPoint",
    "OrderLine",
    "OrderMap",
    "PeakAttribution",
    "SourceMatch",
    "SpectraSet",
    "SpectralPeak",
    "Spectrum",
    "SpectrumSettings",
    "amplitude_spectrum",
    "attribute_peaks",
    "choose_settings",
    "coherence",
    "coherence_at",
    "coherence_stream",
    "cross_spectra_stream",
    "explain_recording",
    "explain_recordings",
    "explain_spectrum",
    "find_spectral_peaks",
    "order_map",
    "power_spectrum",
    "speed_independent_lines",
    "welch_stream",
]
