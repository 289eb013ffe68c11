"""ASAM MDF 4 files (INCA, CANape, CANedge, asammdf).

Measurement tools write one data group per acquisition raster (INCA: "10ms", "100ms", ...;
CANape: one group per measurement raster or CAN message), each with its own master channel, all
named ``time``, and the same channel name may occur in several groups. A channel that occurs once
is addressed by its name; otherwise its table name is ``<group>/<name>``, where ``<group>`` is the
group's acquisition name (when it is unique in the file) or its index, and the aliases
``<index>/<name>``, ``<acquisition name>/<name>``, ``<comment>/<name>`` and
``<source name or path>/<name>`` address it too. A plain name that occurs in several groups is
ambiguous (the error lists the qualified candidates) unless the map's ``[file] group`` names the
group. Raw bus logging (CANedge and other loggers: ``CAN_DataFrame`` frames without decoded
signals) is refused with the way to decode it.
"""

from __future__ import annotations

import contextlib
import gc
import sys
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from rollerrig.recordings.channels import time_unit
from rollerrig.recordings.formats._sliced import (
    add_channel,
    checked_slice,
    read_in_slices,
    store_json,
)
from rollerrig.recordings.formats._table import Column, Table, add_alias, require_module
from rollerrig.recordings.recording import RecordingError

_BUS_FRAMES = (
    "CAN_DataFrame",
    "CAN_RemoteFrame",
    "CAN_ErrorFrame",
    "CAN_OverloadFrame",
    "LIN_Frame",
    "LIN_SyncError",
    "LIN_TransmissionError",
    "LIN_ChecksumError",
    "LIN_ReceiveError",
    "FLX_Frame",
    "ETH_Frame",
    "MOST_Packet",
)
"""Channel names (ASAM MDF 4.1 bus logging) of raw bus frames."""

_FLAG_CG_BUS_EVENT = 1 << 1  # ASAM MDF 4.1 CG flag "bus event"


def _hd_comment_text(comment: str) -> str:
    try:
        root = ET.fromstring(comment)
    except ET.ParseError:
        return comment
    tx = root.find("TX")
    return tx.text if tx is not None and tx.text else comment


def _text(value) -> str:
    return value.strip() if isinstance(value, str) else ""


def _group_labels(cg) -> dict[str, str]:
    """What a data group can be called by: acquisition name, comment, source name and path."""
    labels = {"acquisition name": _text(getattr(cg, "acq_name", ""))}
    comment = _text(getattr(cg, "comment", ""))
    labels["comment"] = _hd_comment_text(comment).strip() if comment else ""
    source = getattr(cg, "acq_source", None)
    if source is not None:
        labels["source"] = _text(getattr(source, "name", ""))
        labels["source path"] = _text(getattr(source, "path", ""))
    return {k: v for k, v in labels.items() if v}


def _is_bus_group(group) -> bool:
    cg = group.channel_group
    if int(getattr(cg, "flags", 0) or 0) & _FLAG_CG_BUS_EVENT:
        return True
    return any(ch.name.split(".")[0] in _BUS_FRAMES for ch in group.channels)


def _open_quietly(asammdf, path: Path):
    """``asammdf.MDF(path)``, or None and the reason.

    When asammdf fails half-way through opening a damaged file, the half-built object's
    ``__del__`` raises ``AttributeError`` as it is freed ("Exception ignored in ...", printed to
    stderr); that noise is swallowed here, the reason is returned instead.
    """
    hook = sys.unraisablehook

    def quiet(unraisable) -> None:
        if not (
            isinstance(unraisable.exc_value, AttributeError) and "MDF" in repr(unraisable.object)
        ):
            hook(unraisable)

    sys.unraisablehook = quiet
    try:
        try:
            return asammdf.MDF(str(path)), None
        except Exception as exc:
            problem = str(exc) or type(exc).__name__
        gc.collect()
        return None, problem
    finally:
        sys.unraisablehook = hook


@contextlib.contextmanager
def open_mdf(path: Path) -> Iterator[Table]:
    asammdf = require_module("asammdf", "MDF4 files")
    mdf, problem = _open_quietly(asammdf, path)
    if mdf is None:
        raise RecordingError(
            f"{path}: not a readable MDF file: {problem} (damaged, truncated or not ASAM MDF)"
        )
    try:
        try:
            table = _table(mdf, path)
        except RecordingError:
            raise
        except Exception as exc:  # a damaged block structure that asammdf read without complaint
            raise RecordingError(f"{path}: not a readable MDF file: {exc}") from exc
        yield table
    finally:
        mdf.close()


