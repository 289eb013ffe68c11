"""``rollerrig transfer``: a creep curve measured on the roller, predicted on the rail."""

from __future__ import annotations

import math
from enum import StrEnum
from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.table import Table
from rich.text import Text

from rollerrig.analysis.transfer import MIN_DRAWS
from rollerrig.cli._console import QuietOption, console, note, print_written, steps
from rollerrig.cli._options import (
    DEFAULT_OUT,
    FigureFormat,
    FigureFormatOption,
    OutOption,
    RigOption,
    check_option,
    check_radius_mm,
    check_speed_kmh,
    check_wheel_load_kn,
    load_rig,
)
from rollerrig.cli._outputs import command_outputs, safe_file_stem

__all__ = ["Creepage", "TransferLaw", "transfer"]


class TransferLaw(StrEnum):
    """The laws of :data:`rollerrig.analysis.transfer.TRANSFER_LAWS`."""

    modified_fastsim = "modified-fastsim"
    polach = "polach"


class Creepage(StrEnum):
    """What a CSV's creep is referred to."""

    roller = "roller"
    mean = "mean"


def transfer(
    source: Annotated[
        Path,
        typer.Argument(
            help="<name>-analysis.json (or .nc) of `rollerrig analyze`, or a CSV of points with "
            "columns 'creep [-]' (or [%]) and 'coa [-]'; optional 'slip_velocity [m/s]', "
            "'normal_load [N]' (or [kN]), 'rolling_speed [m/s]' (or [km/h]), "
            "'coa_uncertainty [-]'."
        ),
    ],
    rig_file: RigOption = None,
    law: Annotated[
        TransferLaw,
        typer.Option(
            "--law",
            help="Creep law fitted on the roller: modified-fastsim (k0, alpha_inf, beta; "
            "Spiryagin et al. 2013; the factor to the rail from the strip theory with the same "
            "parameters, within 0.8 % of Kalker's exact theory at Coulomb friction; default) "
            "or polach (Polach 2005; its factor within 3.2 %).",
        ),
    ] = TransferLaw.modified_fastsim,
    crown_radius_mm: Annotated[
        float | None,
        typer.Option(
            "--rail-crown-radius-mm",
            help="Rail head transverse radius [mm]; default the roller's (same crown).",
        ),
    ] = None,
    curve_radius_m: Annotated[
        float | None,
        typer.Option("--curve-radius-m", help="Curved track: radius of the curve [m]."),
    ] = None,
    contact_angle_deg: Annotated[
        float,
        typer.Option(
            "--contact-angle-deg",
            help="Contact angle on curved track [deg] (0: on the crown, no longitudinal "
            "curvature).",
        ),
    ] = 0.0,
    load_kn: Annotated[
        float | None,
        typer.Option(
            "--load-kn",
            help="Normal load [kN] at which the curve is transferred (default the median "
            "load of the points). A CSV without a 'normal_load' column needs it: it is then "
            "every point's load too. Where the points have measured loads (the CSV's column, "
            "an analysis), they keep them for the fit on the roller, and a note says so.",
        ),
    ] = None,
    speed_kmh: Annotated[
        float | None,
        typer.Option(
            "--speed-kmh",
            help="Rolling speed [km/h], as --load-kn: of the transfer (default the median "
            "speed of the points), and every point's for a CSV without a 'rolling_speed' "
            "column; measured speeds are kept for the points.",
        ),
    ] = None,
    creepage: Annotated[
        Creepage,
        typer.Option(
            "--creepage",
            help="What a CSV's creep is referred to: roller (the rig's speed, Kayaalp eq. 4.21) "
            "or mean (Kalker's mean rolling speed).",
        ),
    ] = Creepage.roller,
    profile_uncertainty: Annotated[
        float,
        typer.Option(
            "--profile-radius-uncertainty",
            help="Relative standard uncertainty of the transverse profile radii [-] (wheel, "
            "roller, rail crown).",
        ),
    ] = 0.05,
    coa_systematic: Annotated[
        float | None,
        typer.Option(
            "--coa-systematic",
            help="Relative standard uncertainty of the measured CoA common to all points [-], "
            "put in the band (default: not in the band, stated).",
        ),
    ] = None,
    draws: Annotated[
        int, typer.Option("--draws", min=MIN_DRAWS, help=f"Monte Carlo draws (>= {MIN_DRAWS}) [-].")
    ] = 400,
    seed: Annotated[int, typer.Option("--seed", min=0, help="Seed of the draws (>= 0).")] = 0,
    out: OutOption = DEFAULT_OUT,
    figure_format: FigureFormatOption = FigureFormat.png,
    quiet: QuietOption = False,
) -> None:
    """Transfer a creep-CoA curve measured on the rig's roller to the rail, with its band.

    Fits the law's surface parameters (slope reduction, mu0, A, B) to the measured points on
    the roller's Hertz ellipse, and evaluates the law with them on the rail's ellipse at the
    same load [kN] and speed [km/h]: the elastic part (ellipse, Kalker C_ij, creep stiffness
    G a b C11, saturation shape) transfers by contact mechanics; the surface part is carried
    over as measured (an assumption, stated). Creep s is the rig's (referred to the roller
    speed, Kayaalp eq. 4.21); the laws use Kalker's xi = 2s/(2+s). Writes
    <name>-transfer.csv, <name>-transfer.json and <name>-transfer.png.
    """
    from rollerrig._validation import ParameterError, folder_not_file
    from rollerrig.analysis.measured_curve import curve_csv_columns
    from rollerrig.analysis.transfer import (
        ContactGeometry,
        RailGeometry,
        read_analysis,
        read_curve_csv,
        transfer_curve,
    )
    from rollerrig.report.transfer import write_transfer

    folder = folder_not_file(
        source, "a curve file", "an analysis' <name>-analysis.json or a creep-CoA CSV"
    )
    if folder is not None:  # had been "no such file"
        raise ParameterError(folder)
    if not source.is_file():
        raise ParameterError(f"{source}: no such file")
    check_wheel_load_kn("--load-kn", load_kn)
    check_speed_kmh("--speed-kmh", speed_kmh)
    rig = load_rig(rig_file)
    load = None if load_kn is None else float(load_kn) * 1e3
    speed = None if speed_kmh is None else float(speed_kmh) / 3.6
    for name, value in (("--load-kn", load), ("--speed-kmh", speed)):
        if value is not None and not (math.isfinite(value) and value > 0):
            raise ParameterError(f"{name} must be a number > 0")
    is_csv = source.suffix.lower() == ".csv"
    if is_csv:
        # The option is the transfer's load; a CSV's column is the points' measured load. The
        # reader refuses both for the points, so the option fills in only a missing column.
        columns = curve_csv_columns(source)
        for name, units, option, value in (
            ("normal_load", "[N]' (or [kN])", "--load-kn", load),
            ("rolling_speed", "[m/s]' (or [km/h])", "--speed-kmh", speed),
        ):
            if name not in columns and value is None:
                raise ParameterError(
                    f"{source}: no '{name} {units} column: give {option} (then every point's)"
                )
        measured = read_curve_csv(
            source,
            creepage=Creepage(creepage).value,
            normal_load=None if "normal_load" in columns else load,
            rolling_speed=None if "rolling_speed" in columns else speed,
        )
        measured_in = {n: f"the '{n}' column of {source.name}" for n in columns}
        stem = source.stem
    else:
        if creepage != Creepage.roller:
            raise ParameterError("--creepage applies to a CSV; an analysis's creep is the rig's")
        measured = read_analysis(source, rig)
        measured_in = dict.fromkeys(("normal_load", "rolling_speed"), f"the analysis {source.name}")
        stem = source.name.rsplit("-analysis.", 1)[0]
    # Which load and speed the transfer is at, and where the points' came from: recorded in
    # the provenance, and a note where an option sets the transfer apart from measured data.
    load_source, load_note = _condition_source(
        "--load-kn", load, measured.normal_load, "kN", 1e-3, "load",
        measured_in.get("normal_load"),
    )  # fmt: skip
    speed_source, speed_note = _condition_source(
        "--speed-kmh", speed, measured.rolling_speed, "km/h", 3.6, "speed",
        measured_in.get("rolling_speed"),
    )  # fmt: skip
    # checked as typed (mm, m, deg), not as the SI parameters they become
    check_radius_mm("--rail-crown-radius-mm", crown_radius_mm)
    check_option("--curve-radius-m", curve_radius_m, "m", above=0)
    check_option("--contact-angle-deg", contact_angle_deg, "deg", above=-90, below=90)
    rail = RailGeometry(
        crown_radius=None if crown_radius_mm is None else crown_radius_mm * 1e-3,
        curve_radius=math.inf if curve_radius_m is None else curve_radius_m,
        contact_angle=math.radians(contact_angle_deg),
    )
    geometry = ContactGeometry.from_rig(rig, profile_radius_uncertainty=profile_uncertainty)
    with command_outputs(
        out,
        run=f"transfer-{safe_file_stem(stem)}",
        inputs={"source": source, "rig": rig_file},
        rig=rig,
        law=TransferLaw(law).value,
        rail=rail.describe(geometry.roller_radius_y),
        normal_load=load_source,
        rolling_speed=speed_source,
        draws=draws,
        seed=seed,
    ) as stage:
        with steps(f"transfer {stem}", f"a band from {draws} draws") as say:
            result = transfer_curve(
                measured,
                geometry,
                rail,
                TransferLaw(law).value,
                normal_load=load,
                rolling_speed=speed,
                draws=draws,
                seed=seed,
                coa_systematic=coa_systematic,
                progress=say,
            )
            say("writing")
            write_transfer(
                result, stage.dir, safe_file_stem(stem), FigureFormat(figure_format).value
            )
    console.print(_table(result))
    for line in (load_note, speed_note):
        if line is not None:
            note(line)
    written = out / f"{safe_file_stem(stem)}-transfer.json"  # keeps every note whole
    for line in result.assumptions:
        note(line, f"{written}, 'assumptions'")
    for line in result.notes:
        note(line, f"{written}, 'notes'")
    print_written(stage.written)


