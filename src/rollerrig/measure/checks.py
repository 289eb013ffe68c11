"""Refuse recordings an adhesion-test analysis cannot compute with, saying what to change.

Each check raises :class:`~rollerrig.recordings.recording.RecordingError` naming the file, the
channel, its file column and channel-map entry: inputs missing from the channel map
(:func:`require_analysis_inputs`), values no analysis can compute with
(:func:`check_channel_values`), a recording without a torque ramp
(:func:`require_adhesion_test`).
"""

from __future__ import annotations

import numpy as np

from rollerrig.measure.facts import describe_channel, source_prefix
from rollerrig.recordings.recording import Recording, RecordingError

__all__ = [
    "ANALYSED_CHANNELS",
    "check_channel_values",
    "require_adhesion_test",
    "require_analysis_inputs",
]

# Channels the analysis reads, checked for values it can compute with.
ANALYSED_CHANNELS = (
    "torque",
    "torque_request",
    "wheel_speed",
    "roller_speed",
    "wheel_encoder_counts",
    "roller_encoder_counts",
    "air_spring_pressure",
    "normal_load",
)
"""Channels an adhesion-test analysis reads, checked for values it can compute with."""

_TORQUE_RANGE_FACTOR = 10.0  # torque beyond 10 x the sensor's range: a unit or scale mistake

# What an adhesion-test analysis needs, each as alternatives a channel map can give.
_ANALYSIS_INPUTS = (
    (("torque",), "the roller-shaft torque T56"),
    (("roller_speed", "roller_encoder_counts"), "the roller speed"),
    (("wheel_speed", "wheel_encoder_counts"), "the wheel speed"),
    (("normal_load", "air_spring_pressure"), "the normal load"),
)


def check_channel_values(recording: Recording, names, rig=None) -> None:
    """Refuse channels whose values no analysis can compute with, naming channel and map entry.

    Every given channel (those present) must be finite and small enough that sums of squares
    over the recording stay finite; the torque must stay within 10 x the torque sensor's range
    of the rig (``sensors.torque_sensor_range``), beyond which it is a unit or scale mistake.

    Parameters
    ----------
    recording : Recording
    names : iterable of str
        Channels to check (absent ones are skipped).
    rig : RigParameters, optional
        For the torque sensor's range.

    Raises
    ------
    RecordingError
        Naming the file, the channel, its file column and map entry, and what to check.

    Examples
    --------
    >>> t = np.arange(4) / 250.0
    >>> rec = Recording(t, {"torque": np.full(4, 1e300)}, {"torque": "N.m"})
    >>> check_channel_values(rec, ["torque"])
    Traceback (most recent call last):
    ...
    rollerrig.recordings.recording.RecordingError: channel 'torque' (map entry [channels.torque]) reaches 1e+300 N.m: too large to compute with (its squares overflow); check the unit, scale and offset of that map entry
    """  # noqa: E501
    for name in names:
        if name not in recording:
            continue
        x = np.asarray(recording[name], dtype=float)
        unit = recording.units.get(name, "")
        what = f"{source_prefix(recording)}{describe_channel(recording, name)}"
        bad = ~np.isfinite(x)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            derived = name in ((recording.metadata.get("derived") or {}).get("channels") or ())
            hint = (
                "check the unit, scale and offset of the channels it is computed from in the "
                "channel map"
                if derived
                else "a lenient read (--lenient) interpolates short runs"
            )
            raise RecordingError(
                f"{what} has {int(bad.sum())} NaN/inf samples, first at sample {k}; {hint}"
            )
        peak = float(np.max(np.abs(x))) if x.size else 0.0
        with np.errstate(over="ignore"):
            overflow = not np.isfinite(np.sum(x * x))
        if overflow:
            raise RecordingError(
                f"{what} reaches {peak:.3g} {unit}: too large to compute with (its squares "
                "overflow); check the unit, scale and offset of that map entry"
            )
        if name == "torque" and rig is not None:
            rated = float(getattr(rig.sensors, "torque_sensor_range", 0.0) or 0.0)
            if rated > 0 and peak > _TORQUE_RANGE_FACTOR * rated:
                raise RecordingError(
                    f"{what} reaches {peak:.3g} N.m, more than {_TORQUE_RANGE_FACTOR:g} x the "
                    f"torque sensor's range ({rated:g} N.m, sensors.torque_sensor_range of the "
                    "rig file): check the unit and scale of that map entry (or the rig file)"
                )


def require_analysis_inputs(recording) -> None:
    """RecordingError naming the channel-map entries to add when an input is missing."""
    have = set(recording.names if hasattr(recording, "iter_chunks") else recording.channels)
    missing = [
        (names, what) for names, what in _ANALYSIS_INPUTS if not any(n in have for n in names)
    ]
    if missing:
        source = recording.metadata.get("source", "the recording")
        wants = "; ".join(
            f"{what}: [channels.{names[0]}]"
            + (f" or [channels.{names[1]}]" if len(names) > 1 else "")
            for names, what in missing
        )
        raise RecordingError(
            f"{source}: an adhesion-test analysis needs {wants}; add these entries to the "
            f"channel map (--channels), the recording has {sorted(have)}"
        )


def require_adhesion_test(rec: Recording, phases) -> None:
    """Refuse a recording without an adhesion test, naming the channel that was segmented."""
    source = "torque_request" if "torque_request" in rec else "torque"
    u = np.asarray(rec[source], dtype=float)
    t = rec.time
    # Noise of the segmented channel from successive differences (robust: MAD).
    d = np.diff(u)
    noise = 1.4826 * float(np.median(np.abs(d - np.median(d)))) / np.sqrt(2.0)
    rises = []
    for ph in phases:
        if ph.name != "ramp_up" or ph.start <= t[0]:
            continue
        i0, i1 = np.searchsorted(t, [ph.start, ph.end])
        i1 = min(int(i1), t.size - 1)
        a = float(np.median(u[max(int(i0) - 2, 0) : int(i0) + 3]))
        b = float(np.median(u[max(i1 - 2, 0) : i1 + 3]))
        rises.append(abs(b - a))
    if any(r > 5.0 * noise and r > 0 for r in rises):
        return
    unit = rec.units.get(source, "")
    lo, hi = float(np.min(u)), float(np.max(u))
    raise RecordingError(
        f"{source_prefix(rec)}no adhesion test found: {describe_channel(rec, source)} shows no "
        f"torque ramp rising from a resting level (it stays within {lo:.4g}..{hi:.4g} {unit}, "
        f"noise {noise:.3g} {unit}). `rollerrig analyze` needs a test with ramp, hold and release; "
        "for free rolling use `rollerrig spectrum`, and check that the map entry names the "
        "right column"
    )
