"""MATLAB .mat files (v4/v5/v7 via scipy; v7.3 and plain HDF5 via h5py, read lazily).

Variables that are numeric vectors become columns; structs are flattened (``meas.torque``).
Units come from a struct ``units`` of text fields (``units.torque = 'N.m'``, as
:func:`rollerrig.output.write_table` writes it) or from the JSON text variable
``rollerrig_units`` of older rollerrig files; ``rollerrig_metadata`` and ``provenance`` (JSON
text) give the stored metadata and provenance.
HDF5-based files (v7.3) are read one variable at a time, and :attr:`Table.slicer` reads parts
of a variable (chunked reading); v4-v7 files are read whole by :func:`scipy.io.loadmat`.

Cell arrays of numbers (v7.3: a dataset of HDF5 object references into ``#refs#``, as MATLAB
writes them) are read as one column: a cell of numeric vectors (segments) is joined in
MATLAB's order, a cell of per-sample scalars becomes the vector of those scalars. Every element
is an HDF5 object of its own (slow to open), so a cell of more than :data:`MAX_CELL_ELEMENTS`
elements, or one that holds text, structs or nested cells, is not read; the note (and the error
when a channel map names it) names the field and what to save instead (``cell2mat``).

A struct array (Simulink's "Structure with time", ``logsout.signals(k).values``; dSPACE
ControlDesk's ``Y(k).Data``) gives element k's fields as ``name(k).field``; where an element
labels its signal (``label``, ``name``), the label names its ``values`` (``Data``) too.

A 2-D numeric matrix (``data``, n x k, as many lab scripts save) is read when the file holds
exactly one cell array (or char matrix) of k texts beside it that no other matrix matches: its
columns become channels named by those texts (``"torque [N.m]"`` gives the unit, as a CSV
header does; a cell array called ``units`` of k texts gives units too), and a column named
``time`` is the time as elsewhere. A k x n matrix whose k rows match the names is read by rows.
Any other matrix is not read; when nothing else is readable either, the error lists the
variables (names and shapes) and what layout to save instead.

MATLAB class objects (``timeseries``, ``table``, ``timetable``, ``datetime``, ``string``,
Simulink datasets...) hold their data in MATLAB's private "MCOS" stream, which only MATLAB can
decode. They are not read; they are listed by name and class (v5: scipy's ``MatlabOpaque``
carries both; scipy names every top-level object ``None``, so the file is split into its
variables to list each one), with the MATLAB code that saves their data as plain arrays.
"""

from __future__ import annotations

import contextlib
import json
import re
import warnings
import weakref
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from rollerrig.recordings.channels import split_unit_header
from rollerrig.recordings.formats._table import (
    META_KEY,
    PROVENANCE_KEY,
    UNITS_KEY,
    UNITS_STRUCT,
    Column,
    Slicer,
    Table,
    add_alias,
    require_module,
)
from rollerrig.recordings.recording import RecordingError

MAX_CELL_ELEMENTS = 10_000
"""Most elements of a v7.3 cell array read as a column (each is an HDF5 object of its own)."""


def _cell_advice(name: str, numbers: bool = True) -> str:
    """What to save instead of the cell array ``name`` (MATLAB code for the user to run)."""
    if numbers:
        fix = f"in MATLAB: {name} = cell2mat({name}(:)); then save again"
    else:
        fix = "convert it to numbers in MATLAB (e.g. seconds since the start) and save again"
    return f"save a numeric vector instead ({fix}), or export the signals as CSV or MDF4"


def _object_class(value) -> tuple[str, str] | None:
    """``(name stored in it, MATLAB class)`` of a v5 MATLAB class object (scipy's
    ``MatlabOpaque``); None for anything else. The stored name is empty inside structs/cells."""
    try:
        from scipy.io.matlab import MatlabOpaque
    except ImportError:  # pragma: no cover - read_mat needs scipy anyway
        return None
    if not isinstance(value, MatlabOpaque) or value.size < 1:
        return None

    def text(field: str) -> str:
        raw = value.reshape(-1)[0][field]
        return raw.decode("latin-1") if isinstance(raw, bytes) else str(raw)

    try:
        return text("s0"), text("s2") or "unknown class"
    except (KeyError, ValueError, IndexError):
        return "", "unknown class"


def _object_fix(name: str, cls: str) -> str:
    """MATLAB code that saves the data of object ``name`` of class ``cls`` as plain arrays."""
    last = re.sub(r"\(\d+\)", "", name).rsplit(".", 1)[-1]
    short = re.sub(r"^ts_|_ts$", "", last, flags=re.IGNORECASE)
    data = short if short.isidentifier() else last
    if cls == "timeseries":
        return f"t = {name}.Time; {data} = {name}.Data; save('out.mat', 't', '{data}')"
    if cls == "table":
        return f"writetable({name}, 'out.csv')"
    if cls == "timetable":
        return f"writetimetable({name}, 'out.csv')"
    if cls == "datetime":
        return f"{name} = posixtime({name}) (seconds since 1970) before saving"
    if cls == "duration":
        return f"{name} = seconds({name}) before saving"
    if cls == "string":
        return f"{name} = char({name}) before saving"
    if cls.startswith("Simulink."):
        return (
            f"s = {name}.getElement(1).Values; t = s.Time; x = s.Data; save('out.mat', 't', "
            "'x'), or log in the format 'Structure with time'"
        )
    return f"take the numbers out of {name} and save them as numeric vectors"