def _table(mdf, path: Path) -> Table:
    groups = mdf.groups
    masters = getattr(mdf, "masters_db", {}) or {}
    labels = [_group_labels(g.channel_group) for g in groups]
    acq_names = [lab.get("acquisition name", "") for lab in labels]
    records = [int(getattr(g.channel_group, "cycles_nr", 0) or 0) for g in groups]

    # bus logging: raw frames, no signals
    bus = {i for i, g in enumerate(groups) if _is_bus_group(g)}
    signals = [
        (i, j, ch.name)
        for i, g in enumerate(groups)
        if i not in bus
        for j, ch in enumerate(g.channels)
    ]
    if bus and not [s for s in signals if masters.get(s[0]) != s[1]]:
        frames = sorted(
            {ch.name.split(".")[0] for i in bus for ch in groups[i].channels} & set(_BUS_FRAMES)
        ) or ["bus events"]
        where = ", ".join(
            f"data group {i}" + (f" ({acq_names[i]!r})" if acq_names[i] else "")
            for i in sorted(bus)
        )
        names = sorted({ch.name for i in bus for ch in groups[i].channels})
        raise RecordingError(
            f"{path}: this MDF file holds raw bus logging ({', '.join(frames)} in {where}), not "
            "decoded signals; decode it with the bus database (DBC/ARXML) first, e.g. "
            "asammdf.MDF(path).extract_bus_logging({'CAN': [('rig.dbc', 0)]}).save('decoded.mf4') "
            f"(or the logger vendor's converter), and read the decoded file; channels in this "
            f"file: {names[:40]}"
        )

    count: dict[str, int] = {}
    for _, _, name in signals:
        count[name] = count.get(name, 0) + 1
    label_count: dict[str, int] = {}
    for a in acq_names:
        if a:
            label_count[a] = label_count.get(a, 0) + 1

    table = Table(names=[], load=lambda n: None)  # type: ignore[arg-type,return-value]
    where_of: dict[str, tuple[int, int]] = {}
    empty_duplicates: list[str] = []
    for i, j, name in signals:
        label = acq_names[i] if acq_names[i] and label_count[acq_names[i]] == 1 else str(i)
        qualified = name if count[name] == 1 else f"{label}/{name}"
        if qualified in where_of:  # the same name twice in one group
            qualified = f"{i}/{name}#{j}"
        where_of[qualified] = (i, j)
        group_keys = list(dict.fromkeys([str(i), *labels[i].values()]))
        aliases = [f"{key}/{name}" for key in group_keys]
        add_channel(table, qualified, name, groups=group_keys, aliases=aliases)
        if count[name] > 1:
            if records[i] == 0 and any(
                records[k] > 0 for k, _, n in signals if n == name and k != i
            ):
                if masters.get(i) != j:
                    empty_duplicates.append(qualified)
            else:
                add_alias(table, name, qualified)
    if empty_duplicates:
        table.notes.append(
            f"MDF channels {empty_duplicates} are in data groups without records; their plain "
            "names mean the channel of the same name in a group with records"
        )
    if bus:
        table.skipped.append(
            "raw bus frames in data group(s) "
            f"{sorted(bus)} (decode with a DBC first: asammdf MDF.extract_bus_logging)"
        )

    def describe(i: int) -> str:
        lab = labels[i]
        text = ", ".join(f"{k} {v!r}" for k, v in lab.items())
        return f"data group {i}" + (f" ({text})" if text else "")

    def length(name: str) -> int:
        return records[where_of[name][0]]

    # A master that is not a time (an angle, a distance, an index: cn_sync_type 2-4) is no time
    # base: its values were taken as seconds (a crank angle of 0.5 deg a step read as 2 Hz).
    not_time = {
        i: _SYNC_TYPES.get(sync, f"sync type {sync}")
        for i, j in masters.items()
        if i < len(groups) and j is not None and j < len(groups[i].channels)
        if (sync := int(getattr(groups[i].channels[j], "sync_type", 1) or 0)) not in (0, 1)
    }
    if not_time:
        table.notes.append(
            "MDF data group(s) "
            + ", ".join(f"{i} ({kind})" for i, kind in sorted(not_time.items()))
            + " have a master that is not time: their channels have no time base of their own "
            "(give [time] sample_rate_Hz or a time column in the channel map)"
        )

    def unit_of(i: int, j: int, unit: str | None) -> str | None:
        """The channel's unit, else its conversion rule's (ASAM MDF 4: INCA and CANape
        often write it there only); "" is no unit."""
        if unit:
            return unit
        conversion = getattr(groups[i].channels[j], "conversion", None)
        return getattr(conversion, "unit", None) or None

    # The raw records of the last range read, shared by the channels of a group (one disk read
    # per chunk, not one per channel). asammdf's get(record_offset=, record_count=) reads the
    # whole group when it holds more than 200 MB and slices afterwards; its records are read
    # here as asammdf's own MDF.iter_get reads them (_load_data fragments passed to get(data=)).
    fragments: dict[tuple[int, int, int], list] = {}
    load_data = getattr(getattr(mdf, "_mdf", None), "_load_data", None)

    # Samples the logger flagged invalid (MDF4 invalidation bits) are kept, as NaN: asammdf
    # drops them by default, which left a channel shorter than its group's time base.
    def _get(i: int, j: int, start: int, stop: int) -> tuple[np.ndarray, np.ndarray, str | None]:
        if load_data is None or (start == 0 and stop == records[i]):
            sig = mdf.get(
                group=i,
                index=j,
                record_offset=start,
                record_count=stop - start,
                ignore_invalidation_bits=True,
            )
            return _valid(sig), np.asarray(sig.timestamps, dtype=float), unit_of(i, j, sig.unit)
        key = (i, start, stop)
        if key not in fragments:
            fragments.clear()
            fragments[key] = list(
                load_data(groups[i], record_offset=start, record_count=stop - start)
            )
        parts = [
            mdf.get(group=i, index=j, data=f, ignore_invalidation_bits=True) for f in fragments[key]
        ]
        if not parts:
            return np.zeros(0), np.zeros(0), None
        values = np.concatenate([_valid(p) for p in parts])
        stamps = np.concatenate([np.asarray(p.timestamps, dtype=float) for p in parts])
        return values, stamps, unit_of(i, j, parts[0].unit)

    def read(name: str, start: int, stop: int) -> Column:
        i, j = where_of[name]
        n = records[i]
        if n == 0:
            others = [q for q in table.names if table.base[q] == table.base[name] and q != name]
            raise RecordingError(
                f"{path}: MDF channel {name!r} is in {describe(i)}, which holds no samples "
                "(0 records)"
                + (f"; the same name with samples: {others}" if others else "")
                + "; map another channel or group"
            )
        start, stop = max(0, start), min(n, stop)
        values, stamps, unit = checked_slice(
            f"{path}: MDF channel {name!r} ({describe(i)})",
            lambda: _get(i, j, start, stop),
            stop - start,
            "the group",
        )
        if i in not_time:
            if masters.get(i) == j:  # the master itself: an angle, not seconds
                unit = unit if unit and time_unit(unit) is None else not_time[i]
            return Column(values, unit, None)
        return Column(values, unit, stamps)

    table.own_time_exact = True
    comment = getattr(mdf.header, "comment", "") or ""
    if comment:
        store_json(table, _hd_comment_text(comment))
    return read_in_slices(table, length, read)


_SYNC_TYPES = {2: "angle", 3: "distance", 4: "index"}
"""ASAM MDF 4 cn_sync_type of a master channel that is not time (1)."""


def _valid(signal) -> np.ndarray:
    """An asammdf signal's samples with those its invalidation bits flag as NaN (numbers
    become floats for it); the samples as they are when none is flagged."""
    values = np.asarray(signal.samples)
    bits = getattr(signal, "invalidation_bits", None)
    if bits is None:
        return values
    flagged = np.asarray(bits, dtype=bool)
    if not flagged.any():
        return values
    if values.dtype.kind not in "biuf":
        raise RecordingError(
            f"MDF channel {signal.name!r}: {int(flagged.sum())} sample(s) flagged invalid in a "
            f"channel of {values.dtype} values, which has no NaN to mark them"
        )
    values = values.astype(float)
    values[flagged] = np.nan
    return values