def _condition_source(
    option: str,
    given: float | None,
    points,
    unit: str,
    scale: float,
    noun: str,
    measured_in: str | None,
) -> tuple[str, str | None]:
    """Where the transfer's load (or speed) and the points' come from.

    Parameters
    ----------
    option : str
        The command's option (``--load-kn``).
    given : float or None
        Its value in SI, None when not given.
    points : array_like
        The points' values in SI, as read.
    unit : str
        The option's unit (``kN``).
    scale : float
        From SI to ``unit``.
    noun : str
        What the value is (``load``).
    measured_in : str or None
        Where the points' values were measured (a CSV's column, an analysis); None where
        they are the option's.

    Returns
    -------
    source : str
        For the provenance.
    note : str or None
        A note to print where the option sets the transfer apart from measured data.
    """
    median = float(np.median(np.asarray(points, float))) * scale
    if given is None:
        return f"{median:.3g} {unit}: the median of the points' {noun}s ({measured_in})", None
    value = f"{option} {given * scale:.3g} {unit}"
    if measured_in is None:
        return f"{value}, also every point's {noun} (the file has no column for it)", None
    kept = f"the points keep their measured {noun}s ({measured_in}, median {median:.3g} {unit})"
    return (
        f"{value} (the transfer's {noun}); {kept}",
        f"{value} is the {noun} of the transfer only; {kept} for the fit on the roller",
    )


