"""Apache Parquet files."""

from __future__ import annotations

import json
from pathlib import Path

from rollerrig.measure.formats._table import (
    Table,
    header_table,
)
from rollerrig.measure.recording import RecordingError


def read_parquet(path: Path) -> Table:
    import pyarrow.parquet as pq

    try:
        arrow = pq.read_table(path)
    except Exception as exc:
        raise RecordingError(f"{path}: not a readable Parquet file: {exc}") from exc
    units: dict[str, str] = {}
    for f in arrow.schema:
        if f.metadata and b"unit" in f.metadata:
            units[f.name] = f.metadata[b"unit"].decode()
    stored = None
    meta = arrow.schema.metadata or {}
    if b"rollerrig" in meta:
        blob = json.loads(meta[b"rollerrig"])
        units = {**blob.get("units", {}), **units}
        stored = blob.get("metadata")
    table = header_table(arrow.to_pandas(), units=units)
    table.stored_metadata = stored
    return table
