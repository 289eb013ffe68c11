"""The digital twin on the command line: ``simulate`` and ``modes``.

Studies have their own module, :mod:`rollerrig.cli.studies`.
"""

from __future__ import annotations

import hashlib
import json
import tomllib
from pathlib import Path
from typing import Annotated

import typer
from rich.text import Text

from rollerrig._optional import require
from rollerrig._toml import read_toml
from rollerrig.cli._boundary import UserError
from rollerrig.cli._console import QuietOption, console, note, print_removed, print_written
from rollerrig.cli._options import (
    DEFAULT_OUT,
    FigureFormat,
    FigureFormatOption,
    FrameModel,
    Friction,
    OutOption,
    ResultsFormat,
    RigOption,
    RollerDrive,
    Solver,
    WheelDrive,
    check_option,
    check_speed_kmh,
    check_wheel_load_kn,
    figure_file,
    load_rig,
)
from rollerrig.cli._outputs import command_outputs
from rollerrig.cli.contact import CreepLaw

__all__ = ["modes", "protocol_inputs", "simulate", "variant_stem"]

_FORMAT_NEEDS = {"nc": ("h5py",), "parquet": ("pyarrow",)}
"""Optional packages the results writer needs per ``--format``: the results are written without
xarray (:func:`rollerrig.solve.simulation.Simulation.solve`)."""


def variant_stem(
    name: str,
    *,
    wheel: str = WheelDrive.pmsm.value,
    roller: str = RollerDrive.induction.value,
    roller_lag: float | None = None,
    solver: str = Solver.fast.value,
    rig_file: Path | None = None,
    frame: str = FrameModel.rigid.value,
    law: str = CreepLaw.polach.value,
) -> str:
    """Output stem of a simulation: the experiment's name and what differs from the defaults.

    Variants of one experiment (other drives, lag, solver, rig file) never overwrite each
    other's files.

    Examples
    --------
    >>> variant_stem("seed-30kmh-dry")
    'seed-30kmh-dry'
    >>> variant_stem("seed-30kmh-dry", roller="ideal_speed", roller_lag=0.0)
    'seed-30kmh-dry_roller-ideal_speed_lag-0s'
    >>> variant_stem("x", solver="reference", rig_file=Path("rigs/soft.toml"))
    'x_solver-reference_rig-soft'
    """
    parts = _variant_parts(wheel, roller, roller_lag, solver, rig_file, frame, law)
    return "_".join([_bounded(name), *(stem for stem, _ in parts)])


def _variant_parts(wheel, roller, roller_lag, solver, rig_file, frame, law):
    """What differs from the defaults: (file-name part, words for a title) each."""
    parts = []
    if wheel != WheelDrive.pmsm.value:
        parts.append((f"wheel-{wheel}", f"wheel drive {wheel}"))
    if roller != RollerDrive.induction.value:
        parts.append((f"roller-{roller}", f"roller drive {roller}"))
    if roller_lag is not None:
        parts.append((f"lag-{roller_lag:g}s", f"roller lag {roller_lag:g} s"))
    if frame != FrameModel.rigid.value:
        parts.append((f"frame-{frame}", f"{frame} frame"))
    if law != CreepLaw.polach.value:
        parts.append((f"law-{law}", f"law {law}"))
    if solver != Solver.fast.value:
        parts.append((f"solver-{solver}", f"solver {solver}"))
    if rig_file is not None:
        parts.append((f"rig-{Path(rig_file).stem}", f"rig file {Path(rig_file).name}"))
    return parts


def variant_title(title: str, **variant) -> str:
    """A figure title that names the variant: ``title`` and what differs from the defaults.

    Takes the keywords of :func:`variant_stem` (without the name).

    Examples
    --------
    >>> variant_title("seed-30kmh-dry on Pardubice", roller_lag=0.0)
    'seed-30kmh-dry on Pardubice; variant: roller lag 0 s'
    >>> variant_title("seed-30kmh-dry on Pardubice")
    'seed-30kmh-dry on Pardubice'
    """
    keys = ("wheel", "roller", "roller_lag", "solver", "rig_file", "frame", "law")
    defaults = dict(
        zip(keys, (WheelDrive.pmsm.value, RollerDrive.induction.value, None,
                   Solver.fast.value, None, FrameModel.rigid.value, CreepLaw.polach.value),
            strict=True)
    )  # fmt: skip
    words = [w for _, w in _variant_parts(**(defaults | variant))]
    return f"{title}; variant: {', '.join(words)}" if words else title


