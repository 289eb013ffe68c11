"""A :class:`~rollerrig.recordings.formats._table.Table` of a file read in slices.

TDMS and MDF4 files hold channels in groups and are read a slice at a time (chunked reading,
:mod:`rollerrig.recordings.source`). Their readers share how a channel enters the table
(:func:`add_channel`: name, short name, groups, other spellings), how its slices are read
(:func:`read_in_slices`: whole columns are the slice ``0:length``, a read that fails or gives
fewer samples than the file promises is a damaged file) and how rollerrig's own provenance,
stored in the file as JSON text, is taken back (:func:`store_json`).
"""

from __future__ import annotations

import contextlib
import json
from collections.abc import Callable, Iterable
from typing import Any

import numpy as np

from rollerrig.recordings.formats._table import Column, Slicer, Table, add_alias, add_to_group
from rollerrig.recordings.recording import RecordingError

__all__ = ["add_channel", "checked_slice", "read_in_slices", "store_json"]


def add_channel(
    table: Table, name: str, base: str, *, groups: Iterable[Any] = (), aliases: Iterable[str] = ()
) -> None:
    """Add the channel ``name`` (short name ``base``) in ``groups``, also called ``aliases``."""
    table.names.append(name)
    table.base[name] = base
    for group in groups:
        add_to_group(table, group, name)
    for alias in aliases:
        add_alias(table, alias, name)


def read_in_slices(
    table: Table, length: Callable[[str], int], read: Callable[[str, int, int], Column]
) -> Table:
    """``table`` reading its columns with ``read(name, start, stop)``; ``load`` reads them whole."""
    table.load = lambda name: read(name, 0, length(name))
    table.slicer = Slicer(length=length, read=read)
    return table


def checked_slice(
    what: str, get: Callable[[], tuple], promised: int | None = None, promiser: str = ""
) -> tuple:
    """``get()``: what one read of a slice gives, each array in it checked to hold ``promised``
    samples (None: not checked).

    Raises
    ------
    RecordingError
        ``what`` could not be read, or gave another number of samples than ``promiser`` (the
        file's index, the data group) promises: the file is damaged or truncated. A
        RecordingError of ``get`` itself passes unchanged.
    """
    try:
        got = get()
    except RecordingError:
        raise
    except Exception as exc:
        raise RecordingError(
            f"{what} could not be read: {exc}; the file is damaged or truncated"
        ) from exc
    for values in got:
        if promised is not None and isinstance(values, np.ndarray) and values.shape[0] != promised:
            raise RecordingError(
                f"{what} gave {values.shape[0]} samples where {promiser} promises {promised}; "
                "the file is damaged or truncated"
            )
    return got


def store_json(table: Table, text: Any) -> None:
    """Set ``table.stored_metadata`` from JSON ``text`` rollerrig wrote (left unset if not JSON)."""
    with contextlib.suppress(json.JSONDecodeError, TypeError):
        table.stored_metadata = json.loads(text)
