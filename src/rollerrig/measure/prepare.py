"""A recording brought to what an analysis needs: a uniform time base at the analysis rate.

- :func:`fill_short_gaps`: a lenient read's short gaps (and sample-time jitter) filled by
  linear interpolation onto a uniform grid; a long gap is an error naming it;
- :func:`analysis_recording`: a recording faster than :data:`DECIMATE_ABOVE` decimated to
  :data:`ANALYSIS_RATE` (anti-alias FIR), an open long file while it is read;
- :func:`analysis_rate_facts`: what an analysis summary says about that rate.
"""

from __future__ import annotations

import numpy as np

from rollerrig._validation import require_in_range, require_positive
from rollerrig.measure.facts import source_prefix
from rollerrig.recordings.recording import Recording, RecordingError
from rollerrig.recordings.validate import MAX_INTERPOLATED_NAN_RUN, describe_gap, find_gaps

__all__ = [
    "ANALYSIS_RATE",
    "DECIMATE_ABOVE",
    "MIN_ANALYSIS_RATE",
    "analysis_rate_facts",
    "analysis_recording",
    "fill_short_gaps",
    "nominal_rate",
]

ANALYSIS_RATE = 1000.0
"""Rate [Hz] an analysis works at for recordings faster than :data:`DECIMATE_ABOVE`.

The anti-alias decimation (:func:`rollerrig.signal.decimate.decimate_recording`) keeps
0-400 Hz (within 0.03 %): the torsional modes of the rig (up to ~112 Hz), the motor lines and
the roller acceleration of the dynamics correction, at 1/19 of the samples of a 19.2 kHz
recording (one hour: 3.6 M samples per channel instead of 69 M).
"""

DECIMATE_ABOVE = 1500.0
"""Recordings faster than this [Hz] are decimated to :data:`ANALYSIS_RATE` before the analysis."""


MIN_ANALYSIS_RATE = 250.0
"""Lowest analysis rate :func:`analysis_recording` takes [Hz]: the Pardubice rig's DAQ rate, at
which the analysis was built (the decimation keeps 0.8 of Nyquist, 0-100 Hz there: the
roller-shaft mode, the release transients and the drives' first lines, not the wheel shaft's
112 Hz mode, which :data:`ANALYSIS_RATE` keeps). A rate of 5 Hz had returned 5 samples a second
of a 19.2 kHz test, 1e-3 Hz tried to allocate 6 GiB."""


def _checked_rate(name: str, value, lowest: float) -> float:
    """``value`` [Hz], finite and at least ``lowest`` (above 0 where that is 0)."""
    if lowest > 0.0:
        return require_in_range(name, value, lowest, np.inf, "Hz", low_inclusive=True, single=True)
    return require_positive(name, value, "Hz", single=True)


def nominal_rate(recording) -> float:
    """Sample rate [Hz] of a uniform recording, to 10 significant digits (19200, not 19199.99)."""
    return float(f"{float(recording.sample_rate):.10g}")


def fill_short_gaps(recording: Recording) -> tuple[Recording, list[str]]:
    """The recording on a uniform time base, short gaps filled; for analyses that need one.

    A lenient read keeps gaps (dropped samples, ``metadata["gaps"]``). Gaps of at most
    :data:`rollerrig.recordings.validate.MAX_INTERPOLATED_NAN_RUN` missing samples are filled by
    linear interpolation of every channel onto the uniform grid t0 + k/f_s (the policy of
    NaN runs); a longer gap is an error naming it. The recording's metadata keeps its
    ``gaps``; the notes say what was filled.

    Returns
    -------
    (Recording, list of str)
        The uniform recording (the input itself when it has no gap) and one note per gap.

    Raises
    ------
    RecordingError
        A gap longer than the interpolation limit, with its time and size.
    """
    t = recording.time
    step, gaps = find_gaps(t)
    if not gaps and np.all(np.abs(np.diff(t) - step) <= 0.01 * step):
        return recording, []
    notes = []
    for gap in gaps:
        where = f"{source_prefix(recording)}gap of {describe_gap(gap)}"
        if gap["missing_samples"] > MAX_INTERPOLATED_NAN_RUN:
            raise RecordingError(
                f"{where}: too long to fill for the analysis (at most "
                f"{MAX_INTERPOLATED_NAN_RUN} samples); analyse the parts before and after it "
                "separately"
            )
        notes.append(f"{where} filled by linear interpolation onto the uniform time base")
    # Whole steps up to the last sample: a grid point past it cannot be interpolated, and one
    # moved back onto it would make the last step short (a non-uniform base again).
    n = int(np.floor(float(t[-1] - t[0]) / step + 1e-6)) + 1
    grid = t[0] + np.arange(n) * step
    channels = {name: np.interp(grid, t, x) for name, x in recording.channels.items()}
    if not notes:
        notes.append(
            f"{source_prefix(recording)}irregular sample times (jitter above 1 % of the step "
            f"{step:.6g} s) put onto a uniform time base of {1.0 / step:.6g} Hz by linear "
            "interpolation; for a band-limited resampling give resample_Hz = "
            f"{float(f'{1.0 / step:.3g}'):g} in the channel map's [time] section"
        )
    meta = dict(recording.metadata)
    meta["notes"] = [*list(meta.get("notes") or []), *notes]
    return Recording(grid, channels, dict(recording.units), meta), notes


