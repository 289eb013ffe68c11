"""Outputs that never destroy: all or none, inside --out, never over an input, one run at a time.

``staged_outputs`` on its own (no command): what lands in ``--out``, what is refused before
anything moves, the lock and the run's manifest.
"""

import json
import os
import shutil
import subprocess
import sys
import textwrap

import pytest

from rollerrig.cli import MAX_OUTPUT_STEM, command_outputs, staged_outputs
from rollerrig.cli._outputs import LOCK_NAME, STAGE_PREFIX
from rollerrig.output import OutputError, file_sha256


def _files(folder):
    return sorted(p.name for p in folder.rglob("*")) if folder.exists() else []


def test_staged_outputs_commit_together_or_not_at_all(tmp_path):
    out = tmp_path / "a" / "b"
    with staged_outputs(out) as stage:
        stage.path("x.json").write_text("{}")
        (stage.dir / "sub").mkdir()
        (stage.dir / "sub" / "y.txt").write_text("y")
        assert not (out / "x.json").exists()  # nothing visible before the end
    assert sorted(p.relative_to(out).as_posix() for p in stage.written) == ["sub/y.txt", "x.json"]
    with pytest.raises(RuntimeError), staged_outputs(out) as stage:
        stage.path("x.json").write_text("new")
        stage.path("z.json").write_text("z")
        raise RuntimeError("failed half-way")
    assert (out / "x.json").read_text() == "{}" and not (out / "z.json").exists()
    # No staging folder and no lock file left.
    assert _files(tmp_path) == ["a", "b", "sub", "x.json", "y.txt"]