def _object_entry(name: str, cls: str) -> str:
    """The ``skipped`` entry of the MATLAB object ``name``: its class and what to save."""
    return (
        f"{name} (MATLAB {cls} object, which cannot be read outside MATLAB: save its data as "
        f"plain arrays, e.g. {_object_fix(name, cls)})"
    )


def _objects_text(objects: Mapping[str, str]) -> str:
    """The objects (name -> class) and, once per class, the MATLAB code that saves their data."""
    listed = ", ".join(f"{n} ({c})" for n, c in objects.items())
    first = {c: n for n, c in reversed(list(objects.items()))}  # class -> its first variable
    ordered = list(reversed(list(first.items())))
    fixes = (
        _object_fix(ordered[0][1], ordered[0][0])
        if len(ordered) == 1
        else "; ".join(f"for a {c}: {_object_fix(n, c)}" for c, n in ordered)
    )
    return (
        f"it holds MATLAB objects: {listed}; MATLAB objects (timeseries, table, timetable, ...) "
        f"cannot be read outside MATLAB: save their data as plain arrays, e.g. {fixes}"
    )


def _text_list(value) -> list[str] | None:
    """The texts of a cell array of strings or of a char matrix (rows); None if not that."""
    if isinstance(value, list | tuple) or (isinstance(value, np.ndarray) and value.dtype == object):
        items = (
            list(value) if isinstance(value, list | tuple) else list(value.reshape(-1, order="F"))
        )
        if items and all(isinstance(v, str) for v in items):
            return [v.strip() for v in items]
        return None
    if isinstance(value, np.ndarray) and value.dtype.kind == "U" and value.ndim == 1:
        return [str(v).strip() for v in value]
    return None


def _flatten_mat(
    data: Mapping[str, Any],
    prefix: str,
    out: dict,
    skipped: list,
    matrices: dict | None = None,
    texts: dict | None = None,
    objects: dict | None = None,
) -> None:
    """Numeric vectors and text into ``out``; 2-D numeric matrices into ``matrices`` and lists
    of texts (cell arrays of strings, char matrices) into ``texts`` as ``(texts, value)``, to
    be paired (:func:`_pair_matrices`); MATLAB class objects into ``objects`` (name -> class);
    what else is not readable into ``skipped``."""
    matrices = {} if matrices is None else matrices
    texts = {} if texts is None else texts
    objects = {} if objects is None else objects
    for key, value in data.items():
        if key.startswith("__") or key.startswith("#"):
            continue
        name = f"{prefix}{key}"
        if (found := _object_class(value)) is not None:
            objects[name] = found[1]
        elif isinstance(value, Mapping):
            _flatten_mat(value, f"{name}.", out, skipped, matrices, texts, objects)
        elif _is_struct_list(value):  # a struct array: element k's fields as name(k).field
            for k, element in enumerate(value):
                _flatten_mat(element, f"{name}({k + 1}).", out, skipped, matrices, texts, objects)
        elif isinstance(value, str):
            out[name] = value
        elif (listed := _text_list(value)) is not None:
            texts[name] = (listed, value)
        elif isinstance(value, list | tuple) or (
            isinstance(value, np.ndarray) and value.dtype == object
        ):
            _flatten_cell(name, value, out, skipped)
        else:
            arr = np.asarray(value)
            if arr.dtype.kind in "biuf" and arr.size >= 1:
                squeezed = arr.reshape(-1) if arr.ndim <= 1 or max(arr.shape) == arr.size else arr
                if squeezed.ndim == 1:
                    out[name] = squeezed
                    continue
                if squeezed.ndim == 2:
                    matrices[name] = squeezed
                    continue
                if squeezed.ndim >= 3:
                    skipped.append(f"{name} ({arr.dtype}, {_three_d(arr.shape)})")
                    continue
            skipped.append(f"{name} ({arr.dtype}, shape {arr.shape})")


_UNIT_LISTS = frozenset({"units", "unit", "einheiten", "einheit"})
"""Names (last part, lower case) of a cell array of texts that holds a matrix's units."""

_MATRIX_ADVICE = (
    "save each signal as a numeric vector (e.g. torque = data(:, 2); save('run.mat', "
    "'time', 'torque', ...)), or the matrix with one cell array of its column names beside it "
    "(names = {'time', 'torque', ...}; save('run.mat', 'data', 'names')), or export CSV"
)


