"""The one results writer: every format round-trips through the package's readers and an
independent reader (pandas, pyarrow, nptdms, asammdf, scipy.io.loadmat, h5py, xarray), with a
unit on every column, the metadata object and the provenance record."""

import errno
import json
import os
import stat

import numpy as np
import pytest
import xarray as xr

from rollerrig._validation import ParameterError
from rollerrig.output import OutputError, run_context, write_dataset, write_table
from rollerrig.recordings.readers import read_recording

N = 500
T = 0.5 + np.arange(N) / 250.0
COLUMNS = {
    "torque": (400.0 * np.sin(T), "N.m", "roller shaft torque T56"),
    "roller_speed": (5.0 + T, "rad/s", "roller speed"),
    "coa": (0.01 * T, "1", "adhesion coefficient"),
}
UNITS = {"time": "s", "torque": "N.m", "roller_speed": "rad/s", "coa": "1"}
ATTRS = {"title": "a test run", "seed": 7, "nested": {"a": [1, 2]}}
CASES = [
    ("csv", {}),
    ("parquet", {}),
    ("tdms", {}),
    ("mf4", {}),
    ("mat", {}),
    ("mat", {"mat_version": "7.3"}),
]


def _write(tmp_path, fmt, **kw):
    with run_context(command=["rollerrig", "test", fmt], fs=250.0):
        return write_table(tmp_path / f"run.{fmt}", COLUMNS, time=T, attrs=ATTRS, **kw)


@pytest.mark.parametrize(("fmt", "kw"), CASES)
def test_round_trip_through_the_package_reader(tmp_path, fmt, kw):
    path = _write(tmp_path, fmt, **kw)
    rec = read_recording(path)
    # Binary formats store the values; CSV text their 12 significant digits (no float noise).
    rtol = 5e-12 if fmt == "csv" else 0.0
    np.testing.assert_allclose(rec.time, T, rtol=rtol, atol=0.0)
    for name, (values, unit, _) in COLUMNS.items():
        np.testing.assert_allclose(rec[name], values, rtol=rtol, atol=0.0)
        assert rec.units[name] == unit
    assert rec.metadata["stored_metadata"] == ATTRS
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


def _stored_object(path, fmt):
    """The metadata object (JSON) as an independent reader finds it in the file."""
    if fmt == "csv":
        return json.loads(path.with_suffix(".metadata.json").read_text())
    if fmt == "parquet":
        import pyarrow.parquet as pq

        return json.loads(pq.read_schema(path).metadata[b"rollerrig"])["metadata"]
    if fmt == "tdms":
        from nptdms import TdmsFile

        return json.loads(TdmsFile.read_metadata(path).properties["rollerrig_metadata"])
    from asammdf import MDF

    with MDF(path) as mdf:
        comment = mdf.header.comment
    import xml.etree.ElementTree as ET

    try:
        return json.loads(ET.fromstring(comment).find("TX").text)
    except ET.ParseError:
        return json.loads(comment)


@pytest.mark.parametrize("fmt", ["csv", "parquet", "tdms", "mf4"])
def test_metadata_object_holds_attrs_variables_and_provenance(tmp_path, fmt):
    path = _write(tmp_path, fmt)
    meta = _stored_object(path, fmt)
    assert {k: meta[k] for k in ATTRS} == ATTRS
    assert meta["provenance"]["command"] == ["rollerrig", "test", fmt]
    assert meta["provenance"]["parameters"] == {"fs": 250.0}
    assert meta["variables"]["torque"] == {"units": "N.m", "long_name": "roller shaft torque T56"}
    assert {n: v["units"] for n, v in meta["variables"].items()} == UNITS


def test_csv_headers_and_pandas(tmp_path):
    import pandas as pd

    path = _write(tmp_path, "csv")
    frame = pd.read_csv(path)
    assert list(frame.columns) == ["time [s]", "torque [N.m]", "roller_speed [rad/s]", "coa [-]"]
    # Each value as its 12 significant digits (no float noise), read back exactly by pandas.
    twelve = [float(f"{v:.11e}") for v in COLUMNS["torque"][0]]
    np.testing.assert_array_equal(frame["torque [N.m]"], twelve)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.csv", "run.metadata.json"]


