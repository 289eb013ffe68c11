"""The ``rollerrig`` command: the front door to the toolkit.

Units at this edge follow rig practice (kN, km/h, mm); everything inside is SI.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from rollerrig._validation import ParameterError

app = typer.Typer(
    name="rollerrig",
    help="Wheel-roller adhesion rig toolkit: contact mechanics, digital twin, measurements.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
console = Console(width=110)
err_console = Console(stderr=True)

DEFAULT_OUT = Path("rollerrig-output")


@app.callback()
def _root(
    version: Annotated[bool, typer.Option("--version", help="Print the version and exit.")] = False,
) -> None:
    """Wheel-roller adhesion rig toolkit."""
    if version:
        from rollerrig import __version__

        console.print(f"rollerrig {__version__}")
        raise typer.Exit()


def _fail(message: str) -> None:
    err_console.print(f"[bold red]error:[/] {message}")
    raise typer.Exit(code=2)


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

    try:
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
    except ParameterError as exc:
        _fail(str(exc))
        return

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
    paths = [
        save_figure(fig1, out / "contact-creep-curves.png", metadata=record),
        save_figure(fig2, out / "contact-vs-roller-radius.png", metadata=record),
    ]
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
    paths.append(write_json(out / "contact-report.json", summary))
    for p in paths:
        console.print(f"wrote {p}")


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
    try:
        rig = _load_rig(rig_file)
        drives = DriveConfig(wheel=wheel_drive, roller=roller_drive, roller_lag=roller_lag_s)
        sim = Simulation(rig, experiment, drives=drives, solver=solver)
    except (ParameterError, FileNotFoundError) as exc:
        _fail(str(exc))
        return
    results_path = out / f"{sim.protocol.name}{suffix}"
    figure_path = out / f"{sim.protocol.name}.png"
    console.print(
        f"simulating [bold]{sim.protocol.name}[/] ({sim.protocol.duration:g} s) on "
        f"[bold]{rig.meta.name}[/]: wheel {drives.wheel}, roller {drives.roller}, solver {solver}"
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
    # Outputs are replaced atomically on a re-run; inputs are never written to.
    save_dataset(ds, results_path, overwrite=True)
    save_figure(experiment_figure(ds), figure_path)
    rows = modal_table(rig)
    text = format_modal_table(rows)
    atomic_write(out / "modes.txt", lambda p: p.write_text(text + "\n", encoding="utf-8"))
    console.print(text)
    release = _release_summary(ds, sim.protocol)
    if release:
        console.print(release)
    for path in (results_path, figure_path, out / "modes.txt"):
        console.print(f"wrote {path}")


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

    try:
        rig = _load_rig(rig_file)
        result = run_study(name, rig)
    except ParameterError as exc:
        _fail(str(exc))
        return
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
    paths = [
        save_figure(fig, out / f"study-{name}.png"),
        write_json(out / f"study-{name}.json", {"study": name, "rows": result.rows()}),
    ]
    for path in paths:
        console.print(f"wrote {path}")


@app.command()
def modes(
    rig_file: Annotated[
        Path | None, typer.Option("--rig", help="Rig parameter file (TOML); default: bundled rig.")
    ] = None,
) -> None:
    """Natural frequencies, damping and dominant bodies of the torsional chain."""
    from rollerrig.rig.chain import format_modal_table, modal_table

    try:
        rig = _load_rig(rig_file)
    except ParameterError as exc:
        _fail(str(exc))
        return
    console.print(format_modal_table(modal_table(rig)))


def _read(path: Path, channels: Path | None, lenient: bool):
    from rollerrig.measure.readers import read_recording

    return read_recording(path, channels, validate="lenient" if lenient else "strict")


ChannelsOption = Annotated[
    Path | None,
    typer.Option("--channels", help="Channel map (TOML): which column is which quantity, units."),
]
LenientOption = Annotated[
    bool,
    typer.Option(help="Fill short NaN runs and accept gaps (reported) instead of failing."),
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

    Writes <name>-analysis.json (every result with units), <name>-analysis.nc (the processed
    channels) and a self-contained <name>-report.html with the figures.
    """
    from rollerrig.measure.analysis import analyze_test
    from rollerrig.report.analysis import write_analysis

    try:
        rec = _read(recording, channels, lenient)
        rig = _load_rig(rig_file)
        truth_ds = None
        if truth is not None:
            import xarray as xr

            truth_ds = xr.load_dataset(truth, engine="h5netcdf")
        result = analyze_test(rec, rig, truth=truth_ds, run_study=study)
    except (ParameterError, FileNotFoundError, ImportError) as exc:
        _fail(str(exc))
        return
    paths = write_analysis(
        result,
        out,
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
    for path in paths:
        console.print(f"wrote {path}")


def _print_analysis(result) -> None:
    table = Table(title="Polach fit to the ascending branches")
    table.add_column("parameter")
    table.add_column("corrected CoA", justify="right")
    table.add_column("rig CoA T56/(r_r N)", justify="right")
    keys = ("static_friction", "limit_ratio", "friction_decay", "k_adhesion", "k_slip")
    names = ("μ0 [-]", "A [-]", "B [s/m]", "kA [-]", "kS [-]")
    for i, (key, name) in enumerate(zip(keys, names, strict=True)):
        cells = []
        for fit in (result.fit, result.fit_rig_coa):
            cells.append(
                "–"
                if fit is None
                else f"{fit.parameters.as_tuple()[i]:.4g} ± {fit.stderr[key]:.2g}"
            )
        table.add_row(name, *cells)
    console.print(table)
    for key, value in result.truth_errors.items():
        console.print(f"{key}: {value:.4f}")
    if result.spectrum is not None:
        console.print(result.spectrum.format_table())
    if result.study:
        best = result.study[0]
        console.print(
            f"filter study: best {best.label} (cost {best.score.cost:.3f}); Savitzky-Golay tuned "
            f"to order {result.smoothing_order}, window {result.smoothing_window} samples"
        )
    for note in result.notes:
        console.print(f"[yellow]note:[/] {note}")


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
    lines that stay put at every speed (speed-independent)."""
    from rollerrig.measure.quantities import derive_quantities
    from rollerrig.report._io import save_figure, write_json
    from rollerrig.report.spectra import coherence_figure, order_map_figure, spectrum_figure
    from rollerrig.rig.chain import modal_table
    from rollerrig.signal.spectra import (
        coherence,
        coherence_at,
        explain_spectrum,
        order_map,
        speed_independent_lines,
    )

    try:
        rig = _load_rig(rig_file)
        modes = [row.frequency for row in modal_table(rig) if row.frequency > 0]
        loaded = [(p, derive_quantities(_read(p, channels, lenient), rig)) for p in recordings]
        coherences = {}
        if coherence_with is not None:
            for path, rec in loaded:
                rec.require(channel, coherence_with)
                coherences[path] = coherence(rec[channel], rec[coherence_with], rec.sample_rate)
        explained = [(p, explain_spectrum(r, channel, rig_modes=modes)) for p, r in loaded]
        fixed = speed_independent_lines([e for _, e in explained]) if len(explained) > 1 else []
        if len(fixed):  # explain again, now with the lines that stay put at every speed
            explained = [
                (p, explain_spectrum(r, channel, rig_modes=modes, speed_independent=fixed))
                for p, r in loaded
            ]
    except (ParameterError, FileNotFoundError, ImportError) as exc:
        _fail(str(exc))
        return
    summary = {}
    for path, e in explained:
        speed_kmh = e.roller_speed * rig.geometry.roller_radius_x * 3.6
        console.print(f"[bold]{path.name}[/]: roller {speed_kmh:.1f} km/h")
        console.print(e.format_table())
        save_figure(
            spectrum_figure(e, title=f"{path.name} ({speed_kmh:.1f} km/h)"),
            out / f"{path.stem}-spectrum.png",
        )
        summary[path.name] = {"roller_speed [rad/s]": e.roller_speed, "peaks": list(e.table())}
        if path in coherences:
            coh = coherences[path]
            freqs = [r.frequency for r in e.rows]
            gamma = coherence_at(coh, freqs)
            for row, g in zip(summary[path.name]["peaks"], gamma, strict=True):
                row[f"coherence with {coherence_with}"] = float(g)
            console.print(
                f"coherence {channel}–{coherence_with} at the peaks: "
                + ", ".join(f"{f:.2f} Hz: {g:.2f}" for f, g in zip(freqs, gamma, strict=True))
            )
            save_figure(
                coherence_figure(
                    coh, freqs, [r.label for r in e.rows], names=(channel, coherence_with)
                ),
                out / f"{path.stem}-coherence.png",
            )
    if len(explained) > 1:
        console.print(
            "speed-independent lines [Hz]: " + (", ".join(f"{f:.3f}" for f in fixed) or "none")
        )
        omap = order_map([e for _, e in explained], speed_independent=fixed)
        save_figure(
            order_map_figure(omap, roller_radius=rig.geometry.roller_radius_x),
            out / "order-map.png",
        )
    summary["speed_independent_lines [Hz]"] = [float(f) for f in fixed]
    write_json(out / "spectra.json", summary)
    console.print(f"wrote spectra to {out}")


@app.command()
def filters(
    recording: Annotated[Path, typer.Argument(help="Recording with a torque channel.")],
    channels: ChannelsOption = None,
    channel: Annotated[str, typer.Option(help="Channel to smooth.")] = "torque",
    out: Annotated[Path, typer.Option("--out", help="Output folder.")] = DEFAULT_OUT,
    top: Annotated[int, typer.Option(help="Rows of the ranked table to print.")] = 15,
    lenient: LenientOption = False,
) -> None:
    """The seed's smoothing-filter study as a ranked table and figures (truth-free scoring)."""
    from rollerrig.report._io import save_figure, write_json
    from rollerrig.report.filters import savitzky_golay_grid_figure, study_ranking_figure
    from rollerrig.signal.scoring import filter_study, tune_savitzky_golay

    try:
        rec = _read(recording, channels, lenient)
        rec.require(channel)
        rows = filter_study(rec.time, rec[channel])
        order, window, grid = tune_savitzky_golay(rec.time, rec[channel])
    except (ParameterError, FileNotFoundError, ImportError) as exc:
        _fail(str(exc))
        return
    table = Table(title=f"Smoothing filters on {recording.name}:{channel} (lower cost is better)")
    for col in ("rank", "filter", "noise left", "peak kept", "lag [s]", "cost"):
        table.add_column(col, justify="right" if col != "filter" else "left")
    for r in rows[:top]:
        s = r.score
        table.add_row(
            str(r.rank),
            r.label,
            f"{s.noise_left:.3f}",
            f"{s.peak_kept:.3f}",
            f"{s.lag:.3f}",
            f"{s.cost:.3f}",
        )
    console.print(table)
    console.print(
        f"Savitzky-Golay tuned for this recording: order {order}, window {window} samples"
    )
    save_figure(study_ranking_figure(rows), out / f"{recording.stem}-filter-ranking.png")
    save_figure(savitzky_golay_grid_figure(grid), out / f"{recording.stem}-sg-grid.png")
    write_json(
        out / f"{recording.stem}-filters.json",
        {
            "ranking": [r.as_dict() for r in rows],
            "savitzky_golay": {"order": order, "window": window},
        },
    )
    console.print(f"wrote figures and {recording.stem}-filters.json to {out}")


@app.command()
def demo(
    out: Annotated[Path, typer.Option("--out", help="Output folder.")] = DEFAULT_OUT,
) -> None:
    """End to end on the bundled rig: simulate, record, analyse, report.

    1. simulates the 30 km/h dry adhesion test on the digital twin (1 kHz);
    2. writes what the rig's DAQ would record (250 Hz, motor lines, ripple, noise, encoders) as
       an NI TDMS file, with the truth beside it (NetCDF);
    3. records free rolling at 5, 10, 20 and 30 km/h as ASAM MDF4 files;
    4. analyses the test and writes the HTML report; explains the free-rolling spectra.
    """
    from rollerrig.demo import run_demo

    paths = run_demo(out, console)
    result = paths["result"]
    _print_analysis(result)
    lines = ", ".join(f"{f:.3f} Hz" for f in paths["speed_independent"]) or "none"
    console.print(f"speed-independent lines in the free-rolling spectra: {lines}")
    for path in paths.values():
        if isinstance(path, Path):
            console.print(f"wrote {path}")


def main() -> None:  # pragma: no cover - console entry point
    app()


if __name__ == "__main__":  # pragma: no cover
    main()