def _pair_matrices(
    shapes: dict[str, tuple[int, int]],
    texts: dict[str, list[str]],
    taken: set[str],
    times: Mapping[str, int] | None = None,
) -> tuple[dict[str, tuple], dict[str, str]]:
    """Which matrix (MATLAB shape rows x columns) the texts of which variable name.

    Returns ``pairs`` (matrix -> (read by rows, column names, units, the variables of the
    names and of the units (or None), the time vector of a signal's values (or None)))
    and ``reasons`` (matrix -> why it is not read). ``taken``: names of the file's columns.
    ``times``: the file's vectors and their lengths; a matrix that no texts name and that is a
    multi-dimensional signal's values beside its time (:func:`_signal_time`) is read by
    columns as ``name[1]`` ... ``name[k]``.
    """
    unit_vars = [v for v in texts if v.rsplit(".", 1)[-1].lower() in _UNIT_LISTS]
    name_vars = [v for v in texts if v not in unit_vars]
    pairs: dict[str, tuple] = {}
    reasons: dict[str, str] = {}
    for mat_name, (rows, cols) in shapes.items():
        what = f"a {rows} x {cols} matrix"
        by_rows = False
        cands = [v for v in name_vars if len(texts[v]) == cols]
        if not cands and rows != cols:
            cands = [v for v in name_vars if len(texts[v]) == rows]
            by_rows = True
        time_var = _signal_time(mat_name, rows, times or {}) if not cands else None
        if time_var is not None:
            names = [f"{mat_name}[{j + 1}]" for j in range(cols)]
            if not any(n in taken for n in names):
                pairs[mat_name] = (False, names, [None] * cols, None, None, time_var)
                continue
        if not cands:
            found = {v: len(t) for v, t in texts.items()}
            reasons[mat_name] = (
                f"{what}; no cell array of {cols} column names beside it (cell/char arrays "
                f"of text and their lengths: {found or 'none'})"
            )
            continue
        if len(cands) > 1:
            reasons[mat_name] = f"{what}; several cell arrays could name its columns: {cands}"
            continue
        names = texts[cands[0]]
        k = len(names)
        others = [m for m, (r, c) in shapes.items() if m != mat_name and k in (r, c)]
        if others:
            reasons[mat_name] = (
                f"{what}; its names {cands[0]!r} could as well name those of {others}"
            )
            continue
        bad = sorted({n for n in names if not n or names.count(n) > 1 or n in taken})
        if bad:
            reasons[mat_name] = (
                f"{what}; its column names ({cands[0]!r}) are empty, repeated or names of "
                f"other variables: {bad}"
            )
            continue
        unit_cands = [v for v in unit_vars if len(texts[v]) == k]
        unit_var = unit_cands[0] if len(unit_cands) == 1 else None
        units = [u or None for u in texts[unit_var]] if unit_var else [None] * k
        pairs[mat_name] = (by_rows, names, units, cands[0], unit_var, None)
    return pairs, reasons


_ROOT_TIMES = ("tout", "time")
"""Top-level time vectors of a Simulink log (``tout`` beside the "Array" format's ``yout``)."""


def _signal_time(mat_name: str, rows: int, times: Mapping[str, int]) -> str | None:
    """The time vector of ``rows`` samples that makes the matrix ``mat_name`` (rows x columns)
    one multi-dimensional signal's values, one sample per row (a Mux'd signal logged
    "Structure with time", ``logsout.signals.values`` beside ``logsout.time``; or "Array",
    ``yout`` beside ``tout``): the nearest ``time`` of the structs holding it, else a
    top-level ``tout`` / ``time``; None when there is none."""
    parts = mat_name.split(".")
    for k in range(len(parts) - 1, 0, -1):
        # logsout.signals(2).values: logsout.signals(2).time, then logsout.time
        found = f"{'.'.join(parts[:k])}.time"
        if times.get(found) == rows:
            return found
    return next((t for t in _ROOT_TIMES if times.get(t) == rows), None)


def _three_d(shape: tuple[int, ...]) -> str:
    """Why a numeric array of three or more dimensions is not read, and what to save."""
    return (
        f"{len(shape)}-D values, shape {shape}: a matrix per sample is not read as channels; "
        "save a 2-D array of one row per sample (n x k; Simulink logs a matrix signal time "
        "last: reshape(values, [], size(values, 3)).'), or log the signal as a vector"
    )


