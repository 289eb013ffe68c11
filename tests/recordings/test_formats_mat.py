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


# ----------------------------------------------------------------- one 2-D matrix plus names


def _matrix(n=200):
    t = np.arange(n) / 100.0
    return t, np.column_stack([t, 2.0 * t, 3.0 * t])


def test_a_v5_matrix_with_a_cell_array_of_column_names_is_read(tmp_path):
    from scipy.io import savemat

    from rollerrig.recordings.readers import read_recording

    t, data = _matrix()
    names = np.empty((1, 3), dtype=object)
    names[0, :] = ["time [s]", "torque [N.m]", "normal_load [kN]"]
    f = tmp_path / "lab.mat"
    savemat(f, {"data": data, "names": names})
    rec = read_recording(f)  # no map: the names carry the units, "time" is the time
    np.testing.assert_allclose(rec.time, t)
    np.testing.assert_allclose(rec["torque"], 2.0 * t)
    np.testing.assert_allclose(rec["normal_load"], 3e3 * t)
    assert any("MAT variable data (200 x 3 matrix)" in n for n in rec.metadata["notes"])
    # a k x n matrix read by rows, names as a char matrix, units from a cell array "units"
    units = np.empty((3, 1), dtype=object)
    units[:, 0] = ["s", "N.m", "N"]
    g = tmp_path / "rows.mat"
    savemat(g, {"M": data.T, "labels": np.array(["time", "torque", "normal_load"]), "units": units})
    rec = read_recording(g)
    np.testing.assert_allclose(rec["normal_load"], 3.0 * t)
    assert not any("not read" in n for n in rec.metadata["notes"])


def test_a_matrix_without_names_is_an_error_that_lists_the_variables(tmp_path):
    from scipy.io import savemat

    from rollerrig.recordings.readers import read_recording
    from rollerrig.recordings.recording import RecordingError

    _, data = _matrix()
    f = tmp_path / "bare.mat"
    savemat(f, {"data": data})
    with pytest.raises(RecordingError, match=r"bare\.mat: no readable signals") as e:
        read_recording(f)
    assert "data (float64, a 200 x 3 matrix; no cell array of 3 column names" in str(e.value)
    assert "save('run.mat', 'data', 'names')" in str(e.value)
    # two cell arrays that could both name the columns: ambiguous, not guessed
    a, b = np.empty((1, 3), dtype=object), np.empty((1, 3), dtype=object)
    a[0, :], b[0, :] = ["time", "torque", "normal_load"], ["x", "y", "z"]
    g = tmp_path / "two.mat"
    savemat(g, {"data": data, "a": a, "b": b})
    with pytest.raises(RecordingError, match=r"several cell arrays could name its columns"):
        read_recording(g)


def _write_mat73_header(path):
    """MATLAB's 512-byte user block of a v7.3 (HDF5) file: its text, version 0x0200, "IM"."""
    header = b"MATLAB 7.3 MAT-file".ljust(116, b" ") + b" " * 8 + b"\x00\x02" + b"IM"
    with path.open("r+b") as fh:
        fh.write(header.ljust(512, b"\x00"))


def test_a_v73_matrix_with_a_cell_array_of_names_is_read_in_slices(tmp_path):
    import h5py

    from rollerrig.recordings.readers import read_recording

    t, data = _matrix()
    f = tmp_path / "lab73.mat"
    with h5py.File(f, "w", userblock_size=512, libver="earliest") as h:
        ds = h.create_dataset("data", data=data.T)  # MATLAB writes column-major: 3 x 200
        ds.attrs["MATLAB_class"] = np.bytes_("double")
        refs = h.create_group("#refs#")
        out = np.empty((3, 1), dtype=h5py.ref_dtype)
        for k, text in enumerate(["time [s]", "torque [N.m]", "normal_load [N]"]):
            codes = np.frombuffer(text.encode("utf-16-le"), dtype=np.uint16).reshape(-1, 1)
            c = refs.create_dataset(f"n{k}", data=codes)
            c.attrs["MATLAB_class"] = np.bytes_("char")
            out[k, 0] = c.ref
        cell = h.create_dataset("names", data=out, dtype=h5py.ref_dtype)
        cell.attrs["MATLAB_class"] = np.bytes_("cell")
    _write_mat73_header(f)
    rec = read_recording(f)
    np.testing.assert_allclose(rec.time, t)
    np.testing.assert_allclose(rec["normal_load"], 3.0 * t)
    table = read_mat(f)
    np.testing.assert_allclose(table.slicer.read("torque [N.m]", 10, 20).values, 2.0 * t[10:20])
    assert table.slicer.length("torque [N.m]") == 200


