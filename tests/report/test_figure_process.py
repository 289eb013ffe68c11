"""The experiment figure drawn by a helper process (rollerrig.report.figure_process).

The helper is used only where matplotlib is not imported yet, so its path runs in fresh
processes here (this test process has imported matplotlib): the caller then imports no
matplotlib at all, the figure carries the caller's provenance, a helper that died is replaced
by drawing in the caller, and a run that fails stops its helper and leaves no file behind.
"""

from __future__ import annotations

import json
import os
import pickle
import subprocess
import sys

import pytest

from rollerrig.output import figure_provenance, provenance
from rollerrig.report.figure_process import FigureProcess
from rollerrig.studies.executor_choice import available_cores

RECORD = {"software": "rollerrig", "version": "0", "command": ["rollerrig", "simulate", "-e", "x"]}
"""The caller's provenance record, handed to the helper: the figure must carry this one."""

_CALLER = """
import json, pickle, sys
from rollerrig.report.figure_process import FigureProcess
results_file, target, mode = sys.argv[1:4]
with open(results_file, "rb") as f:
    results = pickle.load(f)
record = json.loads(sys.argv[4])
state = {}
try:
    with FigureProcess() as drawing:
        state["helped"] = drawing.helped
        proc = drawing._proc
        if mode == "killed":  # the helper dies before it gets its job
            proc.kill()
            proc.wait()
        if mode == "fails":
            raise RuntimeError("the run failed before its results")
        drawing.submit(results, "release-test", target, record)
        drawing.finish()
except RuntimeError:
    state["stopped"] = proc.poll() is not None
state["matplotlib"] = "matplotlib" in sys.modules
print(json.dumps(state))
"""


@pytest.fixture(scope="module")
def results_file(tmp_path_factory):
    from rollerrig.solve.simulation import Simulation

    path = tmp_path_factory.mktemp("results") / "results.pickle"
    path.write_bytes(pickle.dumps(Simulation(experiment="release-test").solve()))
    return path


def _caller(tmp_path, results_file, mode: str) -> tuple[dict, os.PathLike]:
    """Run the caller in a fresh process with its own temporary folder; its state and figure."""
    temp = tmp_path / "temp"
    temp.mkdir()
    target = tmp_path / "figure.png"
    env = {**os.environ, "TMPDIR": str(temp), "TEMP": str(temp), "TMP": str(temp)}
    env.pop("MPLBACKEND", None)
    done = subprocess.run(
        [sys.executable, "-c", _CALLER, str(results_file), str(target), mode, json.dumps(RECORD)],
        capture_output=True,
        text=True,
        timeout=300,
        env=env,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert list(temp.iterdir()) == []  # the handed-over results are removed
    return json.loads(done.stdout.splitlines()[-1]), target


needs_two_cores = pytest.mark.skipif(
    available_cores() < 2, reason="the helper runs only beside the caller, on a second core"
)


@needs_two_cores
def test_the_helper_draws_and_the_caller_imports_no_matplotlib(tmp_path, results_file):
    state, figure = _caller(tmp_path, results_file, "normal")
    assert state == {"helped": True, "matplotlib": False}
    assert figure.stat().st_size > 10_000
    assert figure_provenance(figure) == RECORD  # the caller's, not the helper's command


@needs_two_cores
def test_a_helper_that_died_is_replaced_by_drawing_here(tmp_path, results_file):
    state, figure = _caller(tmp_path, results_file, "killed")
    assert state == {"helped": True, "matplotlib": True}  # drawn by the caller after all
    assert figure_provenance(figure) == RECORD


@needs_two_cores
def test_a_failed_run_stops_its_helper(tmp_path, results_file):
    state, figure = _caller(tmp_path, results_file, "fails")
    assert state == {"helped": True, "stopped": True, "matplotlib": False}
    assert not figure.exists()


def test_with_matplotlib_imported_the_figure_is_drawn_here(tmp_path, results_file):
    import matplotlib  # noqa: F401  (what a notebook or this test session has)

    results = pickle.loads(results_file.read_bytes())
    record = provenance(case="here")
    with FigureProcess() as drawing:
        assert not drawing.helped
        drawing.submit(results, "release-test", tmp_path / "figure.svg", record)
        path = drawing.finish()
    assert path == tmp_path / "figure.svg"
    assert figure_provenance(path)["parameters"] == {"case": "here"}


def test_finish_without_a_job_says_so():
    with FigureProcess(enabled=False) as drawing, pytest.raises(RuntimeError, match="nothing"):
        drawing.finish()