def test_parquet_with_pyarrow(tmp_path):
    import pyarrow.parquet as pq

    table = pq.read_table(_write(tmp_path, "parquet"))
    assert table.column_names == list(UNITS)
    for field in table.schema:
        assert field.metadata[b"unit"].decode() == UNITS[field.name]
    assert table.schema.field("torque").metadata[b"long_name"] == b"roller shaft torque T56"
    np.testing.assert_array_equal(table["roller_speed"].to_numpy(), COLUMNS["roller_speed"][0])


def test_tdms_with_nptdms_root_name_is_the_stem(tmp_path):
    from nptdms import TdmsFile

    path = write_table(tmp_path / "seed-30kmh-dry.tdms", COLUMNS, time=T)
    tdms = TdmsFile.read(path)
    assert tdms.properties["name"] == "seed-30kmh-dry"  # not the temporary file's name
    group = tdms["rollerrig"]
    assert [c.name for c in group.channels()] == list(UNITS)
    for ch in group.channels():
        assert ch.properties["unit_string"] == UNITS[ch.name]
    assert group["torque"].properties["description"] == "roller shaft torque T56"
    assert group["torque"].properties["wf_increment"] == pytest.approx(1 / 250.0)
    np.testing.assert_array_equal(group["torque"][:], COLUMNS["torque"][0])


def test_mf4_with_asammdf(tmp_path):
    from asammdf import MDF

    with MDF(_write(tmp_path, "mf4")) as mdf:
        sig = mdf.get("torque")
        assert sig.unit == "N.m" and sig.comment == "roller shaft torque T56"
        np.testing.assert_array_equal(sig.samples, COLUMNS["torque"][0])
        np.testing.assert_allclose(sig.timestamps, T)
        assert mdf.get("coa").unit == "1"


def test_mat5_with_scipy_column_vectors_and_units_struct(tmp_path):
    from scipy.io import loadmat

    mat = loadmat(_write(tmp_path, "mat"))
    for name in UNITS:
        assert mat[name].shape == (N, 1)  # MATLAB column vectors
    np.testing.assert_array_equal(mat["torque"][:, 0], COLUMNS["torque"][0])
    units = mat["units"][0, 0]  # a MATLAB struct
    assert {n: str(units[n][0]) for n in units.dtype.names} == UNITS
    record = json.loads(str(mat["provenance"][0]))
    assert record["software"] == "rollerrig" and record["parameters"] == {"fs": 250.0}
    meta = json.loads(str(mat["rollerrig_metadata"][0]))
    assert meta["seed"] == 7 and meta["variables"]["coa"]["units"] == "1"


def test_mat73_with_h5py_column_vectors_and_units_struct(tmp_path):
    import h5py
    from scipy.io.matlab import matfile_version

    path = _write(tmp_path, "mat", mat_version="7.3")
    assert path.read_bytes()[:10] == b"MATLAB 7.3" and matfile_version(str(path)) == (2, 0)

    def text(ds):
        return np.asarray(ds[()], dtype=np.uint16).T.tobytes().decode("utf-16-le")

    with h5py.File(path, "r") as h:
        assert h["torque"].shape == (1, N)  # MATLAB n x 1, column-major
        assert h["torque"].attrs["MATLAB_class"] == b"double"
        units = h["units"]
        assert units.attrs["MATLAB_class"] == b"struct"
        assert {n: text(units[n]) for n in units} == UNITS
        fields = [b"".join(f).decode() for f in units.attrs["MATLAB_fields"]]
        assert sorted(fields) == sorted(UNITS)
        assert json.loads(text(h["provenance"]))["software"] == "rollerrig"


