"""``rollerrig contact``: the wheel-roller contact (Hertz, Kalker, a creep law) against a rail."""

from __future__ import annotations

from enum import StrEnum
from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.table import Table

from rollerrig.cli._console import QuietOption, console, print_written
from rollerrig.cli._options import (
    DEFAULT_OUT,
    FigureFormat,
    FigureFormatOption,
    RigOption,
    check_option,
    check_radius_mm,
    check_speed_kmh,
    check_wheel_load_kn,
    figure_file,
    load_rig,
)
from rollerrig.cli._outputs import command_outputs

__all__ = ["CreepLaw", "contact"]


class CreepLaw(StrEnum):
    """The creep laws of :data:`rollerrig.contact.laws.CREEP_LAWS`."""

    polach = "polach"
    fastsim = "fastsim"
    modified_fastsim = "modified-fastsim"
    fastrip = "fastrip"


def contact(
    load_kn: Annotated[float, typer.Option("--load-kn", help="Normal load [kN].")] = 10.0,
    speed_kmh: Annotated[
        float, typer.Option("--speed-kmh", help="Rolling speed for the creep curves [km/h].")
    ] = 30.0,
    rig_file: RigOption = None,
    roller_radius_mm: Annotated[
        float | None, typer.Option("--roller-radius-mm", help="Override the roller radius [mm].")
    ] = None,
    wheel_radius_mm: Annotated[
        float | None, typer.Option("--wheel-radius-mm", help="Override the wheel radius [mm].")
    ] = None,
    poisson: Annotated[
        float | None, typer.Option("--poisson", help="Override Poisson's ratio [-], in (0, 0.5).")
    ] = None,
    k_adhesion: Annotated[
        float | None, typer.Option("--ka", help="Override Polach's kA of both friction sets [-].")
    ] = None,
    k_slip: Annotated[
        float | None, typer.Option("--ks", help="Override Polach's kS of both friction sets [-].")
    ] = None,
    law: Annotated[
        CreepLaw,
        typer.Option(
            "--law",
            help="Creep law: polach (Polach 2005), fastsim (Kalker 1982), modified-fastsim "
            "(k0, alpha_inf, beta; Spiryagin et al. 2013) or fastrip (Sichani et al. 2016).",
        ),
    ] = CreepLaw.polach,
    friction_sets: Annotated[
        list[str] | None,
        typer.Option(
            "--friction-set",
            metavar="<name>",
            help="Named friction parameter set(s), repeatable: polach-dry, polach-wet, "
            "eurosprinter-coulomb, eurosprinter-modified-fastsim. Default: Polach's dry and "
            "wet [mu0, A, B in s/m], or the Eurosprinter set for modified-fastsim.",
        ),
    ] = None,
    out: Annotated[
        Path, typer.Option("--out", help="Output folder for the figures and the summary.")
    ] = DEFAULT_OUT,
    wheel_profile: Annotated[
        str | None,
        typer.Option(
            "--wheel-profile",
            help="Wheel profile file (CONTACT's formats: .prw, Miniprof .whl, ...; mm), or "
            "'example' for CONTACT's S1002: with --rail-profile, also solve the profiles on "
            "the tangent rail and on the roller by CONTACT (Kalker's exact theory, "
            "non-Hertzian; needs CONTACT_DIR, about a minute).",
        ),
    ] = None,
    rail_profile: Annotated[
        str | None,
        typer.Option(
            "--rail-profile",
            help="Rail profile file (.prr, Miniprof .ban, ...; mm), or 'example' for "
            "CONTACT's UIC60; the roller's running surface is this profile turned about its "
            "axle at the roller radius.",
        ),
    ] = None,
    figure_format: FigureFormatOption = FigureFormat.png,
    quiet: QuietOption = False,
) -> None:
    """Contact of the rig's wheel-roller pair: Hertz ellipse, Kalker C11, creep curves.

    Prints the contact at the chosen load [kN] beside the same wheel on a tangent rail, and
    writes two figures: creep-adhesion curves by the chosen law (each friction set; roller and
    tangent rail) and contact size versus roller radius; for the FASTSIM family also the
    traction distribution (adhesion and slip zones) on the roller.
    """
    from dataclasses import replace

    from rollerrig._validation import ParameterError
    from rollerrig.cli._contact_profiles import profile_files, run_profiles
    from rollerrig.contact.creep import POLACH_PARAMETER_SETS, PolachParameters
    from rollerrig.contact.curves import polach_creep_curve
    from rollerrig.contact.laws import default_parameter_sets, law_creep_curve, parameter_set
    from rollerrig.contact.roller import contact_versus_roller_radius
    from rollerrig.output import save_figure, write_json
    from rollerrig.report.contact import contact_size_figure, creep_curve_figure

    profiles = profile_files(wheel_profile, rail_profile)  # before any work: errors first
    check_wheel_load_kn("--load-kn", load_kn)
    check_speed_kmh("--speed-kmh", speed_kmh)
    check_radius_mm("--wheel-radius-mm", wheel_radius_mm)
    check_radius_mm("--roller-radius-mm", roller_radius_mm)
    check_option("--poisson", poisson, "", above=0, below=0.5)
    rig = load_rig(rig_file)
    g, mat = rig.geometry, rig.material
    load = load_kn * 1e3
    speed = speed_kmh / 3.6
    wheel_rx = g.wheel_radius_x if wheel_radius_mm is None else wheel_radius_mm * 1e-3
    roller_rx = g.roller_radius_x if roller_radius_mm is None else roller_radius_mm * 1e-3
    nu = mat.poisson if poisson is None else poisson
    law = CreepLaw(law).value
    if friction_sets:
        sets = {name: parameter_set(name) for name in friction_sets}
    elif law == "polach":
        sets = dict(POLACH_PARAMETER_SETS)
    else:
        sets = default_parameter_sets(law)
    if (k_adhesion is not None or k_slip is not None) and law != "polach":
        raise ParameterError("--ka and --ks are Polach's: they apply with --law polach only")
    if law == "polach" and not all(isinstance(p, PolachParameters) for p in sets.values()):
        raise ParameterError("--law polach needs Polach sets: polach-dry or polach-wet")
    if k_adhesion is not None or k_slip is not None:
        sets = {
            name: replace(
                p,
                k_adhesion=p.k_adhesion if k_adhesion is None else k_adhesion,
                k_slip=p.k_slip if k_slip is None else k_slip,
                name=f"{name} (kA/kS overridden)",
            )
            for name, p in sets.items()
        }
    geometry = (wheel_rx, g.wheel_radius_y, roller_rx, g.roller_radius_y)
    parameters = {
        "normal_load_N": load,
        "rolling_speed_m_s": speed,
        "geometry_m": geometry,
        "youngs_modulus_Pa": mat.youngs_modulus,
        "poisson": nu,
        "polach": [p.to_dict() for p in sets.values()],
    }
    if law != "polach":
        parameters["law"] = law
        parameters["friction_sets"] = parameters.pop("polach")
    with command_outputs(
        out, run="contact", inputs={"rig": rig_file}, rig=rig, **parameters
    ) as stage:
        creep = np.linspace(0.0, 0.30, 3001)  # wide enough to contain the wet peak
        rows = {}
        for where, rx in (("roller", roller_rx), ("tangent rail", np.inf)):
            curve = (
                polach_creep_curve
                if law == "polach"
                else lambda *args, **kw: law_creep_curve(law, *args, **kw)
            )
            rows[where] = {
                name: curve(
                    creep,
                    load,
                    speed,
                    geometry[0],
                    geometry[1],
                    rx,
                    geometry[3],
                    p,
                    mat.youngs_modulus,
                    nu,
                )
                for name, p in sets.items()
            }

        first = next(iter(sets))
        c_roll, c_rail = rows["roller"][first], rows["tangent rail"][first]
        if law == "polach":
            fig1, _ = creep_curve_figure(
                sets,
                load,
                speed,
                *geometry,
                youngs_modulus=mat.youngs_modulus,
                poisson=nu,
                max_creep=0.10,
            )
        else:
            from rollerrig.contact.hertz import combined_elastic_constants
            from rollerrig.report.traction import law_curve_figure, traction_figure

            elastic_nu = float(
                combined_elastic_constants(mat.youngs_modulus, nu, mat.youngs_modulus, nu).poisson
            )

            fig1 = law_curve_figure(rows, law, roller_rx, max_creep=0.10)
            fig3 = traction_figure(rows["roller"][first], law, elastic_nu)
        comparison = contact_versus_roller_radius(
            np.geomspace(max(wheel_rx, 0.1), 100.0, 300),
            normal_load=load,
            wheel_radius_x=wheel_rx,
            wheel_radius_y=g.wheel_radius_y,
            roller_radius_y=g.roller_radius_y,
            youngs_modulus=mat.youngs_modulus,
            poisson=nu,
        )
        fig2 = contact_size_figure(comparison, rig_roller_radius=roller_rx)
        summary = {
            "law": law,
            "contact": {
                where: {
                    "semi_axis_x_m": float(c.contact.semi_axis_x),
                    "semi_axis_y_m": float(c.contact.semi_axis_y),
                    "area_m2": float(c.contact.area),
                    "peak_pressure_Pa": float(c.contact.peak_pressure),
                    "approach_m": float(c.contact.approach),
                    "c11": c.c11,
                    "peaks_creep_coa": {n: rows[key][n].peak for n in sets},
                }
                for where, key, c in (
                    ("roller", "roller", c_roll),
                    ("tangent_rail", "tangent rail", c_rail),
                )
            },
        }
        save_figure(fig1, stage.path(figure_file("contact-creep-curves", figure_format)))
        save_figure(fig2, stage.path(figure_file("contact-vs-roller-radius", figure_format)))
        if law != "polach":
            save_figure(fig3, stage.path(figure_file("contact-traction", figure_format)))
        if profiles is not None:
            from rollerrig.contact.hertz import combined_elastic_constants
            from rollerrig.contact.kinematics import rig_creep

            def hertz_factor(xi):
                s = rig_creep(xi)
                on = [np.interp(s, c.creep, c.adhesion_coefficient) for c in (c_rail, c_roll)]
                return on[0] / on[1]

            elastic = combined_elastic_constants(mat.youngs_modulus, nu, mat.youngs_modulus, nu)
            summary["profiles"] = run_profiles(
                profiles,
                load=load,
                wheel_radius=wheel_rx,
                roller_radius=roller_rx,
                friction=float(next(iter(sets.values())).static_friction),
                shear_modulus=float(elastic.shear_modulus),
                poisson=float(elastic.poisson),
                hertz_factor=hertz_factor,
            )
        write_json(stage.path("contact-report.json"), summary)
    title = (
        f"Wheel-roller contact at N = {load_kn:g} kN "
        f"(E = {mat.youngs_modulus / 1e9:g} GPa, ν = {nu:g})"
    )
    console.print(_contact_table(title, rows, roller_rx, speed_kmh))
    law_note = {
        "polach": "Polach (2005) creep law",
        "fastsim": "Kalker's FASTSIM (1982)",
        "modified-fastsim": "modified FASTSIM (Spiryagin et al. 2013)",
        "fastrip": "FaStrip (Sichani et al. 2016)",
    }[law]
    console.print(
        f"Creep is referred to the roller's peripheral speed (Kayaalp eq. 4.21); {law_note}; "
        f"friction sets: {', '.join(sets)}; Kalker C11 from Kalker (1990) Table E.3."
    )
    print_written(stage.written)


