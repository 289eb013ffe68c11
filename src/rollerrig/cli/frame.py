"""``rollerrig frame``: static and modal FE analysis of the rig frame (Kayaalp 4.3.1, 4.4)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import typer
from rich.table import Table

from rollerrig._optional import require
from rollerrig.cli._boundary import UserError
from rollerrig.cli._console import (
    QuietOption,
    console,
    note,
    print_warning,
    print_written,
    steps,
)
from rollerrig.cli._options import (
    DEFAULT_OUT,
    FigureFormat,
    FigureFormatOption,
    OutOption,
    check_wheel_load_kn,
    figure_file,
)
from rollerrig.cli._outputs import command_outputs

__all__ = ["DISSERTATION_TOP_DEFLECTION", "frame"]

DISSERTATION_TOP_DEFLECTION = 0.04e-3
"""Kayaalp 4.4.3: the computed horizontal deflection at the top of the frame under the test
load 'lies around 0.04 mm' [m] (SolidWorks model; the frame's dimensions are not given)."""


def frame(
    frame_file: Annotated[
        Path | None,
        typer.Option(
            "--frame",
            help="Frame file (TOML); default: the bundled Pardubice rig frame (its "
            "dimensions are stated assumptions).",
        ),
    ] = None,
    vertical_kn: Annotated[
        float,
        typer.Option(
            "--vertical-kn",
            help="Normal load: the air-spring force [kN], 0 to 200 (the wheel-load bound of "
            "the other commands).",
        ),
    ] = 20.0,
    horizontal_kn: Annotated[
        float,
        typer.Option(
            "--horizontal-kn",
            help="Traction force at the wheel-roller contact [kN] (> 0 in traction, < 0 in "
            "braking).",
        ),
    ] = 2.0,
    modes: Annotated[
        int,
        typer.Option(
            "--modes",
            help="Natural modes to report and draw [-], 1 to 50 (more are computed when the "
            "contact's dominant mode lies above them).",
        ),
    ] = 6,
    out: OutOption = DEFAULT_OUT,
    figure_format: FigureFormatOption = FigureFormat.png,
    quiet: QuietOption = False,
) -> None:
    """Static and modal FE analysis of the rig frame under the test load (Kayaalp 4.4).

    Prints the largest von Mises stress, the top horizontal deflection (beside the
    dissertation's 0.04 mm), the stress at each strain gauge, the natural frequencies and the
    frame's longitudinal stiffness and modal mass at the contact; writes frame.json (SI
    units), frame-deformed and frame-modes figures (magnification in each title). The mode
    that dominates the contact is found among as many modes as it takes, whatever --modes.
    """
    from rollerrig._validation import ParameterError
    from rollerrig.frame.analysis import MAX_TEST_LOAD

    # The wheel-load bound and message of the other commands (it had taken up to 10 000 kN).
    check_wheel_load_kn("--vertical-kn", vertical_kn, zero=True)
    limit_kn = MAX_TEST_LOAD / 1e3
    if not math.isfinite(horizontal_kn):
        raise UserError(f"--horizontal-kn must be a finite number [kN], got {horizontal_kn!r}")
    if abs(horizontal_kn) > limit_kn:
        raise UserError(
            f"--horizontal-kn must be at most {limit_kn:g} kN in magnitude [kN] (a linear model "
            f"of a rig frame means nothing beyond), got {horizontal_kn:g}"
        )
    if not 1 <= modes <= 50:
        raise UserError(f"--modes must be in [1, 50], got {modes}")
    require("Pynite", "frame", "rollerrig frame")
    from rollerrig.frame import analyze_frame, contact_dof, default_frame, load_frame
    from rollerrig.frame.analysis import check_contact
    from rollerrig.output import save_figure, write_json
    from rollerrig.report.frame import deformed_shape_figure, mode_shape_figure

    structure = default_frame() if frame_file is None else load_frame(frame_file)
    check_contact(structure)
    normal, traction = vertical_kn * 1e3, horizontal_kn * 1e3
    with command_outputs(
        out,
        run="frame",
        inputs={"frame": frame_file},
        frame=structure.name,
        normal_load_N=normal,
        traction_force_N=traction,
        modes=modes,
    ) as stage:
        with steps(f"frame {structure.name}", f"static load case and {modes} modes (FE)") as say:
            result = analyze_frame(structure, normal, traction, n_modes=modes)
            unknown = None
            try:
                dof = contact_dof(result)
            except ParameterError as exc:  # its dominant mode beyond every mode computed
                dof, unknown = None, str(exc)
            summary = frame_summary(result, dof, frame_file, modes=modes, unknown=unknown)
            say("figures: deformed shape, mode shapes")
            fig, _ = deformed_shape_figure(result)
            save_figure(fig, stage.path(figure_file("frame-deformed", figure_format)))
            contact = None if dof is None else dof.mode
            shown = sorted({*range(min(modes, len(result.frequencies))), contact} - {None})
            fig, _ = mode_shape_figure(result, modes=shown, contact_mode=contact)
            save_figure(fig, stage.path(figure_file("frame-modes", figure_format)))
            write_json(stage.path("frame.json"), summary)
    console.print(_table(result, dof, modes))
    if unknown is not None:
        print_warning(unknown)
    if frame_file is None:
        note(
            "the bundled frame's dimensions and sections are assumptions (the dissertation's "
            "figures are lost); give the real rig's with --frame"
        )
    print_written(stage.written)


def frame_summary(
    result, dof, frame_file: Path | None, *, modes: int | None = None, unknown: str | None = None
) -> dict:
    """The contents of ``frame.json``: SI values, their units under ``units``.

    ``natural_frequencies`` holds the first ``modes`` (all computed when None); ``dof`` is None
    when the contact's dominant mode is not established, ``unknown`` saying why.
    """
    peak = result.max_von_mises
    reported = result.frequencies[: len(result.frequencies) if modes is None else modes]
    if dof is None:
        contact = {
            "stiffness": result.longitudinal_stiffness_at_contact,
            "dominant_mode": "not established",
            "why": unknown,
        }
    else:
        contact = {
            "stiffness": dof.stiffness,
            "mode": dof.mode + 1,
            "frequency": dof.frequency,
            "modal_mass": dof.modal_mass,
            "modal_stiffness": dof.modal_stiffness,
            "participation": dof.participation,
            "equivalent_mass": dof.equivalent_mass,
        }
    return {
        "frame": result.frame.name,
        "frame_file": str(frame_file) if frame_file is not None else "bundled default",
        "normal_load": result.normal_load,
        "traction_force": result.traction_force,
        "max_von_mises_stress": peak.value,
        "max_von_mises_location": {"member": peak.member, "position": peak.position},
        "top_horizontal_deflection": result.top_horizontal_deflection,
        "top_longitudinal_deflection": result.top_longitudinal_deflection,
        "top_node": result.top_node,
        "strain_gauge_stresses": dict(result.gauge_stresses),
        "strain_gauge_influence": {
            name: {"normal": g.normal, "traction": g.traction} for name, g in result.gauges.items()
        },
        "natural_frequencies": [float(f) for f in reported],
        "modes_computed": len(result.frequencies),
        "longitudinal_stiffness_at_contact": result.longitudinal_stiffness_at_contact,
        "contact_dof": contact,
        "frame_mass": result.frame_mass,
        "member_end_forces": {
            name: {"start": f.start, "end": f.end} for name, f in result.member_forces.items()
        },
        "dissertation": {
            "top_horizontal_deflection": DISSERTATION_TOP_DEFLECTION,
            "source": "Kayaalp 4.4.3: 'around 0.04 mm' at the top under 20 kN + 2 kN "
            "(SolidWorks, frame dimensions not given)",
        },
        "units": {
            "normal_load": "N",
            "traction_force": "N",
            "max_von_mises_stress": "Pa",
            "max_von_mises_location.position": "m (from the member's first node)",
            "top_horizontal_deflection": "m",
            "top_longitudinal_deflection": "m",
            "strain_gauge_stresses": "Pa (axial, > 0 tension)",
            "strain_gauge_influence": "Pa/N",
            "natural_frequencies": "Hz (the first --modes; modes_computed were computed to "
            "find the contact's dominant mode)",
            "longitudinal_stiffness_at_contact": "N/m",
            "contact_dof": "stiffness, modal_stiffness N/m; frequency Hz; masses kg; "
            "participation 1 (the mode's share of the contact's static flexibility)",
            "frame_mass": "kg",
            "member_end_forces": "N, N.m (local axes: y along the web)",
        },
    }


def _table(result, dof, modes: int) -> Table:
    table = Table(
        title=f"Frame {result.frame.name}: N = {result.normal_load / 1e3:g} kN, "
        f"F_x = {result.traction_force / 1e3:g} kN"
    )
    table.add_column("quantity")
    table.add_column("unit")
    table.add_column("value", justify="right")
    peak = result.max_von_mises
    table.add_row(
        f"largest von Mises stress ({peak.member}, {peak.position:.2f} m)",
        "MPa",
        f"{peak.value / 1e6:.2f}",
    )
    table.add_row(
        f"top horizontal deflection ({result.top_node})",
        "mm",
        f"{result.top_horizontal_deflection * 1e3:.4f}",
    )
    table.add_row(
        "  Kayaalp 4.4.3 (SolidWorks, real frame)", "mm", f"~{DISSERTATION_TOP_DEFLECTION * 1e3:g}"
    )
    for name, value in result.gauge_stresses.items():
        table.add_row(f"gauge {name}", "MPa", f"{value / 1e6:.3f}")
    for i, f in enumerate(result.frequencies[:modes]):
        table.add_row(f"natural frequency {i + 1}", "Hz", f"{f:.2f}")
    table.add_row(
        "longitudinal stiffness at the contact",
        "N/m",
        f"{result.longitudinal_stiffness_at_contact:.4g}",
    )
    if dof is None:
        table.add_row("  dominant mode at the contact", "-", "not established")
    else:
        beyond = f" (computed beyond --modes {modes})" if dof.mode >= modes else ""
        table.add_row(
            f"  dominant mode at the contact: mode {dof.mode + 1}{beyond}",
            "Hz",
            f"{dof.frequency:.2f}",
        )
        table.add_row(
            "  its own modal mass at the contact (m_r/q_r²)", "kg", f"{dof.modal_mass:.4g}"
        )
        # what a rig file's [frame] modal_mass is (the twin's one-mass frame at this
        # frequency on the static stiffness), the modal mass above being the mode's alone
        table.add_row(
            "  the twin's [frame] modal_mass: stiffness/(2π f)²",
            "kg",
            f"{dof.equivalent_mass:.4g}",
        )
        table.add_row("  its share of the contact flexibility", "-", f"{dof.participation:.3f}")
    table.add_row("frame mass (members and lumped masses)", "kg", f"{result.frame_mass:.0f}")
    return table