MAX_NAME_IN_STEM = 64
"""Most characters of an experiment's name in an output stem [-]: with the variant parts and
suffixes (``_roller-ideal_speed_lag-0s-modes``) the stem stays under the output layer's limit,
so a long name never cuts away what tells variants apart."""


def _bounded(name: str) -> str:
    """``name``, or its first characters and a hash of the whole when it is too long.

    Examples
    --------
    >>> len(_bounded("x" * 300)), _bounded("x" * 300)[-9:]
    (64, '-0d4e2ca9')
    """
    if len(name) <= MAX_NAME_IN_STEM:
        return name
    digest = hashlib.sha256(name.encode("utf-8")).hexdigest()[:8]
    return f"{name[: MAX_NAME_IN_STEM - 9]}-{digest}"


def protocol_inputs(experiment: str) -> dict[str, Path]:
    """The files an experiment reads: the protocol TOML and a replayed torque trace (CSV).

    Empty for a bundled protocol. The CLI hashes them into the provenance and never writes an
    output over them.
    """
    from rollerrig.experiment import bundled_protocols

    path = Path(experiment)
    if experiment in bundled_protocols() or not path.is_file():
        return {}
    found = {"experiment": path}
    try:
        doc = read_toml(path)
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return found  # the protocol reader gives the error
    replay = doc.get("replay")
    csv = replay.get("csv") if isinstance(replay, dict) else None
    if isinstance(csv, str):
        trace = Path(csv)
        found["replayed_torque"] = trace if trace.is_absolute() else path.parent / trace
    return found


MAX_ROLLER_LAG = 2.0
"""Largest ``--roller-lag-s`` [s]: 5.5 x the bundled rig's lag (0.364 s, Kayaalp's fit). On the
seed's test the three releases stay alike up to 2 s (overshoot 64 %); at 3 s the roller's speed
drifts between them (63, 33, 29 %), at 10 s the wheel has lost its traction before the releases,
and 1e6 (no drive) reported one release of three."""


def _experiment_list(names) -> str:
    """One line per bundled experiment: its name, duration and the first sentence of its
    description (``simulate --list``)."""
    from rollerrig.experiment import load_protocol

    protocols = {name: load_protocol(name) for name in names}
    width = max((len(n) for n in protocols), default=0)
    lines = []
    for name, p in protocols.items():
        text = " ".join(p.description.split())
        first = text.split(". ")[0].rstrip(".") + "." if text else "(no description)"
        lines.append(f"{name:<{width}}  {p.duration:5.1f} s  {first}")
    return "\n".join(lines)