def _matrix_columns(pairs, shapes, units: dict[str, str], notes: list[str]) -> dict[str, str]:
    """Notes on the matrices read, their columns' units into ``units``; ``{column: base}``."""
    bases: dict[str, str] = {}
    for mat_name, (by_rows, names, col_units, names_var, units_var, time_var) in pairs.items():
        rows, cols = shapes[mat_name]
        if time_var is not None:  # a signal's values: its names are no "name [unit]" headers
            notes.append(
                f"MAT variable {mat_name} ({rows} x {cols}) is one signal of {cols} elements "
                f"per sample (a Mux): read as {cols} channels {names[0]} .. {names[-1]}, each "
                f"on the time {time_var}"
            )
            continue
        for name, unit in zip(names, col_units, strict=True):
            base, header_unit = split_unit_header(name)
            bases[name] = base
            if unit or header_unit:
                units[name] = unit or header_unit
        notes.append(
            f"MAT variable {mat_name} ({rows} x {cols} matrix) read by "
            + ("rows" if by_rows else "columns")
            + f" as {len(names)} channels named by {names_var}: {names}"
            + (f" (units from {units_var})" if units_var else "")
        )
    return bases


def _no_columns(
    path: Path, skipped: list[str], objects: Mapping[str, str] | None = None
) -> RecordingError:
    """The error for a MAT file none of whose variables is readable as a signal; ``objects``
    (name -> MATLAB class) are listed with what to save instead."""
    if objects:
        others = (
            f"; other variables not read: {skipped}; for a matrix: {_MATRIX_ADVICE}"
            if skipped
            else ""
        )
        return RecordingError(
            f"{path}: no readable signals in the MAT file: {_objects_text(objects)}{others}"
        )
    return RecordingError(
        f"{path}: no readable signals in the MAT file (no numeric vector, no matrix with its "
        f"column names); variables found: {skipped}; {_MATRIX_ADVICE}"
    )


def _set_bases(table: Table, bases: dict[str, str]) -> None:
    for name, base in bases.items():
        table.base[name] = base
        add_alias(table, base, name)


def _is_struct_list(value) -> bool:
    """Whether ``value`` (from :func:`scipy.io.loadmat` with ``simplify_cells``) is a struct
    array: a list or object array of structs (dicts)."""
    items = list(value) if isinstance(value, list | tuple) or (
        isinstance(value, np.ndarray) and value.dtype == object and value.ndim == 1
    ) else []  # fmt: skip
    return bool(items) and all(isinstance(v, Mapping) for v in items)


_SIGNAL_LABELS = ("label", "name", "Name")
"""Fields of a struct array's element that name its signal (Simulink's ``signals(k).label``,
ControlDesk's ``Y(k).Name``)."""
_SIGNAL_VALUES = ("values", "Data")
"""Fields of a struct array's element that hold its samples."""


def _label_struct_signals(table: Table, strings: Mapping[str, str]) -> None:
    """Make ``label`` (``Trq``) name ``x.signals(k).values`` where element k of a struct
    array labels its signal (Simulink's "Structure with time", ControlDesk's ``Y(k).Name``).

    A struct array of one element is stored as a plain struct (MATLAB saves a 1x1 struct
    array as one struct; a "Structure with time" of one signal is one): its ``x.signals.values``
    is named by its label and as ``x.signals(1).values`` too, as with several signals.
    """
    for name, text in strings.items():
        head, _, field = name.rpartition(".")
        label = text.replace("\x00", "").strip()
        if field not in _SIGNAL_LABELS or not head or not label:
            continue
        for values in _SIGNAL_VALUES:
            column = f"{head}.{values}"
            _label_elements(table, head, column, label)
            if column not in table.names:
                continue
            if label not in table.names:
                add_alias(table, label, column)
            indexed = f"{head}(1).{values}"
            if not head.endswith(")") and indexed not in table.names:
                add_alias(table, indexed, column)


def _label_elements(table: Table, head: str, column: str, label: str) -> None:
    """``label[j]`` (and ``head(1).values[j]`` for a struct of one signal) naming the columns
    ``column[j]`` of a multi-dimensional signal's values (:func:`_signal_time`)."""
    field = column[len(head) :]  # ".values"
    j = 1
    while (target := f"{column}[{j}]") in table.names:
        aliases = [f"{label}[{j}]"] + ([] if head.endswith(")") else [f"{head}(1){field}[{j}]"])
        for alias in aliases:
            if alias not in table.names:
                add_alias(table, alias, target)
        j += 1


def _flatten_cell(name: str, value, out: dict, skipped: list) -> None:
    """A v5 cell array (a list from :func:`scipy.io.loadmat`) of numbers as one column."""
    items = value if isinstance(value, list | tuple) else list(value.reshape(-1, order="F"))
    if len(items) > MAX_CELL_ELEMENTS:
        skipped.append(f"{name} (cell array of {len(items)} elements; {_cell_advice(name)})")
        return
    parts = []
    for k, item in enumerate(items):
        arr = np.asarray(item)
        if arr.dtype.kind not in "biuf" or arr.size < 1 or sum(d != 1 for d in arr.shape) > 1:
            kind = "text" if arr.dtype.kind in "SU" else f"{arr.dtype}, shape {arr.shape}"
            kind = "a struct" if isinstance(item, Mapping) else kind
            if (found := _object_class(item)) is not None:
                kind = f"a MATLAB {found[1]} object"
            skipped.append(
                f"{name} (cell array whose element {k + 1} is {kind}, not a number or numeric "
                f"vector; {_cell_advice(name, arr.dtype.kind in 'biuf')})"
            )
            return
        parts.append(arr.astype(float).reshape(-1))
    if parts:
        out[name] = np.concatenate(parts)
    else:
        skipped.append(f"{name} (empty cell array)")


