"""Put channels recorded on their own time bases onto one common time base.

Acquisition software writes channels of one file on different rasters (TDMS waveforms with their
own ``wf_increment``/``wf_start_offset``, MDF4 groups with their own master channel). Analyses
need one time base; this module decides it and moves every channel onto it.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rollerrig.measure.recording import RecordingError

__all__ = ["align_channels"]


def align_channels(
    time: np.ndarray,
    loaded: list,
    own_times: list,
    *,
    own_time_exact: bool,
    info: dict[str, Any],
    notes: list[str],
    where: str,
) -> tuple[np.ndarray, dict[str, np.ndarray], dict[str, str]]:
    """Channels on the reference ``time`` [s].

    Parameters
    ----------
    time : ndarray
        Reference time base [s].
    loaded : list of (ChannelSpec, values, SI unit, own time or None)
        Channels as read, in SI units.
    own_times : list of ndarray or None
        Each channel's own time base [s] (None: sample-aligned with ``time``).
    own_time_exact : bool
        Own time bases beat index alignment even when the lengths agree (MDF masters).
    info, notes : dict, list
        Provenance and reader notes, extended in place (``info["resampled"]``).
    where : str
        Prefix of error messages (the file).

    Returns
    -------
    time, channels, units
        The (possibly trimmed) common time [s], channel values and their SI units.
    """
    table_own_time_exact = own_time_exact
    channels: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    needs: list[int] = []
    for i, (spec, values, _si, _own) in enumerate(loaded):
        own = own_times[i]
        same = own is not None and own.size == time.size and np.allclose(own, time)
        if own is not None and not same and (table_own_time_exact or values.size != time.size):
            needs.append(i)
        elif values.size != time.size:
            raise RecordingError(
                f"{where} column {info['columns'][spec.name]!r} (channel map entry {spec.entry}) "
                f"has {values.size} samples, time has {time.size}"
            )
    if needs:
        starts = [time[0]] + [own_times[i][0] for i in needs]
        ends = [time[-1]] + [own_times[i][-1] for i in needs]
        lo, hi = max(starts), min(ends)
        keep = (time >= lo) & (time <= hi)
        if not keep.any():
            raise RecordingError(f"{where} the channels' time ranges do not overlap")
        resampled = {}
        for i in needs:
            spec, values, own = loaded[i][0], loaded[i][1], own_times[i]
            if own.size != values.size or np.any(np.diff(own) <= 0):
                raise RecordingError(
                    f"{where} column {info['columns'][spec.name]!r}: its time base is not "
                    "strictly increasing or has the wrong length"
                )
            rate = 1.0 / float(np.median(np.diff(own))) if own.size > 1 else float("nan")
            resampled[spec.name] = {"from_rate_Hz": rate, "method": "linear"}
        ref_rate = 1.0 / float(np.median(np.diff(time))) if time.size > 1 else float("nan")
        info["resampled"] = {
            "onto": info["columns"].get("time", "time"),
            "rate_Hz": ref_rate,
            "channels": resampled,
        }
        notes.append(
            f"channels {sorted(resampled)} resampled (linear) onto the time base of "
            f"{info['resampled']['onto']} ({ref_rate:.6g} Hz)"
        )
        if not keep.all():
            notes.append(
                f"time trimmed to the common span {lo:.6g} s .. {hi:.6g} s "
                f"({int((~keep).sum())} samples dropped)"
            )
        full_time = time
        time = time[keep]
        for i, (spec, values, si, _own) in enumerate(loaded):
            if i in needs:
                channels[spec.name] = np.interp(time, own_times[i], values)
            else:
                channels[spec.name] = values[keep] if values.size == full_time.size else values
            units[spec.name] = si
    else:
        for spec, values, si, _ in loaded:
            channels[spec.name] = values
            units[spec.name] = si
    return np.asarray(time, dtype=float), channels, units