def _simulink_v73(path, time, signals):
    """Simulink's "Structure with time" as MATLAB v7.3 writes it: ``logsout.time`` and the
    1 x k struct array ``logsout.signals`` whose fields are datasets of k references into
    ``#refs#`` (``values``, ``label``)."""
    import h5py

    def char(group, key, text):
        codes = np.frombuffer(text.encode("utf-16-le"), dtype=np.uint16).reshape(-1, 1)
        ds = group.create_dataset(key, data=codes)
        ds.attrs["MATLAB_class"] = np.bytes_("char")
        return ds

    with h5py.File(path, "w", userblock_size=512, libver="earliest") as h:
        log = h.create_group("logsout")
        log.attrs["MATLAB_class"] = np.bytes_("struct")
        ds = log.create_dataset("time", data=time.reshape(1, -1))
        ds.attrs["MATLAB_class"] = np.bytes_("double")
        sig = log.create_group("signals")
        sig.attrs["MATLAB_class"] = np.bytes_("struct")
        refs = h.create_group("#refs#")
        for field in ("values", "label"):
            out = np.empty((len(signals), 1), dtype=h5py.ref_dtype)
            for k, (label, values) in enumerate(signals.items()):
                if field == "label":
                    target = char(refs, f"{field}{k}", label)
                else:
                    target = refs.create_dataset(f"{field}{k}", data=values.reshape(1, -1))
                    target.attrs["MATLAB_class"] = np.bytes_("double")
                out[k, 0] = target.ref
            sig.create_dataset(field, data=out, dtype=h5py.ref_dtype)
    _write_mat73_header(path)


@pytest.mark.parametrize("version", ["5", "7.3"])
def test_a_struct_array_of_signals_is_one_column_per_signal(tmp_path, version):
    """Simulink's ``signals(k).values`` (dSPACE ControlDesk's ``Y(k).Data`` likewise): element
    k is its own channel, ``logsout.signals(k).values`` or its label. In v7.3 the fields were
    read as cell arrays, the k signals joined end to end into one column (with a sample-rate
    map: 2 s of data, the first half torque, the second speed); v5 was refused."""
    from scipy.io import savemat

    from rollerrig.recordings.readers import read_recording

    t = np.arange(500) / 1000.0
    signals = {"Trq": 10.0 + np.sin(t), "Spd": 100.0 + t}
    f = tmp_path / "sim.mat"
    if version == "5":
        sig = np.zeros((1, 2), dtype=[("values", object), ("label", object)])
        for k, (label, values) in enumerate(signals.items()):
            sig[0, k] = (values.reshape(-1, 1), label)
        savemat(f, {"logsout": {"time": t.reshape(-1, 1), "signals": sig}})
    else:
        _simulink_v73(f, t, signals)
    for column in ("Trq", "logsout.signals(1).values"):
        rec = read_recording(f, {"time": {"sample_rate_Hz": 1000.0}, "channels": {
            "torque": {"column": column, "unit": "N.m"}}})  # fmt: skip
        np.testing.assert_array_equal(rec["torque"], signals["Trq"])
    rec = read_recording(f, {"time": {"column": "logsout.time", "unit": "s"}, "channels": {
        "torque": {"column": "Spd", "unit": "N.m"}}})  # fmt: skip
    np.testing.assert_array_equal(rec["torque"], signals["Spd"])


