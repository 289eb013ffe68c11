"""NI TDMS files (LabVIEW, DAQmx logging)."""

from __future__ import annotations

import contextlib
import json
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from rollerrig.measure.formats._table import (
    META_KEY,
    Column,
    Table,
    add_alias,
    require_module,
)
from rollerrig.measure.recording import RecordingError


@contextlib.contextmanager
def open_tdms(path: Path) -> Iterator[Table]:
    nptdms = require_module("nptdms", "TDMS files")
    try:
        tdms = nptdms.TdmsFile.read(str(path))
    except Exception as exc:
        raise RecordingError(f"{path}: not a readable TDMS file: {exc}") from exc
    chans = {}
    table = Table(names=[], load=lambda n: None)  # type: ignore[arg-type,return-value]
    for group in tdms.groups():
        for ch in group.channels():
            name = f"{group.name}/{ch.name}"
            chans[name] = ch
            table.names.append(name)
            table.base[name] = ch.name
            add_alias(table, ch.name, name)
            add_alias(table, ch.path, name)

    def load(name: str) -> Column:
        ch = chans[name]
        values = ch[:]
        props = ch.properties
        own = None
        if "wf_increment" in props and float(props["wf_increment"]) > 0:
            inc = float(props["wf_increment"])
            own = float(props.get("wf_start_offset", 0.0)) + np.arange(len(values)) * inc
        unit = props.get("unit_string") or None
        return Column(np.asarray(values), unit, own)

    table.load = load
    raw = tdms.properties.get(META_KEY)
    if raw:
        with contextlib.suppress(json.JSONDecodeError, TypeError):
            table.stored_metadata = json.loads(raw)
    yield table