def _table(result) -> Table:
    e = result.elastic
    r, t = e["roller"], e["track"]
    table = Table(
        title=Text(
            f"Roller to rail ({result.law}): N = {result.normal_load / 1e3:.3g} kN, "
            f"{result.speed_text()}"
        )
    )
    for name in ("quantity", "unit", "roller", "rail", "rail / roller"):
        table.add_column(Text(name), justify="left" if name in ("quantity", "unit") else "right")

    def row(label, unit, key, scale, fmt):
        a, b = r[key] * scale, t[key] * scale
        table.add_row(Text(label), Text(unit), f"{a:{fmt}}", f"{b:{fmt}}", f"{b / a:.3f}")

    row("semi-axis a (rolling)", "mm", "semi_axis_x [m]", 1e3, ".3f")
    row("semi-axis b (lateral)", "mm", "semi_axis_y [m]", 1e3, ".3f")
    row("Kalker C11", "-", "C11 [-]", 1, ".3f")
    row("creep stiffness G·a·b·C11", "MN", "creep_stiffness G a b C11 [N]", 1e-6, ".3f")
    pr, pt = result.peaks["roller"], result.peaks["track"]
    inside = pr.get("inside_measured_range", True) and pt.get("inside_measured_range", True)
    table.add_row(
        Text("peak creepage ξ (95 %)"),
        Text("%"),
        result.peak_creepage_text("roller"),
        result.peak_creepage_text("track"),
        f"{pt['creepage [-]'] / pr['creepage [-]']:.3f}" if inside else "-",
    )
    table.add_row(
        Text("peak CoA (95 %)"),
        Text("-"),
        result.peak_coa_text("roller"),
        result.peak_coa_text("track"),
        f"{pt['coa [-]'] / pr['coa [-]']:.3f}" if inside else "-",
    )
    maxima = [result.curve_maximum_text(name) for name in ("roller", "track")]
    if any(m is not None for m in maxima):
        table.add_row(
            Text("curve's largest CoA at ξ"), Text("-, %"), *(m or "-" for m in maxima), "-"
        )
    table.caption = result.factor_text()
    return table
