"""Attribution of spectral peaks: which source explains each line, and which lines stay put.

Candidates for a peak at ``f`` (Kayaalp, sections 4.5.2.3-4.5.2.4, Tables 3-4), with the mean
roller and wheel angular speeds ``ω_r``, ``ω_w`` [rad/s], ``f_r = ω_r / 2π``, ``f_w = ω_w / 2π``:

* AM electrical frequency ``f_AM = p_AM f_r / (1 - s_AM)`` and its harmonics (``p_AM = 5``;
  Kayaalp takes the slip ``s_AM = 0``, section 4.5.2.4);
* roller rotation orders ``k f_r`` (out-of-roundness, shaft eccentricity, section 4.5.2.3);
* wheel rotation orders ``k f_w``;
* PMSM electrical frequency ``f_PMSM = p_PMSM f_w`` (``p_PMSM = 22``) and its harmonics;
* speed-independent lines found across recordings (:func:`speed_independent_lines`);
* the damped modes of the coupled twin that can ring (:mod:`rollerrig.rig.linear`: oscillatory,
  damping ratio below the threshold); overdamped modes and real poles never label a line.

Tolerance rule
--------------
A peak at ``f`` matches a speed-proportional candidate at ``f_c`` when
``|f - f_c| <= tol(f_c)`` with ``tol(f_c) = 1.5 Δf + ε f_c`` where ``Δf`` is the bin spacing of
the spectrum (1.5 bins: the half-width of the main lobe of the Hann window is 2 bins and the
interpolated peak frequency is within a small fraction of a bin) and ``ε`` is the
``relative_tolerance`` (default 0.5 %: the mean speed of a recording and the speed drift during it
are not known better; Kayaalp's Table 3 harmonics scatter by up to 0.5 % about ``k f_AM``). A
speed-independent line matches within ``1.5 Δf``. A twin mode at damped frequency ``f_d`` with
damping ratio ``ζ`` matches within ``1.5 Δf + (0.02 + ζ) f_d`` (2 % for the model, and the
resonance's half-power half-width ``ζ f_n``); a bare frequency given as a mode, within
``1.5 Δf + 0.02 f_d``. A ``tolerance_hz`` given by the caller replaces the rule by that fixed
tolerance [Hz]. When several candidates match, all are reported, the best first: smallest
``|f - f_c|``, then lowest order (candidates with the same predicted frequency, such as AM
electrical ×1 and roller order ×5, are ranked by order, then AM electrical, roller, PMSM
electrical, wheel, speed-independent, rig mode).

A peak that matches nothing is stated as ``"unexplained"`` with the reason (the nearest
candidate and by how much it misses); its ``delta_f`` is None, never NaN.

References
----------
Kayaalp (dissertation, the seed), sections 4.5.2.3-4.5.2.4, Tables 3-4.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rollerrig._validation import (
    ParameterError,
    require_finite,
    require_nonnegative,
    require_positive,
    require_whole,
)
from rollerrig.signal._numeric import finite_or_none
from rollerrig.signal.peaks import SpectralPeak

__all__ = [
    "SOURCE_KINDS",
    "PeakAttribution",
    "SourceMatch",
    "attribute_peaks",
    "speed_independent_lines",
]

SOURCE_KINDS: dict[str, str] = {
    "am_electrical": "AM electrical",
    "roller_order": "roller order",
    "pmsm_electrical": "PMSM electrical",
    "wheel_order": "wheel order",
    "speed_independent": "speed-independent line",
    "rig_mode": "rig mode",
    "unexplained": "unexplained",
}
"""Source kind -> label prefix, in the order used to break ties between coincident candidates."""

_KIND_RANK = {k: i for i, k in enumerate(SOURCE_KINDS)}
_BIN_TOLERANCE = 1.5  # bins; see the module docstring
_MODEL_TOLERANCE = 0.02  # relative uncertainty of a twin mode frequency
_TWO_PI = 2.0 * np.pi


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
    power : float or None
        Peak power (scaling of the spectrum; None when the peak was given as a bare frequency).
    label : str
        Label of the best match, ``"unexplained"`` when none matches.
    order : int
        Harmonic number of the best match (0 when unexplained, speed-independent or a mode).
    source : str
        Source kind of the best match, a key of :data:`SOURCE_KINDS`.
    delta_f : float or None
        Peak minus predicted frequency of the best match [Hz] (None when unexplained).
    matches : tuple of SourceMatch
        Every matching source, the best first.
    reason : str
        Why the peak is unexplained (the nearest candidate and its miss); ``""`` otherwise.
    """

    frequency: float
    power: float | None
    label: str
    order: int
    source: str
    delta_f: float | None
    matches: tuple[SourceMatch, ...] = field(default_factory=tuple)
    reason: str = ""

    @property
    def explained(self) -> bool:
        """True when a source explains the peak."""
        return self.source != "unexplained"

    def as_row(self) -> dict[str, Any]:
        """The attribution as a flat, JSON-ready table row: finite numbers or None.

        Keys: ``frequency_hz``, ``power``, ``label``, ``order``, ``source``, ``explained``,
        ``delta_f_hz`` (None when unexplained), ``reason`` (None when explained), ``also`` (the
        other matches' labels).
        """
        return {
            "frequency_hz": finite_or_none(self.frequency),
            "power": finite_or_none(self.power),
            "label": self.label,
            "order": int(self.order),
            "source": self.source,
            "explained": self.explained,
            "delta_f_hz": finite_or_none(self.delta_f),
            "reason": self.reason or None,
            "also": "; ".join(m.label for m in self.matches[1:]),
        }