def analysis_recording(recording, *, rate: float | None = None, above: float | None = None):
    """The recording at the rate the analysis works at, and a note saying what was done.

    A recording faster than ``above`` (default :data:`DECIMATE_ABOVE`, 1.5 kHz) is brought to
    ``rate`` (default :data:`ANALYSIS_RATE`, 1 kHz) by the zero-phase anti-alias FIR of
    :func:`rollerrig.signal.decimate.decimate_recording` (every channel; the metadata's
    ``notes`` and ``decimated`` say how). An open
    :class:`rollerrig.recordings.source.RecordingSource` is decimated while it is read, chunk by
    chunk, and never held at its own rate; a source at or below ``above`` is read whole.

    Parameters
    ----------
    recording : Recording or RecordingSource
        Uniformly sampled (a lenient read's gaps filled first: :func:`fill_short_gaps`).
    rate : float, optional
        Analysis rate [Hz], at least :data:`MIN_ANALYSIS_RATE`; default :data:`ANALYSIS_RATE`.
        At or above the recording's own rate nothing is decimated.
    above : float, optional
        Recordings faster than this [Hz] are decimated; default :data:`DECIMATE_ABOVE`.

    Returns
    -------
    (Recording, str or None)
        The recording to analyse, and a note for the analysis' notes (None when nothing was
        done).

    Raises
    ------
    RecordingError
        Naming the file: a non-uniform time base, non-finite samples (a source is read
        strictly).

    Examples
    --------
    >>> t = np.arange(19200) / 19200.0
    >>> rec, note = analysis_recording(Recording(t, {"torque": 100.0 + t}, {"torque": "N.m"}))
    >>> round(rec.sample_rate), rec.metadata["decimated"]["from_rate_Hz"]
    (1000, 19200.0)
    >>> note[:48]
    'analysed at 1000 Hz: the recording (19200 Hz) wa'
    """
    from rollerrig.signal.decimate import decimate_recording

    rate = ANALYSIS_RATE if rate is None else _checked_rate("rate", rate, MIN_ANALYSIS_RATE)
    above = DECIMATE_ABOVE if above is None else _checked_rate("above", above, 0.0)
    streamed = hasattr(recording, "iter_chunks")
    fs = nominal_rate(recording)
    if fs <= above or rate >= fs * (1.0 - 1e-9):
        if streamed:  # slow enough to hold: read it whole
            chunk = recording.read()
            meta = dict(recording.metadata)
            meta["notes"] = list(meta.get("notes") or [])
            return Recording(
                np.array(chunk.time),
                {name: np.array(v) for name, v in chunk.channels.items()},
                dict(recording.units),
                meta,
            ), None
        return recording, None
    out = decimate_recording(recording, rate)
    how = "while streaming it from the file, never holding it whole" if streamed else "first"
    note = (
        f"analysed at {out.metadata['decimated']['rate_Hz']:g} Hz: the recording ({fs:g} Hz) "
        f"was decimated {how} (recordings faster than {above:g} Hz are; ANALYSIS_RATE, "
        "DECIMATE_ABOVE); 0-400 Hz is kept, the rig's torsional modes and motor lines included"
    )
    return out, note


def analysis_rate_facts(rec: Recording, above: float = DECIMATE_ABOVE) -> dict:
    """What the summary says about the rate the analysis ran at."""
    decimated = rec.metadata.get("decimated")
    rate = nominal_rate(rec)
    out = {
        "rate [Hz]": rate,
        "recording rate [Hz]": float(decimated["from_rate_Hz"]) if decimated else rate,
        "decimated above [Hz]": above,
        "decimation": dict(decimated) if decimated else None,
    }
    if not decimated:
        out["decimation_null_because"] = (
            f"the recording ({rate:g} Hz) is not faster than {above:g} Hz"
        )
    return out
