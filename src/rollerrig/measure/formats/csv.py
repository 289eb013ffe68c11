"""CSV files (delimited text with a header row)."""

from __future__ import annotations

import json
import re
from pathlib import Path

from rollerrig.measure.formats._table import (
    Table,
    header_table,
)
from rollerrig.measure.recording import RecordingError


def read_csv(path: Path) -> Table:
    import pandas as pd

    notes = []
    encoding = "utf-8-sig"
    try:
        head = path.read_bytes()[:65536].decode(encoding)
    except UnicodeDecodeError:
        encoding = "latin-1"
        head = path.read_bytes()[:65536].decode(encoding)
        notes.append("CSV is not UTF-8; read as Latin-1")
    lines = [ln for ln in head.splitlines() if ln.strip()]
    if not lines:
        raise RecordingError(f"{path}: the CSV file is empty")
    sep = max([",", ";", "\t"], key=lambda s: lines[0].count(s))
    decimal = "."
    if sep != "," and len(lines) > 1 and re.search(r"\d,\d", lines[1]):
        decimal = ","
        notes.append("CSV uses decimal commas")
    try:
        frame = pd.read_csv(path, sep=sep, decimal=decimal, encoding=encoding)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, ValueError) as exc:
        raise RecordingError(f"{path}: not a readable CSV file: {exc}") from exc
    table = header_table(frame)
    table.notes += notes
    sidecar = path.with_suffix(".metadata.json")
    if sidecar.is_file():
        try:
            table.stored_metadata = json.loads(sidecar.read_text(encoding="utf-8"))
            table.notes.append(f"provenance read from {sidecar.name}")
        except json.JSONDecodeError:
            table.notes.append(f"sidecar {sidecar.name} is not valid JSON; ignored")
    return table
