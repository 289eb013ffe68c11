"""Apache Parquet files.

Columns are read one at a time, only those asked for; :attr:`Table.slicer` reads parts of a
column by row group (chunked reading).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from rollerrig.recordings.formats._sliced import checked_slice
from rollerrig.recordings.formats._table import Column, Slicer, Table, header_table, require_module
from rollerrig.recordings.recording import RecordingError


def _numpy(chunked) -> np.ndarray:
    """A pyarrow column as numpy, as pandas would give it (nulls -> NaN / None); timestamps
    with a time zone as UTC datetime64 (as objects, pandas' Timestamps went through the text
    parser: 42 s for 2 million rows)."""
    pa = require_module("pyarrow", "Parquet files")
    kind = chunked.type
    if pa.types.is_timestamp(kind) and kind.tz is not None:
        chunked = chunked.cast(pa.timestamp(kind.unit))  # the UTC instants, as stored
    return chunked.to_pandas().to_numpy()


def read_parquet(path: Path) -> Table:
    pq = require_module("pyarrow.parquet", "Parquet files")
    pd = require_module("pandas", "Parquet files")

    try:
        pf = pq.ParquetFile(path)
        schema = pf.schema_arrow
        n_rows = pf.metadata.num_rows
        starts = np.cumsum(
            [0] + [pf.metadata.row_group(i).num_rows for i in range(pf.num_row_groups)]
        )
    except Exception as exc:
        raise RecordingError(f"{path}: not a readable Parquet file: {exc}") from exc
    units: dict[str, str] = {}
    for f in schema:
        if f.metadata and b"unit" in f.metadata:
            units[f.name] = f.metadata[b"unit"].decode()
    stored = None
    meta = schema.metadata or {}
    if b"rollerrig" in meta:
        try:
            blob = json.loads(meta[b"rollerrig"])
            units = {**blob.get("units", {}), **units}
            stored = blob.get("metadata")
        except (json.JSONDecodeError, TypeError, AttributeError):
            pass
    names = [str(n) for n in schema.names]
    # names, short names and units as for a table of columns with "name [unit]" headers
    table = header_table(pd.DataFrame(columns=names), units=units)
    unit = {name: table.load(name).unit for name in names}
    table.stored_metadata = stored

    cache: dict[str, tuple[int, int, np.ndarray]] = {}  # column -> (first, last group, values)

    def read(name: str, start: int, stop: int) -> Column:
        start, stop = max(0, start), min(n_rows, stop)
        g0 = int(np.searchsorted(starts, start, side="right")) - 1
        g1 = max(g0, int(np.searchsorted(starts, stop, side="left")) - 1)
        if start >= stop:
            (values,) = checked_slice(
                f"{path}: Parquet column {name!r}",
                lambda: (_numpy(pf.schema_arrow.empty_table().column(name)),),
            )
            return Column(values, unit[name])
        hit = cache.get(name)
        if hit is None or hit[0] > g0 or hit[1] < g1:
            groups = list(range(g0, g1 + 1))
            (values,) = checked_slice(
                f"{path}: Parquet column {name!r}",
                lambda: (_numpy(pf.read_row_groups(groups, columns=[name]).column(0)),),
            )
            hit = cache[name] = (g0, g1, values)
        offset = int(starts[hit[0]])
        return Column(hit[2][start - offset : stop - offset], unit[name])

    def load(name: str) -> Column:
        (values,) = checked_slice(
            f"{path}: Parquet column {name!r}",
            lambda: (_numpy(pq.read_table(path, columns=[name]).column(0)),),
        )
        return Column(values, unit[name])

    table.load = load
    table.slicer = Slicer(length=lambda name: n_rows, read=read)
    return table