def _label(kind: str, order: int, frequency: float) -> str:
    if kind == "speed_independent":
        return f"{SOURCE_KINDS[kind]} ({frequency:.3f} Hz)"
    if kind == "rig_mode":
        return f"{SOURCE_KINDS[kind]} {frequency:.2f} Hz"
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


def _mode_candidates(rig_modes) -> list[tuple[float, float, str]]:
    """(damped frequency [Hz], relative tolerance [-], label) of the modes that can ring.

    Entries are :class:`rollerrig.rig.linear.CoupledMode` objects (those that cannot ring are
    skipped: an overdamped mode or a real pole never explains a line) or bare frequencies [Hz].
    """
    out = []
    for md in rig_modes:
        if hasattr(md, "can_ring"):
            if md.can_ring:
                zeta = float(md.damping_ratio or 0.0)
                out.append((float(md.frequency), _MODEL_TOLERANCE + zeta, md.label))
        else:
            fc = require_finite("rig_modes", md, "Hz", single=True)
            out.append((fc, _MODEL_TOLERANCE, _label("rig_mode", 0, fc)))
    return out


def _match(
    f: float,
    sources: list[tuple[str, int, float]],
    fixed: np.ndarray,
    bin_tol: float,
    relative_tolerance: float,
    tolerance_hz: float | None,
    modes=(),
) -> tuple[list[SourceMatch], str]:
    """Matching candidates, best first, and (when none matches) the reason."""
    found: list[SourceMatch] = []
    nearest: tuple[float, str, float] | None = None  # (|Δf| - tol, label, tol)

    def consider(kind, order, fc, tol, label):
        nonlocal nearest
        miss = abs(f - fc) - tol
        if miss <= 0.0:
            found.append(SourceMatch(kind, order, float(fc), f - fc, tol, label))
        elif nearest is None or miss < nearest[0]:
            nearest = (miss, label, tol)

    for kind, order, fc in sources:
        tol = tolerance_hz if tolerance_hz is not None else bin_tol + relative_tolerance * fc
        consider(kind, order, fc, tol, _label(kind, order, fc))
    for fc in fixed:
        tol = tolerance_hz if tolerance_hz is not None else bin_tol
        consider("speed_independent", 0, float(fc), tol, _label("speed_independent", 0, fc))
    for fc, rel, label in modes:
        tol = tolerance_hz if tolerance_hz is not None else bin_tol + rel * fc
        consider("rig_mode", 0, fc, tol, label)

    # Coincident predictions (AM ×k and roller ×5k) differ only by rounding: compare |Δf| on a
    # grid far finer than any spectral resolution, then order, then kind.
    def key(m: SourceMatch):
        return (round(abs(m.delta_f), 9), m.order, _KIND_RANK[m.source])

    reason = ""
    if not found:
        if nearest is None:
            reason = "no candidate source (no speed, no speed-independent line, no twin mode)"
        else:
            miss, label, tol = nearest
            reason = (
                f"no source within tolerance; nearest {label} misses by {miss + tol:.3g} Hz "
                f"(tolerance {tol:.3g} Hz)"
            )
    return sorted(found, key=key), reason


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
    return f, None, None


