"""The ``rollerrig`` command: the front door to the toolkit.

Units at this edge follow rig practice (kN, km/h, mm); everything inside is SI.

Conventions for every command (the error boundary and the output rules):

- **Text is printed literally.** ``console`` and ``err_console`` have Rich markup off, and the
  help is rendered without markup (``rich_markup_mode=None``), so ``[kN]``, ``[channels.torque]``
  or ``rollerrig[io]`` always survive. Style a part with :class:`rich.text.Text`
  (``Text.assemble(("bold part", "bold"), " plain part")``), never with ``[bold]`` markup.
  :func:`note` prints a yellow ``note:`` line.
- **One error boundary** (:class:`_BoundaryGroup`) around every command: a
  :class:`~rollerrig._validation.ParameterError` (so also ``RecordingError``),
  :class:`UserError`, ``FileNotFoundError``, ``ImportError`` (naming the extra to install) or
  another ``OSError`` becomes one red ``error:`` line and exit code 2; any other exception one
  ``internal error`` line (type and message, "please report") and exit code 3. No traceback
  unless ``--debug`` or ``ROLLERRIG_DEBUG=1``. Commands need no ``try`` of their own; raise
  :class:`UserError` (or call :func:`_fail`) for a bad option.
- **No partial outputs.** Compute everything first, then write every file of the command inside
  ``with staged_outputs(out) as stage:`` into ``stage.dir``; the files are moved into ``out``
  (each atomically) only when the block ends without an exception, and ``stage.written`` lists
  their final paths. A failure leaves nothing new behind.
"""

from __future__ import annotations

import contextlib
import json
import logging
import os
import re
import shutil
import tempfile
import traceback
from pathlib import Path
from typing import Annotated, NoReturn

import click
import numpy as np
import typer
from rich.console import Console
from rich.table import Table
from rich.text import Text
from typer.core import TyperGroup

from rollerrig._validation import ParameterError

console = Console(width=110, markup=False, highlight=False)
err_console = Console(stderr=True, markup=False, highlight=False, soft_wrap=True)

DEFAULT_OUT = Path("rollerrig-output")
DEBUG_ENV = "ROLLERRIG_DEBUG"
ISSUES_URL = "the rollerrig issue tracker"

# Optional dependency -> the extra that installs it (pyproject.toml).
_EXTRAS = {
    "nptdms": "io",
    "asammdf": "io",
    "numba": "twin",
    "xarray": "twin",
    "pandas": "twin",
    "h5netcdf": "twin",
    "h5py": "twin",
    "pyarrow": "twin",
}


class UserError(Exception):
    """A problem with what the user gave (option, file, folder): printed as one error line."""


def _print_error(message: str) -> None:
    err_console.print(Text.assemble(("error: ", "bold red"), str(message)))


def _fail(message: str) -> NoReturn:
    """Print one error line (literally, no markup) and exit with code 2."""
    _print_error(message)
    raise typer.Exit(code=2)


def note(text: str) -> None:
    """Print a ``note:`` line (the text literally)."""
    console.print(Text.assemble(("note: ", "yellow"), str(text)), soft_wrap=True)


def _import_message(exc: ImportError) -> str:
    text = str(exc)
    if "rollerrig[" in text:
        return text
    module = (exc.name or "").split(".")[0]
    extra = _EXTRAS.get(module)
    if extra is None:
        return f"{text} (a package rollerrig needs is missing; reinstall rollerrig)"
    return f"{text}: install the optional packages with pip install 'rollerrig[{extra}]'"


def _os_message(exc: OSError) -> str:
    what = exc.strerror or str(exc)
    names = [str(n) for n in (exc.filename, exc.filename2) if n is not None]
    if isinstance(exc, FileNotFoundError) and names:
        return f"file not found: {names[0]}"
    return f"{what}: {' -> '.join(names)}" if names else what


def _user_message(exc: BaseException) -> str | None:
    """The one-line message of a user-side error, or None for an internal error."""
    if isinstance(exc, ParameterError | UserError):
        return str(exc)
    if isinstance(exc, ImportError):
        return _import_message(exc)
    if isinstance(exc, OSError):
        return _os_message(exc)
    return None


def _debug_wanted(ctx: click.Context) -> bool:
    return bool(ctx.params.get("debug")) or os.environ.get(DEBUG_ENV, "") not in ("", "0")


# Exits, usage errors and aborts keep click's/typer's own handling.
_PASS_THROUGH = (
    click.exceptions.Exit,
    click.ClickException,
    click.Abort,
    typer.Exit,
    typer.Abort,
)


class _BoundaryGroup(TyperGroup):
    """The error boundary of every command (see the module docstring)."""

    def invoke(self, ctx: click.Context):
        try:
            return super().invoke(ctx)
        except _PASS_THROUGH:
            raise
        except Exception as exc:  # the boundary: everything else ends as one line
            message = _user_message(exc)
            if _debug_wanted(ctx):
                traceback.print_exception(exc)
            if message is not None:
                _print_error(message)
                raise typer.Exit(code=2) from None
            text = " ".join(str(exc).split()) or "(no message)"
            err_console.print(
                Text.assemble(
                    ("internal error: ", "bold red"),
                    f"{type(exc).__name__}: {text} (please report this to {ISSUES_URL}, "
                    f"with the output of the same command run with --debug)",
                )
            )
            raise typer.Exit(code=3) from None


