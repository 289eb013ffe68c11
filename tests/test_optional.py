"""Optional packages: one table (module -> extra), one sentence naming the extra to install."""

import sys
import tomllib
from pathlib import Path

import pytest

from rollerrig._optional import (
    DISTRIBUTIONS,
    EXTRAS,
    JOBS,
    MissingExtraError,
    extra_for,
    missing_extra_message,
    require,
)

PYPROJECT = Path(__file__).resolve().parents[1] / "pyproject.toml"


def test_require_returns_the_module_or_names_the_extra(monkeypatch):
    assert require("json").__name__ == "json"
    monkeypatch.setitem(sys.modules, "nptdms", None)  # as if it were not installed
    with pytest.raises(MissingExtraError) as info:
        require("nptdms", purpose="reading TDMS files")
    assert str(info.value) == "reading TDMS files needs nptdms: pip install 'rollerrig[io]'"
    assert isinstance(info.value, ImportError) and info.value.name == "nptdms"
    monkeypatch.setitem(sys.modules, "numba", None)
    with pytest.raises(MissingExtraError, match=r"the fast solver needs numba: .*\[twin\]"):
        require("numba", "twin", "the fast solver")


def test_a_module_in_several_extras_is_named_by_the_job():
    # xarray writes the twin's results (twin) and the analysis' NetCDF (io).
    assert extra_for("xarray", job="simulate") == "twin"
    assert extra_for("xarray", job="analyze") == "io"
    assert extra_for("xarray", job="demo") == "all"
    assert extra_for("nptdms", job="simulate") == "io"  # only io holds it
    assert extra_for("pyarrow.parquet") == "io"
    assert extra_for("matplotlib") is None  # a core dependency: no extra


def test_missing_extra_message_for_any_import_error():
    exc = ModuleNotFoundError("No module named 'xarray'", name="xarray")
    assert missing_extra_message(exc, "simulate") == (
        "rollerrig simulate needs xarray: pip install 'rollerrig[twin]'"
    )
    exc = ModuleNotFoundError("No module named 'pandas'", name="pandas")
    assert missing_extra_message(exc, "filters") == (
        "rollerrig filters needs pandas: pip install 'rollerrig[io]'"
    )
    assert missing_extra_message(ModuleNotFoundError("x", name="scipy"), "simulate") is None
    kept = MissingExtraError("asammdf", "io", "reading MDF4 files")
    assert str(kept) == "reading MDF4 files needs asammdf: pip install 'rollerrig[io]'"
    assert missing_extra_message(kept, "analyze") == str(kept)


def test_an_extra_left_open_by_require_is_the_job_s(monkeypatch):
    # h5netcdf is in twin and io: require() alone names "all"; simulate names twin.
    monkeypatch.setitem(sys.modules, "h5netcdf", None)
    with pytest.raises(MissingExtraError) as info:
        require("h5netcdf", purpose="writing NetCDF files")
    assert str(info.value).endswith("pip install 'rollerrig[all]'")
    assert missing_extra_message(info.value, "simulate") == (
        "writing NetCDF files needs h5netcdf: pip install 'rollerrig[twin]'"
    )
    assert missing_extra_message(info.value, "analyze").endswith("'rollerrig[io]'")


@pytest.mark.skipif(not PYPROJECT.is_file(), reason="run from an installed package")
def test_the_table_agrees_with_pyproject():
    extras = tomllib.loads(PYPROJECT.read_text())["project"]["optional-dependencies"]

    def names(requirements):
        return {r.split(">")[0].split("=")[0].split("[")[0].strip() for r in requirements}

    for extra, modules in EXTRAS.items():
        assert names(extras[extra]) == {DISTRIBUTIONS.get(m, m) for m in modules}, extra
    assert "all" in extras
    assert set(JOBS.values()) <= set(EXTRAS) | {"all"}