def simulate(
    experiment: Annotated[
        str,
        typer.Option(
            "--experiment", "-e", help="Bundled protocol name (see --list) or a protocol TOML file."
        ),
    ] = "seed-30kmh-dry",
    rig_file: RigOption = None,
    out: OutOption = DEFAULT_OUT,
    solver: Annotated[
        Solver,
        typer.Option(
            help="fast (numba ETDRK4; ROS34PW2 on the segments where ETDRK4's own error "
            "estimate is too large, such as macro-slip at low speed) or reference (scipy Radau)."
        ),
    ] = Solver.fast,
    wheel_drive: Annotated[
        WheelDrive, typer.Option(help="Wheel drive: PMSM model or ideal torque source.")
    ] = WheelDrive.pmsm,
    roller_drive: Annotated[
        RollerDrive,
        typer.Option(
            help="Roller drive: induction (the induction motor under V/f with a response lag), "
            "induction_linear (its linear fit), ideal_speed, servo, or induction_dq (the "
            "dynamic dq machine under open-loop V/f, the rig's [roller_drive_vf] settings)."
        ),
    ] = RollerDrive.induction,
    roller_lag_s: Annotated[
        float | None,
        typer.Option(
            help=f"Roller-drive lag τ [s], 0-{MAX_ROLLER_LAG:g} s; default from the rig (c_lp; "
            "0.36 s on the bundled rig). Not with --roller-drive induction_dq (its dynamics are "
            "the machine's own)."
        ),
    ] = None,
    frame: Annotated[
        FrameModel,
        typer.Option(
            help="The rig frame: rigid, or flexible (one longitudinal degree of freedom at the "
            "contact with the rig's [frame] stiffness [N/m], mass [kg] and damping)."
        ),
    ] = FrameModel.rigid,
    law: Annotated[
        CreepLaw,
        typer.Option(
            "--law",
            help="Creep law of the contact force: polach (Polach 2005), fastsim (Kalker 1982), "
            "modified-fastsim (k0, alpha_inf, beta of the Eurosprinter set) or fastrip "
            "(Sichani et al. 2016), the FASTSIM family from a table in G a b C11 xi/(mu N).",
        ),
    ] = CreepLaw.polach,
    output_format: Annotated[
        ResultsFormat,
        typer.Option("--format", case_sensitive=False, help="Results file format."),
    ] = ResultsFormat.nc,
    figure_format: FigureFormatOption = FigureFormat.png,
    figure: Annotated[
        bool,
        typer.Option(
            "--figure/--no-figure",
            help="Draw the six-panel experiment figure (default; a helper process imports "
            "matplotlib and draws it while the run solves and writes). --no-figure leaves it "
            "out, and the helper.",
        ),
    ] = True,
    list_experiments: Annotated[
        bool,
        typer.Option(
            "--list", help="List the bundled experiments (duration, what each does) and exit."
        ),
    ] = False,
    quiet: QuietOption = False,
) -> None:
    """Simulate an adhesion experiment on the digital twin and write results and figures.

    Writes the labelled results (truth beside what the rig measures, with provenance), the
    six-panel experiment figure and the modal table of the torsional chain. Output names are
    the experiment's name plus what differs from the defaults (e.g.
    seed-30kmh-dry_roller-ideal_speed.nc), so variants never overwrite each other.
    """

    check_option(
        "--roller-lag-s", roller_lag_s, "s", at_least=0.0, at_most=MAX_ROLLER_LAG,
        why="a drive slower than that no longer holds the roller's set speed through a test",
    )  # fmt: skip
    _lag_used_by(roller_drive, roller_lag_s)
    from rollerrig.experiment import bundled_protocols

    if list_experiments:
        console.print(_experiment_list(bundled_protocols()), soft_wrap=True)
        return
    if experiment not in bundled_protocols() and not Path(experiment).is_file():
        from rollerrig.experiment import load_protocol

        load_protocol(experiment)  # its error (the bundled names, the nearest) before the imports
    from rollerrig.report.figure_process import FigureProcess

    # The figure's helper process imports matplotlib on another core while this one loads
    # the rest, solves and writes; it is stopped however the run ends.
    with FigureProcess(enabled=figure) as drawing:
        from rollerrig.output import provenance, write_text
        from rollerrig.rig.chain import format_modal_table, modal_table
        from rollerrig.rig.model import DriveConfig
        from rollerrig.solve.results import save_dataset
        from rollerrig.solve.simulation import Simulation

        # Packages the run will need, checked before the simulation (the error names the extra).
        if solver is Solver.fast:
            require("numba", purpose="rollerrig simulate")
        for module in _FORMAT_NEEDS.get(output_format.value, ()):
            require(module, purpose=f"rollerrig simulate --format {output_format.value}")
        rig = load_rig(rig_file)
        drives = DriveConfig(
            wheel=wheel_drive.value,
            roller=roller_drive.value,
            roller_lag=roller_lag_s,
            frame=frame.value,
            law=law.value,
        )
        sim = Simulation(rig, experiment, drives=drives, solver=solver.value)
        variant = dict(  # what differs from the defaults: in the file names and the title
            wheel=drives.wheel,
            roller=drives.roller,
            roller_lag=roller_lag_s,
            solver=solver.value,
            rig_file=rig_file,
            frame=frame.value,
            law=law.value,
        )
        stem = variant_stem(sim.protocol.name, **variant)
        inputs = {**protocol_inputs(experiment), "rig": rig_file}
        with command_outputs(
            out,
            run=f"simulate-{stem}",
            inputs=inputs,
            rig=rig,
            experiment=sim.protocol.name,
            wheel_drive=drives.wheel,
            roller_drive=drives.roller,
            roller_lag_s=roller_lag_s,
            frame=frame.value,
            creep_law=law.value,
            solver=solver.value,
        ) as stage:
            console.print(
                Text.assemble(
                    "simulating ",
                    (sim.protocol.name, "bold"),
                    f" ({sim.protocol.duration:g} s) on ",
                    (rig.meta.name, "bold"),
                    f": wheel {drives.wheel}, roller {drives.roller}, law {drives.law}, "
                    f"solver {solver.value}",
                )
            )
            cached, announced = True, False
            with _progress() as bar:
                duration = sim.protocol.duration
                if solver is Solver.fast:
                    cached, announced = _say_compile_stage(
                        dq=drives.roller == "induction_dq", inputs=sim.inputs
                    )
                task = bar.add_task("simulating", total=duration, info="solving")
                ds = sim.solve(  # the results without xarray: written, drawn and summarised
                    progress=lambda t, end: bar.update(task, completed=t, info=f"t = {t:.2f} s"),
                    notify=None if announced else note,  # the fallback's compilation, once
                )
                bar.update(task, completed=duration, info="done")
            for fmt in FigureFormat:  # an earlier run's figure that this run does not draw
                if not (figure and fmt == FigureFormat(figure_format)):
                    stage.supersede(figure_file(stem, fmt))
            if figure:  # drawn by the helper while the rest is summarised and written
                title = variant_title(ds.attrs.get("title", sim.protocol.name), **variant)
                figure_path = stage.path(figure_file(stem, figure_format))
                drawing.submit(ds, title, figure_path, provenance())
            console.print(_solved_line(_solver_stats(ds), duration, cached))
            text = format_modal_table(modal_table(rig))
            release = _release_summary(ds, sim.protocol)
            save_dataset(ds, stage.path(f"{stem}.{output_format.value}"), overwrite=True)
            write_text(stage.path(f"{stem}-modes.txt"), text + "\n", comment="#")
            if figure:
                drawing.finish()
        console.print(text)
        if release:
            console.print(release)
        print_written(stage.written)
        print_removed(stage.removed, stage.kept)


