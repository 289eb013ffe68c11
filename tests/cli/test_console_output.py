"""What the commands print when piped: whole lines (never a number broken from its sign or its
unit at 110 characters), tables still laid out; ``--quiet`` on every command that works; and
the dimensionless unit spelled one way in what a run writes (the rule of
:mod:`rollerrig.units`)."""

from __future__ import annotations

import io
import json
import re

import h5py
import pytest
import typer
from rich.table import Table

from rollerrig.cli import app
from rollerrig.cli._console import WIDTH, _Console

LISTINGS = {("study", "show"), ("study", "list"), ("rig", "list"), ("rig", "show")}
"""Commands that only list or show what is stored: nothing to be quiet about."""


def _commands(command, prefix=()):
    if hasattr(command, "commands"):
        for name in list(command.commands):
            yield from _commands(command.commands[name], (*prefix, name))
    else:
        yield prefix, command


def test_every_command_that_computes_takes_quiet_modes_included():
    commands = dict(_commands(typer.main.get_command(app)))
    assert ("modes",) in commands and LISTINGS <= set(commands)
    lacking = [
        " ".join(name)
        for name, command in commands.items()
        if name not in LISTINGS and not any(p.name == "quiet" for p in command.params)
    ]
    assert not lacking, f"no --quiet: {lacking}"


def test_modes_quiet_prints_the_same_results(runner):
    plain = runner.invoke(app, ["modes"])
    quiet = runner.invoke(app, ["modes", "--quiet"])
    assert plain.exit_code == 0 and quiet.exit_code == 0, quiet.output
    assert quiet.output == plain.output and "roller_shaft" in quiet.output


def test_a_piped_console_prints_a_long_line_whole_and_a_table_in_its_width():
    out = io.StringIO()  # not a terminal
    console = _Console(file=out, width=WIDTH, markup=False, highlight=False)
    line = "; ".join(f"min {-k * 1234.5678:.4f} N" for k in range(16))  # 300 characters
    assert len(line) > 2 * WIDTH
    console.print(line)
    table = Table("quantity", "value [-]")
    table.add_row("peak adhesion", "0.455")
    console.print(table)
    lines = out.getvalue().splitlines()
    assert lines[0] == line
    assert all(len(row) <= WIDTH for row in lines[1:]) and "0.455" in out.getvalue()


def test_a_terminal_console_still_wraps_words():
    class Tty(io.StringIO):
        def isatty(self):
            return True

    out = Tty()
    console = _Console(file=out, width=40, markup=False, highlight=False, color_system=None)
    console.print("word " * 20)
    assert max(len(row) for row in out.getvalue().splitlines()) <= 40


def test_simulate_piped_lines_are_whole_and_its_files_spell_units_one_way(tmp_path, runner):
    out = tmp_path / "out"
    result = runner.invoke(app, ["simulate", "-e", "release-test", "--out", str(out), "-q"])
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    # Lines longer than the 110 columns a terminal would wrap them at, printed whole: the
    # release line ends with the true contact force and its unit, on the same line.
    releases = [row for row in lines if row.startswith("release at")]
    assert releases and all(len(row) > WIDTH for row in releases)
    assert all(re.search(r"true contact force min +-?\d+ N$", row) for row in releases)
    assert not [row for row in lines if re.match(r"^-?\d+ N$", row.strip())]  # no stray tail
    header = next(row for row in lines if row.startswith("simulating release-test"))
    assert header.endswith("solver fast")
    # What the run wrote: JSON keys with [-], never [1]; NetCDF units "1", never "-".
    texts = [p.read_text() for p in out.iterdir() if p.suffix in (".json", ".txt")]
    assert texts and not any("[1]" in text for text in texts)
    for path in out.glob("*.json"):
        json.loads(path.read_text())
    units = []
    (nc,) = out.glob("*.nc")
    with h5py.File(nc) as f:
        f.visititems(lambda name, obj: units.append(obj.attrs.get("units")))
    units = [u.decode() if isinstance(u, bytes) else u for u in units if u is not None]
    assert "1" in units and not {"-", "[-]", "[1]"} & set(units)


@pytest.mark.parametrize("command", [["modes"], ["frame"], ["transfer"], ["calibrate"]])
def test_help_spells_a_dimensionless_unit_as_a_label(runner, command):
    result = runner.invoke(app, [*command, "--help"], terminal_width=200)
    assert result.exit_code == 0 and "[1]" not in result.output, result.output