def test_netcdf_cf_attributes_with_xarray(tmp_path):
    import xarray as xr

    with run_context(command=["rollerrig", "simulate", "x"]):
        path = write_table(tmp_path / "run.nc", COLUMNS, time=T, attrs=ATTRS)
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        assert ds.attrs["Conventions"] == "CF-1.10"
        assert ds.attrs["title"] == "a test run"
        assert "rollerrig" in ds.attrs["history"] and "simulate x" in ds.attrs["history"]
        record = json.loads(ds.attrs["provenance"])
        assert record["command"] == ["rollerrig", "simulate", "x"]
        assert json.loads(ds.attrs["rollerrig_metadata"])["nested"] == {"a": [1, 2]}
        assert ds.attrs["seed"] == 7
        assert ds["time"].attrs["units"] == "s" and "standard_name" not in ds["time"].attrs
        for name, (values, unit, long_name) in COLUMNS.items():
            assert ds[name].attrs["units"] == unit and ds[name].attrs["long_name"] == long_name
            np.testing.assert_array_equal(ds[name].values, values)
            assert ds[name].dims == ("time",)


def test_netcdf_text_column_and_nan_meaning(tmp_path):
    import xarray as xr

    creep = np.where(T < 1.0, np.nan, 0.01)
    cols = {
        "measured_creep": (creep, "1", "creep", {"nan_meaning": "undefined at standstill"}),
        "friction_condition": (np.array(["dry"] * N), None, "friction condition"),
    }
    path = write_table(tmp_path / "run.nc", cols, time=T)
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        assert ds["measured_creep"].attrs["nan_meaning"] == "undefined at standstill"
        assert int(np.isnan(ds["measured_creep"].values).sum()) == int(np.isnan(creep).sum())
        assert "units" not in ds["friction_condition"].attrs
        assert ds["friction_condition"].values[0] == "dry"


@pytest.mark.parametrize(("fmt", "kw"), [*CASES, ("nc", {})])
def test_nan_without_a_meaning_is_refused(tmp_path, fmt, kw):
    bad = {"torque": (np.array([1.0, np.nan, 3.0]), "N.m")}
    with pytest.raises(ParameterError, match=r"'torque' has 1 NaN/inf.*nan_meaning"):
        write_table(tmp_path / f"run.{fmt}", bad, time=[0.0, 0.1, 0.2], **kw)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(("fmt", "kw"), [*CASES, ("nc", {})])
def test_nan_with_a_meaning_is_kept(tmp_path, fmt, kw):
    cols = {"creep": (np.array([np.nan, 0.1, 0.2]), "1", "creep", {"nan_meaning": "standstill"})}
    path = write_table(tmp_path / f"run.{fmt}", cols, time=[0.0, 0.1, 0.2], **kw)
    assert path.is_file()


def test_every_numeric_column_needs_a_unit(tmp_path):
    with pytest.raises(ParameterError, match="'torque' has no unit"):
        write_table(tmp_path / "run.csv", {"torque": ([1.0], "")})
    with pytest.raises(ParameterError, match="different lengths"):
        write_table(tmp_path / "run.csv", {"a": ([1.0], "1"), "b": ([1.0, 2.0], "1")})
    with pytest.raises(ParameterError, match="numbers only"):
        write_table(tmp_path / "run.tdms", {"label": (["dry"], None)}, time=[0.0])
    with pytest.raises(OutputError, match=r"unknown results format '\.xlsx'"):
        write_table(tmp_path / "run.xlsx", {"a": ([1.0], "1")})
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(("fmt", "kw"), [*CASES, ("nc", {})])
def test_overwrite_false_refuses_an_existing_file(tmp_path, fmt, kw):
    path = _write(tmp_path, fmt, **kw)
    before = path.read_bytes()
    with pytest.raises(FileExistsError, match="overwrite=True"):
        _write(tmp_path, fmt, **kw)
    assert path.read_bytes() == before
    _write(tmp_path, fmt, overwrite=True, **kw)
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


def test_csv_refuses_an_existing_sidecar(tmp_path):
    (tmp_path / "run.metadata.json").write_text("{}")
    with pytest.raises(FileExistsError, match=r"run\.metadata\.json"):
        _write(tmp_path, "csv")
    assert not (tmp_path / "run.csv").exists()


