"""MAT files: units from the ``units`` struct (new) and the ``rollerrig_units`` JSON text (older
rollerrig files), provenance split from the stored metadata."""

import json

import numpy as np
import pytest

from rollerrig.recordings.formats.mat import read_mat

T = np.arange(5) / 250.0


def test_units_struct_of_a_foreign_v5_file(tmp_path):
    from scipy.io import savemat

    f = tmp_path / "lab.mat"
    savemat(f, {"t": T.reshape(-1, 1), "F": np.ones((5, 1)), "units": {"t": "s", "F": "kN"}})
    table = read_mat(f)
    assert sorted(table.names) == ["F", "t"]
    assert table.load("F").unit == "kN" and table.load("t").unit == "s"


def test_older_rollerrig_units_json_text_is_still_read(tmp_path):
    from scipy.io import savemat

    f = tmp_path / "old.mat"
    savemat(
        f,
        {
            "time": T.reshape(-1, 1),
            "torque": np.ones((5, 1)),
            "rollerrig_units": json.dumps({"time": "s", "torque": "N.m"}),
            "rollerrig_metadata": json.dumps({"seed": 3}),
        },
    )
    table = read_mat(f)
    assert table.load("torque").unit == "N.m"
    assert table.stored_metadata == {"seed": 3} and table.stored_provenance is None


@pytest.mark.parametrize("version", ["5", "7.3"])
def test_write_table_mat_gives_units_metadata_and_provenance(tmp_path, version):
    from rollerrig.output import write_table

    f = write_table(
        tmp_path / "run.mat",
        {"torque": (np.arange(5.0), "N.m", "shaft torque")},
        time=T,
        attrs={"seed": 3},
        mat_version=version,
    )
    table = read_mat(f)
    assert table.load("torque").unit == "N.m" and table.load("time").unit == "s"
    assert table.stored_metadata == {"seed": 3}
    assert table.stored_provenance["software"] == "rollerrig"
    assert table.stored_variables["torque"]["long_name"] == "shaft torque"
    assert "units.torque" not in table.names and "provenance" not in table.names


# ----------------------------------------------------------------- cell arrays (issue 24, 9)


@pytest.mark.parametrize("kind", ["scalars", "arrays"])
def test_a_v73_time_held_in_a_cell_array_is_read(tmp_path, kind):
    """A cell of per-sample scalars, or of numeric blocks, referenced through HDF5 object
    references into ``#refs#`` as MATLAB writes them, is the time column."""
    import vendor_files as vf
    from rollerrig.recordings.readers import read_recording

    v = vf.matlab_struct_mat(tmp_path, version="7.3", time_cell=kind)
    source = v.facts["source"]
    rec = read_recording(v.path, v.write_map())
    np.testing.assert_allclose(rec.time, source.time - source.time[0], atol=1e-12)
    np.testing.assert_allclose(rec["torque"], source["torque"], atol=1e-9)
    expected = "500 per-sample scalars" if kind == "scalars" else "3 numeric arrays joined"
    assert any("Messung.Zeit is a cell array" in n and expected in n for n in rec.metadata["notes"])
    table = read_mat(v.path)  # chunked reading of the cell column
    part = table.slicer.read("Messung.Zeit", 10, 20).values
    np.testing.assert_allclose(part, (source.time - source.time[0])[10:20], atol=1e-12)


def test_a_cell_array_that_is_not_numbers_names_the_field_and_the_fix(tmp_path, monkeypatch):
    import vendor_files as vf
    from rollerrig.recordings.formats import mat
    from rollerrig.recordings.readers import read_recording
    from rollerrig.recordings.recording import RecordingError

    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    v = vf.matlab_struct_mat(tmp_path / "a", version="7.3", time_cell="text")
    with pytest.raises(RecordingError, match=r"'Messung\.Zeit', which the file holds but") as e:
        read_recording(v.path, v.write_map())
    assert "element 1 is char" in str(e.value) and "export the signals as CSV or MDF4" in str(
        e.value
    )
    # More elements than are worth opening one by one: the advice is cell2mat.
    monkeypatch.setattr(mat, "MAX_CELL_ELEMENTS", 100)
    v = vf.matlab_struct_mat(tmp_path / "b", version="7.3", time_cell="scalars")
    with pytest.raises(RecordingError, match=r"cell array of 500 elements, more than 100"):
        read_recording(v.path, v.write_map())
    with pytest.raises(RecordingError, match=r"Messung\.Zeit = cell2mat\(Messung\.Zeit\(:\)\)"):
        read_recording(v.path, v.write_map())


def test_v5_cell_arrays_of_numbers_are_read_and_text_is_named(tmp_path):
    from scipy.io import savemat

    scalars = np.empty((5, 1), dtype=object)
    scalars[:, 0] = list(T)
    blocks = np.empty((2, 1), dtype=object)
    blocks[0, 0], blocks[1, 0] = T[:2].reshape(-1, 1), T[2:].reshape(-1, 1)
    text = np.empty((2, 1), dtype=object)
    text[:, 0] = ["12:00:00", "12:00:01"]
    f = tmp_path / "cells.mat"
    savemat(f, {"m": {"a": scalars, "b": blocks, "c": text, "F": np.ones((5, 1))}})
    table = read_mat(f)
    np.testing.assert_allclose(table.load("m.a").values, T)
    np.testing.assert_allclose(table.load("m.b").values, T)
    assert "m.c" not in table.names
    assert any(s.startswith("m.c (cell array whose element 1 is text") for s in table.skipped)
