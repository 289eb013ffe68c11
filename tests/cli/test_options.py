"""Help texts, choices and the version: units in brackets survive, every choice is listed and a
wrong one is one usage error, each enum equals the package's own table."""

import pytest

from rollerrig import __version__
from rollerrig.cli import COMMANDS, app, load_command
from rollerrig.cli._options import (
    Executor,
    FrameModel,
    Friction,
    ResultsFormat,
    RollerDrive,
    Solver,
    WheelDrive,
)

NAMES = (
    "contact",
    "transfer",
    "simulate",
    "modes",
    "frame",
    "analyze",
    "spectrum",
    "filters",
    "calibrate",
    "demo",
)


def _flat(text: str) -> str:
    return " ".join(text.split())


def test_every_command_is_registered():
    assert tuple(COMMANDS) == (*NAMES, "study", "rig")
    for name in NAMES:
        assert load_command(name).__name__ == name


@pytest.mark.parametrize(
    "command", [*NAMES, "study", "study run", "study show", "study list", "rig", "rig list"]
)
def test_help_of_every_command_keeps_units_in_brackets(command, runner):
    result = runner.invoke(app, [*command.split(), "--help"])
    assert result.exit_code == 0, result.output
    assert "Traceback" not in result.output and "Usage:" in result.output
    # Every "[" of the help survives: Rich markup would have eaten "[kN]" and friends.
    expected = {
        "contact": ["Normal load [kN]", "[km/h]", "[mm]", "Poisson's ratio [-]"],
        "simulate": ["Roller-drive lag τ [s]", "<nc|csv|parquet|mat>", "<fast|reference>"],
        "modes": ["Roller speed [km/h]", "Normal load [kN]", "<dry|wet>"],
        "analyze": ["--lenient"],
        "study run": ["--scheduler", "--workers", "<auto|dask|local>", "12 [s]", "--restart"],
        "filters": ["--lenient"],
    }
    text = _flat(result.output)
    for fragment in expected.get(command, []):
        assert fragment in text, fragment
    assert "Normal load ." not in text


def test_every_choice_is_listed_in_the_help(runner):
    text = _flat(runner.invoke(app, ["simulate", "--help"]).output)
    for enum in (Solver, WheelDrive, RollerDrive, ResultsFormat):
        assert "<" + "|".join(e.value for e in enum) + ">" in text, enum.__name__


@pytest.mark.parametrize(
    ("args", "option"),
    [
        (["simulate", "--roller-drive", "steam"], "--roller-drive"),
        (["simulate", "--wheel-drive", "diesel"], "--wheel-drive"),
        (["simulate", "--solver", "euler"], "--solver"),
        (["simulate", "--format", "xlsx"], "--format"),
        (["study", "run", "lag", "--executor", "spark"], "--executor"),
        (["modes", "--friction", "icy"], "--friction"),
    ],
)
def test_a_wrong_choice_is_one_usage_error_naming_the_choices(tmp_path, runner, args, option):
    result = runner.invoke(app, [*args] + (["--out", str(tmp_path)] if args[0] != "modes" else []))
    assert result.exit_code == 2, result.output
    errors = [ln for ln in result.output.splitlines() if ln.startswith("Error:")]
    assert len(errors) == 1, result.output
    assert f"Invalid value for '{option}'" in errors[0]
    assert "is not one of" in errors[0] and "Traceback" not in result.output
    assert list(tmp_path.iterdir()) == []


def test_a_choice_is_case_insensitive_where_a_user_would_expect_it(tmp_path, runner):
    # --format CSV was accepted before the enums; it still is (--list exits before running).
    result = runner.invoke(app, ["simulate", "--format", "CSV", "--list"])
    assert result.exit_code == 0, result.output
    assert "seed-30kmh-dry" in result.output


def test_each_enum_equals_the_table_it_mirrors():
    from rollerrig.contact.creep import POLACH_PARAMETER_SETS
    from rollerrig.rig.model import FRAME_MODES, ROLLER_MODES, WHEEL_MODES
    from rollerrig.solve.results import SAVE_FORMATS
    from rollerrig.solve.simulation import SOLVERS
    from rollerrig.studies.runner import EXECUTORS

    def values(enum):
        return {e.value for e in enum}

    assert values(Solver) == set(SOLVERS)
    assert values(WheelDrive) == set(WHEEL_MODES)
    assert values(RollerDrive) == set(ROLLER_MODES)
    assert values(ResultsFormat) == {s.lstrip(".") for s in SAVE_FORMATS}
    assert values(Friction) == set(POLACH_PARAMETER_SETS)
    assert values(Executor) == set(EXECUTORS)
    assert values(FrameModel) == set(FRAME_MODES)


def test_root_help_and_version(runner):
    result = runner.invoke(app, ["--help"])
    assert result.exit_code == 0
    for command in NAMES:
        assert command in result.output
    result = runner.invoke(app, ["--version"])
    assert result.exit_code == 0, result.output
    assert result.output.strip() == f"rollerrig {__version__}"