@pytest.mark.parametrize(("fmt", "kw"), [*CASES, ("nc", {})])
@pytest.mark.parametrize(("umask", "mode"), [(0o022, 0o644), (0o077, 0o600)])
def test_mode_follows_the_umask(tmp_path, fmt, kw, umask, mode):
    old = os.umask(umask)
    try:
        _write(tmp_path, fmt, **kw)
    finally:
        os.umask(old)
    for p in tmp_path.iterdir():
        assert stat.S_IMODE(p.stat().st_mode) == mode, p.name


def test_interrupt_inside_a_writer_leaves_nothing(tmp_path, monkeypatch):
    import pandas as pd

    def interrupted(self, path, *args, **kwargs):
        open(path, "w").write("half")
        raise KeyboardInterrupt

    monkeypatch.setattr(pd.DataFrame, "to_csv", interrupted)
    with pytest.raises(KeyboardInterrupt):
        _write(tmp_path, "csv")
    assert list(tmp_path.iterdir()) == []


def test_a_parent_that_is_a_file_is_an_output_error(tmp_path):
    (tmp_path / "out").write_text("x")
    with pytest.raises(OutputError, match="out: cannot create the folder"):
        write_table(tmp_path / "out" / "run.parquet", COLUMNS, time=T)


def test_write_dataset_keeps_every_dimension_in_netcdf(tmp_path):
    import xarray as xr

    from rollerrig.output import write_dataset

    ds = xr.Dataset(
        {
            "line_frequency": (("time", "line"), np.ones((N, 2)), {"units": "Hz"}),
            "torque": ("time", COLUMNS["torque"][0], {"units": "N.m", "long_name": "T56"}),
        },
        coords={"time": T, "line": ["am", "pmsm"]},
        attrs={"title": "truth", "provenance": json.dumps({"software": "rollerrig", "x": 1})},
    )
    path = write_dataset(tmp_path / "truth.nc", ds)
    with xr.open_dataset(path, engine="h5netcdf") as back:
        assert back["line_frequency"].dims == ("time", "line")
        assert back["line_frequency"].attrs == {"units": "Hz", "long_name": "line_frequency"}
        assert back.attrs["Conventions"] == "CF-1.10" and back.attrs["title"] == "truth"
        assert json.loads(back.attrs["provenance"]) == {"software": "rollerrig", "x": 1}
        assert back["time"].attrs["long_name"].startswith("time since")
    assert ds.attrs["title"] == "truth" and "long_name" not in ds["time"].attrs  # untouched
    with pytest.raises(FileExistsError):
        write_dataset(tmp_path / "truth.nc", ds)
    with pytest.raises(ParameterError, match="dimensions"):
        write_dataset(tmp_path / "truth.csv", ds)
    bad = ds.assign(coa=("time", np.full(N, np.nan), {"units": "1"}))
    with pytest.raises(ParameterError, match="'coa' has 500 NaN"):
        write_dataset(tmp_path / "bad.nc", bad)
    unitless = ds.assign(coa=("time", np.zeros(N)))
    with pytest.raises(ParameterError, match="'coa' has no unit"):
        write_dataset(tmp_path / "bad.nc", unitless)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["truth.nc"]


ODD_NAMES = {
    "oil temp/bearing": "oil_temp_bearing",
    "Group/Channel": "Group_Channel",
    "[bold]x[/bold]": "bold_x_bold",
    "Öl-Temp": "Ol_Temp",
    "oil temp_bearing": "oil_temp_bearing_2",  # collides with the first after mapping
    "units": "units_2",  # the MAT file's own struct (renamed in MAT only)
}


@pytest.mark.parametrize("kw", [{}, {"mat_version": "7.3"}])
def test_mat_stores_names_it_cannot_hold_under_identifiers_with_the_original(tmp_path, kw):
    from scipy.io import loadmat

    cols = {name: (np.arange(3.0) + i, "degC") for i, name in enumerate(ODD_NAMES)}
    path = write_table(tmp_path / "run.mat", cols, time=[0.0, 0.1, 0.2], **kw)
    if kw:
        import h5py

        with h5py.File(path, "r") as f:
            stored = {n: f[n][()].ravel() for n in ODD_NAMES.values()}
    else:
        mat = loadmat(path)
        stored = {n: mat[n].ravel() for n in ODD_NAMES.values()}
    for i, (name, new) in enumerate(ODD_NAMES.items()):
        assert stored[new].tolist() == (np.arange(3.0) + i).tolist(), name
    rec = read_recording(path)  # rollerrig's reader gives the names back
    assert set(ODD_NAMES) <= set(rec.channels)


