"""The one-run path: a command imports its own module and what it uses, nothing more.

Run in fresh processes (what is imported cannot be seen in the test process, which has
imported everything): ``rollerrig rig list`` imports no other command's module;
``rollerrig simulate`` imports neither dask nor distributed (xarray's probes, its NetCDF
writer's scheduler probe) and writes a NetCDF file xarray reads.
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import xarray as xr

from rollerrig.cli import COMMANDS

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


def test_simulate_imports_neither_dask_nor_distributed(tmp_path):
    out = tmp_path / "out"
    modules = _imported(tmp_path, "simulate", "-e", "release-test", "--out", str(out), "--quiet")
    heavy = sorted(m for m in modules if m.split(".")[0] in ("dask", "distributed"))
    assert heavy == []
    # Only the command's module (and the creep-law choice it shares with `contact`).
    assert modules & _COMMAND_MODULES == {"rollerrig.cli.twin", "rollerrig.cli.contact"}
    with xr.open_dataset(out / "release-test.nc") as ds:
        assert ds.attrs["Conventions"] == "CF-1.10"
        assert ds["coa"].attrs["units"] == "1" and np.isfinite(ds["coa"].values).any()
        assert "_FillValue" not in ds["coa"].encoding
    assert (out / "release-test.png").stat().st_size > 10_000
