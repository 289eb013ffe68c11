"""Format readers: each turns one file format into a :class:`Table` of named columns.

The channel map is applied afterwards, in :mod:`rollerrig.measure.readers`, the same way for every
format.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from pathlib import Path

from rollerrig.measure.formats._table import Column, Table
from rollerrig.measure.formats.csv import read_csv
from rollerrig.measure.formats.mat import read_mat
from rollerrig.measure.formats.mdf import open_mdf
from rollerrig.measure.formats.parquet import read_parquet
from rollerrig.measure.formats.tdms import open_tdms

__all__ = ["Column", "Table", "open_table"]


@contextlib.contextmanager
def open_table(path: Path, fmt: str) -> Iterator[Table]:
    if fmt == "csv":
        yield read_csv(path)
    elif fmt == "parquet":
        yield read_parquet(path)
    elif fmt == "mat":
        yield read_mat(path)
    elif fmt == "tdms":
        with open_tdms(path) as t:
            yield t
    else:
        with open_mdf(path) as t:
            yield t