LAGLESS_ROLLER_DRIVES = (RollerDrive.induction_dq,)
"""Roller drives that take no response lag τ (:class:`rollerrig.rig.model.DriveConfig`): the dq
machine's dynamics are its fluxes and its V/f controller."""


def _lag_used_by(roller_drive: RollerDrive, roller_lag_s: float | None) -> None:
    """Refuse an explicitly given ``--roller-lag-s`` with a roller drive that ignores it (it
    would only change the output's name)."""
    if roller_lag_s is not None and roller_drive in LAGLESS_ROLLER_DRIVES:
        raise UserError(
            f"--roller-lag-s {roller_lag_s:g} with --roller-drive {roller_drive.value}: that "
            "drive takes no response lag (its dynamics are the dq machine's fluxes and its V/f "
            "controller, see the rig's [roller_drive_vf]); leave out --roller-lag-s, or choose "
            "a --roller-drive that uses it: "
            + ", ".join(d.value for d in RollerDrive if d not in LAGLESS_ROLLER_DRIVES)
        )


def _progress():
    """The progress bar of the twin's commands: what runs, how far, and the time it took
    (:func:`rollerrig.cli._console.progress`: plain lines when piped, none with --quiet)."""
    from rollerrig.cli._console import progress

    return progress()


def _solved_line(stats: dict, duration: float, cached: bool) -> str:
    """``solved in … s (method), N x real time``, and apart the time the compiled solver took
    to load from its cache (numba's start included) or, with ``cached`` False, to compile."""
    wall = float(stats.get("wall_time_s", float("nan")))
    load = float(stats.get("load_time_s", 0.0))
    solve = max(wall - load, 0.0)
    line = f"solved in {solve:.2f} s ({stats.get('name', '')})"
    if solve > 0.0:
        line += f", {duration / solve:,.0f} x real time"
    if load >= 0.005:
        what = "loading the compiled solver" if cached else "compiling the solver (once)"
        line += f"; {what} took {load:.2f} s"
    return line


def _say_compile_stage(*, dq: bool = False, inputs=None) -> tuple[bool, bool]:
    """Say when the fast solver will compile (first run after an install or an upgrade) rather
    than load from its cache, so that a silent half minute is not taken for a hang; with the
    experiment's ``inputs``, also when a segment of it needs the fallback, ROS34PW2, whose
    driver compiles the first time a run needs it. Returns whether the driver is cached and
    whether the fallback's compilation was announced."""
    from rollerrig.solve.fast import is_compiled, needs_fallback

    cached = is_compiled(dq=dq)
    if not cached:
        note(
            "compiling the fast solver for this installation (once: about half a minute on 2 "
            "cores); later runs load it from the cache"
        )
    announced = (
        inputs is not None and not is_compiled(dq=dq, method="ros34pw2") and needs_fallback(inputs)
    )
    if announced:
        note(
            "this protocol ramps the roller to or from standstill, which the fast solver leaves "
            "to its fallback (ROS34PW2): compiling it for this installation (once: 10-20 s)"
        )
    return cached, announced


