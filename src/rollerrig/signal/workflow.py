"""One spectrum workflow for every output: CLI ``spectrum``, ``analyze``, the demo and the report.

:func:`explain_recording` takes one channel of a recording (in memory, or a chunked source that
streams from disk) and the rig, and returns an :class:`ExplainedSpectrum` that carries
everything it decided:

1. the operating point: mean roller and wheel speeds (speed channels, else the mean speed from
   the first and last encoder counts), the mean normal load (``normal_load`` channel, else the
   air-spring pressure times the rig's effective area, else the seed's test load 4.3 kN), each
   with its source stated (:mod:`rollerrig.signal.operating_point`);
2. the damped modes of the coupled, linearised twin at that operating point
   (:func:`rollerrig.rig.linear.coupled_modes`); only those that can ring label peaks;
3. the spectral settings, chosen from the signal unless given
   (:func:`rollerrig.signal.spectrum_settings.choose_settings`: the segment length from the
   wanted resolution, set by the closest spacing of the first-order rotation lines, versus the
   record length; at least 8 averages where the record allows);
4. the Welch spectrum (and the coherence with a second channel, from the same segments) in one
   streaming pass (:mod:`rollerrig.signal.welch`), peaks (:mod:`rollerrig.signal.peaks`) and
   their attribution (:mod:`rollerrig.signal.attribution`).

:func:`explain_recordings` runs it on several recordings, finds the lines that stay put at every
speed and attributes the peaks again with them (no second pass over the data). Every output
states the settings (:mod:`rollerrig.signal.explained_spectrum`: :meth:`ExplainedSpectrum.summary`,
:meth:`ExplainedSpectrum.caption`), and nothing in a summary is NaN or inf (None with a reason
instead). :func:`explain_spectrum` is the lower level: explicit settings, no twin.

The result types, the settings, the operating point and the access to a recording live in their
own modules (above); their public names are importable from here as well.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from rollerrig._validation import ParameterError, require_positive
from rollerrig.signal.attribution import attribute_peaks, speed_independent_lines
from rollerrig.signal.explained_spectrum import (
    ExplainedSpectrum,
    SpectraSet,
    coherence_at,
    line_frequencies,
)
from rollerrig.signal.operating_point import OperatingPoint, operating_point
from rollerrig.signal.peaks import find_spectral_peaks
from rollerrig.signal.recording_access import DEFAULT_CHUNK, RecordingAccess
from rollerrig.signal.spectrum_settings import (
    SpectrumSettings,
    choose_settings,
    line_spacing,
    segment_count,
)
from rollerrig.signal.welch import cross_spectra_stream, power_spectrum, welch_stream

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
        In memory (:class:`rollerrig.recordings.recording.Recording`), or an object with
        ``iter_chunks(names=, chunk_samples=)``, ``names``, ``units``, ``sample_rate``,
        ``n_samples`` and ``metadata`` (streamed from disk: bounded memory).
    channel : str
        Channel analysed, e.g. ``"torque"``.
    rig : RigParameters, optional
        The rig (radii, pole pairs, encoders, air spring, the twin); default the bundled rig.
    coherence_with : str, optional
        Second channel: its coherence with ``channel`` from the same segments.
    settings : SpectrumSettings, optional
        Fixed settings; default :func:`rollerrig.signal.spectrum_settings.choose_settings` from
        the record length and the closest spacing of the roller and wheel rotation lines
        (:func:`rollerrig.signal.spectrum_settings.line_spacing`).
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
        a record shorter than one segment. A roller at rest is no error: the spectrum and its
        peaks are the result, the rotation orders and motor lines unattributed, with a note.

    Examples
    --------
    >>> from rollerrig.recordings.recording import Recording
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
    access = RecordingAccess(recording)
    names = [channel] if coherence_with is None else [channel, coherence_with]
    access.require(*names)
    op = operating_point(access, rig, roller_speed, wheel_speed)
    notes: list[str] = []
    if op.load_source.startswith("no load channel"):
        notes.append(f"twin modes at the default load 4.3 kN ({op.load_source})")
    threshold = settings.damping_threshold if settings is not None else 0.3
    modes = None
    if op.at_rest:
        notes.append(
            f"{op.speed_source}: rotation orders and motor lines (roller, AM, wheel, PMSM) are "
            "not attributed, since at standstill they all lie at 0 Hz; the peaks are listed "
            "unattributed unless a speed-independent line explains them. The twin's modes are "
            "not computed: the coupled twin is linearised about a rolling contact (speed > 0)"
        )
    else:
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
        # Rotation frequencies, whichever way the shafts turn; a wheel at rest has no lines.
        f_w = None if not op.wheel_speed else abs(op.wheel_speed) / (2 * np.pi)
        f_r = None if op.at_rest else abs(op.roller_speed) / (2 * np.pi)
        spacing = line_spacing(f_r, f_w) if f_r else None
        try:
            settings = choose_settings(access.n_samples, access.sample_rate, spacing)
        except ParameterError as exc:
            raise access.fail(f"channel {channel!r}: {exc}") from None
    welch = (
        access.sample_rate,
        settings.nperseg,
        settings.noverlap,
        settings.window,
        settings.detrend,
        settings.scaling,
    )
    chunks = access.chunks(names, chunk_samples)
    labels = [f"channel {name!r}" for name in names]
    try:
        if coherence_with is None:
            spec = welch_stream((c[0] for c in chunks), *welch, name=labels[0])
            coh = None
        else:
            cs = cross_spectra_stream(chunks, *welch, names=tuple(labels))
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
    if op.wheel_speed is None and not op.at_rest:
        notes.append(f"wheel speed unknown ({op.wheel_source}): wheel and PMSM lines not tried")
    unsteady = _unsteady_speed_note(op)
    if unsteady:
        notes.append(unsteady)
    unexplained = ExplainedSpectrum(
        channel=channel,
        unit=access.units.get(channel, ""),
        spectrum=spec,
        peaks=tuple(peaks),
        rows=(),
        roller_speed=op.roller_speed,
        wheel_speed=op.wheel_speed,
        am_pole_pairs=int(rig.induction_motor.pole_pairs),
        pmsm_pole_pairs=int(rig.pmsm.pole_pairs),
        am_slip=0.0,
        settings=settings,
        operating_point=op,
        modes=modes,
        coherence=coh,
        coherence_with=coherence_with,
        source=access.source,
        notes=tuple(notes),
    )
    return unexplained.with_speed_independent(speed_independent)


UNSTEADY_SPEED = 0.02
"""Relative range of the roller speed's 1 s means [-] beyond which a spectrum's note says the
speed was not steady: a whole adhesion test (16.7 to 19.9 rad/s on the demo's) had its AM
lines read "unexplained, misses by 0.389 Hz" at the mean speed, with no word why."""


def _unsteady_speed_note(op) -> str | None:
    """A note when the roller speed's 1 s means span more than :data:`UNSTEADY_SPEED` of
    their mean: the orders and motor lines move with the speed over the recording."""
    if op.at_rest or op.roller_speed_range is None:
        return None
    low, high = op.roller_speed_range
    mean = abs(op.roller_speed)
    if not mean > 0 or (high - low) / mean <= UNSTEADY_SPEED:
        return None
    return (
        f"the roller speed is not steady over the recording: its 1 s means span {low:.4g} to "
        f"{high:.4g} rad/s ({100 * (high - low) / mean:.0f} % of the mean {mean:.4g} rad/s), "
        "so its rotation orders and motor lines move by as much and may read as unexplained "
        "at the mean speed or be smeared; take a stretch at steady speed (rollerrig analyze "
        "takes the longest phase without torque activity)"
    )


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


def _given_mean_speed(recording, name: str, given: float | None, required: bool) -> float | None:
    if given is not None:
        return require_positive(name, abs(given), "rad/s", single=True)
    if name not in recording:
        if required:
            recording.require(name)
        return None
    return require_positive(
        f"mean {name} of the recording", abs(np.mean(recording[name])), "rad/s", single=True
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
    >>> from rollerrig.recordings.recording import Recording
    >>> fs, w_r = 250.0, 30 / 3.6 / 0.452
    >>> t = np.arange(30_000) / fs
    >>> T = 5.0 * np.sin(2 * np.pi * 5 * w_r / (2 * np.pi) * t)
    >>> rec = Recording(t, {"torque": T, "roller_speed": np.full(t.size, w_r)},
    ...                 {"torque": "N.m", "roller_speed": "rad/s"})
    >>> [r.label for r in explain_spectrum(rec).rows]
    ['AM electrical ×1 (14.67 Hz)']
    """
    recording.require(channel)
    # The spectrum takes the samples as equally spaced (a gap is refused, not taken for a step).
    RecordingAccess(recording)
    w_r = _given_mean_speed(recording, "roller_speed", roller_speed, required=True)
    w_w = _given_mean_speed(recording, "wheel_speed", wheel_speed, required=False)
    from rollerrig.recordings.recording import RecordingError

    try:
        spec = power_spectrum(
            recording[channel],
            recording.sample_rate,
            method=method,
            nperseg=nperseg,
            window=window,
            scaling=scaling,
            name=f"channel {channel!r}",
        )
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
        speed_independent=line_frequencies(speed_independent),
    )
