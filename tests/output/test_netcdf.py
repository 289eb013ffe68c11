"""NetCDF through h5py directly: the file xarray's own writer would write (same variables,
dimensions, coordinates, attributes and encodings as read back by ``xarray.open_dataset``),
without xarray's scheduler probe; a simulation's results round-trip."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

from rollerrig.output import netcdf, write_dataset, write_table

PROVENANCE = {"software": "rollerrig", "version": "0", "command": ["rollerrig", "test"]}


def _encodings(ds: xr.Dataset) -> dict:
    """Each variable's encoding as read back, without where it was read from."""
    return {
        name: {k: v for k, v in var.encoding.items() if k != "source"}
        for name, var in ds.variables.items()
    }


def _same_file(direct, by_xarray) -> None:
    """Both files read back alike: values, dtypes, attributes (and their types), encodings."""
    with xr.open_dataset(direct) as a, xr.open_dataset(by_xarray) as b:
        assert a.identical(b)
        assert list(a.variables) == list(b.variables) and dict(a.sizes) == dict(b.sizes)
        for name in a.variables:
            assert a[name].dtype == b[name].dtype, name
            assert list(a[name].attrs) == list(b[name].attrs), name
        assert list(a.attrs) == list(b.attrs)
        assert {k: type(v) for k, v in a.attrs.items()} == {k: type(v) for k, v in b.attrs.items()}
        assert _encodings(a) == _encodings(b)


def _written_twice(tmp_path, monkeypatch, write):
    """``write(folder)`` directly, then again through xarray's writer (the way before)."""
    (tmp_path / "direct").mkdir()
    (tmp_path / "xarray").mkdir()
    calls = []
    real = netcdf.write_netcdf

    def counted(*args, **kwargs):
        calls.append(args[0])
        return real(*args, **kwargs)

    monkeypatch.setattr(netcdf, "write_netcdf", counted)
    direct = write(tmp_path / "direct")
    assert calls, "not written directly"
    monkeypatch.setattr(netcdf, "writable_directly", lambda ds, variables: False)
    monkeypatch.setattr(netcdf, "write_netcdf", real)
    return direct, write(tmp_path / "xarray")


def _mixed() -> xr.Dataset:
    t = np.arange(5) * 0.1
    return xr.Dataset(
        {
            "force": ("time", np.linspace(0, 1, 5), {"units": "N", "long_name": "force"}),
            "count": ("time", np.arange(5), {"units": "1", "n": 3}),
            "flag": ("time", np.array([True, False, True, True, False]), {"units": "1"}),
            "surface": ("time", np.array(["dry", "wet", "dry", "dry", "wet"])),
            "label": ("time", np.array(["a", "bb", "c", "d", "Öl"], dtype=object)),
            "lines": (("time", "line"), np.ones((5, 3)), {"units": "Hz"}),
            "order": ("line", np.arange(3, dtype="u2"), {"units": "1"}),
            "radius": ((), 0.452, {"units": "m"}),
            "creep": (
                "time",
                [np.nan, 0.1, 0.2, 0.3, 0.4],
                {"units": "1", "nan_meaning": "standstill", "weights": [1, 2], "ok": True},
            ),
        },
        coords={"time": ("time", t, {"units": "s"})},
        attrs={"title": "mixed", "count": 3, "nested": {"a": 1}, "rate": 1.5, "flag": False},
    )


def test_a_dataset_of_every_kind_is_written_as_xarray_writes_it(tmp_path, monkeypatch):
    def write(folder):
        return write_dataset(folder / "x.nc", _mixed(), provenance=PROVENANCE)

    _same_file(*_written_twice(tmp_path, monkeypatch, write))
    with xr.open_dataset(tmp_path / "direct" / "x.nc") as back:
        assert back["flag"].dtype == bool and back["surface"].dtype.kind == "U"
        assert back["label"].values[-1] == "Öl" and back["lines"].dims == ("time", "line")
        assert back["creep"].attrs["nan_samples"] == 1 and np.isnan(back["creep"].values[0])
        assert "_FillValue" not in back["force"].encoding
        assert json.loads(back.attrs["provenance"]) == PROVENANCE


@pytest.mark.parametrize("with_time", [True, False])
def test_columns_are_written_as_xarray_writes_them(tmp_path, monkeypatch, with_time):
    columns = {
        "a": (np.arange(4.0), "m", "length"),
        "lab": (np.array(["x", "y", "z", "w"]), None),
        "n": (np.array([1.0, np.nan, 2, 3]), "1", "", {"nan_meaning": "gap"}),
    }
    time = np.arange(4) * 0.5 if with_time else None

    def write(folder):
        return write_table(folder / "t.nc", columns, time=time, provenance=PROVENANCE)

    _same_file(*_written_twice(tmp_path, monkeypatch, write))