MAX_OUTPUT_STEM = 120
"""Longest output file stem [characters] (the suffix is kept whole)."""


def safe_file_name(name: str) -> str:
    """``name`` as a plain, portable file name (see :meth:`staged_outputs.path`).

    Leading dots are dropped: a hidden name would be taken for a writer's temporary file, and
    ``..`` must not climb out of the output folder.

    Examples
    --------
    >>> safe_file_name("../escaped.nc"), safe_file_name("run 05 [wet].png")
    ('_escaped.nc', 'run_05__wet_.png')
    """
    text = re.sub(r"[^A-Za-z0-9._+-]", "_", str(name)).lstrip(".") or "_"
    stem, dot, suffix = text.rpartition(".")
    if not dot or not stem:
        stem, suffix = text, ""
    stem = stem[:MAX_OUTPUT_STEM]
    return f"{stem}.{suffix}" if suffix else stem


class staged_outputs:  # a context manager that reads as a function
    """Write all files of one command together, or none of them.

    ``with staged_outputs(out) as stage:`` creates a hidden staging folder next to ``out`` (on
    the same file system); write into ``stage.dir`` (or ``stage.path(name)``). When the block
    ends without an exception, every staged file is moved into ``out`` with ``os.replace``
    (atomic per file; an existing file of that name is replaced) and ``stage.written`` lists
    the final paths; on an exception the staging folder is removed and ``out`` is untouched
    (not even created).
    """

    def __init__(self, out: str | os.PathLike):
        self.out = Path(out)
        self.dir: Path | None = None
        self.written: list[Path] = []

    def __enter__(self) -> staged_outputs:
        if self.out.exists() and not self.out.is_dir():
            raise UserError(f"--out {self.out} is a file, not a folder; give a folder")
        anchor = self.out
        while not anchor.exists():
            anchor = anchor.parent
        self.dir = Path(tempfile.mkdtemp(prefix=f".rollerrig-{self.out.name}-", dir=anchor))
        return self

    def path(self, name: str) -> Path:
        """Staged path of the output file ``name``: a plain file name, made safe.

        Names come from user data (an experiment's name, a recording's stem): every character
        other than letters, digits, ``.``, ``_``, ``-`` and ``+`` becomes ``_`` (so ``../x``
        cannot leave ``out``), and the stem is cut to :data:`MAX_OUTPUT_STEM` characters (file
        systems refuse names over 255 bytes).
        """
        return self.dir / safe_file_name(name)

    def final(self, staged: str | os.PathLike) -> Path:
        """Where a staged path ends up in ``out``."""
        return self.out / Path(staged).relative_to(self.dir)

    def __exit__(self, exc_type, exc, tb) -> None:
        try:
            if exc_type is None:
                files = sorted(p for p in self.dir.rglob("*") if p.is_file())
                files = [p for p in files if not p.name.startswith(".")]  # writers' temporaries
                for src in files:  # every clash is found before anything is moved
                    dest = self.final(src)
                    if dest.is_dir():
                        raise UserError(
                            f"output {dest} is a folder; remove it or choose another --out"
                        )
                self.out.mkdir(parents=True, exist_ok=True)
                for src in files:
                    dest = self.final(src)
                    dest.parent.mkdir(parents=True, exist_ok=True)
                    os.replace(src, dest)
                    self.written.append(dest)
        finally:
            shutil.rmtree(self.dir, ignore_errors=True)


def _version_callback(value: bool) -> None:
    if value:
        from rollerrig import __version__

        console.print(f"rollerrig {__version__}")
        raise typer.Exit()


app = typer.Typer(
    name="rollerrig",
    help="Wheel-roller adhesion rig toolkit: contact mechanics, digital twin, measurements.",
    cls=_BoundaryGroup,
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,  # help texts print literally: units such as [kN] survive
)


@app.callback()
def _root(
    version: Annotated[
        bool,
        typer.Option(
            "--version",
            help="Print the version and exit.",
            callback=_version_callback,
            is_eager=True,
        ),
    ] = False,
    debug: Annotated[
        bool,
        typer.Option(
            "--debug",
            help=f"Show the full traceback of an error (also: environment {DEBUG_ENV}=1).",
        ),
    ] = False,
) -> None:
    """Wheel-roller adhesion rig toolkit."""


def _load_rig(rig_file: Path | None):
    from rollerrig.rig.parameters import default_rig, load_rig

    return default_rig() if rig_file is None else load_rig(rig_file)