def _is_hdf5(path: Path) -> bool:
    signature = b"\x89HDF\r\n\x1a\n"
    with path.open("rb") as fh:
        for offset in (0, 512, 1024, 2048):
            fh.seek(offset)
            if fh.read(8) == signature:
                return True
    return False


_NUMERIC_CLASSES = {
    "double",
    "single",
    "int8",
    "int16",
    "int32",
    "int64",
    "uint8",
    "uint16",
    "uint32",
    "uint64",
    "logical",
}


_PLAIN_CLASSES = _NUMERIC_CLASSES | {"char", "cell", "struct"}
"""MATLAB classes of plain data; any other ``MATLAB_class`` in a v7.3 file is a class object."""


def _h5_object_class(item) -> str | None:
    """The MATLAB class of a v7.3 class object (a dataset of references into MATLAB's
    private MCOS stream, or an old-style object group); None for plain data."""
    cls = _attr_text(item, "MATLAB_class")
    if "MATLAB_object_decode" in item.attrs or (cls and cls not in _PLAIN_CLASSES):
        return cls or "unknown class"
    return None


def _attr_text(item, key: str) -> str:
    value = item.attrs.get(key, b"")
    return value.decode() if isinstance(value, bytes) else str(value)


def _hdf5_table(path: Path, what: str) -> Table:
    """Table over an HDF5 file (MATLAB v7.3 or plain): numeric vectors read lazily with h5py.

    MATLAB stores an n x 1 (or 1 x n) vector as an HDF5 dataset of shape (1, n) (or (n, 1));
    each is one column, read (whole or a slice) by opening the file for that read only. Structs
    are groups (``meas.torque``); char arrays (uint16 text) are read whole; cells, sparse and
    complex arrays and matrices are listed as not readable.
    """
    h5py = require_module("h5py", what)
    # name -> (HDF5 path, long axis, length, (axis, index) fixed for a matrix column or None)
    datasets: dict[str, tuple[str, int, int, tuple[int, int] | None]] = {}
    matrices: dict[str, tuple[str, tuple[int, int], bool]] = {}  # (path, shape, MATLAB's)
    texts: dict[str, list[str]] = {}  # cell arrays of text, char matrices: pairing names
    text_skips: dict[str, str] = {}  # their skipped entry when no matrix uses them
    cells: dict[str, np.ndarray] = {}  # name -> the values of a cell array of numbers
    strings: dict[str, str] = {}
    skipped: list[str] = []
    objects: dict[str, str] = {}  # MATLAB class objects: name -> class

    def cell(f, name: str, item) -> None:
        """A cell array of numbers as one column (module docstring), else a skipped entry."""
        refs = np.asarray(item[()], dtype=object).reshape(-1)  # MATLAB's column-major order
        words = _char_cell(f, refs) if refs.size <= MAX_CELL_ELEMENTS else None
        if words is not None:  # names of a matrix's columns, or else skipped
            texts[name] = words
            text_skips[name] = (
                f"{name} (cell array whose element 1 is char, not a number or numeric vector; "
                f"{_cell_advice(name, False)})"
            )
            return
        if refs.size > MAX_CELL_ELEMENTS:
            skipped.append(
                f"{name} (cell array of {refs.size} elements, more than {MAX_CELL_ELEMENTS} "
                f"read one by one; {_cell_advice(name)})"
            )
            return
        parts = []
        for k, ref in enumerate(refs):
            target = f[ref] if ref else None
            cls = "" if target is None else _attr_text(target, "MATLAB_class")
            ok = (
                isinstance(target, h5py.Dataset)
                and target.dtype.kind in "biuf"
                and (not cls or cls in _NUMERIC_CLASSES)
                and "MATLAB_empty" not in target.attrs
                and sum(d != 1 for d in target.shape) <= 1
            )
            if not ok:
                kind = cls or ("group" if isinstance(target, h5py.Group) else "empty")
                skipped.append(
                    f"{name} (cell array whose element {k + 1} is {kind}, not a number or "
                    f"numeric vector; {_cell_advice(name, kind not in ('char', 'cell'))})"
                )
                return
            parts.append(np.asarray(target[()], dtype=float).reshape(-1))
        if not parts:
            skipped.append(f"{name} (empty cell array)")
            return
        cells[name] = np.concatenate(parts)
        scalars = all(p.size == 1 for p in parts)
        notes.append(
            f"MAT variable {name} is a cell array: read as one column ("
            + (
                f"{len(parts)} per-sample scalars)"
                if scalars
                else f"{len(parts)} numeric arrays joined in order)"
            )
        )

    notes: list[str] = []

    def _char_cell(f, refs) -> list[str] | None:
        """The texts of a cell array of char arrays, else None."""
        words = []
        for ref in refs:
            target = f[ref] if ref else None
            if not isinstance(target, h5py.Dataset) or _attr_text(target, "MATLAB_class") != (
                "char"
            ):
                return None
            if "MATLAB_empty" in target.attrs:
                words.append("")
                continue
            codes = np.asarray(target[()], dtype=np.uint16)
            words.append(codes.T.tobytes().decode("utf-16-le", errors="replace").strip())
        return words or None

    def walk(group, prefix: str) -> None:
        for key, item in group.items():
            if not key.startswith("#"):
                visit(group.file, f"{prefix}{key}", item)

    def struct_array(f, name: str, group) -> bool:
        """A MATLAB struct array (Simulink's ``signals(k).values``, dControlDesk's
        ``Y(k).Data``): each field a dataset of references, one per element. Element k's field
        is read as ``name(k).field``; True where ``group`` is one (its fields had been read as
        cell arrays, the k signals joined into one column)."""
        if _attr_text(group, "MATLAB_class") != "struct":
            return False
        fields = {k: v for k, v in group.items() if not k.startswith("#")}
        sizes = set()
        for item in fields.values():
            if (
                not isinstance(item, h5py.Dataset)
                or h5py.check_ref_dtype(item.dtype) is None
                or _attr_text(item, "MATLAB_class") == "cell"
            ):
                return False
            sizes.add(int(np.prod(item.shape)))
        if len(sizes) != 1 or not fields:
            return False
        for key, item in fields.items():
            refs = np.asarray(item[()], dtype=object).reshape(-1)  # as cell() reads them
            for k, ref in enumerate(refs):
                if ref:
                    visit(f, f"{name}({k + 1}).{key}", f[ref])
        notes.append(f"MAT struct array {name}: its {sizes.pop()} elements read as {name}(k).")
        return True

    def visit(f, name: str, item) -> None:
        """One MAT variable (a dataset or a group) called ``name``."""
        if "MATLAB_sparse" not in item.attrs and (found := _h5_object_class(item)) is not None:
            objects[name] = found  # its shape is that of its reference, not of its data
            return
        if isinstance(item, h5py.Group):
            if "MATLAB_sparse" in item.attrs:
                skipped.append(f"{name} (sparse)")
            elif not struct_array(f, name, item):
                walk(item, f"{name}.")
            return
        cls = _attr_text(item, "MATLAB_class")
        shape, dtype = tuple(item.shape), item.dtype
        if cls == "cell" or h5py.check_ref_dtype(dtype) is not None:
            cell(f, name, item)
            return
        if cls == "char":
            codes = np.asarray(item[()], dtype=np.uint16)
            strings[name] = codes.T.tobytes().decode("utf-16-le", errors="replace")
            if codes.ndim == 2 and min(codes.shape) > 1 and "MATLAB_empty" not in item.attrs:
                rows = [r.tobytes().decode("utf-16-le", errors="replace") for r in codes.T]
                texts[name] = [r.replace("\x00", "").strip() for r in rows]
                text_skips[name] = f"{name} (char matrix of {len(rows)} rows of text)"
            return
        if not cls and h5py.check_string_dtype(dtype) is not None and len(shape) == 1:
            words = [
                w.decode(errors="replace") if isinstance(w, bytes) else str(w) for w in item[()]
            ]
            texts[name] = [w.strip() for w in words]
            text_skips[name] = f"{name} (text, shape {shape})"
            return
        long = [k for k, d in enumerate(shape) if d != 1]
        numeric = dtype.kind in "biuf" and (not cls or cls in _NUMERIC_CLASSES)
        if numeric and len(shape) == len(long) == 2 and "MATLAB_empty" not in item.attrs:
            matrices[name] = (item.name, (int(shape[0]), int(shape[1])), bool(cls))
            return
        if numeric and len(long) > 2 and "MATLAB_empty" not in item.attrs:
            matlab = shape[::-1] if cls else shape  # HDF5 keeps MATLAB's shape reversed
            skipped.append(f"{name} ({cls or dtype}, {_three_d(matlab)})")
            return
        if not numeric or "MATLAB_empty" in item.attrs or len(long) > 1 or int(np.prod(shape)) < 1:
            skipped.append(f"{name} ({cls or dtype}, shape {shape})")
            return
        axis = long[0] if long else 0
        datasets[name] = (item.name, axis, int(np.prod(shape)), None)

    try:
        with h5py.File(path, "r") as f:
            walk(f, "")
    except Exception as exc:  # h5py raises OSError, RuntimeError, KeyError... on damaged files
        raise RecordingError(
            f"{path}: not a readable HDF5 file: {exc} (damaged or truncated?)"
        ) from exc

    # a matrix: MATLAB's shape is HDF5's reversed (column-major); plain HDF5 keeps its own
    shapes = {m: (sh[::-1] if by_matlab else sh) for m, (_, sh, by_matlab) in matrices.items()}
    times = {k: d[2] for k, d in datasets.items()} | {k: v.size for k, v in cells.items()}
    pairs, reasons = _pair_matrices(shapes, texts, {*datasets, *cells, *strings}, times)
    used = {v for p in pairs.values() for v in p[3:]}
    for mat_name, (by_rows, names, *_) in pairs.items():
        h5path, sh, by_matlab = matrices[mat_name]
        rows_axis = 1 if by_matlab else 0  # the HDF5 axis of MATLAB's rows
        axis = 1 - rows_axis if by_rows else rows_axis
        for j, name in enumerate(names):
            datasets[name] = (h5path, axis, sh[axis], (1 - axis, j))
    for mat_name, why in reasons.items():
        skipped.append(f"{mat_name} ({why})")
    skipped.extend(why for name, why in text_skips.items() if name not in used)
    if not datasets and not cells and (skipped or objects):
        raise _no_columns(path, skipped, objects)
    skipped.extend(_object_entry(n, c) for n, c in objects.items())
    bases_units: dict[str, str] = {}
    bases = _matrix_columns(pairs, shapes, bases_units, notes)

    handle: list = []  # the file, opened on the first read, closed with the table

    def read(name: str, start: int, stop: int) -> Column:
        if name in cells:
            return Column(cells[name][max(0, start) : max(0, stop)], units.get(name))
        h5path, axis, n, fixed = datasets[name]
        start, stop = max(0, start), min(n, stop)
        try:
            if not handle:
                handle.append(h5py.File(path, "r"))
            ds = handle[0][h5path]
            index = [0] * ds.ndim
            if ds.ndim:
                index[axis] = slice(start, stop)
            if fixed is not None:
                index[fixed[0]] = fixed[1]
            values = np.asarray(ds[tuple(index)]).reshape(-1)
        except Exception as exc:  # h5py: OSError, RuntimeError, KeyError, ValueError...
            raise RecordingError(
                f"{path}: MAT variable {name!r} could not be read: {exc}; the file is damaged "
                "or truncated"
            ) from exc
        return Column(values, units.get(name))

    def length(name: str) -> int:
        return cells[name].size if name in cells else datasets[name][2]

    units: dict[str, str] = dict(bases_units)
    table = _finish(
        path,
        [*datasets, *cells],
        lambda n: read(n, 0, length(n)),
        strings,
        skipped,
        units,
        notes,
    )
    _set_bases(table, bases)
    _label_struct_signals(table, strings)
    table.slicer = Slicer(length=length, read=read)
    weakref.finalize(table.slicer, _close, handle)  # the slicer outlives the table in use
    return table