def _simulink_one_signal_v73(path, time, label, values):
    """A "Structure with time" of one signal as MATLAB v7.3 writes it: a 1 x 1 struct array
    is one struct, ``logsout.signals`` a group whose fields are plain datasets (``values`` of
    shape (n,) or, a Mux, (n, k))."""
    import h5py

    with h5py.File(path, "w", userblock_size=512, libver="earliest") as h:
        log = h.create_group("logsout")
        log.attrs["MATLAB_class"] = np.bytes_("struct")
        ds = log.create_dataset("time", data=time.reshape(1, -1))
        ds.attrs["MATLAB_class"] = np.bytes_("double")
        sig = log.create_group("signals")
        sig.attrs["MATLAB_class"] = np.bytes_("struct")
        # n x k values (a Mux) as MATLAB's column-major k x n; a vector as 1 x n
        ds = sig.create_dataset("values", data=np.ascontiguousarray(np.atleast_2d(values.T)))
        ds.attrs["MATLAB_class"] = np.bytes_("double")
        codes = np.frombuffer(label.encode("utf-16-le"), dtype=np.uint16).reshape(-1, 1)
        ds = sig.create_dataset("label", data=codes)
        ds.attrs["MATLAB_class"] = np.bytes_("char")
    _write_mat73_header(path)


@pytest.mark.parametrize("version", ["5", "7.3"])
def test_a_structure_with_time_of_one_signal_is_named_as_with_several(tmp_path, version):
    """One To Workspace block writes ``logsout.signals`` as a 1 x 1 struct, which MATLAB and
    scipy store as a plain struct: its label and ``logsout.signals(1).values``, as the guide
    says and as with two signals, had been "not in the file"; only
    ``logsout.signals.values`` read (a review, 2026-12-03)."""
    from scipy.io import savemat

    from rollerrig.recordings.readers import read_recording

    t = np.arange(500) / 1000.0
    torque = 10.0 + np.sin(t)
    f = tmp_path / "sim.mat"
    if version == "5":
        signals = {"values": torque.reshape(-1, 1), "label": "Trq", "dimensions": 1}
        savemat(f, {"logsout": {"time": t.reshape(-1, 1), "signals": signals}})
    else:
        _simulink_one_signal_v73(f, t, "Trq", torque)
    for column in ("Trq", "logsout.signals(1).values", "logsout.signals.values"):
        rec = read_recording(f, {"time": {"column": "logsout.time", "unit": "s"}, "channels": {
            "torque": {"column": column, "unit": "N.m"}}})  # fmt: skip
        np.testing.assert_array_equal(rec["torque"], torque)


# ----------------------------------------------------------------- MATLAB class objects


def _tag(kind, data):
    """One MAT v5 data element: its tag and its data, padded to 8 bytes."""
    import struct

    return struct.pack("<II", kind, len(data)) + data + b"\0" * (-len(data) % 8)


def _v5_object(name, cls, compressed=False):
    """A MATLAB class object (``timeseries``, ``table``) as MATLAB saves it in a v5/v7 file:
    an mxOPAQUE_CLASS element holding its name, "MCOS", its class and a uint32 reference into
    the file's private MCOS stream (scipy reads it as ``MatlabOpaque``). MATLAB's default
    ``save`` (v7) compresses each variable."""
    import struct
    import zlib

    def text(s):
        return _tag(1, s.encode())

    ref = struct.pack("<6I", 0xDD000000, 2, 1, 1, 1, 1)
    arr = _tag(14, _tag(6, struct.pack("<II", 13, 0)) + _tag(5, struct.pack("<ii", 6, 1))
               + text("") + _tag(6, ref))  # fmt: skip
    element = _tag(14, _tag(6, struct.pack("<II", 17, 0)) + text(name) + text("MCOS")
                   + text(cls) + arr)  # fmt: skip
    if compressed:
        packed = zlib.compress(element)
        return struct.pack("<II", 15, len(packed)) + packed
    return element


