"""The one-run path: a command imports its own module and what it uses, nothing more.

Run in fresh processes (what is imported cannot be seen in the test process, which has imported
everything): ``rollerrig rig list`` imports no other command's module; ``rollerrig simulate``
imports neither xarray (nor pandas or pyarrow under it) nor dask, distributed or pyplot (nor
the studies' runner), nor matplotlib where its figure's helper process draws (two cores or
more: rollerrig.report.figure_process), and writes a NetCDF file with the same variables,
values and attributes as :meth:`Simulation.run`'s Dataset saved through the package's writer
(that this writer gives the file xarray's own would: tests/output/test_netcdf.py); with
``--no-figure`` it imports no matplotlib and writes no figure.
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import xarray as xr

from rollerrig.cli import COMMANDS
from rollerrig.output import figure_provenance
from rollerrig.studies.executor_choice import available_cores

_RUN = """
import atexit, json, sys
record = sys.argv[1]
atexit.register(lambda: open(record, "w").write(json.dumps(sorted(sys.modules))))
sys.argv = ["rollerrig", *sys.argv[2:]]
from rollerrig.cli import main
main()
"""
"""A fresh ``rollerrig`` process that writes the names of its imported modules at exit."""

_COMMAND_MODULES = {f"rollerrig.cli.{target.split(':')[0]}" for target in COMMANDS.values()}


def _imported(tmp_path, *args: str) -> set[str]:
    """The modules a fresh process of ``rollerrig ARGS`` imported (it must succeed)."""
    record = tmp_path / "modules.json"
    done = subprocess.run(
        [sys.executable, "-c", _RUN, str(record), *args],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    return set(json.loads(record.read_text()))


def test_a_command_imports_no_other_commands_module(tmp_path):
    modules = _imported(tmp_path, "rig", "list")
    assert modules & _COMMAND_MODULES == {"rollerrig.cli.rigs"}


_NOT_ON_THE_ONE_RUN_PATH = ("xarray", "pandas", "pyarrow", "dask", "distributed")
"""Top-level packages ``rollerrig simulate`` must not import: it writes, draws and summarises
its results without xarray (pandas and pyarrow come with xarray; dask with xarray's probes)."""


def test_simulate_imports_no_xarray_pandas_dask_or_pyplot(tmp_path):
    out = tmp_path / "out"
    modules = _imported(tmp_path, "simulate", "-e", "release-test", "--out", str(out), "--quiet")
    heavy = sorted(m for m in modules if m.split(".")[0] in _NOT_ON_THE_ONE_RUN_PATH)
    assert heavy == []
    assert "matplotlib.pyplot" not in modules  # the figure on an Agg canvas of its own
    if available_cores() >= 2:  # drawn by the helper process, which imported matplotlib
        assert not [m for m in modules if m.split(".")[0] == "matplotlib"]
    else:  # drawn here (the check sees matplotlib's names)
        assert "matplotlib.backends.backend_agg" in modules
    # Only the command's module (and the creep-law choice it shares with `contact`).
    assert modules & _COMMAND_MODULES == {"rollerrig.cli.twin", "rollerrig.cli.contact"}
    # The release overshoots come from the studies' metrics: not the runner, store or summaries
    # that an eager rollerrig.studies imported with them.
    assert "rollerrig.studies.metrics" in modules
    assert not modules & {"rollerrig.studies.runner", "rollerrig.studies.store"}
    assert (out / "release-test.png").stat().st_size > 10_000
    # The figure carries the command's provenance, whichever process drew it.
    assert figure_provenance(out / "release-test.png")["command"][1:] == [
        "simulate", "-e", "release-test", "--out", str(out), "--quiet"
    ]  # fmt: skip

    # The file is the one the Dataset of `Simulation.run` gives, saved by the same writer.
    from rollerrig.solve.results import save_dataset
    from rollerrig.solve.simulation import Simulation

    before = save_dataset(Simulation(experiment="release-test").run(), tmp_path / "before.nc")
    with xr.open_dataset(out / "release-test.nc") as ds, xr.open_dataset(before) as ref:
        assert ds.attrs["Conventions"] == "CF-1.10"
        assert ds["coa"].attrs["units"] == "1" and np.isfinite(ds["coa"].values).any()
        assert "_FillValue" not in ds["coa"].encoding
        assert list(ds.variables) == list(ref.variables)
        for name, var in ref.variables.items():
            assert ds[name].attrs == var.attrs, name
            assert ds[name].dtype == var.dtype, name
            if var.dtype.kind == "f":  # the solver's wall time aside, the run is deterministic
                np.testing.assert_array_equal(ds[name].values, var.values, err_msg=name)
            else:
                assert list(ds[name].values) == list(var.values), name
        # The file's attributes alike but for when and by which command it was made.
        made = ("provenance", "history")
        assert {k: v for k, v in ds.attrs.items() if k not in made} == {
            k: v for k, v in ref.attrs.items() if k not in made
        }
        assert list(ds.attrs) == list(ref.attrs)


def test_simulate_without_the_figure_imports_no_matplotlib(tmp_path):
    out = tmp_path / "out"
    args = ("simulate", "-e", "release-test", "--no-figure", "--out", str(out), "--quiet")
    modules = _imported(tmp_path, *args)
    assert not [m for m in modules if m.split(".")[0] in ("matplotlib", "PIL")]
    assert sorted(p.name for p in out.iterdir()) == [
        "release-test-modes.txt",
        "release-test.nc",
        "simulate-release-test-run.json",
    ]


_FROZEN_AT_EXIT = """
import atexit, gc, sys
record = sys.argv[1]
atexit.register(lambda: open(record, "w").write(str(gc.get_freeze_count())))
sys.argv = ["rollerrig", "--version"]
from rollerrig._command import main
main()
"""


def test_the_console_command_leaves_its_objects_out_of_the_exit_collection(tmp_path):
    """``rollerrig`` is :func:`rollerrig.cli.main` (through :mod:`rollerrig._command`, which
    guards Ctrl-C while it imports), which freezes the collector's objects when
    the command ends: the interpreter's exit then skips them (about 0.5 s of a fresh
    ``simulate``: the collector's passes over every object numpy, scipy and numba made)."""
    from importlib.metadata import entry_points

    (script,) = entry_points(group="console_scripts", name="rollerrig")
    assert script.value == "rollerrig._command:main"
    record = tmp_path / "frozen.txt"
    done = subprocess.run(
        [sys.executable, "-c", _FROZEN_AT_EXIT, str(record)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert int(record.read_text()) > 10_000  # the frozen objects: typer, rich, numpy, ...