@app.command()
def contact(
    load_kn: Annotated[float, typer.Option("--load-kn", help="Normal load [kN].")] = 10.0,
    speed_kmh: Annotated[
        float, typer.Option("--speed-kmh", help="Rolling speed for the creep curves [km/h].")
    ] = 30.0,
    rig_file: Annotated[
        Path | None,
        typer.Option("--rig", help="Rig parameter file (TOML); default: bundled rig."),
    ] = None,
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
    out: Annotated[Path, typer.Option("--out", help="Output folder for figures.")] = DEFAULT_OUT,
) -> None:
    """Contact of the rig's wheel-roller pair: Hertz ellipse, Kalker C11, Polach curves.

    Prints the contact at the chosen load beside the same wheel on a tangent rail, and writes
    two figures: creep-adhesion curves (dry, wet; roller and tangent rail) and contact size
    versus roller radius.
    """
    from dataclasses import replace

    from rollerrig.contact.creep import POLACH_PARAMETER_SETS
    from rollerrig.contact.curves import polach_creep_curve
    from rollerrig.contact.roller import contact_versus_roller_radius
    from rollerrig.report._io import provenance, save_figure, write_json
    from rollerrig.report.contact import contact_size_figure, creep_curve_figure

    rig = _load_rig(rig_file)
    g, mat = rig.geometry, rig.material
    load = load_kn * 1e3
    speed = speed_kmh / 3.6
    wheel_rx = g.wheel_radius_x if wheel_radius_mm is None else wheel_radius_mm * 1e-3
    roller_rx = g.roller_radius_x if roller_radius_mm is None else roller_radius_mm * 1e-3
    nu = mat.poisson if poisson is None else poisson
    sets = dict(POLACH_PARAMETER_SETS)
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
    creep = np.linspace(0.0, 0.30, 3001)  # wide enough to contain the wet peak
    rows = {}
    for where, rx in (("roller", roller_rx), ("tangent rail", np.inf)):
        rows[where] = {
            name: polach_creep_curve(
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

    table = Table(
        title=f"Wheel-roller contact at N = {load_kn:g} kN (E = {mat.youngs_modulus / 1e9:g} GPa, "
        f"ν = {nu:g})"
    )
    table.add_column("quantity")
    table.add_column("unit")
    table.add_column(f"roller (R = {roller_rx * 1e3:.0f} mm)", justify="right")
    table.add_column("tangent rail", justify="right")
    table.add_column("roller / rail", justify="right")
    first = next(iter(sets))
    c_roll, c_rail = rows["roller"][first], rows["tangent rail"][first]

    def add(label, unit, f, fmt):
        vr, vt = f(c_roll), f(c_rail)
        table.add_row(label, unit, format(vr, fmt), format(vt, fmt), f"{vr / vt:.3f}")

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
                f"{vr / vt:.3f}",
            )
    console.print(table)
    console.print(
        "Creep is referred to the roller's peripheral speed (Kayaalp eq. 4.21); Polach (2005) "
        "dry/wet parameter sets; Kalker C11 from Kalker (1990) Table E.3."
    )

    fig1, _ = creep_curve_figure(
        sets, load, speed, *geometry, youngs_modulus=mat.youngs_modulus, poisson=nu, max_creep=0.10
    )
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
    record = provenance(
        normal_load_N=load,
        rolling_speed_m_s=speed,
        geometry_m=geometry,
        youngs_modulus_Pa=mat.youngs_modulus,
        poisson=nu,
        polach=[p.to_dict() for p in sets.values()],
        rig=rig.meta.name,
    )
    summary = {
        "provenance": record,
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
    with staged_outputs(out) as stage:
        save_figure(fig1, stage.path("contact-creep-curves.png"), metadata=record)
        save_figure(fig2, stage.path("contact-vs-roller-radius.png"), metadata=record)
        write_json(stage.path("contact-report.json"), summary)
    _print_written(stage.written)


@app.command()
def simulate(
    experiment: Annotated[
        str,
        typer.Option(
            "--experiment", "-e", help="Bundled protocol name (see --list) or a protocol TOML file."
        ),
    ] = "seed-30kmh-dry",
    rig_file: Annotated[
        Path | None, typer.Option("--rig", help="Rig parameter file (TOML); default: bundled rig.")
    ] = None,
    out: Annotated[Path, typer.Option("--out", help="Output folder.")] = DEFAULT_OUT,
    solver: Annotated[
        str, typer.Option(help="fast (numba ROS2) or reference (scipy Radau).")
    ] = "fast",
    wheel_drive: Annotated[str, typer.Option(help="pmsm or ideal_torque.")] = "pmsm",
    roller_drive: Annotated[
        str, typer.Option(help="induction, induction_linear, ideal_speed or servo.")
    ] = "induction",
    roller_lag_s: Annotated[
        float | None, typer.Option(help="Roller-drive lag τ [s]; default from the rig (c_lp).")
    ] = None,
    output_format: Annotated[
        str, typer.Option("--format", help="Results file format: nc, csv, parquet or mat.")
    ] = "nc",
    list_experiments: Annotated[
        bool, typer.Option("--list", help="List the bundled experiments and exit.")
    ] = False,
) -> None:
    """Simulate an adhesion experiment on the digital twin and write results and figures.

    Writes the labelled results (truth beside what the rig measures, with provenance), the
    six-panel experiment figure and the modal table of the torsional chain.
    """
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    from rollerrig.experiment import bundled_protocols
    from rollerrig.report._io import atomic_write, save_figure
    from rollerrig.report.twin import experiment_figure
    from rollerrig.rig.chain import format_modal_table, modal_table
    from rollerrig.rig.model import DriveConfig
    from rollerrig.solve.results import SAVE_FORMATS, save_dataset
    from rollerrig.solve.simulation import Simulation

    if list_experiments:
        for name in bundled_protocols():
            console.print(name)
        return
    suffix = "." + output_format.lower().lstrip(".")
    if suffix not in SAVE_FORMATS:
        _fail(f"unknown results format {output_format!r}; choose one of {SAVE_FORMATS}")
    rig = _load_rig(rig_file)
    drives = DriveConfig(wheel=wheel_drive, roller=roller_drive, roller_lag=roller_lag_s)
    sim = Simulation(rig, experiment, drives=drives, solver=solver)
    console.print(
        Text.assemble(
            "simulating ",
            (sim.protocol.name, "bold"),
            f" ({sim.protocol.duration:g} s) on ",
            (rig.meta.name, "bold"),
            f": wheel {drives.wheel}, roller {drives.roller}, solver {solver}",
        )
    )
    with Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        TextColumn("{task.fields[info]}"),
        TimeElapsedColumn(),
        console=console,
        transient=False,
    ) as bar:
        task = bar.add_task("simulating", total=sim.protocol.duration, info="compiling/solving")
        ds = sim.run(progress=lambda t, end: bar.update(task, completed=t, info=f"t = {t:.2f} s"))
        bar.update(task, completed=sim.protocol.duration, info="done")
    stats = json.loads(ds.attrs["provenance"])["solver"]
    console.print(f"solved in {stats['wall_time_s']:.2f} s ({stats['name']})")
    rows = modal_table(rig)
    text = format_modal_table(rows)
    release = _release_summary(ds, sim.protocol)
    figure = experiment_figure(ds)
    # All outputs together; a re-run replaces them; inputs are never written to.
    with staged_outputs(out) as stage:
        save_dataset(ds, stage.path(f"{sim.protocol.name}{suffix}"), overwrite=True)
        save_figure(figure, stage.path(f"{sim.protocol.name}.png"))
        atomic_write(stage.path("modes.txt"), lambda p: p.write_text(text + "\n", "utf-8"))
    console.print(text)
    if release:
        console.print(release)
    _print_written(stage.written)


def _release_summary(ds, protocol) -> str:
    """One line per sudden torque release: how far T56 overshoots below zero, vs the truth."""
    from rollerrig.studies import release_overshoots

    return "\n".join(
        f"release at {r['time [s]']:5.2f} s: force from T56 {r['force_before [N]']:7.0f} N -> "
        f"min {r['measured_min [N]']:7.0f} N (overshoot {r['measured_overshoot [-]']:5.1%}); "
        f"true contact force min {r['true_min [N]']:7.0f} N"
        for r in release_overshoots(ds, protocol)
    )


@app.command()
def study(
    name: Annotated[str, typer.Argument(help="stiffness, lag or drives.")],
    rig_file: Annotated[
        Path | None, typer.Option("--rig", help="Rig parameter file (TOML); default: bundled rig.")
    ] = None,
    out: Annotated[Path, typer.Option("--out", help="Output folder.")] = DEFAULT_OUT,
) -> None:
    """The seed's parametric studies on the twin: overshoot of the torque-sensor force after a
    sudden release, versus roller-shaft stiffness, motor lag, or roller drive."""
    from rollerrig.report._io import save_figure, write_json
    from rollerrig.report.twin import sweep_figure
    from rollerrig.studies import run_study

    rig = _load_rig(rig_file)
    result = run_study(name, rig)
    table = Table(title=f"Study '{name}': overshoot below zero after a sudden torque release")
    table.add_column("variant")
    table.add_column("T56 / r_r", justify="right")
    table.add_column("true F_x", justify="right")
    for label, m, t in zip(
        result.labels, result.measured_overshoot, result.true_overshoot, strict=True
    ):
        table.add_row(label, f"{m:.1%}", f"{t:.1%}")
    console.print(table)
    numeric = name != "drives"
    fig = sweep_figure(
        np.asarray(result.values) / (1e3 if name == "stiffness" else 1.0)
        if numeric
        else result.labels,
        {"force from T56": result.measured_overshoot, "true contact force": result.true_overshoot},
        xlabel=(
            f"{result.parameter} [{'kN·m/rad' if name == 'stiffness' else result.unit}]"
            if numeric
            else ""
        ),
        title=f"Overshoot after a sudden release: {result.parameter}",
    )
    with staged_outputs(out) as stage:
        save_figure(fig, stage.path(f"study-{name}.png"))
        write_json(stage.path(f"study-{name}.json"), {"study": name, "rows": result.rows()})
    _print_written(stage.written)


@app.command()
def modes(
    rig_file: Annotated[
        Path | None, typer.Option("--rig", help="Rig parameter file (TOML); default: bundled rig.")
    ] = None,
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
        str, typer.Option(help="Friction condition of the coupled twin's contact: dry or wet.")
    ] = "dry",
) -> None:
    """Natural frequencies, damping and dominant bodies of the torsional chain; with
    --speed-kmh (and --load-kn), the damped modes of the coupled, linearised twin beside them:
    frequency, damping ratio and what moves, and which modes can ring."""
    from rollerrig.rig.chain import format_modal_table, modal_table
    from rollerrig.rig.linear import DEFAULT_NORMAL_LOAD, coupled_modes, format_coupled_modes

    rig = _load_rig(rig_file)
    coupled = None
    if speed_kmh is None and load_kn is not None:
        raise UserError("--load-kn needs --speed-kmh: give the roller speed [km/h] as well")
    if speed_kmh is not None:
        # Upper bounds: the twin's drives and contact are parametrised for a tram wheel; far
        # beyond them the steady state is not found and the linearisation means nothing.
        if not (np.isfinite(speed_kmh) and 0 < speed_kmh <= 300):
            raise UserError(f"--speed-kmh must be in (0, 300] [km/h], got {speed_kmh:g}")
        if load_kn is not None and not (np.isfinite(load_kn) and 0 < load_kn <= 200):
            raise UserError(f"--load-kn must be in (0, 200] [kN], got {load_kn:g}")
        load = DEFAULT_NORMAL_LOAD if load_kn is None else load_kn * 1e3
        source = "--load-kn" if load_kn is not None else "default: the seed's test load"
        coupled = coupled_modes(rig, speed_kmh / 3.6, load, friction=friction, load_source=source)
    console.print("Free torsional chain (no contact, no drives):")
    console.print(format_modal_table(modal_table(rig)), soft_wrap=True)
    if coupled is not None:
        console.print()
        console.print(format_coupled_modes(coupled), soft_wrap=True)


