"""The options the commands share, and an enum for every choice.

Each enum lists the values its option accepts: ``--help`` shows them and a wrong value is one
usage error naming them. The values are the package's own names (a test checks that each enum
equals the table it mirrors: :data:`rollerrig.rig.model.WHEEL_MODES`, ``ROLLER_MODES``,
:data:`rollerrig.output.figures.FIGURE_FORMATS`,
:data:`rollerrig.solve.simulation.SOLVERS`, :data:`rollerrig.solve.results.SAVE_FORMATS`,
:data:`rollerrig.studies.runner.EXECUTORS`,
:data:`rollerrig.contact.creep.POLACH_PARAMETER_SETS`); they
are spelled out here so that ``rollerrig --help`` imports none of those modules (fast, and on a
core install without the optional packages).
"""

from __future__ import annotations

from enum import StrEnum
from pathlib import Path
from typing import Annotated

import typer

__all__ = [
    "DEFAULT_OUT",
    "ChannelsOption",
    "Executor",
    "FigureFormat",
    "FigureFormatOption",
    "FrameModel",
    "Friction",
    "LenientOption",
    "OutOption",
    "ResultsFormat",
    "RigOption",
    "RollerDrive",
    "Solver",
    "WheelDrive",
    "check_option",
    "figure_file",
    "load_rig",
]

DEFAULT_OUT = Path("rollerrig-output")


class Solver(StrEnum):
    """The twin's solver."""

    fast = "fast"
    reference = "reference"


class WheelDrive(StrEnum):
    """The wheel's drive model."""

    pmsm = "pmsm"
    ideal_torque = "ideal_torque"


class RollerDrive(StrEnum):
    """The roller's drive model."""

    induction = "induction"
    induction_linear = "induction_linear"
    ideal_speed = "ideal_speed"
    servo = "servo"
    induction_dq = "induction_dq"


class FrameModel(StrEnum):
    """The rig frame in the twin (:data:`rollerrig.rig.model.FRAME_MODES`)."""

    rigid = "rigid"
    flexible = "flexible"


class ResultsFormat(StrEnum):
    """File format of the twin's results."""

    nc = "nc"
    csv = "csv"
    parquet = "parquet"
    mat = "mat"


class FigureFormat(StrEnum):
    """File format of a command's figures (:data:`rollerrig.output.figures.FIGURE_FORMATS`)."""

    png = "png"
    svg = "svg"
    pdf = "pdf"


FigureFormatOption = Annotated[
    FigureFormat,
    typer.Option(
        "--figure-format",
        help="File format of the figures: png (raster, 150 dpi), svg or pdf (vector, for "
        "print); each carries the run's provenance. An HTML report embeds PNG whatever this is.",
        case_sensitive=False,
    ),
]
"""``--figure-format``: one definition for every command that writes figures."""


def figure_file(stem: str, figure_format: FigureFormat | str = FigureFormat.png) -> str:
    """File name of a figure: ``stem`` with the suffix of ``--figure-format``.

    The one way a command names its figures; :func:`rollerrig.output.save_figure` writes the
    format the suffix says.

    Examples
    --------
    >>> figure_file("order-map"), figure_file("order-map", FigureFormat.svg)
    ('order-map.png', 'order-map.svg')
    """
    return f"{stem}.{FigureFormat(figure_format).value}"


class Executor(StrEnum):
    """Where a study runs (:data:`rollerrig.studies.runner.EXECUTORS`)."""

    auto = "auto"
    dask = "dask"
    local = "local"


class Friction(StrEnum):
    """Friction condition (a Polach parameter set)."""

    dry = "dry"
    wet = "wet"


def _rig_by_name(value: Path | None) -> Path | None:
    """``--rig NAME``: a value that is no file and has no suffix names a registered rig set
    (``rollerrig rig list``), whose file it becomes; a path is left to the rig-file reader,
    unless nothing is there (said now, before the command imports its modules for seconds)."""
    if value is None or value.is_file():
        return value
    if value.suffix or len(value.parts) > 1:
        if not value.exists():
            raise typer.BadParameter(f"{value}: rig file not found")
        return value
    from rollerrig._validation import ParameterError
    from rollerrig.rig.library import resolve_rig

    try:
        return resolve_rig(value)
    except ParameterError as exc:
        raise typer.BadParameter(str(exc)) from None


RigOption = Annotated[
    Path | None,
    typer.Option(
        "--rig",
        help="Rig parameter file (TOML) or the name of a rig set (rollerrig rig list); "
        "default: the bundled Pardubice rig.",
        callback=_rig_by_name,
    ),
]
OutOption = Annotated[Path, typer.Option("--out", help="Output folder.")]
ChannelsOption = Annotated[
    Path | None,
    typer.Option("--channels", help="Channel map (TOML): which column is which quantity, units."),
]
LenientOption = Annotated[
    bool,
    typer.Option(
        help="Fill short NaN runs and accept gaps instead of failing; every interpolated run, "
        "gap and reader note is reported in every output."
    ),
]


