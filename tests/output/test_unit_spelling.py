"""One spelling of the dimensionless unit (the rule of :mod:`rollerrig.units`): ``"1"`` as a unit
value (attributes, ``units`` fields), ``[-]`` in names and labels (CSV headers, JSON keys, help,
messages); ``[1]`` never written, ``"-"`` never as a unit value.

Checked on what the writers write (read back with h5py and pyarrow, not the package's reader),
on every user-facing string literal of the package's source, and on the labels and messages the
package builds.
"""

from __future__ import annotations

import ast
import json
import re
from pathlib import Path

import h5py
import numpy as np
import pytest
import xarray as xr

import rollerrig
from rollerrig._validation import ParameterError, require_positive
from rollerrig.output import write_dataset, write_table
from rollerrig.units import (
    DIMENSIONLESS,
    DIMENSIONLESS_LABEL,
    is_dimensionless,
    labelled,
    normalize_unit,
    unit_label,
)

SOURCE = Path(rollerrig.__file__).parent
OTHER_LABEL = re.compile(r"\[1\]")


def _docstrings(tree: ast.AST) -> set[int]:
    """ids of the string constants that are docstrings (module, class, function, and the
    attribute docstrings that follow an assignment)."""
    ids = set()
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if not isinstance(body, list):
            continue
        for i, stmt in enumerate(body):
            if (
                isinstance(stmt, ast.Expr)
                and isinstance(stmt.value, ast.Constant)
                and isinstance(stmt.value.value, str)
                and (i == 0 or isinstance(body[i - 1], ast.Assign | ast.AnnAssign))
            ):
                ids.add(id(stmt.value))
    return ids


def _user_facing_strings():
    """(file, line, text) of every string literal of the package that is not a docstring: the
    texts that reach a file, a console, a help or an error message."""
    for path in sorted(SOURCE.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        docs = _docstrings(tree)
        for node in ast.walk(tree):
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                if id(node) not in docs:
                    yield path.relative_to(SOURCE), node.lineno, node.value


def test_no_string_the_package_writes_or_prints_spells_the_dimensionless_unit_1():
    found = [
        f"{path}:{line}: {text!r}"
        for path, line, text in _user_facing_strings()
        if OTHER_LABEL.search(text)
    ]
    assert not found, "write [-] (rollerrig.units.labelled), not [1]:\n" + "\n".join(found)


def test_the_scan_finds_a_literal_and_skips_a_docstring(tmp_path):
    # The scanner itself: a label in code is found, the same text in a docstring is not.
    tree = ast.parse('"""Ratio [1]."""\nX = 1\n"""Doc [1]."""\nf(f"cost [1] {x}")\n')
    docs = _docstrings(tree)
    texts = [
        n.value
        for n in ast.walk(tree)
        if isinstance(n, ast.Constant) and isinstance(n.value, str) and id(n) not in docs
    ]
    assert texts == ["cost [1] "]


def test_the_labels_of_the_registry():
    assert (DIMENSIONLESS, DIMENSIONLESS_LABEL) == ("1", "[-]")
    assert [labelled("creep", u) for u in ("1", "-", " 1 ")] == ["creep [-]"] * 3
    assert labelled("torque", "N.m") == "torque [N.m]" and labelled("phase", None) == "phase"
    assert unit_label("") == "" and unit_label("rad/s") == "[rad/s]"
    assert is_dimensionless("1") and is_dimensionless("-") and not is_dimensionless(None)
    # What is written is read: a header's [-] is the unit "1".
    assert normalize_unit("-") == DIMENSIONLESS


def test_a_message_about_a_dimensionless_value_says_the_unit_as_a_label():
    with pytest.raises(ParameterError) as info:
        require_positive("kA", -1.0, "1")
    assert "[-]" in str(info.value) and "[1]" not in str(info.value)


@pytest.mark.parametrize("unit", ["1", "-"])
def test_written_tables_spell_it_one_way_per_place(tmp_path, unit):
    import pyarrow.parquet as pq

    columns = {"coa": ([0.1, 0.2], unit, "adhesion coefficient")}
    csv_path = write_table(tmp_path / "t.csv", columns, time=[0.0, 0.1])
    assert csv_path.read_text().splitlines()[0] == "time [s],coa [-]"
    sidecar = json.loads(csv_path.with_suffix(".metadata.json").read_text())
    assert sidecar["variables"]["coa"]["units"] == "1"
    with h5py.File(write_table(tmp_path / "t.nc", columns, time=[0.0, 0.1])) as f:
        assert f["coa"].attrs["units"] == "1"  # CF-1.10, UDUNITS
    field = pq.read_schema(write_table(tmp_path / "t.parquet", columns)).field("coa")
    assert field.metadata[b"unit"] == b"1"


def test_write_dataset_gives_netcdf_the_cf_unit_and_leaves_the_dataset_alone(tmp_path):
    ds = xr.Dataset(
        {"creep": (("time",), np.zeros(3), {"units": "-"})}, coords={"time": [0.0, 0.1, 0.2]}
    )
    with h5py.File(write_dataset(tmp_path / "d.nc", ds)) as f:
        assert f["creep"].attrs["units"] == "1"
    assert ds["creep"].attrs["units"] == "-"