def _quiet_reader_console_logs() -> None:
    """nptdms prints its warnings through its own console handler; the reader collects them as
    notes (or errors), so the console copy is dropped, except with --debug."""
    ctx = click.get_current_context(silent=True)
    if ctx is not None and _debug_wanted(ctx.find_root()):
        return
    try:
        from nptdms.log import log_manager
    except ImportError:  # no TDMS support installed: nothing to quiet
        return
    log_manager.console_handler.setLevel(logging.ERROR)


def _read(path: Path, channels: Path | None, lenient: bool, needed=None):
    """Read a recording; ``needed``: the channels the command needs (others only noted)."""
    from rollerrig.measure.readers import read_recording

    _quiet_reader_console_logs()
    return read_recording(
        path,
        channels,
        validate="lenient" if lenient else "strict",
        channels=None if needed is None else list(needed),
    )


def _print_written(paths) -> None:
    for path in paths:
        console.print(f"wrote {path}")


def _print_recording_notes(rec) -> None:
    """The reader's notes, interpolated NaN runs, gaps and injected lines, one line each."""
    from rollerrig.measure.analysis import recording_note_lines

    for line in recording_note_lines(rec):
        note(f"recording: {line}")


def _load_truth(path: Path):
    """The twin's truth (NetCDF) of a synthetic recording, or one clear error."""
    import errno

    import xarray as xr

    if not path.is_file():
        raise FileNotFoundError(errno.ENOENT, "truth file not found", str(path))
    try:
        ds = xr.load_dataset(path, engine="h5netcdf")
    except Exception as exc:  # any failure of the NetCDF reader: not a usable truth file
        raise UserError(
            f"--truth {path}: not a NetCDF file ({type(exc).__name__}: "
            f"{' '.join(str(exc).split())[:200]}); give the *-truth.nc written beside the "
            "synthetic recording"
        ) from None
    ds.encoding.setdefault("source", str(path))
    if "coa" not in ds:
        raise UserError(
            f"--truth {path}: a NetCDF file without the variable 'coa' (the true contact CoA); "
            "give the *-truth.nc written beside the synthetic recording"
        )
    return ds


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