def test_netcdf_stores_names_with_a_slash_and_keeps_the_original(tmp_path):
    cols = {name: (np.arange(3.0) + i, "degC") for i, name in enumerate(ODD_NAMES)}
    path = write_table(tmp_path / "run.nc", cols, time=[0.0, 0.1, 0.2])
    expected = {**ODD_NAMES, "units": "units"}  # NetCDF has no variable of that name
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        for i, (name, new) in enumerate(expected.items()):
            assert ds[new].values.tolist() == (np.arange(3.0) + i).tolist(), name
            assert ds[new].attrs.get("original_name", new) == name
        assert "original_name" not in ds["units"].attrs


def test_write_dataset_maps_variable_names_for_netcdf(tmp_path):
    ds = xr.Dataset(
        {"a/b": ("time", [1.0, 2.0], {"units": "1"}), "a_b": ("time", [3.0, 4.0], {"units": "1"})},
        coords={"time": [0.0, 0.1]},
    )
    path = write_dataset(tmp_path / "x.nc", ds)
    with xr.open_dataset(path, engine="h5netcdf") as back:
        assert back["a_b"].values.tolist() == [3.0, 4.0]
        assert back["a_b_2"].values.tolist() == [1.0, 2.0]
        assert back["a_b_2"].attrs["original_name"] == "a/b"


def test_a_documented_nan_is_stated_on_the_variable_in_every_format(tmp_path):
    """Issue 24, point 9: the measured creep at standstill (NaN) said why only in the file's
    metadata object; every format now carries the meaning and the count on the variable."""
    import asammdf
    import nptdms
    import pyarrow.parquet as pq

    why = "creep undefined at standstill: roller encoder speed 0"
    cols = {"measured_creep": ([np.nan, np.nan, 0.02], "1", "creep", {"nan_meaning": why})}
    paths = {f: write_table(tmp_path / f"r.{f}", cols, time=[0, 0.1, 0.2]) for f in ("csv",
             "parquet", "tdms", "mf4", "nc")}  # fmt: skip
    sidecar = json.loads((tmp_path / "r.metadata.json").read_text())
    entry = sidecar["variables"]["measured_creep"]
    assert (entry["nan_meaning"], entry["nan_samples"]) == (why, 2)
    field = pq.read_schema(paths["parquet"]).field("measured_creep").metadata
    assert field[b"nan_meaning"] == why.encode() and field[b"nan_samples"] == b"2"
    props = nptdms.TdmsFile.read(paths["tdms"])["rollerrig"]["measured_creep"].properties
    assert props["nan_meaning"] == why and props["nan_samples"] == "2"
    mdf = asammdf.MDF(paths["mf4"])
    try:
        assert mdf.get("measured_creep").comment == f"creep; NaN in 2 samples: {why}"
    finally:
        mdf.close()
    with xr.open_dataset(paths["nc"], engine="h5netcdf") as ds:
        assert ds["measured_creep"].attrs["nan_meaning"] == why
        assert int(ds["measured_creep"].attrs["nan_samples"]) == 2
    ds = xr.Dataset(
        {"measured_creep": ("time", [np.nan, 0.1], {"units": "1", "nan_meaning": why})},
        coords={"time": [0.0, 0.1]},
    )
    with xr.open_dataset(write_dataset(tmp_path / "d.nc", ds), engine="h5netcdf") as back:
        assert int(back["measured_creep"].attrs["nan_samples"]) == 1
    assert "nan_samples" not in ds["measured_creep"].attrs  # the caller's dataset untouched


# ----------------------------------------------------------------- bad input (probe findings)


