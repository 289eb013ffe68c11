"""Calibration on the command line: ``rollerrig calibrate``."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.table import Table

from rollerrig._optional import require
from rollerrig.cli._boundary import UserError
from rollerrig.cli._console import (
    console,
    note,
    print_recording_notes,
    print_warning,
    print_written,
)
from rollerrig.cli._options import (
    DEFAULT_OUT,
    ChannelsOption,
    Friction,
    LenientOption,
    OutOption,
    RigOption,
    load_rig,
)
from rollerrig.cli._outputs import command_outputs

FIT_FIGURE_NAME = "calibration-fit.png"
"""The figure of the fit: recorded against simulated T56 and speeds, before and after."""

__all__ = ["calibrate", "print_calibration"]


def calibrate(
    recording: Annotated[
        Path | None,
        typer.Argument(
            help="Recording of an adhesion test with the torque request, the torque sensor, "
            "both encoder counts and the air-spring pressure (or the normal load); not needed "
            "with --list-keys.",
            show_default=False,
        ),
    ] = None,
    free: Annotated[
        str | None,
        typer.Option(
            "--free",
            help="Free parameters, comma-separated dotted keys of the rig file (e.g. "
            "stiffness.roller_shaft,bearing.friction_coefficient,inertia.roller) or of the "
            "recording's friction law (polach.static_friction, polach.limit_ratio, "
            "polach.friction_decay, polach.k_adhesion, polach.k_slip); --list-keys lists them.",
        ),
    ] = None,
    channels: ChannelsOption = None,
    rig_file: RigOption = None,
    friction: Annotated[
        Friction,
        typer.Option(help="Polach set the recording's friction law starts from."),
    ] = Friction.dry,
    torque_noise: Annotated[
        float | None,
        typer.Option(
            "--torque-noise",
            help="Noise of the torque sensor [N.m] for the first weights; default 1/3000 of "
            "sensors.torque_sensor_range of the rig (1 N.m on the bundled rig).",
        ),
    ] = None,
    max_iterations: Annotated[
        int,
        typer.Option(min=1, help="Most Levenberg-Marquardt iterations per stage [1]."),
    ] = 20,
    out: OutOption = DEFAULT_OUT,
    lenient: LenientOption = False,
    list_keys: Annotated[
        bool, typer.Option("--list-keys", help="List the keys --free accepts and exit.")
    ] = False,
) -> None:
    """Fit the twin's parameters to a recorded test: values with standard errors [SI].

    Replays the recorded wheel-torque request through the twin (fast solver, at the
    recording's load and roller speed) and fits the free parameters so that the simulated
    roller-shaft torque T56 and both encoder speeds match the recording; the weights come from
    the sensor noise, the encoders' quantisation is modelled, the torque's motor and order lines
    are fitted. Writes calibration.json (each value and standard error [SI], correlations,
    residuals before and after, whiteness, warnings for what the recording cannot identify),
    calibrated-rig.toml (a complete rig file for --rig), calibration-fit.nc (recorded against
    simulated channels) and its figure calibration-fit.png; all of them or none.
    """
    if list_keys:
        from rollerrig.calibrate import free_parameter_catalogue

        for key in free_parameter_catalogue():
            console.print(key, markup=False, highlight=False)
        return
    if recording is None:
        raise UserError(
            "give the RECORDING to calibrate to (rollerrig calibrate RECORDING --free KEYS), or "
            "--list-keys to list the keys --free accepts"
        )
    if not free:
        raise UserError(
            "--free is required: name the parameters to fit, e.g. --free "
            "stiffness.roller_shaft,bearing.friction_coefficient (--list-keys lists them)"
        )
    for module in ("xarray", "numba"):
        require(module, purpose="rollerrig calibrate")
    from rollerrig.calibrate import calibrate as run_calibration
    from rollerrig.calibrate import free_parameter_catalogue, write_calibration
    from rollerrig.cli._inputs import read
    from rollerrig.cli.twin import _progress, _say_compile_stage

    keys = [k.strip() for k in free.split(",") if k.strip()]
    unknown = [k for k in keys if k not in free_parameter_catalogue()]
    if unknown:  # before reading anything: one line naming what is accepted
        from rollerrig.calibrate import CalibrationError

        raise CalibrationError(
            f"--free: unknown key(s) {unknown}; valid: {', '.join(free_parameter_catalogue())} "
            "(--list-keys lists them)"
        )
    rig = load_rig(rig_file)
    with command_outputs(
        out,
        run=f"calibrate-{recording.stem}",
        inputs={"recording": recording, "rig": rig_file},
        rig=rig,
        channel_map=channels,
        free=keys,
        friction=friction.value,
        torque_noise=torque_noise,
        max_iterations=max_iterations,
        lenient=lenient,
    ) as stage:
        rec = read(recording, channels, lenient)
        _say_compile_stage(batch=True)
        with _progress() as bar:
            task = bar.add_task("calibrating", total=3 * max_iterations, info="replaying")

            def progress(done: int, total: int, text: str) -> None:
                bar.update(task, completed=done, total=total, info=text)

            result = run_calibration(
                rec,
                keys,
                rig=rig,
                friction=friction.value,
                max_iterations=max_iterations,
                progress=progress,
                torque_noise=torque_noise,
            )
            bar.update(task, completed=bar.tasks[0].total, info="done")
        write_calibration(result, stage.dir)
        from rollerrig.output import save_figure
        from rollerrig.report.calibration import calibration_figure

        save_figure(
            calibration_figure(result.fit_dataset(), title=f"Calibration to {recording.name}"),
            stage.dir / FIT_FIGURE_NAME,
        )
    print_recording_notes(rec)
    print_calibration(result)
    print_written(stage.written)


def _number(value: float | None, digits: int = 6) -> str:
    return "–" if value is None else f"{value:.{digits}g}"


def print_calibration(result) -> None:
    """The fitted values, the channels' residuals, the warnings and notes of a calibration."""
    table = Table(title="Calibrated parameters (one standard error, Newey-West)")
    for col in ("parameter", "value", "± standard error", "unit", "start", "rel. error"):
        table.add_column(col, justify="left" if col in ("parameter", "unit") else "right")
    rows = [*result.parameters.values(), *result.nuisance.values()]
    for p in rows:
        rel = p.relative_standard_error
        table.add_row(
            p.key,
            _number(p.value) if p.identified else "not identified",
            _number(p.standard_error, 3),
            p.unit,
            _number(p.initial),
            "–" if rel is None else f"{100 * rel:.3g} %",
        )
    console.print(table)
    fit = Table(title="Residuals of the fitted channels (RMS)")
    for col in ("channel", "before", "after", "unit", "white (Ljung-Box p)"):
        fit.add_column(col, justify="left" if col in ("channel", "unit") else "right")
    for name, ch in result.channels.items():
        fit.add_row(
            name,
            f"{ch.rms_before:.4g}",
            f"{ch.rms_after:.4g}",
            ch.unit,
            f"{'yes' if ch.whiteness['white'] else 'no'} ({ch.whiteness['ljung_box_p']:.2g})",
        )
    console.print(fit)
    info = result.fit
    console.print(
        f"{info['iterations']} iterations, {info['simulations']} simulations, "
        f"{info['wall_time [s]']:.1f} s" + ("" if info["converged"] else " (not converged)"),
        soft_wrap=True,
    )
    for text in result.warnings:
        print_warning(text)
    for text in result.notes:
        note(text)