@app.command()
def analyze(
    recording: Annotated[Path, typer.Argument(help="Recording: CSV, Parquet, TDMS, MF4 or MAT.")],
    channels: ChannelsOption = None,
    rig_file: Annotated[
        Path | None, typer.Option("--rig", help="Rig parameter file (TOML); default: bundled rig.")
    ] = None,
    truth: Annotated[
        Path | None,
        typer.Option(help="Twin truth (NetCDF) of a synthetic recording, for error figures."),
    ] = None,
    out: Annotated[Path, typer.Option("--out", help="Output folder.")] = DEFAULT_OUT,
    study: Annotated[bool, typer.Option(help="Run the full smoothing-filter study.")] = True,
    lenient: LenientOption = False,
) -> None:
    """Analyse an adhesion test: phases, corrected CoA, creep-CoA branches, Polach fit, spectrum.

    Recordings faster than 1.5 kHz are analysed at 1 kHz (anti-alias decimation, stated);
    long files are decimated while they are read, never held whole. Writes
    <name>-analysis.json (every result with units), <name>-analysis.nc (the processed channels)
    and a self-contained <name>-report.html with the figures; all three or none.
    """
    from rollerrig.measure.analysis import analyze_test
    from rollerrig.report.analysis import write_analysis

    rig = _load_rig(rig_file)
    truth_ds = None if truth is None else _load_truth(truth)
    with contextlib.ExitStack() as files:
        loaded = _open_input(recording, channels, lenient, None, files)
        result = analyze_test(loaded, rig, truth=truth_ds, run_study=study)
    rec = result.recording
    with staged_outputs(out) as stage:
        write_analysis(
            result,
            stage.dir,
            recording.stem,
            source=str(recording),
            truth=truth_ds,
            extra_provenance={
                "channel_map": str(channels) if channels else None,
                "rig": rig.meta.name,
                "recording_sha256": rec.metadata.get("sha256"),
            },
        )
    _print_analysis(result)
    _print_written(stage.written)