def _solver_stats(ds) -> dict:
    """The solver's name and wall time from the results' provenance."""
    record = json.loads(ds.attrs.get("provenance", "{}"))
    solver = record.get("solver") or record.get("parameters", {}).get("solver") or {}
    return {"name": ds.attrs.get("solver", ""), **solver}


def _release_summary(ds, protocol) -> str:
    """One line per sudden torque release: how far T56 overshoots below zero, vs the truth;
    and a line for the releases left out, with why (a list that silently had one of three)."""
    from rollerrig.studies.metrics import RELEASE_MIN_COA, release_overshoots

    rows = release_overshoots(ds, protocol)
    lines = [
        f"release at {r['time [s]']:5.2f} s: force from T56 {r['force_before [N]']:7.0f} N -> "
        f"min {r['measured_min [N]']:7.0f} N (overshoot {r['measured_overshoot [-]']:5.1%}); "
        f"true contact force min {r['true_min [N]']:7.0f} N"
        for r in rows
    ]
    shown = {r["time [s]"] for r in rows}
    left = [
        e.start for e in protocol.events if e.action == "release_torque" and e.start not in shown
    ]
    if left:
        lines.append(
            f"release at {', '.join(f'{t:.2f}' for t in left)} s: no overshoot stated, no "
            f"traction to release (force from T56 below {RELEASE_MIN_COA:g} x the load before "
            "it)"
        )
    return "\n".join(lines)


def modes(
    rig_file: RigOption = None,
    speed_kmh: Annotated[
        float | None,
        typer.Option(
            "--speed-kmh",
            help="Roller speed [km/h]: also print the damped modes of the coupled twin "
            "(contact and drives in) linearised at steady free rolling at this speed.",
        ),
    ] = None,
    load_kn: Annotated[
        float | None,
        typer.Option(
            "--load-kn",
            help="Normal load [kN] of the coupled twin (default 4.3 kN, the seed's test load).",
        ),
    ] = None,
    friction: Annotated[
        Friction, typer.Option(help="Friction condition of the coupled twin's contact.")
    ] = Friction.dry,
    roller_drive: Annotated[
        RollerDrive,
        typer.Option(
            "--roller-drive",
            help="Roller drive of the coupled twin: induction (the lag model, default), "
            "induction_linear, ideal_speed, servo, or induction_dq (the dq machine under "
            "open-loop V/f with the rig's [roller_drive_vf] settings, its fluxes and filters "
            "among the states).",
        ),
    ] = RollerDrive.induction,
    quiet: QuietOption = False,
) -> None:
    """Natural frequencies, damping and dominant bodies of the torsional chain; with
    --speed-kmh (and --load-kn), the damped modes of the coupled, linearised twin beside them:
    frequency, damping ratio and what moves, and which modes can ring (any roller drive)."""
    from rollerrig.rig.chain import format_modal_table, modal_table
    from rollerrig.rig.linear import DEFAULT_NORMAL_LOAD, format_coupled_modes
    from rollerrig.rig.model import DriveConfig
    from rollerrig.rig.modes import twin_modes

    rig = load_rig(rig_file)
    coupled = None
    if speed_kmh is None and load_kn is not None:
        raise UserError("--load-kn needs --speed-kmh: give the roller speed [km/h] as well")
    if speed_kmh is not None:
        # Upper bounds: the twin's drives and contact are parametrised for a tram wheel; far
        # beyond them the steady state is not found and the linearisation means nothing.
        check_speed_kmh("--speed-kmh", speed_kmh)
        check_wheel_load_kn("--load-kn", load_kn)
        load = DEFAULT_NORMAL_LOAD if load_kn is None else load_kn * 1e3
        source = "--load-kn" if load_kn is not None else "default: the seed's test load"
        coupled = twin_modes(
            rig,
            speed_kmh / 3.6,
            load,
            drives=DriveConfig(roller=roller_drive.value),
            friction=friction.value,
            load_source=source,
        )
    console.print("Free torsional chain (no contact, no drives):")
    console.print(format_modal_table(modal_table(rig)), soft_wrap=True)
    if coupled is not None:
        console.print()
        console.print(format_coupled_modes(coupled), soft_wrap=True)
