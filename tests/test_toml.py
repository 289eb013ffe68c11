"""The one TOML reader (rollerrig._toml): nesting and size bombs are one clear error in every
reader of a user file (issue 24, point 7), found before the parser spends time on them."""

import time
import tomllib

import pytest
from typer.testing import CliRunner

from rollerrig._toml import MAX_TOML_BYTES, MAX_TOML_DEPTH, parse_toml, read_toml
from rollerrig.cli import app

BOMBS = {
    "inline tables": "x = " + "{a=" * 100_000 + "1" + "}" * 100_000 + "\n",
    "arrays": "x = " + "[" * 100_000 + "]" * 100_000 + "\n",
    "dotted key": "x." + ".".join(["a"] * 100_000) + " = 1\n",
    "table header": "[" + ".".join(["a"] * 40) + "]\nb = 1\n",
}


@pytest.mark.parametrize("kind", list(BOMBS))
def test_bombs_are_refused_quickly(kind):
    start = time.perf_counter()
    with pytest.raises(tomllib.TOMLDecodeError, match=r"nested deeper than|dotted parts"):
        parse_toml(BOMBS[kind])
    # tomllib alone needs minutes for the dotted key (quadratic); the pre-scan finds it at once.
    assert time.perf_counter() - start < 5.0


def test_limits_allow_ordinary_files():
    nested = "a = " + "[" * MAX_TOML_DEPTH + "1" + "]" * MAX_TOML_DEPTH
    assert parse_toml(nested)["a"]
    # A comment with many section numbers is not a key.
    assert parse_toml("# see 4.1.1, 4.3.1 and 5.1.1. in Kayaalp.\nx = 1.5\n") == {"x": 1.5}


def test_too_large_file_is_refused_before_reading(tmp_path):
    path = tmp_path / "big.toml"
    with path.open("wb") as fh:
        fh.truncate(MAX_TOML_BYTES + 1)
    with pytest.raises(tomllib.TOMLDecodeError, match="more than the limit"):
        read_toml(path)


@pytest.mark.parametrize(
    "args",
    [
        ["simulate", "--rig", "{f}"],
        ["simulate", "--experiment", "{f}"],
        ["study", "run", "{f}", "--out", "{out}"],
        ["frame", "--frame", "{f}", "--out", "{out}"],
        ["analyze", "{rec}", "--channels", "{f}", "--out", "{out}"],
    ],
)
def test_every_reader_reports_a_bomb_as_one_error(tmp_path, args):
    bomb = tmp_path / "bomb.toml"
    bomb.write_text(BOMBS["dotted key"])
    rec = tmp_path / "r.csv"
    rec.write_text("time [s],torque [N.m]\n0,1\n0.01,2\n")
    argv = [a.format(f=bomb, out=tmp_path / "out", rec=rec) for a in args]
    result = CliRunner().invoke(app, argv)
    assert result.exit_code not in (0, 1), result.output
    assert "Traceback" not in result.output
    assert "nested deeper" in result.output or "dotted parts" in result.output, result.output