_FIT_ROWS = (
    ("static_friction", "μ0 [-]"),
    ("limit_ratio", "A [-]"),
    ("friction_decay", "B [s/m]"),
    ("k_adhesion", "kA [-]"),
    ("k_slip", "kS [-]"),
)


def _fit_cell(fit, i: int, key: str, truth: dict | None) -> str:
    if fit is None:
        return "–"
    value, sd = fit.parameters.as_tuple()[i], fit.stderr[key]
    cell = f"{value:.4g} ± {sd:.2g}"
    if truth is not None and np.isfinite(sd) and sd > 0:
        cell += f" ({abs(value - truth[key]) / sd:.1f} σ)"
    return cell


def _print_analysis(result) -> None:
    truth = result.true_parameters
    table = Table(title="Polach fit to the ascending branches")
    table.add_column("parameter")
    table.add_column("corrected CoA", justify="right")
    table.add_column("rig CoA T56/(r_r N)", justify="right")
    if truth is not None:
        table.add_column("true (twin)", justify="right")
    for i, (key, name) in enumerate(_FIT_ROWS):
        cells = [_fit_cell(fit, i, key, truth) for fit in (result.fit, result.fit_rig_coa)]
        if truth is not None:
            cells.append(f"{truth[key]:.4g}")
        table.add_row(name, *cells)
    console.print(table)
    if truth is not None:
        console.print(
            "(n σ): distance from the true value in standard errors; truth from "
            f"{result.true_parameters_source}",
            soft_wrap=True,
        )
    shown = []  # fit warnings whose content the lines below already give
    for label, fit in (("corrected CoA", result.fit), ("rig CoA", result.fit_rig_coa)):
        if fit is None:
            continue
        if fit.coverage is not None:
            text = fit.coverage.describe(reasons=False)
            why = "" if fit.coverage.a_and_b_identifiable else " (why: see the notes)"
            console.print(f"fit to the {label}: {text}{why}", soft_wrap=True)
        if fit.residual_structure is not None:
            text = fit.residual_structure.describe()
            console.print(f"fit to the {label}: {text}", soft_wrap=True)
            shown.append(f"fit to the {label}: Polach fit residuals are structured")
    for key, value in result.truth_errors.items():
        console.print(f"{key}: {value:.4f}")
    if result.spectrum is not None:
        console.print(result.spectrum.format_table())
    rate = result.recording.sample_rate
    tuned = result.smoothing_tuned_at
    console.print(
        f"Savitzky-Golay smoothing: order {result.smoothing_order}, window "
        f"{result.smoothing_window} samples at {rate:.6g} Hz "
        f"({result.smoothing_window / rate:.3f} s"
        + ("; given, not tuned)" if tuned is None else f"; tuned at {tuned:g} Hz)"),
        soft_wrap=True,
    )
    if result.study:
        best = result.study[0]
        console.print(
            f"filter study: best {best.label} (cost {best.score.cost:.3f})", soft_wrap=True
        )
        basis = getattr(result.study, "basis", None)
        if basis is not None:
            note(basis.note())
        if result.study:
            for text in result.study.unscored_notes():
                note(f"filter study: {text}")
    _print_recording_notes(result.recording)
    for text in result.notes:
        if not text.startswith(tuple(shown)):
            note(text)


_SPECTRUM_IN_MEMORY = 1 << 22
"""Samples per channel up to which ``analyze``, ``spectrum`` and ``filters`` read a file whole
(4.2 M: 3.6 min at 19.2 kHz, 4.7 h at 250 Hz); longer files on one time base are streamed in
chunks (bounded memory). One threshold for the three commands (the name is historical)."""


def _open_input(path: Path, channels, lenient: bool, needed, files):
    """The recording a command works on: read whole, or an open source streaming from the file.

    Short files, multi-rate files (the reader resamples them onto one base) and ``--lenient``
    reads are read whole (:func:`_read`), a ``Recording``. A file on one time base with more
    than :data:`_SPECTRUM_IN_MEMORY` samples per channel, read strictly, is opened for chunked
    reading (:func:`rollerrig.measure.source.open_recording`, entered into the ExitStack
    ``files``) and returned as a ``RecordingSource``: the command streams it and never holds
    it whole. With ``--lenient`` such a file is still read whole (interpolating NaN runs and
    keeping gaps needs the whole file), and a note says so and how large it is.
    """
    from rollerrig.measure.recording import RecordingError
    from rollerrig.measure.source import open_recording

    _quiet_reader_console_logs()
    try:
        source = files.enter_context(open_recording(path, channels, channels=needed))
    except (RecordingError, OSError):
        # e.g. channels on several time bases (the reader resamples them); a file that cannot
        # be opened gets the reader's own error below
        source = None
    if source is None or source.n_samples <= _SPECTRUM_IN_MEMORY:
        return _read(path, channels, lenient, needed=needed)
    if not lenient:
        files.enter_context(_strict_stream_hint())
        return source
    n, names = source.n_samples, len(source.names)
    rec = _read(path, channels, lenient, needed=needed)
    meta = dict(rec.metadata)
    meta["notes"] = [
        *list(meta.get("notes") or []),
        f"read whole for --lenient ({n} samples per channel x {names} channels, "
        f"{n * names * 8 / 2**20:.3g} MiB as float64): without --lenient a file this long is "
        "streamed in chunks in bounded memory",
    ]
    return type(rec)(rec.time, rec.channels, rec.units, meta)