def _check_attribution_options(
    am_pole_pairs, pmsm_pole_pairs, max_harmonic, tolerance_hz, relative_tolerance, am_slip
) -> None:
    for name, value in (
        ("am_pole_pairs", am_pole_pairs),
        ("pmsm_pole_pairs", pmsm_pole_pairs),
        ("max_harmonic", max_harmonic),
    ):
        require_whole(name, value, minimum=1)
    if tolerance_hz is not None:
        require_positive("tolerance_hz", tolerance_hz, "Hz")
    if not 0.0 <= relative_tolerance < 0.5:
        raise ParameterError(
            f"relative_tolerance must lie in [0, 0.5) [-], got {relative_tolerance}"
        )
    if not -1.0 < am_slip < 1.0:
        raise ParameterError(f"am_slip must lie in (-1, 1) [-], got {am_slip}")


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
        ε of the tolerance rule [-] (uncertainty of the mean speed).
    am_slip : float
        Slip of the induction motor [-] (Kayaalp: 0).
    rig_modes : sequence of CoupledMode or float
        Modes of the coupled twin (:func:`rollerrig.rig.linear.coupled_modes`; only those that
        can ring are used, matched within ``1.5 Δf + (0.02 + ζ) f_d``), or bare frequencies
        [Hz] (matched within ``1.5 Δf + 0.02 f``).

    Returns
    -------
    list of PeakAttribution
        One row per peak, in the order of ``peaks``; an unexplained peak has ``source`` and
        ``label`` ``"unexplained"``, ``delta_f`` None and the reason.

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
        roller_speed = require_positive("roller_speed", abs(roller_speed), "rad/s", single=True)
    if wheel_speed is not None:
        wheel_speed = require_positive("wheel_speed", abs(wheel_speed), "rad/s", single=True)
    f, pw, res = _peak_values(peaks)
    if resolution is not None:
        res = require_positive("resolution", resolution, "Hz", single=True)
    if f.size == 0:
        return []  # nothing to attribute (no peak above the thresholds)
    if tolerance_hz is None and res is None:
        raise ParameterError(
            "attribute_peaks needs the spectral resolution [Hz] to set the tolerance: pass "
            "SpectralPeaks, resolution= or tolerance_hz="
        )
    fixed = np.atleast_1d(require_finite("speed_independent", speed_independent, "Hz"))
    modes = _mode_candidates(rig_modes)
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
    for i, fi in enumerate(f):
        pi = None if pw is None else float(pw[i])
        matches, reason = _match(
            float(fi), sources, fixed, bin_tol, relative_tolerance, tolerance_hz, modes
        )
        if matches:
            best = matches[0]
            rows.append(
                PeakAttribution(
                    float(fi),
                    pi,
                    best.label,
                    best.order,
                    best.source,
                    best.delta_f,
                    tuple(matches),
                )
            )
        else:
            rows.append(
                PeakAttribution(float(fi), pi, "unexplained", 0, "unexplained", None, (), reason)
            )
    return rows


def _entry(item) -> tuple[float | None, float | None, list, float | None]:
    """(roller speed, wheel speed, peaks, resolution) of an ExplainedSpectrum or a tuple
    (roller speed None: at rest)."""
    if hasattr(item, "peaks") and hasattr(item, "spectrum"):  # an ExplainedSpectrum
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
    require_nonnegative("peaks", f, "Hz")  # a frequency; a negative one is a sign slip
    peaks = list(peaks) if res is not None else list(f)
    # A speed is finite or None (at rest): a NaN one had put its peaks at speed NaN, off
    # every line, and an infinite one stretched the map's speed axis to infinity.
    roller = (
        None if roller is None else require_finite("roller_speed", roller, "rad/s", single=True)
    )
    wheel = None if wheel is None else require_finite("wheel_speed", wheel, "rad/s", single=True)
    return roller, wheel, peaks, res


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
        Least ratio of the fastest to the slowest roller speed in a group [-].
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
        raise ParameterError(f"min_speed_ratio must be >= 1 [-], got {min_speed_ratio}")
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
        speed = 0.0 if roller is None else abs(roller)  # at rest: a line there is not k f_r
        pool += [(r.frequency, i, speed) for r in rows if r.source == "unexplained"]
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