def _close(handles: list) -> None:
    for h in handles:
        with contextlib.suppress(Exception):
            h.close()


def _finish(
    path: Path,
    names: list[str],
    load,
    strings: dict[str, str],
    skipped: list[str],
    units: dict[str, str],
    notes: list[str],
) -> Table:
    """The table of a MAT file, with rollerrig's stored units and metadata (char variables).

    Units: the text fields of the struct ``units`` (``units.torque``) and, from older rollerrig
    files, the JSON text variable ``rollerrig_units``.
    """
    stored = _json_text(strings, META_KEY)
    provenance = _json_text(strings, PROVENANCE_KEY)
    legacy = _json_text(strings, UNITS_KEY)
    if isinstance(legacy, dict):
        units.update({str(k): str(v) for k, v in legacy.items()})
    prefix = f"{UNITS_STRUCT}."
    units.update({k[len(prefix) :]: v for k, v in strings.items() if k.startswith(prefix) and v})
    table = Table(
        names=names,
        load=load,
        base={n: n for n in names},
        notes=notes,
        skipped=skipped,
        stored_metadata=stored,
    )
    if isinstance(provenance, dict) and table.stored_provenance is None:
        table.stored_provenance = provenance
    _controldesk_rasters(table)
    if skipped:
        table.notes.append(f"MAT variables not read (not numeric vectors): {skipped}")
    return table


