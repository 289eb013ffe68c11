"""LabelledData: a Dataset's content without xarray, written as the Dataset is written."""

from __future__ import annotations

import pickle
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from rollerrig.output import write_dataset
from rollerrig.output.labelled import LabelledData

PROVENANCE = {"software": "rollerrig", "version": "0", "command": ["rollerrig", "test"]}


def _arguments():
    """Constructor arguments both xarray and LabelledData take."""
    t = np.arange(4) * 0.5
    data = {
        "force": ("time", np.linspace(0.0, 1.0, 4), {"units": "N", "long_name": "force"}),
        "creep": ("time", np.array([np.nan, 0.1, 0.2, 0.3]), {"units": "1", "nan_meaning": "s"}),
        "surface": ("time", np.array(["dry", "wet", "dry", "dry"])),
        "oil temp/bearing": ("time", np.ones(4), {"units": "K"}),
        "lines": (("time", "line"), np.ones((4, 2)), {"units": "Hz"}),
    }
    coords = {"time": ("time", t, {"units": "s", "long_name": "time"})}
    attrs = {"title": "x", "count": 3, "provenance": "{}"}
    return data, coords, attrs


def test_it_holds_what_the_dataset_holds_in_its_order():
    data, coords, attrs = _arguments()
    ds = xr.Dataset(data, coords=coords, attrs=attrs)
    labelled = LabelledData(data, coords=coords, attrs=attrs)
    assert labelled.to_xarray().identical(ds)
    assert list(labelled.variables) == list(ds.variables)
    assert list(labelled) == list(ds.data_vars) and list(labelled.coords) == list(ds.coords)
    assert labelled.sizes == dict(ds.sizes)
    back = LabelledData.from_xarray(ds)
    assert back.to_xarray().identical(ds) and list(back.variables) == list(ds.variables)
    # What the figure and the metrics read.
    assert labelled.force.attrs["units"] == "N" and labelled["time"].values[-1] == 1.5
    assert "time" in labelled and "nothing" not in labelled
    with pytest.raises(AttributeError, match="nothing"):
        _ = labelled.nothing
    again = pickle.loads(pickle.dumps(labelled))  # a study's worker sends results back
    assert again.to_xarray().identical(ds)


def test_values_xarray_converts_are_converted_as_xarray_does():
    # Objects, dates and durations take xarray's own path (it converts them); a plain
    # array of numbers or strings is handed over as it is.
    data = {
        "when": ("time", np.array(["2026-12-01T08:00", "2026-12-01T08:01"], dtype="M8[s]")),
        "took": ("time", np.array([1, 2], dtype="m8[s]")),
        "note": ("time", np.array(["a", None], dtype=object)),
        "force": ("time", np.array([1.0, 2.0])),
    }
    ds = xr.Dataset(data, coords={"time": ("time", np.array([0.0, 1.0]))})
    converted = LabelledData(data, coords={"time": ("time", np.array([0.0, 1.0]))}).to_xarray()
    assert converted.identical(ds)
    assert converted.when.dtype == ds.when.dtype and converted.took.dtype == ds.took.dtype


def test_the_dataset_is_built_without_importing_dask():
    # xarray's probe of dask's array type imports dask.array (0.25-0.75 s of a fresh process)
    # for every array it is given, unless it is handed over as it is (issue 20).
    pytest.importorskip("dask")
    code = (
        "import sys, numpy as np, xarray\n"
        "from rollerrig.output.labelled import LabelledData\n"
        "d = LabelledData({'f': ('time', np.ones(3), {'units': 'N'})},"
        " coords={'time': ('time', np.arange(3.0))}).to_xarray()\n"
        "assert d.f.values.tolist() == [1.0, 1.0, 1.0]\n"
        "sys.exit(int('dask.array' in sys.modules))\n"
    )
    assert subprocess.run([sys.executable, "-c", code]).returncode == 0


def test_variables_of_different_lengths_are_refused():
    with pytest.raises(ValueError, match="'b': dimension 'time' has sizes 3 and 2"):
        LabelledData({"a": ("time", np.ones(3)), "b": ("time", np.ones(2))})
    with pytest.raises(ValueError, match="dimensions"):
        LabelledData({"a": (("time", "line"), np.ones(3))})


@pytest.mark.parametrize("suffix", [".nc", ".csv"])
def test_it_is_written_as_its_dataset_is(tmp_path, suffix):
    data, coords, attrs = _arguments()
    if suffix != ".nc":  # columns along time alone
        del data["lines"]
    a = write_dataset(
        tmp_path / f"labelled{suffix}",
        LabelledData(data, coords=coords, attrs=attrs),
        provenance=PROVENANCE,
    )
    b = write_dataset(
        tmp_path / f"dataset{suffix}",
        xr.Dataset(data, coords=coords, attrs=attrs),
        provenance=PROVENANCE,
    )
    if suffix == ".csv":
        assert a.read_text() == b.read_text()
        sidecar = ".metadata.json"
        assert a.with_suffix(sidecar).read_text() == b.with_suffix(sidecar).read_text()
        return
    with xr.open_dataset(a) as x, xr.open_dataset(b) as y:
        assert x.identical(y) and list(x.variables) == list(y.variables)
        assert x["oil_temp_bearing"].attrs["original_name"] == "oil temp/bearing"
        assert x["creep"].attrs["nan_samples"] == 1