@pytest.mark.parametrize("fmt", ["csv", "nc"])
def test_a_nan_sample_time_is_refused_not_written_as_an_empty_cell(tmp_path, fmt):
    import re

    path = tmp_path / f"run.{fmt}"
    with pytest.raises(ParameterError, match=re.escape("time must be finite [s]")):
        write_table(path, {"a": ([1.0, 2.0], "N")}, time=[0.0, np.nan])
    assert not path.exists()


def test_a_time_going_back_is_refused(tmp_path):
    import re

    with pytest.raises(ParameterError, match=re.escape("time must be non-decreasing [s]")):
        write_table(tmp_path / "run.csv", {"a": ([1.0, 2.0], "N")}, time=[1.0, 0.0])


def test_a_complex_column_is_refused_not_written_as_its_real_part(tmp_path):
    import re

    with pytest.raises(ParameterError, match=re.escape("column 'a' holds complex numbers")):
        write_table(tmp_path / "run.csv", {"a": (np.array([1 + 1j, 2 + 2j]), "N")})


def test_a_date_column_is_refused_not_written_as_days_under_seconds(tmp_path):
    import re

    dates = np.array(["2020-01-01", "2020-01-02"], dtype="datetime64[D]")
    with pytest.raises(ParameterError, match=re.escape("column 'a' holds dates or durations")):
        write_table(tmp_path / "run.csv", {"a": (dates, "s")})


def test_numbers_with_a_none_are_not_written_as_text_without_their_unit(tmp_path):
    import re

    with pytest.raises(ParameterError, match=re.escape("column 'a' has 1 NaN/inf samples")):
        write_table(tmp_path / "run.csv", {"a": ([1.0, None], "N")})
    with pytest.raises(ParameterError, match=re.escape("column 'a' holds text but has unit 'N'")):
        write_table(tmp_path / "run.csv", {"a": (["x", "y"], "N")})


@pytest.mark.parametrize(
    ("columns", "message"),
    [
        ({"a": ([1.0, 2.0],)}, "column 'a' must be given as (values, unit"),
        ({"a": [[1.0, 2.0], "N"]}, "column 'a' must be given as (values, unit"),
        ({"a": {"value": [1.0], "unit": "N"}}, "unknown key 'value' (did you mean 'values'?)"),
        ({"a": ([1.0, 2.0], 5)}, "column 'a' has unit 5; a unit is a str"),
        ({"a": ([1.0, 2.0], "N", "", 5)}, "column 'a' has attrs 5; attrs are a mapping"),
        ({5: ([1.0, 2.0], "N")}, "column names must be str, got 5 (int)"),
        ([("a", [1.0], "N")], "columns must be a mapping of name -> (values, unit"),
    ],
)
def test_a_malformed_column_is_one_clear_error(tmp_path, columns, message):
    import re

    with pytest.raises(ParameterError, match=re.escape(message)):
        write_table(tmp_path / "run.nc", columns)


def test_a_format_that_is_no_str_or_misspelt_is_one_clear_error(tmp_path):
    import re

    cols = {"a": ([1.0, 2.0], "N")}
    with pytest.raises(OutputError, match=re.escape("format must be a str")):
        write_table(tmp_path / "run.csv", cols, format=5)
    with pytest.raises(OutputError, match=re.escape("(did you mean 'parquet'?)")):
        write_table(tmp_path / "run.csv", cols, format="parqet")
    with pytest.raises(ParameterError, match=re.escape("attrs must be a mapping (dict) or None")):
        write_table(tmp_path / "run.csv", cols, attrs=[1, 2])


def test_write_dataset_refuses_what_is_no_dataset_and_a_nan_time_coordinate(tmp_path):
    import re

    from rollerrig.output.labelled import LabelledData

    with pytest.raises(ParameterError, match=re.escape("ds must be an xarray Dataset")):
        write_dataset(tmp_path / "x.nc", {"a": 1})
    data = LabelledData(
        {"a": ("time", [1.0, 2.0], {"units": "N"})},
        coords={"time": ("time", [0.0, np.nan], {"units": "s"})},
    )
    with pytest.raises(ParameterError, match=re.escape("time must be finite [s]")):
        write_dataset(tmp_path / "x.nc", data)
    data = LabelledData(
        {"a": ("time", [1.0, 2.0], {"units": "N"})},
        coords={"time": ("time", [0.0, 1.0], {"units": "s"})},
        attrs={"provenance": "{not json"},
    )
    with pytest.raises(ParameterError, match=re.escape("provenance attribute is not JSON")):
        write_dataset(tmp_path / "y.nc", data)
    assert not list(tmp_path.iterdir())


