"""``rollerrig transfer``: a creep curve measured on the roller, predicted on the rail."""

from __future__ import annotations

import math
from enum import StrEnum
from pathlib import Path
from typing import Annotated

import typer
from rich.table import Table
from rich.text import Text

from rollerrig.cli._console import QuietOption, console, note, print_written, steps
from rollerrig.cli._options import (
    DEFAULT_OUT,
    FigureFormat,
    FigureFormatOption,
    OutOption,
    RigOption,
    load_rig,
)
from rollerrig.cli._outputs import command_outputs, safe_file_name

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
            help="Normal load [kN]: of the transfer (default the median contact load of the "
            "points), and of every CSV point without a normal_load column.",
        ),
    ] = None,
    speed_kmh: Annotated[
        float | None,
        typer.Option(
            "--speed-kmh",
            help="Rolling speed [km/h]: as --load-kn (default the median roller speed).",
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
    draws: Annotated[int, typer.Option("--draws", help="Monte Carlo draws [-].")] = 400,
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
    from rollerrig._validation import ParameterError
    from rollerrig.analysis.transfer import (
        ContactGeometry,
        RailGeometry,
        read_analysis,
        read_curve_csv,
        transfer_curve,
    )
    from rollerrig.report.transfer import write_transfer

    if not source.is_file():
        raise ParameterError(f"{source}: no such file")
    rig = load_rig(rig_file)
    load = None if load_kn is None else float(load_kn) * 1e3
    speed = None if speed_kmh is None else float(speed_kmh) / 3.6
    for name, value in (("--load-kn", load), ("--speed-kmh", speed)):
        if value is not None and not (math.isfinite(value) and value > 0):
            raise ParameterError(f"{name} must be a number > 0")
    is_csv = source.suffix.lower() == ".csv"
    if is_csv:
        measured = read_curve_csv(
            source, creepage=Creepage(creepage).value, normal_load=load, rolling_speed=speed
        )
        stem = source.stem
    else:
        if creepage != Creepage.roller:
            raise ParameterError("--creepage applies to a CSV; an analysis's creep is the rig's")
        measured = read_analysis(source, rig)
        stem = source.name.rsplit("-analysis.", 1)[0]
    rail = RailGeometry(
        crown_radius=None if crown_radius_mm is None else crown_radius_mm * 1e-3,
        curve_radius=math.inf if curve_radius_m is None else curve_radius_m,
        contact_angle=math.radians(contact_angle_deg),
    )
    geometry = ContactGeometry.from_rig(rig, profile_radius_uncertainty=profile_uncertainty)
    with command_outputs(
        out,
        run=f"transfer-{safe_file_name(stem)}",
        inputs={"source": source, "rig": rig_file},
        rig=rig,
        law=TransferLaw(law).value,
        rail=rail.describe(geometry.roller_radius_y),
        draws=draws,
        seed=seed,
    ) as stage:
        with steps(f"transfer {stem}", f"{draws} draws of the uncertain inputs"):
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
            )
            write_transfer(
                result, stage.dir, safe_file_name(stem), FigureFormat(figure_format).value
            )
    console.print(_table(result))
    for line in result.assumptions:
        note(line)
    for line in result.notes:
        note(line)
    print_written(stage.written)


def _table(result) -> Table:
    e = result.elastic
    r, t, ratio = e["roller"], e["track"], e["ratio_track_over_roller"]
    table = Table(
        title=Text(
            f"Roller to rail ({result.law}): N = {result.normal_load / 1e3:.3g} kN, "
            f"V = {result.rolling_speed * 3.6:.3g} km/h"
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
    lo, hi = ratio["creep_stiffness_95"]

    def creepage(p):  # a peak at the end of the measured range is a bound, not a peak
        if not p.get("inside_measured_range", True):
            return f"≥ {100 * p['creepage [-]']:.2f} (still rising)"
        lo95, hi95 = p["creepage_95 [-]"]
        return f"{100 * p['creepage [-]']:.2f} ({100 * lo95:.2f}-{100 * hi95:.2f})"

    def coa(p):
        text = f"{p['coa [-]']:.3f} ({p['coa_95 [-]'][0]:.3f}-{p['coa_95 [-]'][1]:.3f})"
        return text if p.get("inside_measured_range", True) else f"≥ {text}"

    inside = pr.get("inside_measured_range", True) and pt.get("inside_measured_range", True)
    table.add_row(
        Text("peak creepage ξ (95 %)"),
        Text("%"),
        creepage(pr),
        creepage(pt),
        f"{pt['creepage [-]'] / pr['creepage [-]']:.3f}" if inside else "-",
    )
    table.add_row(
        Text("peak CoA (95 %)"),
        Text("-"),
        coa(pr),
        coa(pt),
        f"{pt['coa [-]'] / pr['coa [-]']:.3f}" if inside else "-",
    )
    table.caption = (
        f"factor F_rail/F_roller at small creepage {result.stiffness_ratio:.3f} "
        f"(95 %: {lo:.3f}-{hi:.3f}), at the roller's peak "
        f"{result.factor_at(pr['creepage [-]']):.3f}, at the largest creepage "
        f"{result.factor[-1]:.3f}"
    )
    return table