_RASTER_SIGNAL = re.compile(r"(?P<head>.*)\.Y\((?P<k>\d+)\)\.Data")
"""A dSPACE ControlDesk signal's samples, ``rec.Y(k).Data``; ``rec.Y(k).XIndex`` names its
raster, whose times are ``rec.X(XIndex).Data``."""


def _controldesk_rasters(table: Table) -> None:
    """A ControlDesk signal's raster (``Y(k).XIndex`` -> ``X(XIndex).Data``) as its time base
    (:attr:`Table.time_of`): a recording with several rasters has a time vector per raster."""
    for name in table.names:
        m = _RASTER_SIGNAL.fullmatch(name)
        xindex = f"{m['head']}.Y({m['k']}).XIndex" if m else None
        if xindex is None or xindex not in table.names:
            continue
        try:
            value = np.asarray(table.load(xindex).values, dtype=float).reshape(-1)
        except Exception:  # an unreadable index: the signal keeps the map's time
            continue
        if value.size != 1 or not np.isfinite(value[0]) or value[0] != round(value[0]):
            continue
        raster = f"{m['head']}.X({int(value[0])}).Data"
        if raster in table.names:
            table.time_of[name] = (raster,)


def _json_text(strings: dict[str, str], key: str) -> Any:
    """The JSON value of text variable ``key``; None when absent or not JSON."""
    if key in strings:
        with contextlib.suppress(json.JSONDecodeError):
            return json.loads(strings[key])
    return None


