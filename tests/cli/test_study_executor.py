"""``study run --executor auto`` (issue 20): the help, the line that says where and why, the
record in the JSON summary, and --workers as a request for dask."""

import json

import pytest

from rollerrig.cli import app
from rollerrig.studies import runner as runner_module
from rollerrig.studies.runner import _local

TINY = """
name = "tiny"
[grid]
"stiffness.roller_shaft" = { values = [43.5, 143.5], unit = "kN.m/rad" }
[outputs]
metrics = ["release_overshoot"]
"""


def test_help_shows_auto_as_the_default_and_keeps_the_units(runner):
    result = runner.invoke(app, ["study", "run", "--help"], terminal_width=200)
    assert result.exit_code == 0
    text = " ".join(result.output.split())
    assert "<auto|dask|local>" in text and "[default: auto]" in text
    assert "about 12 [s] on 2 free cores, 30 [s] under load" in text  # a unit in brackets survives
    assert "under --executor auto, a request for dask" in text


def test_auto_says_where_the_points_ran_and_why_and_records_it(tmp_path, runner):
    study = tmp_path / "tiny.toml"
    study.write_text(TINY)
    out = tmp_path / "out"
    result = runner.invoke(app, ["study", "run", str(study), "--out", str(out)])
    assert result.exit_code == 0, result.output
    text = " ".join(result.output.split())
    assert "executor auto: the first batch here" in text
    assert "executor local: every point ran in the first batch" in text
    assert "on 2 threads" in text or "threads)" in text
    doc = json.loads((out / "study-tiny.json").read_text())
    assert doc["executor"] == "local" and doc["executor_asked"] == "auto"
    assert doc["executor_reason"] == "every point ran in the first batch"
    assert doc["fixed_cost_s"]["solver_load_s"] >= 0 and doc["serial_s_per_point"] > 0


class _FakeDask:
    """The dask executor's stand-in: runs the batches here (no cluster in a fast test)."""

    def __init__(self, scheduler, workers):
        self.workers, self.start_s, self.warm_s = workers, 0.0, 0.0

    def warm(self, point, args):
        pass

    def run(self, batches, args):
        return _local(batches, args)

    def close(self, *, interrupted=False):
        pass


def test_workers_under_auto_are_honoured_as_a_request_for_dask(tmp_path, runner, monkeypatch):
    monkeypatch.setattr(runner_module, "_DaskExecutor", _FakeDask)
    study = tmp_path / "tiny.toml"
    study.write_text(TINY)
    out = tmp_path / "out"
    result = runner.invoke(app, ["study", "run", str(study), "--workers", "3", "--out",
                                 str(out)])  # fmt: skip
    assert result.exit_code == 0, result.output
    text = " ".join(result.output.split())
    assert "on a local dask cluster of 3 workers" in text
    assert "executor dask: 3 workers asked for: a local dask cluster" in text
    assert "points/s on 3 workers" in text
    doc = json.loads((out / "study-tiny.json").read_text())
    assert doc["executor"] == "dask" and doc["workers"] == 3


@pytest.mark.parametrize("extra", [["--workers", "2"], ["--scheduler", "tcp://10.0.0.5:8786"]])
def test_local_with_a_dask_option_is_one_error_line(tmp_path, runner, extra):
    result = runner.invoke(app, ["study", "run", "lag", "--executor", "local", *extra, "--out",
                                 str(tmp_path / "out")])  # fmt: skip
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert "need --executor dask (or auto, the default)" in " ".join(result.output.split())
    assert not (tmp_path / "out").exists()