@contextlib.contextmanager
def _strict_stream_hint():
    """A streamed file that stops at a NaN/inf sample or a gap: say what the option is called."""
    from rollerrig.measure.recording import RecordingError

    try:
        yield
    except RecordingError as exc:
        if "chunked reading is strict" not in str(exc):
            raise
        raise RecordingError(
            f"{exc}; on the command line: --lenient (reads the file whole, in memory)"
        ) from None


def _derived(loaded, rig):
    """A recording read whole with the quantities the rig derives; a source as it is."""
    from rollerrig.measure.quantities import derive_quantities

    return loaded if hasattr(loaded, "iter_chunks") else derive_quantities(loaded, rig)


@app.command()
def spectrum(
    recordings: Annotated[list[Path], typer.Argument(help="One or more recordings.")],
    channels: ChannelsOption = None,
    channel: Annotated[str, typer.Option(help="Channel to analyse.")] = "torque",
    rig_file: Annotated[
        Path | None, typer.Option("--rig", help="Rig parameter file (TOML); default: bundled rig.")
    ] = None,
    coherence_with: Annotated[
        str | None,
        typer.Option(
            "--coherence",
            help="Second channel: coherence with it at every peak (e.g. a laser displacement).",
        ),
    ] = None,
    out: Annotated[Path, typer.Option("--out", help="Output folder.")] = DEFAULT_OUT,
    lenient: LenientOption = False,
) -> None:
    """Spectra whose peaks explain themselves; with several recordings, an order map and the
    lines that stay put at every speed (speed-independent). Settings are chosen from each
    signal and stated; the coupled twin's damped modes at each recording's speed and load are
    among the sources."""
    from rollerrig.report._io import save_figure, write_json
    from rollerrig.report.spectra import coherence_figure, order_map_figure, spectrum_figure
    from rollerrig.signal.workflow import explain_recordings

    rig = _load_rig(rig_file)
    needed = [channel] if coherence_with is None else [channel, coherence_with]
    with contextlib.ExitStack() as files:
        loaded = [
            _derived(_open_input(p, channels, lenient, needed, files), rig) for p in recordings
        ]
        result = explain_recordings(loaded, channel, rig, coherence_with=coherence_with)
    from rollerrig.measure.analysis import recording_facts

    stems = [p.stem for p in recordings]
    stems = [s if stems.count(s) == 1 else f"{s}-{i + 1}" for i, s in enumerate(stems)]
    names = [p.name for p in recordings]
    keys = [n if names.count(n) == 1 else str(p) for n, p in zip(names, recordings, strict=True)]
    summary: dict = {}
    with staged_outputs(out) as stage:
        for path, stem, key, rec, e in zip(
            recordings, stems, keys, loaded, result.spectra, strict=True
        ):
            speed_kmh = e.roller_speed * rig.geometry.roller_radius_x * 3.6
            console.print(
                Text.assemble((path.name, "bold"), f": roller {speed_kmh:.1f} km/h"),
                soft_wrap=True,
            )
            _print_recording_notes(rec)
            console.print(e.format_table(), soft_wrap=True)
            for text in e.notes:
                note(text)
            save_figure(
                spectrum_figure(e, title=f"{path.name} ({speed_kmh:.1f} km/h)"),
                stage.path(f"{stem}-spectrum.png"),
            )
            summary[key] = e.summary() | {"recording": recording_facts(rec)}
            if e.coherence is not None:
                gamma = e.coherence_at_peaks()
                console.print(
                    f"coherence {channel}–{coherence_with} at the peaks: "
                    + (
                        ", ".join(
                            f"{r.frequency:.2f} Hz: " + ("–" if g is None else f"{g:.2f}")
                            for r, g in zip(e.rows, gamma, strict=True)
                        )
                        or "no peaks"
                    )
                    + f" ({e.coherence_note})",
                    soft_wrap=True,
                )
                save_figure(
                    coherence_figure(
                        e.coherence,
                        [r.frequency for r in e.rows],
                        [r.label for r in e.rows],
                        names=(channel, coherence_with),
                    ),
                    stage.path(f"{stem}-coherence.png"),
                )
        fixed = result.speed_independent
        if len(result.spectra) > 1:
            console.print(
                "speed-independent lines [Hz]: " + (", ".join(f"{f:.3f}" for f in fixed) or "none")
            )
            save_figure(
                order_map_figure(result.order_map(), roller_radius=rig.geometry.roller_radius_x),
                stage.path("order-map.png"),
            )
        summary["speed_independent_lines [Hz]"] = [float(f) for f in fixed]
        write_json(stage.path("spectra.json"), summary)
    for path in stage.written:
        console.print(f"wrote {path}")