def test_what_needs_xarrays_encoders_still_goes_through_them(tmp_path):
    """Times and a coordinate that is no dimension's own: xarray's writer, as before."""
    ds = _mixed().assign_coords(phase=("time", np.array(list("abcde"))))
    ds = ds.assign(when=("time", np.array(["2026-01-01"] * 5, dtype="datetime64[ns]")))
    path = write_dataset(tmp_path / "x.nc", ds, provenance=PROVENANCE)
    with xr.open_dataset(path) as back:
        assert "phase" in back.coords and back["when"].dtype.kind == "M"


def test_a_variable_named_as_a_dimension_it_does_not_index_is_written(tmp_path):
    """``ch`` along ``time`` beside the dimension ``ch`` (found in review: the direct writer
    made a scale named ``ch`` and then could not create the variable): xarray's writer."""
    ds = xr.Dataset(
        {"f": (("time", "ch"), np.ones((2, 3)), {"units": "N"}),
         "ch": ("time", np.array([1.0, 2.0]), {"units": "m"})},
        coords={"time": [0.0, 1.0]},
    )  # fmt: skip
    path = write_dataset(tmp_path / "clash.nc", ds, provenance=PROVENANCE)
    with xr.open_dataset(path) as back:
        assert back["ch"].dims == ("time",) and back["ch"].values.tolist() == [1.0, 2.0]
        assert back["f"].shape == (2, 3)


@pytest.fixture(scope="module")
def simulated():
    from rollerrig.rig import default_rig
    from rollerrig.solve.simulation import Simulation

    return Simulation(default_rig(), "release-test").run()


def test_a_simulation_round_trips(tmp_path, monkeypatch, simulated):
    from rollerrig.solve.results import save_dataset

    ds = simulated

    def write(folder):
        return save_dataset(ds, folder / "release-test.nc")

    direct, by_xarray = _written_twice(tmp_path, monkeypatch, write)
    _same_file(direct, by_xarray)
    with xr.open_dataset(direct) as back:
        assert list(back.data_vars) == list(ds.data_vars) and list(back.coords) == ["time"]
        assert dict(back.sizes) == dict(ds.sizes)
        for name, var in ds.variables.items():
            got = back[name]
            assert got.dims == var.dims, name
            if var.dtype.kind == "f":
                np.testing.assert_array_equal(got.values, var.values)
                assert got.dtype == var.dtype and got.encoding["dtype"] == var.dtype
                assert "_FillValue" not in got.encoding and "_FillValue" not in got.attrs
            else:
                assert list(got.values) == list(var.values), name
            # The variable's attributes as given (units, long names, NaN meanings) and a long
            # name where it had none.
            for key, value in var.attrs.items():
                assert got.attrs[key] == value, (name, key)
            assert got.attrs["long_name"]
        # The dataset's attributes, the CF ones and the provenance record.
        assert back.attrs["Conventions"] == "CF-1.10"
        assert json.loads(back.attrs["provenance"]) == json.loads(ds.attrs["provenance"])
        for key, value in ds.attrs.items():
            if key != "provenance" and isinstance(value, str):
                assert back.attrs[key] == value, key


class _DiskFillsAfter:
    """``open`` for netcdf's module: a real file whose writes fail with ENOSPC once ``budget``
    bytes are written (a full disk, as a 700 KiB tmpfs gave it)."""

    def __init__(self, budget: int) -> None:
        self.budget = budget

    def __call__(self, path, mode, buffering=-1):
        import errno
        import io

        budget = self.budget

        class Full(io.FileIO):
            def write(self, data):
                nonlocal budget
                size = memoryview(data).nbytes
                if size > budget:
                    raise OSError(errno.ENOSPC, "No space left on device")
                budget -= size
                return super().write(data)

        return Full(path, mode.replace("+", "").replace("w", "w+"))


@pytest.mark.parametrize("budget", [0, 3000, 200_000])
def test_a_full_disk_is_one_clear_error_and_leaves_no_file(tmp_path, monkeypatch, budget):
    # HDF5's own driver could not close its file on a full disk: h5py raised "Can't decrement
    # id ref count" (an internal error) and the process died at exit with a segmentation
    # fault. The first write error is now kept from HDF5 and raised after it closed.
    from rollerrig.output import OutputError, atomic_write

    monkeypatch.setattr(netcdf, "open", _DiskFillsAfter(budget), raising=False)
    variables = {
        "time": netcdf.NcVariable(("time",), np.arange(20_000) / 250.0, {"units": "s"}),
        "torque": netcdf.NcVariable(("time",), np.ones(20_000), {"units": "N.m"}),
    }
    target = tmp_path / "r.nc"
    with pytest.raises(OutputError, match=r"disk is full.*nothing was written"):
        atomic_write(target, lambda tmp: netcdf.write_netcdf(tmp, variables, {"title": "t"}))
    assert list(tmp_path.iterdir()) == []
    monkeypatch.undo()  # and the same write on a disk with room reads back
    atomic_write(target, lambda tmp: netcdf.write_netcdf(tmp, variables, {"title": "t"}))
    with xr.open_dataset(target, engine="h5netcdf") as back:
        np.testing.assert_array_equal(back.torque.values, 1.0)
