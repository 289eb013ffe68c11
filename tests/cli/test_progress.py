"""Progress of the long commands: plain lines when stdout is not a terminal (piped, a notebook,
typer's CliRunner), a live bar on a terminal, nothing with ``--quiet``; texts printed literally
(``[kN]`` survives)."""

from __future__ import annotations

import io
import re

import pytest
from rich.console import Console

from rollerrig.cli import app
from rollerrig.cli._console import ProgressLines, is_quiet, progress, set_quiet, steps

_LINE = re.compile(r"^(?P<what>[^:\n]+): (?P<rest>.*)\((?P<s>\d+\.\d) s\)$", re.M)


@pytest.fixture(autouse=True)
def _not_quiet():
    set_quiet(False)
    yield
    set_quiet(False)


def _console() -> tuple[Console, io.StringIO]:
    buf = io.StringIO()
    return Console(file=buf, width=80, markup=False, highlight=False), buf


def test_a_bar_prints_a_line_at_each_tenth_when_not_a_terminal():
    out, buf = _console()
    bar = progress(out)
    assert isinstance(bar, ProgressLines)  # a StringIO is no terminal
    with bar:
        task = bar.add_task("simulating", total=30.0, info="solving")
        for i in range(301):
            bar.update(task, completed=i / 10, info=f"t = {i / 10:.2f} s")
    lines = buf.getvalue().splitlines()
    assert 11 <= len(lines) <= 12, lines  # the start, each tenth: never one per update
    assert lines[0].startswith("simulating:   0 % solving (")
    assert lines[-1].startswith("simulating: 100 % t = 30.00 s (")
    assert all(_LINE.match(line) for line in lines)
    assert "\r" not in buf.getvalue() and "\x1b" not in buf.getvalue()  # no redrawn bar


def test_steps_print_one_line_per_step_units_in_brackets_kept():
    out, buf = _console()
    with progress(out) as bar:
        task = bar.add_task("analyze test.csv", info="reading")
        bar.update(task, info="load 4.3 [kN], [channels.torque]")
        bar.update(task, info="load 4.3 [kN], [channels.torque]")  # the same step: no line
        bar.update(task, info="done")
    lines = buf.getvalue().splitlines()
    assert [line.split(" (")[0] for line in lines] == [
        "analyze test.csv: reading",
        "analyze test.csv: load 4.3 [kN], [channels.torque]",
        "analyze test.csv: done",
    ]


def test_quiet_prints_nothing_and_a_terminal_gets_a_live_bar():
    out, buf = _console()
    set_quiet(True)
    assert is_quiet()
    with progress(out) as bar:
        bar.update(bar.add_task("x", total=2), completed=2, info="done")
    assert buf.getvalue() == ""
    assert bar.tasks[0].total == 2  # the commands read it back
    set_quiet(False)
    terminal = Console(file=io.StringIO(), force_terminal=True, width=80)
    from rich.progress import Progress

    assert isinstance(progress(terminal), Progress)


def test_steps_say_what_runs_and_done(capsys):
    with steps("study frame", "simulating") as say:
        say("rigid frame (1 of 3)")
    lines = capsys.readouterr().out.splitlines()
    assert [line.split(" (")[0] for line in lines] == [
        "study frame: simulating",
        "study frame: rigid frame",
        "study frame: done",
    ]


def test_the_analysis_reports_its_steps(tmp_path, adhesion_csv):
    from rollerrig.analysis.adhesion import analyze_test
    from rollerrig.recordings.readers import read_recording

    said: list[str] = []
    rec = read_recording(adhesion_csv(tmp_path / "t.csv"))
    analyze_test(rec, run_study=False, progress=said.append)
    assert said[0] == "reading the recording"
    assert "fitting the Polach law" in said and "the spectrum of the quiet phase" in said


def _progress_lines(output: str, what: str) -> list[str]:
    return [m.group(0) for m in _LINE.finditer(output) if m.group("what").startswith(what)]