def _contact_table(title: str, rows: dict, roller_rx: float, speed_kmh: float) -> Table:
    """The contact on the roller beside the tangent rail, and the creep curves' peaks."""
    sets = list(rows["roller"])
    table = Table(title=title)
    table.add_column("quantity")
    table.add_column("unit")
    table.add_column(f"roller (R = {roller_rx * 1e3:.0f} mm)", justify="right")
    table.add_column("tangent rail", justify="right")
    # rail / roller, as transfer states its factor F_rail/F_roller: the creep stiffnesses'
    # ratio here is that factor at small creepage there
    table.add_column("rail / roller", justify="right")
    c_roll, c_rail = rows["roller"][sets[0]], rows["tangent rail"][sets[0]]

    def add(label, unit, f, fmt):
        vr, vt = f(c_roll), f(c_rail)
        table.add_row(label, unit, format(vr, fmt), format(vt, fmt), f"{vt / vr:.3f}")

    add("semi-axis a (rolling)", "mm", lambda c: float(c.contact.semi_axis_x) * 1e3, ".3f")
    add("semi-axis b (lateral)", "mm", lambda c: float(c.contact.semi_axis_y) * 1e3, ".3f")
    add("a/b", "-", lambda c: float(c.contact.a_over_b), ".3f")
    add("contact area", "mm²", lambda c: float(c.contact.area) * 1e6, ".2f")
    add("peak pressure p0", "MPa", lambda c: float(c.contact.peak_pressure) / 1e6, ".0f")
    add("approach δ", "µm", lambda c: float(c.contact.approach) * 1e6, ".2f")
    add("Kalker C11", "-", lambda c: c.c11, ".3f")
    add("creep stiffness G·a·b·C11", "MN", lambda c: c.creep_stiffness / 1e6, ".3f")
    for name in sets:
        for k, label in ((0, "creep at peak"), (1, "peak adhesion")):
            vr = rows["roller"][name].peak[k]
            vt = rows["tangent rail"][name].peak[k]
            unit = "%" if k == 0 else "-"
            scale = 100 if k == 0 else 1
            table.add_row(
                f"{label} ({name}, {speed_kmh:g} km/h)",
                unit,
                f"{scale * vr:.3f}",
                f"{scale * vt:.3f}",
                f"{vt / vr:.3f}",
            )
    return table