def _v5_double(name, values):
    import struct

    values = np.asarray(values, float).reshape(-1)
    return _tag(14, _tag(6, struct.pack("<II", 6, 0)) + _tag(5, struct.pack("<ii", values.size, 1))
                + _tag(1, name.encode()) + _tag(9, values.tobytes()))  # fmt: skip


def _v5_file(path, *elements):
    header = b"MATLAB 5.0 MAT-file, Platform: PCWIN64".ljust(116, b" ") + b"\0" * 8
    path.write_bytes(header + b"\x00\x01IM" + b"".join(elements))
    return path


def test_v5_matlab_objects_are_each_named_with_their_class_and_the_fix(tmp_path):
    """Two timeseries (one compressed, as MATLAB's default save writes it): scipy names every
    object "None", so the error had listed one of them as "None ([('s0', 'O'), ...])" and
    scipy's duplicate-name warning reached stderr (a review, 2024-05-01)."""
    import warnings

    from rollerrig.recordings.readers import read_recording
    from rollerrig.recordings.recording import RecordingError

    f = _v5_file(
        tmp_path / "ts.mat",
        _v5_object("ts_torque", "timeseries"),
        _v5_object("ts_speed", "timeseries", compressed=True),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no scipy warning reaches the user
        with pytest.raises(RecordingError, match=r"ts\.mat: no readable signals") as e:
            read_recording(f)
    msg = str(e.value)
    assert "MATLAB objects: ts_torque (timeseries), ts_speed (timeseries)" in msg
    assert "cannot be read outside MATLAB" in msg
    assert "t = ts_torque.Time; torque = ts_torque.Data; save('out.mat', 't', 'torque')" in msg
    assert "None" not in msg and "s0" not in msg and "shape" not in msg


def test_a_v5_object_beside_signals_is_listed_with_its_fix(tmp_path):
    """A table, and a timeseries in a struct, beside readable vectors: the signals are read,
    the objects listed by name and class with what to save instead."""
    import struct
    import warnings

    from rollerrig.recordings.readers import read_recording
    from rollerrig.recordings.recording import RecordingError

    meas = _tag(14, _tag(6, struct.pack("<II", 2, 0)) + _tag(5, struct.pack("<ii", 1, 1))
                + _tag(1, b"meas") + struct.pack("<HHI", 5, 4, 8) + _tag(1, b"ts".ljust(8, b"\0"))
                + _v5_object("", "timeseries"))  # fmt: skip
    f = _v5_file(
        tmp_path / "tab.mat",
        _v5_object("T", "table", compressed=True),
        _v5_double("time", T),
        meas,
        _v5_object("t0", "datetime"),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        table = read_mat(f)
    assert table.names == ["time"]
    skipped = " | ".join(table.skipped)
    assert "T (MATLAB table object, which cannot be read outside MATLAB" in skipped
    assert "writetable(T, 'out.csv')" in skipped
    assert "meas.ts (MATLAB timeseries object" in skipped and "t = meas.ts.Time" in skipped
    assert "t0 (MATLAB datetime object" in skipped and "posixtime(t0)" in skipped
    with pytest.raises(RecordingError, match=r"'T', which the file holds but cannot be read") as e:
        read_recording(f, {"time": {"column": "time", "unit": "s"},
                           "channels": {"torque": {"column": "T", "unit": "N.m"}}})  # fmt: skip
    assert "writetable(T, 'out.csv')" in str(e.value)


def test_v73_matlab_objects_are_named_without_the_shape_of_their_reference(tmp_path):
    """In v7.3 an object is a uint32 dataset (a reference into MATLAB's MCOS stream) with its
    class in MATLAB_class: the error had shown the reference's shape as the data's."""
    import h5py

    from rollerrig.recordings.readers import read_recording
    from rollerrig.recordings.recording import RecordingError

    f = tmp_path / "ts73.mat"
    ref = np.array([[0xDD000000, 2, 1, 1, 1, 1]], dtype=np.uint32).T
    with h5py.File(f, "w", userblock_size=512) as h:
        for name, cls in (("ts_torque", "timeseries"), ("TT", "timetable")):
            ds = h.create_dataset(name, data=ref)
            ds.attrs["MATLAB_class"] = np.bytes_(cls)
            ds.attrs["MATLAB_object_decode"] = np.int32(3)
        h.create_group("#subsystem#").create_dataset("MCOS", data=np.zeros((1, 1), np.uint32))
    _write_mat73_header(f)
    with pytest.raises(RecordingError, match=r"ts73\.mat: no readable signals") as e:
        read_recording(f)
    msg = str(e.value)
    assert "MATLAB objects: TT (timetable), ts_torque (timeseries)" in msg
    assert "writetimetable(TT, 'out.csv')" in msg and "torque = ts_torque.Data" in msg
    assert "shape" not in msg and "(6, 1)" not in msg


@pytest.mark.parametrize("version", ["5", "7.3"])
def test_controldesk_rasters_each_time_their_own_signals(tmp_path, version):
    """dSPACE ControlDesk with two rasters: ``rec.X(k).Data`` the times of raster k,
    ``rec.Y(j).XIndex`` the raster of signal j. A signal of the 10 ms raster was lined up by
    index on the 1 ms raster mapped as the time (13 bar at 1 s instead of 4)."""
    from rollerrig.recordings.readers import file_sha256, read_recording
    from rollerrig.recordings.recording import RecordingError
    from rollerrig.recordings.source import open_recording

    n = 2000
    f = tmp_path / "controldesk.mat"
    Y = np.zeros((1, 2), dtype=[("Name", object), ("Data", object), ("XIndex", object)])
    Y[0, 0] = ("Torque", np.full((1, n), 100.0), 1.0)
    Y[0, 1] = ("p_air", (3 + np.arange(n) / 100.0).reshape(1, -1), 2.0)
    X = np.zeros((1, 2), dtype=[("Name", object), ("Data", object)])
    X[0, 0] = ("Time", (np.arange(n) / 1000.0).reshape(1, -1))
    X[0, 1] = ("Time", (np.arange(n) / 100.0).reshape(1, -1))
    if version == "5":
        from scipy.io import savemat

        savemat(f, {"rec": {"X": X, "Y": Y}})
    else:
        pytest.importorskip("h5py")
        _controldesk_v73(f, X, Y)
    sha = file_sha256(f)
    cmap = {"time": {"column": "rec.X(1).Data", "unit": "s"}, "channels": {
        "torque": {"column": "Torque", "unit": "N.m"},
        "air_spring_pressure": {"column": "p_air", "unit": "bar"}}}  # fmt: skip
    rec = read_recording(f, cmap)
    assert file_sha256(f) == sha
    assert rec["air_spring_pressure"][1000] == pytest.approx(4.0e5)
    np.testing.assert_allclose(rec["air_spring_pressure"], (3.0 + rec.time) * 1e5, rtol=1e-12)
    np.testing.assert_array_equal(rec["torque"], 100.0)
    assert any("'rec.X(2).Data'" in note for note in rec.metadata["notes"])
    with pytest.raises(RecordingError, match=r"different time bases"):
        open_recording(f, cmap)


def _controldesk_v73(path, X, Y):
    """``rec.X`` and ``rec.Y`` as MATLAB v7.3 writes struct arrays: each field a dataset of
    references, one per element, into ``#refs#``."""
    import h5py

    with h5py.File(path, "w", userblock_size=512, libver="earliest") as h:
        rec = h.create_group("rec")
        rec.attrs["MATLAB_class"] = np.bytes_("struct")
        refs = h.create_group("#refs#")
        for var, arr in (("X", X), ("Y", Y)):
            grp = rec.create_group(var)
            grp.attrs["MATLAB_class"] = np.bytes_("struct")
            for field in arr.dtype.names:
                out = np.zeros((arr.shape[1], 1), dtype=h5py.ref_dtype)
                for k in range(arr.shape[1]):
                    value = arr[0, k][field]
                    if isinstance(value, str):
                        codes = np.frombuffer(value.encode("utf-16-le"), dtype=np.uint16)
                        ds = refs.create_dataset(f"{var}{field}{k}", data=codes.reshape(-1, 1))
                        ds.attrs["MATLAB_class"] = np.bytes_("char")
                    else:
                        data = np.atleast_2d(np.asarray(value, dtype=float))
                        ds = refs.create_dataset(f"{var}{field}{k}", data=data)
                        ds.attrs["MATLAB_class"] = np.bytes_("double")
                    out[k, 0] = ds.ref
                grp.create_dataset(field, data=out, dtype=h5py.ref_dtype)
    _write_mat73_header(path)


# ----------------------------------------------------------- multi-dimensional signal values
@pytest.mark.parametrize("version", ["5", "7.3"])
def test_a_muxed_structure_with_time_is_one_channel_per_element(tmp_path, version):
    """A Mux of three forces logged "Structure with time": ``signals.values`` is n x 3. It had
    been refused as a matrix without column names; each column is a channel of the shared
    time, ``logsout.signals.values[j]`` or ``label[j]``."""
    from scipy.io import savemat

    from rollerrig.recordings.readers import read_recording

    t = np.arange(400) / 1000.0
    values = np.column_stack([10.0 + np.sin(t), 20.0 + t, 30.0 - t])
    f = tmp_path / "mux.mat"
    if version == "5":
        signals = {"values": values, "label": "F", "dimensions": 3}
        savemat(f, {"logsout": {"time": t.reshape(-1, 1), "signals": signals}})
    else:
        _simulink_one_signal_v73(f, t, "F", values)
    for j in (1, 2, 3):
        for column in (f"F[{j}]", f"logsout.signals.values[{j}]"):
            rec = read_recording(f, {"time": {"column": "logsout.time", "unit": "s"}, "channels": {
                "torque": {"column": column, "unit": "N.m"}}})  # fmt: skip
            np.testing.assert_array_equal(rec["torque"], values[:, j - 1])
            np.testing.assert_array_equal(rec.time, t)
    note = next(n for n in rec.metadata["notes"] if "logsout.signals.values" in n and "[1]" in n)
    assert "400 x 3" in note and "logsout.time" in note


def test_a_muxed_array_format_beside_tout_is_one_channel_per_column(tmp_path):
    """Simulink's "Array" format: ``yout`` n x k beside ``tout`` of n samples."""
    from scipy.io import savemat

    from rollerrig.recordings.readers import read_recording

    t = np.arange(300) / 500.0
    yout = np.column_stack([1.0 + t, 2.0 + t])
    f = tmp_path / "array.mat"
    savemat(f, {"tout": t.reshape(-1, 1), "yout": yout})
    rec = read_recording(f, {"time": {"column": "tout", "unit": "s"}, "channels": {
        "torque": {"column": "yout[2]", "unit": "N.m"}}})  # fmt: skip
    np.testing.assert_array_equal(rec["torque"], yout[:, 1])
    assert any("yout" in n and "tout" in n for n in rec.metadata["notes"])


def test_a_three_dimensional_signal_is_refused_naming_its_shape(tmp_path):
    from scipy.io import savemat

    from rollerrig.recordings.readers import read_recording
    from rollerrig.recordings.recording import RecordingError

    t = np.arange(50) / 100.0
    f = tmp_path / "cube.mat"
    savemat(f, {"logsout": {"time": t.reshape(-1, 1), "signals": {
        "values": np.zeros((2, 3, 50)), "label": "M", "dimensions": [2, 3]}}})  # fmt: skip
    with pytest.raises(RecordingError, match=r"logsout\.signals\.values.*\(2, 3, 50\)") as e:
        read_recording(f, {"time": {"column": "logsout.time", "unit": "s"}, "channels": {
            "torque": {"column": "logsout.signals.values", "unit": "N.m"}}})  # fmt: skip
    assert "3-D values" in str(e.value) and "reshape(values" in str(e.value)