def test_analyze_prints_progress_lines_when_piped_and_quiet_silences_a_command(
    tmp_path, runner, adhesion_csv
):
    rec = adhesion_csv(tmp_path / "test.csv")
    args = ["analyze", str(rec), "--no-study"]
    # --quiet first (before the command), then a plain run: --quiet must not stick to later
    # commands of the same process; then --quiet after the command. The quiet runs are of
    # `spectrum` (under a second; the analysis takes 7 s), which says its steps the same way.
    spectrum = ["spectrum", str(rec)]
    result = runner.invoke(app, ["--quiet", *spectrum, "--out", str(tmp_path / "q1")])
    assert result.exit_code == 0, result.output
    assert _progress_lines(result.output, "spectrum") == []
    assert "wrote " in result.output  # the results still print
    result = runner.invoke(app, [*args, "--out", str(tmp_path / "a")])
    assert result.exit_code == 0, result.output
    lines = _progress_lines(result.output, "analyze test.csv")
    steps_said = [line.split(": ", 1)[1].rsplit(" (", 1)[0] for line in lines]
    assert steps_said[0] == "opening the recording" and steps_said[-1] == "done"
    assert "fitting the Polach law" in steps_said
    assert "writing the results and the report (figures)" in steps_said
    assert result.output.index("analyze test.csv: done") < result.output.index("wrote ")
    result = runner.invoke(app, [*spectrum, "--quiet", "--out", str(tmp_path / "q2")])
    assert result.exit_code == 0, result.output
    assert _progress_lines(result.output, "spectrum") == []
    assert "wrote " in result.output


def test_spectrum_prints_its_steps(tmp_path, runner, adhesion_csv):
    rec = adhesion_csv(tmp_path / "test.csv")
    result = runner.invoke(app, ["spectrum", str(rec), "--out", str(tmp_path / "s")])
    assert result.exit_code == 0, result.output
    lines = _progress_lines(result.output, "spectrum")
    assert [line.split(" (")[0] for line in lines][:2] == [
        "spectrum: reading",
        "spectrum: reading test.csv",
    ]
    assert lines[-1].startswith("spectrum: done")


def test_frame_prints_its_steps_and_quiet_silences_them(tmp_path, runner):
    pytest.importorskip("Pynite")
    result = runner.invoke(app, ["frame", "--modes", "2", "--out", str(tmp_path / "f")])
    assert result.exit_code == 0, result.output
    lines = _progress_lines(result.output, "frame")
    assert len(lines) == 3 and "static load case and 2 modes (FE)" in lines[0]
    result = runner.invoke(app, ["frame", "--modes", "2", "-q", "--out", str(tmp_path / "g")])
    assert result.exit_code == 0 and _progress_lines(result.output, "frame") == []


@pytest.mark.parametrize(
    "command",
    [
        ["analyze"],
        ["spectrum"],
        ["frame"],
        ["study", "frame"],
        ["study", "drive-dynamics"],
        ["study", "run"],
        ["calibrate"],
        ["transfer"],
        ["simulate"],
    ],
)
def test_every_long_command_takes_quiet(runner, command):
    result = runner.invoke(app, [*command, "--help"], terminal_width=200)
    assert result.exit_code == 0 and "--quiet" in result.output, result.output


@pytest.mark.parametrize(
    "command",
    ["demo", "simulate", "analyze", "spectrum", "filters", "frame", "calibrate", "transfer",
     "contact", "study run"],
)  # fmt: skip
def test_every_command_that_works_for_long_takes_quiet(runner, command):
    result = runner.invoke(app, [*command.split(), "--help"], env={"COLUMNS": "200"})
    assert result.exit_code == 0, result.output
    assert "--quiet" in result.output


def test_a_terminals_bar_prints_brackets_in_names_literally():
    """On a terminal the bar's description and step went through Rich markup: a file
    ``load[kN].csv`` showed as ``load.csv`` and a frame named ``[/bold]`` stopped the command
    with a MarkupError (a review, 2026-12-03). Piped lines were already literal."""
    terminal = Console(file=io.StringIO(), force_terminal=True, width=100)
    with progress(terminal) as bar:
        task = bar.add_task("analyze load[kN].csv", total=None, info="frame [/bold] v2")
        bar.update(task, info="reading [N.m]")
        bar.refresh()
    text = terminal.file.getvalue()
    assert "load[kN].csv" in text and "[/bold]" in text and "[N.m]" in text