def test_the_wrote_line_says_where_an_earlier_runs_file_was_replaced(tmp_path, capsys):
    # contact, frame and others name their outputs by the command alone: a second run into
    # the same --out had replaced the first's files without a word.
    from rollerrig.cli._console import print_written

    for text in ("first", "second"):
        with staged_outputs(tmp_path, run="contact") as stage:
            stage.path("contact-report.json").write_text(text)
        print_written(stage.written)
    lines = capsys.readouterr().out.splitlines()
    first, second = lines[: len(lines) // 2], lines[len(lines) // 2 :]
    assert not any("replaced" in line for line in first)
    assert all(line.endswith("(replaced an earlier run's)") for line in second)
    assert (tmp_path / "contact-report.json").read_text() == "second"


def test_a_failed_run_removes_the_folders_it_created(tmp_path):
    out = tmp_path / "new" / "deeper"
    with pytest.raises(RuntimeError), staged_outputs(out) as stage:
        stage.path("a.json").write_text("{}")
        raise RuntimeError("failed")
    assert _files(tmp_path) == []


def test_output_names_from_user_data_stay_inside_out(tmp_path):
    # An experiment named "../escaped" or with 300 characters (issue 8): the file lands in
    # --out under a plain, shortened name; nothing is written next to it.
    out = tmp_path / "out"
    with staged_outputs(out) as stage:
        stage.path("../escaped.nc").write_text("e")
        stage.path("x" * 300 + ".png").write_text("x")
    names = sorted(p.name for p in stage.written)
    assert names == ["_escaped.nc", "x" * MAX_OUTPUT_STEM + ".png"]
    assert _files(tmp_path) == sorted(["out", *names])


def test_an_output_name_taken_by_a_folder_is_one_error_and_nothing_moves(tmp_path):
    out = tmp_path / "out"
    (out / "report.html").mkdir(parents=True)
    with pytest.raises(OutputError, match=r"report.html is a folder"), staged_outputs(out) as st:
        st.path("a.json").write_text("{}")
        (st.dir / "report.html").write_text("<html>")  # written by a writer given stage.dir
    assert _files(tmp_path) == ["out", "report.html"]  # a.json was not moved in either
    with pytest.raises(OutputError, match=r"report.html is a folder"), staged_outputs(out) as st:
        st.path("report.html")  # refused as soon as the name is asked for


def test_out_that_is_a_file_is_one_error_naming_it(tmp_path):
    blocker = tmp_path / "out"
    blocker.write_text("not a folder")
    with pytest.raises(OutputError, match=r"out is a file, not a folder"):
        with staged_outputs(blocker):
            pass
    assert blocker.read_text() == "not a folder"
    with pytest.raises(OutputError, match=r"cannot create the folder"):
        with staged_outputs(blocker / "inside"):
            pass
    assert _files(tmp_path) == ["out"]


def _unprivileged() -> list[str]:
    """A command prefix that runs without the power to write into read-only folders."""
    if os.geteuid() != 0:
        return []
    setpriv = shutil.which("setpriv")
    drop = [setpriv, "--bounding-set=-all", "--inh-caps=-all"] if setpriv else None
    if drop is None or subprocess.run([*drop, "true"], capture_output=True).returncode != 0:
        pytest.skip("root writes into read-only folders, and its capabilities cannot be dropped")
    return drop


def test_a_read_only_out_is_one_error_naming_it(tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    prefix = _unprivileged()
    try:
        for out, message in (
            (ro, f"error: --out {ro}: cannot write there: Permission denied"),
            (ro / "sub", f"error: --out {ro / 'sub'}: cannot create the folder: Permission"),
        ):
            done = subprocess.run(
                [*prefix, sys.executable, "-m", "rollerrig.cli", "contact", "--out", str(out)],
                capture_output=True,
                text=True,
                timeout=120,
                env={**os.environ, "MPLBACKEND": "Agg"},
            )
            assert done.returncode == 2, done.stdout + done.stderr
            (line,) = done.stderr.strip().splitlines()
            assert line.startswith(message), line
        assert _files(ro) == []
    finally:
        ro.chmod(0o755)


def test_an_output_that_would_replace_an_input_is_refused_before_anything_moves(tmp_path):
    trace = tmp_path / "trace.csv"
    trace.write_text("time [s],torque [N.m]\n0,0\n1,100\n")
    before = file_sha256(trace)
    with pytest.raises(OutputError, match=r"would replace the input file .*trace.csv"):
        with staged_outputs(tmp_path, inputs=[trace]) as stage:
            (stage.dir / "other.png").write_text("x")
            (stage.dir / "trace.csv").write_text("results")  # what a writer given dir did
    assert file_sha256(trace) == before
    assert _files(tmp_path) == ["trace.csv"]
    # A hard link to the input is the same file too.
    os.link(trace, tmp_path / "link.csv")
    with pytest.raises(OutputError, match=r"link.csv would replace the input"):
        with staged_outputs(tmp_path, inputs=[trace]) as stage:
            stage.path("link.csv")
    assert file_sha256(trace) == before


def test_the_run_manifest_lists_every_file_with_its_hash_and_provenance(tmp_path):
    rec = tmp_path / "in.csv"
    rec.write_text("a,b\n1,2\n")
    out = tmp_path / "out"
    with command_outputs(out, run="analyze-in", inputs={"recording": rec}, fs=250.0) as stage:
        stage.path("in-analysis.json").write_text('{"x": 1}\n')
        stage.path("in-report.html").write_text("<html></html>\n")
    assert [p.name for p in stage.written][-1] == "analyze-in-run.json"  # moved last
    doc = json.loads((out / "analyze-in-run.json").read_text())
    listed = {f["file"]: f["sha256"] for f in doc["files"]}
    assert listed == {n: file_sha256(out / n) for n in ("in-analysis.json", "in-report.html")}
    prov = doc["provenance"]
    assert prov["inputs"]["recording"]["sha256"] == file_sha256(rec)
    assert prov["parameters"]["fs"] == 250.0
    assert prov["command"]  # the command line (sys.argv outside a command)


def test_stale_staging_folders_of_a_killed_run_are_removed(tmp_path):
    out = tmp_path / "out"
    stale = out / f"{STAGE_PREFIX}12345-abc"
    stale.mkdir(parents=True)
    (stale / "half.png").write_text("x")
    with staged_outputs(out) as stage:
        stage.path("a.txt").write_text("a")
    assert _files(out) == ["a.txt"]


_HOLD_THE_LOCK = textwrap.dedent(
    """
    import sys, time
    from rollerrig.cli import staged_outputs
    with staged_outputs(sys.argv[1]) as stage:
        stage.path("slow.txt").write_text("slow")
        print("locked", flush=True)
        time.sleep(60)
    """
)


def test_a_second_run_into_the_same_out_is_one_error_naming_the_pid(tmp_path):
    out = tmp_path / "out"
    holder = subprocess.Popen(
        [sys.executable, "-c", _HOLD_THE_LOCK, str(out)],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert holder.stdout.readline().strip() == "locked"
        with pytest.raises(
            OutputError, match=rf"in use by another rollerrig run \(pid {holder.pid}\)"
        ):
            with staged_outputs(out) as stage:
                stage.path("mine.txt").write_text("mine")
        assert (out / LOCK_NAME).exists()  # the other run's lock is left alone
    finally:
        holder.kill()
        holder.wait()
    # The holder was killed: the kernel released its lock; the next run takes it and removes
    # the killed run's staging folder.
    with staged_outputs(out) as stage:
        stage.path("mine.txt").write_text("mine")
    assert _files(out) == ["mine.txt"]


def test_two_outputs_of_one_run_that_become_one_file_are_one_error(tmp_path):
    out = tmp_path / "out"
    with pytest.raises(OutputError, match=r"both be written to .*a_b\.json"):
        with staged_outputs(out) as stage:
            stage.path("a b.json").write_text("1")
            stage.path("a_b.json").write_text("2")  # would replace the first silently
    assert _files(tmp_path) == []
    with pytest.raises(OutputError, match=r"both be written to .*X\.json"):
        with staged_outputs(out) as stage:
            stage.path("X.json").write_text("1")
            stage.path("x.json")  # one file on Windows and macOS
    with staged_outputs(out) as stage:  # Unicode names differ: two files
        stage.path("试验一.json").write_text("1")
        stage.path("试验二.json").write_text("2")
    assert sorted(p.name for p in stage.written) == ["试验一.json", "试验二.json"]


@pytest.mark.parametrize("failing", ["b.png", "run-run.json"])
def test_a_file_that_cannot_be_replaced_leaves_the_old_outputs_whole(
    tmp_path, monkeypatch, failing
):
    """One output that could not be replaced (a same-named file another user owns in a shared
    folder) had stopped the commit half-way: the new results beside the old figure and
    manifest, the old results lost (a review, 2026-12-03). Now nothing in --out changes."""
    from rollerrig.cli import _outputs

    out = tmp_path / "out"
    with command_outputs(out, run="run") as stage:
        for name in ("a.nc", "b.png", "c.txt"):
            stage.path(name).write_text("old " + name)
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    real = os.replace

    def refuse(src, dst):  # the new file onto the old one, not the old one moved aside
        if os.fspath(dst) == os.fspath(out / failing) and ".replaced" not in os.fspath(src):
            raise PermissionError(1, "Operation not permitted")
        return real(src, dst)

    monkeypatch.setattr(_outputs.os, "replace", refuse)  # the os module: everyone's
    with pytest.raises(OutputError, match=rf"{failing}: cannot write the file.*nothing in"):
        with command_outputs(out, run="run") as stage:
            for name in ("a.nc", "b.png", "c.txt", "d.csv"):
                stage.path(name).write_text("new " + name)
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before


def test_an_earlier_runs_output_this_run_does_not_write_is_removed_with_the_commit(tmp_path):
    # `simulate --no-figure` had left an older run's figure beside the new results. Only a
    # file the earlier run's manifest lists, unchanged, goes; anything else of that name stays.
    with staged_outputs(tmp_path, run="sim") as stage:
        for name in ("r.nc", "r.png", "r.svg"):
            stage.path(name).write_text("first")
    (tmp_path / "r.svg").write_text("edited by hand")  # changed since the run wrote it
    (tmp_path / "other.png").write_text("not this run's")
    with staged_outputs(tmp_path, run="sim") as stage:
        stage.path("r.nc").write_text("second")
        for name in ("r.png", "r.svg", "other.png", "missing.png"):
            stage.supersede(name)
    assert stage.removed == [tmp_path / "r.png"] and not (tmp_path / "r.png").exists()
    assert stage.kept == [tmp_path / "r.svg", tmp_path / "other.png"]
    assert (tmp_path / "r.svg").read_text() == "edited by hand"
    assert (tmp_path / "other.png").read_text() == "not this run's"
    manifest = json.loads((tmp_path / "sim-run.json").read_text())
    assert manifest["removed"] == ["r.png"]
    assert {f["file"] for f in manifest["files"]} == {"r.nc"}
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".rollerrig")]


def test_a_failed_run_removes_no_earlier_output(tmp_path):
    with staged_outputs(tmp_path, run="sim") as stage:
        stage.path("r.png").write_text("first")
    with pytest.raises(RuntimeError), staged_outputs(tmp_path, run="sim") as stage:
        stage.supersede("r.png")
        raise RuntimeError
    assert (tmp_path / "r.png").read_text() == "first"