def _v5_objects(path: Path) -> dict[str, Any]:
    """Every top-level MATLAB class object of a v5 file, by the name it stores.

    :func:`scipy.io.loadmat` names each one ``None`` (the name is inside the object), so all but
    the last are lost; the file is split into its variables and each object is loaded alone.
    (:func:`scipy.io.whosmat` cannot list them: it fails on an object's header.)
    """
    from scipy.io import loadmat
    from scipy.io.matlab import varmats_from_mat

    objects: dict[str, Any] = {}
    with path.open("rb") as fh:
        for k, (name, stream) in enumerate(varmats_from_mat(fh)):
            if name != "None":
                continue
            value = loadmat(stream, squeeze_me=True, variable_names=["None"]).get("None")
            found = _object_class(value)
            if found is not None:
                objects[found[0] or f"(unnamed object {k + 1})"] = value
    return objects


def read_mat(path: Path) -> Table:
    from scipy.io import loadmat
    from scipy.io.matlab import matfile_version

    try:
        major, _ = matfile_version(str(path))
    except Exception as exc:
        if not _is_hdf5(path):
            raise RecordingError(f"{path}: not a MATLAB .mat file: {exc}") from exc
        major = -1  # HDF5 without the MATLAB header (written by h5py or other tools)
    if major == -1:
        table = _hdf5_table(path, "HDF5 .mat files")
        table.notes.insert(0, "HDF5 file without a MATLAB header read with h5py")
        return table
    if major == 2:  # v7.3 = HDF5
        if not _is_hdf5(path):
            raise RecordingError(f"{path}: a MATLAB v7.3 header but no HDF5 data (truncated?)")
        table = _hdf5_table(path, "MATLAB v7.3 files")
        table.notes.insert(0, "MATLAB v7.3 (HDF5) read with h5py")
        return table
    try:
        with warnings.catch_warnings():  # scipy names every object "None": duplicates
            warnings.filterwarnings("ignore", message='Duplicate variable name "None"')
            data = loadmat(str(path), squeeze_me=True, simplify_cells=True)
            if _object_class(data.get("None")) is not None:
                data = {k: v for k, v in data.items() if k != "None"} | _v5_objects(path)
    except Exception as exc:
        raise RecordingError(f"{path}: not a readable MATLAB file: {exc}") from exc
    flat: dict[str, Any] = {}
    skipped: list[str] = []
    matrices: dict[str, np.ndarray] = {}
    texts: dict[str, tuple[list[str], Any]] = {}
    objects: dict[str, str] = {}
    _flatten_mat(data, "", flat, skipped, matrices, texts, objects)
    strings = {k: v for k, v in flat.items() if isinstance(v, str)}
    columns = {k: v for k, v in flat.items() if not isinstance(v, str)}
    shapes = {m: (int(a.shape[0]), int(a.shape[1])) for m, a in matrices.items()}
    pairs, reasons = _pair_matrices(
        shapes,
        {k: t for k, (t, _) in texts.items()},
        set(columns) | set(strings),
        {k: int(np.size(v)) for k, v in columns.items()},
    )
    used = {v for p in pairs.values() for v in p[3:]}
    for mat_name, (by_rows, names, *_) in pairs.items():
        arr = matrices[mat_name]
        for j, name in enumerate(names):
            columns[name] = np.ascontiguousarray(arr[j, :] if by_rows else arr[:, j])
    for mat_name, why in reasons.items():
        skipped.append(f"{mat_name} ({matrices[mat_name].dtype}, {why})")
    for name, (listed, value) in texts.items():
        if name not in used:
            if isinstance(value, np.ndarray) and value.dtype.kind == "U":
                skipped.append(f"{name} (char matrix of {len(listed)} rows of text)")
            else:
                _flatten_cell(name, value, {}, skipped)
    if not columns and (skipped or objects):
        raise _no_columns(path, skipped, objects)
    skipped.extend(_object_entry(n, c) for n, c in objects.items())
    units: dict[str, str] = {}
    notes: list[str] = []
    bases = _matrix_columns(pairs, shapes, units, notes)
    table = _finish(
        path,
        list(columns),
        lambda n: Column(columns[n], units.get(n)),
        strings,
        skipped,
        units,
        notes,
    )
    _set_bases(table, bases)
    _label_struct_signals(table, strings)
    return table