# --------------------------------------------------------------------------------------------
# The CSV table and its sidecar: a pair, both new or both old
# --------------------------------------------------------------------------------------------


def _pair(tmp_path):
    path = tmp_path / "r.csv"
    write_table(path, {"torque": ([1.0, 2.0], "N.m")}, time=[0.0, 0.1], attrs={"run": "old"})
    return path, path.with_suffix(".metadata.json")


def _new(path):
    return write_table(
        path, {"torque": ([3.0, 4.0], "N.m")}, time=[0.0, 0.1], attrs={"run": "new"},
        overwrite=True,
    )  # fmt: skip


def test_a_sidecar_that_fails_while_written_leaves_the_old_pair(tmp_path, monkeypatch):
    """The sidecar was written after the new CSV had replaced the old one: a failure then left
    the new table beside the old metadata."""
    import pathlib

    path, sidecar = _pair(tmp_path)
    before = (path.read_bytes(), sidecar.read_bytes())

    def full(self, *args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(pathlib.Path, "write_text", full)  # the sidecar's writer, not pandas'
    with pytest.raises(OutputError, match=r"r\.metadata\.json: .*disk is full"):
        _new(path)
    monkeypatch.undo()
    assert (path.read_bytes(), sidecar.read_bytes()) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.csv", "r.metadata.json"]


def test_a_sidecar_that_cannot_replace_the_old_one_puts_the_old_table_back(tmp_path, monkeypatch):
    """The second move fails after the first succeeded: the old CSV is put back."""
    path, sidecar = _pair(tmp_path)
    before = (path.read_bytes(), sidecar.read_bytes())
    real = os.replace

    def refuse_sidecar(src, dst, *args, **kwargs):
        if os.fspath(dst) == os.fspath(sidecar):
            raise OSError(errno.EIO, os.strerror(errno.EIO))
        return real(src, dst, *args, **kwargs)

    monkeypatch.setattr(os, "replace", refuse_sidecar)
    with pytest.raises(OutputError, match=r"r\.metadata\.json: cannot write the file"):
        _new(path)
    monkeypatch.undo()
    assert (path.read_bytes(), sidecar.read_bytes()) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.csv", "r.metadata.json"]
    _new(path)  # and then it works: both new
    assert json.loads(sidecar.read_text())["run"] == "new" and "3" in path.read_text()


def test_a_new_pair_that_fails_leaves_neither_file(tmp_path, monkeypatch):
    def refusing(real):
        def move(src, dst, *args, **kwargs):
            if os.fspath(dst).endswith(".metadata.json"):
                raise OSError(errno.EIO, os.strerror(errno.EIO))
            return real(src, dst, *args, **kwargs)

        return move

    # overwrite=False moves by hard link, or by os.replace where links are not supported
    monkeypatch.setattr(os, "link", refusing(os.link))
    monkeypatch.setattr(os, "replace", refusing(os.replace))
    with pytest.raises(OutputError, match=r"metadata\.json"):
        write_table(tmp_path / "r.csv", {"torque": ([1.0], "N.m")}, time=[0.0])
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("path", [None, 5, b"r.csv"])
def test_write_table_refuses_a_path_that_is_not_one(tmp_path, path):
    with pytest.raises(OutputError, match="path must be a file path"):
        write_table(path, {"torque": ([1.0], "N.m")}, time=[0.0])


def test_write_table_refuses_an_overwrite_that_is_text(tmp_path):
    """overwrite="no" is true: it had replaced the file."""
    path, _ = _pair(tmp_path)
    before = path.read_bytes()
    with pytest.raises(ParameterError, match="overwrite must be True or False"):
        write_table(path, {"torque": ([9.0], "N.m")}, time=[0.0], overwrite="no")
    assert path.read_bytes() == before