def load_rig(rig_file: Path | None):
    """The rig parameter set of ``--rig``, or the bundled one."""
    from rollerrig.rig.parameters import default_rig
    from rollerrig.rig.parameters import load_rig as load

    return default_rig() if rig_file is None else load(rig_file)


MAX_WHEEL_LOAD_KN = 200.0
"""Largest wheel load an option takes [kN]: a rail vehicle's static wheel load is below about
125 kN (25 t axle load), and the twin's drives and contact are parametrised for a tram wheel.
A load typed in newtons (4300 for 4.3 kN) lands far beyond it, and is named so."""

MAX_SPEED_KMH = 300.0
"""Largest rolling speed an option takes [km/h] (a rig's, or a high-speed train's)."""

MIN_RADIUS_MM = 5.0
"""Smallest wheel or roller radius an option takes [mm] (a twin-disc machine's discs are about
25 mm): a radius typed in metres (0.452 for 452 mm) lands below it, and is named so."""


def check_wheel_load_kn(option: str, value: float | None, *, zero: bool = False) -> None:
    """``value`` [kN] in (0, :data:`MAX_WHEEL_LOAD_KN`] (``[0, ...]`` with ``zero``: a frame
    unloaded vertically), the error asking whether it is in N."""
    check_option(
        option, value, "kN", above=None if zero else 0, at_least=0 if zero else None,
        at_most=MAX_WHEEL_LOAD_KN, why="a wheel load; a value typed in N?",
    )  # fmt: skip


def check_speed_kmh(option: str, value: float | None) -> None:
    """``value`` [km/h] in (0, :data:`MAX_SPEED_KMH`], the error asking whether it is in m/s
    or m/h."""
    check_option(option, value, "km/h", above=0, at_most=MAX_SPEED_KMH, why="a rolling speed")


def check_radius_mm(option: str, value: float | None) -> None:
    """``value`` [mm] at least :data:`MIN_RADIUS_MM`, the error asking whether it is in m."""
    check_option(option, value, "mm", at_least=MIN_RADIUS_MM, why="a radius; a value typed in m?")


def check_option(
    option: str,
    value: float | None,
    unit: str,
    *,
    above: float | None = None,
    at_least: float | None = None,
    at_most: float | None = None,
    below: float | None = None,
    why: str = "",
) -> None:
    """Check an option's value in the unit the user typed it in, before any conversion to SI.

    So ``--load-kn -3`` is answered "--load-kn must be > 0 kN, got -3 kN", not in newtons.

    Parameters
    ----------
    option : str
        The option as typed (``"--load-kn"``).
    value : float or None
        Its value; None (not given) passes.
    unit : str
        The option's unit as the user reads it (``"kN"``, ``"km/h"``, ``"mm"``; ``""`` for a
        pure number).
    above : float, optional
        Exclusive lower bound.
    at_least : float, optional
        Inclusive lower bound.
    at_most : float, optional
        Inclusive upper bound.
    below : float, optional
        Exclusive upper bound.
    why : str, optional
        What the bound means, appended in parentheses.

    Raises
    ------
    rollerrig.cli._boundary.UserError
        NaN, infinite or out of bounds.
    """
    import math

    from rollerrig.cli._boundary import UserError

    if value is None:
        return
    u = f" {unit}" if unit else ""
    reason = f" ({why})" if why else ""
    if not math.isfinite(value):
        given_in = f" (in {unit})" if unit else ""
        raise UserError(f"{option} must be a finite number{given_in}, got {value!r}")
    if at_least is not None and at_most is not None and not at_least <= value <= at_most:
        span = f"[{at_least:g}, {at_most:g}]"
        raise UserError(f"{option} must be in {span}{u}{reason}, got {value:g}{u}")
    if above is not None and at_most is not None and not above < value <= at_most:
        span = f"({above:g}, {at_most:g}]"
        raise UserError(f"{option} must be in {span}{u}{reason}, got {value:g}{u}")
    if above is not None and below is not None and not above < value < below:
        span = f"({above:g}, {below:g})"
        raise UserError(f"{option} must be in {span}{u}{reason}, got {value:g}{u}")
    if at_least is not None and not value >= at_least:
        raise UserError(f"{option} must be >= {at_least:g}{u}{reason}, got {value:g}{u}")
    if above is not None and not value > above:
        raise UserError(f"{option} must be > {above:g}{u}{reason}, got {value:g}{u}")
    if at_most is not None and not value <= at_most:
        raise UserError(f"{option} must be <= {at_most:g}{u}{reason}, got {value:g}{u}")
    if below is not None and not value < below:
        raise UserError(f"{option} must be < {below:g}{u}{reason}, got {value:g}{u}")
