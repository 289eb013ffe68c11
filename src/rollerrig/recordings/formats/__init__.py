"""Format readers: each turns one file format into a :class:`Table` of named columns.

One module per format (:mod:`.csv`, :mod:`.twincat`, :mod:`.lvm`, :mod:`.parquet`,
:mod:`.tdms`, :mod:`.mdf`, :mod:`.mat`, :mod:`.xlsx`) and what they share: :mod:`._table` (the
table, optional imports), :mod:`.sniff` (the layout of a text file), :mod:`._header` (its header and
units rows), :mod:`._text` (cells, lines, bytes of text files), :mod:`.timestamps` (date/time
columns), :mod:`._sliced` (channels in groups read in slices). The channel map is applied
afterwards, in :mod:`rollerrig.recordings.translate`, the same way for every format.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from pathlib import Path

from rollerrig.recordings.channels import FileSpec
from rollerrig.recordings.formats._table import Column, Table, apply_default_group
from rollerrig.recordings.formats.csv import read_csv
from rollerrig.recordings.formats.lvm import read_lvm
from rollerrig.recordings.formats.mat import read_mat
from rollerrig.recordings.formats.mdf import open_mdf
from rollerrig.recordings.formats.parquet import read_parquet
from rollerrig.recordings.formats.tdms import open_tdms
from rollerrig.recordings.formats.twincat import read_twincat, reads_as_twincat
from rollerrig.recordings.formats.xlsx import read_xlsx
from rollerrig.recordings.recording import RecordingError

__all__ = ["Column", "Table", "open_table"]


@contextlib.contextmanager
def open_table(path: Path, fmt: str, spec: FileSpec | None = None) -> Iterator[Table]:
    """The file as a :class:`Table`; ``spec`` is the channel map's ``[file]`` section.
    ``fmt`` ``"twincat"``: a text file already known to be a TwinCAT Scope export
    (:func:`~rollerrig.recordings.formats.twincat.reads_as_twincat`; ``"csv"`` asks it)."""
    if path.stat().st_size == 0:  # every format's own error would be about something else
        raise RecordingError(f"{path}: the file is empty (0 bytes)")
    if fmt == "twincat" or (fmt == "csv" and reads_as_twincat(path, spec)):
        # a TwinCAT Scope export: channels with time columns of their own, ragged rows
        yield read_twincat(path, spec)
    elif fmt == "csv":
        yield read_csv(path, spec)
    elif fmt == "lvm":
        yield read_lvm(path, spec)
    elif fmt == "parquet":
        yield read_parquet(path)
    elif fmt == "mat":
        yield read_mat(path)
    elif fmt == "xlsx":
        yield read_xlsx(path, spec)
    elif fmt == "tdms":
        with open_tdms(path) as t:
            _default_group(t, spec, path)
            yield t
    else:
        with open_mdf(path) as t:
            _default_group(t, spec, path)
            yield t


def _default_group(table: Table, spec: FileSpec | None, path: Path) -> None:
    group = getattr(spec, "group", None)
    if group is not None:
        apply_default_group(table, group, f"{path}:")