@app.command()
def filters(
    recording: Annotated[Path, typer.Argument(help="Recording with a torque channel.")],
    channels: ChannelsOption = None,
    channel: Annotated[str, typer.Option(help="Channel to smooth.")] = "torque",
    out: Annotated[Path, typer.Option("--out", help="Output folder.")] = DEFAULT_OUT,
    top: Annotated[int, typer.Option(help="Rows of the ranked table to print.")] = 15,
    lenient: LenientOption = False,
) -> None:
    """The seed's smoothing-filter study as a ranked table and figures (truth-free scoring).

    Reads only the channel it smooths (other map entries missing from the file are noted).
    Recordings faster than 500 Hz are studied at 250 Hz (the seed's rate; anti-alias
    decimation, stated); long files are decimated while they are read, never held whole.
    """
    from rollerrig.measure.analysis import (
        check_channel_values,
        fill_short_gaps,
        recording_facts,
    )
    from rollerrig.measure.recording import RecordingError
    from rollerrig.report._io import save_figure, write_json
    from rollerrig.report.filters import savitzky_golay_grid_figure, study_ranking_figure
    from rollerrig.signal.scoring import prepare_study_signal, study_signal_from_source

    with contextlib.ExitStack() as files:
        rec = _open_input(recording, channels, lenient, [channel], files)
        if hasattr(rec, "iter_chunks"):  # a long file: streamed, decimated while read
            try:
                signal = study_signal_from_source(rec, channel)
            except RecordingError:
                raise
            except ParameterError as exc:  # e.g. values whose squares overflow
                raise RecordingError(f"{recording}: channel {channel!r}: {exc}") from None
            fs = float(f"{float(rec.sample_rate):.10g}")
        else:
            rec.require(channel)
            check_channel_values(rec, [channel])
            rec, _ = fill_short_gaps(rec)  # the scoring needs a uniform time base; notes say so
            signal = prepare_study_signal(rec.time, rec[channel])
            fs = float(f"{rec.sample_rate:.10g}")
        rows = signal.filter_study()
        order, window, grid = signal.tune_savitzky_golay()
        facts = recording_facts(rec)
    table = Table(title=f"Smoothing filters on {recording.name}:{channel} (lower cost is better)")
    for col in ("rank", "filter", "noise left", "peak kept", "lag [s]", "cost"):
        table.add_column(col, justify="right" if col != "filter" else "left")
    for r in rows[:top]:
        s = r.score
        table.add_row(
            str(r.rank),
            r.label,
            _cell(s.noise_left),
            _cell(s.peak_kept),
            _cell(s.lag),
            f"{s.cost:.3f}",
        )
    ranking_fig = study_ranking_figure(rows)
    grid_fig = savitzky_golay_grid_figure(grid)
    tuned_at = grid.basis.analysis_rate
    summary = {
        "recording": facts,
        "channel": channel,
        "basis": rows.basis.as_dict(),
        "unscored": dict(rows.unscored),
        "ranking": [r.as_dict() for r in rows],
        "savitzky_golay": {
            "order": order,
            "window [samples]": window,
            "samples at [Hz]": fs,
            "window [s]": window / fs,
            "tuned at [Hz]": tuned_at,
        },
    }
    with staged_outputs(out) as stage:
        save_figure(ranking_fig, stage.path(f"{recording.stem}-filter-ranking.png"))
        save_figure(grid_fig, stage.path(f"{recording.stem}-sg-grid.png"))
        write_json(stage.path(f"{recording.stem}-filters.json"), summary)
    console.print(table)
    console.print(
        f"Savitzky-Golay tuned for this recording: order {order}, window {window} samples at "
        f"{fs:.6g} Hz ({window / fs:.3f} s; tuned at {tuned_at:g} Hz)",
        soft_wrap=True,
    )
    note(rows.basis.note())
    for text in rows.unscored_notes():
        note(text)
    _print_recording_notes(rec)
    _print_written(stage.written)


def _cell(value: float) -> str:
    """A table cell: the number, or a dash where the recording does not allow the score."""
    return f"{value:.3f}" if np.isfinite(value) else "–"


@app.command()
def demo(
    out: Annotated[Path, typer.Option("--out", help="Output folder.")] = DEFAULT_OUT,
) -> None:
    """End to end on the bundled rig: simulate, record, analyse, report.

    \b
    1. simulates the 30 km/h dry adhesion test on the digital twin (1 kHz);
    2. writes what the rig's DAQ would record (250 Hz, motor lines, ripple, noise, encoders) as
       an NI TDMS file, with the truth beside it (NetCDF);
    3. records free rolling at 5, 10, 20 and 30 km/h as ASAM MDF4 files;
    4. analyses the test and writes the HTML report; explains the free-rolling spectra.
    """
    from rollerrig.demo import run_demo

    with staged_outputs(out) as stage:
        paths = run_demo(out, console, workdir=stage.dir)
    result = paths["result"]
    _print_analysis(result)
    lines = ", ".join(f"{f:.3f} Hz" for f in paths["speed_independent"]) or "none"
    console.print(
        f"speed-independent lines in the free-rolling spectra: {lines} (no line is injected "
        "into the demo's recordings: what is listed was found, not put there)"
    )
    _print_written(stage.written)


def main() -> None:  # pragma: no cover - console entry point
    app()


if __name__ == "__main__":  # pragma: no cover
    main()
