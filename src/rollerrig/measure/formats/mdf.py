"""ASAM MDF 4 files (INCA, CANape, CANedge, asammdf)."""

from __future__ import annotations

import contextlib
import json
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from rollerrig.measure.formats._table import (
    Column,
    Table,
    require_module,
)
from rollerrig.measure.recording import RecordingError


def _hd_comment_text(comment: str) -> str:
    try:
        root = ET.fromstring(comment)
    except ET.ParseError:
        return comment
    tx = root.find("TX")
    return tx.text if tx is not None and tx.text else comment


@contextlib.contextmanager
def open_mdf(path: Path) -> Iterator[Table]:
    asammdf = require_module("asammdf", "MDF4 files")
    try:
        mdf = asammdf.MDF(str(path))
    except Exception as exc:
        raise RecordingError(f"{path}: not a readable MDF file: {exc}") from exc
    try:
        db = mdf.channels_db
        table = Table(names=list(db), load=lambda n: None)  # type: ignore[arg-type,return-value]
        for name in table.names:
            table.base[name] = name

        def load(name: str) -> Column:
            occurrences = db[name]
            group, index = occurrences[0]
            if len(occurrences) > 1:
                table.notes.append(
                    f"MDF channel {name!r} occurs {len(occurrences)} times; "
                    f"the one in data group {group} was read"
                )
            sig = mdf.get(name, group=group, index=index)
            return Column(
                np.asarray(sig.samples), sig.unit or None, np.asarray(sig.timestamps, dtype=float)
            )

        table.load = load
        table.own_time_exact = True
        comment = getattr(mdf.header, "comment", "") or ""
        if comment:
            with contextlib.suppress(json.JSONDecodeError, TypeError):
                table.stored_metadata = json.loads(_hd_comment_text(comment))
        yield table
    finally:
        mdf.close()
