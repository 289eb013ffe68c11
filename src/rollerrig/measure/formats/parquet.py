"""Apache Parquet files.

Columns are read one at a time, only those asked for; :attr:`Table.slicer` reads parts of a
column by row group (chunked reading).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from rollerrig.measure.channels import split_unit_header
from rollerrig.measure.formats._table import Column, Slicer, Table, add_alias
from rollerrig.measure.recording import RecordingError


def _numpy(chunked) -> np.ndarray:
    """A pyarrow column as numpy, as pandas would give it (nulls -> NaN / None)."""
    return chunked.to_pandas().to_numpy()


def read_parquet(path: Path) -> Table:
    import pyarrow.parquet as pq

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
    table = Table(names=names, load=lambda n: None, stored_metadata=stored)  # type: ignore[arg-type,return-value]
    header_units: dict[str, str | None] = {}
    for name in names:
        base, unit = split_unit_header(name)
        header_units[name] = unit
        table.base[name] = base
        add_alias(table, base, name)

    def unit_of(name: str) -> str | None:
        return header_units[name] or units.get(name) or units.get(table.base[name])

    cache: dict[str, tuple[int, int, np.ndarray]] = {}  # column -> (first, last group, values)

    def read(name: str, start: int, stop: int) -> Column:
        start, stop = max(0, start), min(n_rows, stop)
        g0 = int(np.searchsorted(starts, start, side="right")) - 1
        g1 = max(g0, int(np.searchsorted(starts, stop, side="left")) - 1)
        hit = cache.get(name)
        try:
            if start >= stop:
                values = _numpy(pf.schema_arrow.empty_table().column(name))
                return Column(values, unit_of(name))
            if hit is None or hit[0] > g0 or hit[1] < g1:
                groups = list(range(g0, g1 + 1))
                part = pf.read_row_groups(groups, columns=[name]).column(0)
                hit = (g0, g1, _numpy(part))
                cache[name] = hit
        except Exception as exc:
            raise RecordingError(
                f"{path}: Parquet column {name!r} could not be read: {exc}; the file is damaged "
                "or truncated"
            ) from exc
        offset = int(starts[hit[0]])
        return Column(hit[2][start - offset : stop - offset], unit_of(name))

    def load(name: str) -> Column:
        try:
            values = _numpy(pq.read_table(path, columns=[name]).column(0))
        except Exception as exc:
            raise RecordingError(
                f"{path}: Parquet column {name!r} could not be read: {exc}; the file is damaged "
                "or truncated"
            ) from exc
        return Column(values, unit_of(name))

    table.load = load
    table.slicer = Slicer(length=lambda name: n_rows, read=read)
    return table
