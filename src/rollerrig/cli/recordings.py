"""Recordings on the command line: ``analyze``, ``spectrum`` and ``filters``."""

from __future__ import annotations

import contextlib
from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.table import Table
from rich.text import Text

from rollerrig._validation import ParameterError
from rollerrig.cli._boundary import warnings_printed
from rollerrig.cli._console import (
    QuietOption,
    console,
    note,
    print_recording_notes,
    print_written,
    steps,
)
from rollerrig.cli._inputs import (
    TWIN_RESULTS_CHANNEL,
    calibration_for,
    channel_names,
    derived,
    load_truth,
    open_input,
    require_inputs,
    twin_results_error,
)
from rollerrig.cli._options import (
    DEFAULT_OUT,
    ChannelsOption,
    FigureFormat,
    FigureFormatOption,
    LenientOption,
    OutOption,
    RigOption,
    figure_file,
    load_rig,
)
from rollerrig.cli._outputs import command_outputs, safe_file_stem, unique_file_stems

__all__ = ["analyze", "filters", "print_analysis", "spectrum"]


def analyze(
    recording: Annotated[
        Path,
        typer.Argument(help="Recording: CSV (text), LVM, Excel .xlsx, Parquet, TDMS, MF4 or MAT."),
    ],
    channels: ChannelsOption = None,
    rig_file: RigOption = None,
    truth: Annotated[
        Path | None,
        typer.Option(help="Twin truth (NetCDF) of a synthetic recording, for error figures."),
    ] = None,
    calibration: Annotated[
        Path | None,
        typer.Option(
            help="calibration.json of `rollerrig calibrate`: its values replace the rig's and "
            "their covariance enters the CoA's uncertainty (with --rig calibrated-rig.toml)."
        ),
    ] = None,
    allow_other_rig: Annotated[
        bool,
        typer.Option(
            "--allow-other-rig",
            help="Use a --calibration made on another rig than the one in use (a warning, "
            "recorded in every output's provenance); without it that is an error.",
        ),
    ] = False,
    out: OutOption = DEFAULT_OUT,
    study: Annotated[bool, typer.Option(help="Run the full smoothing-filter study.")] = True,
    on_track: Annotated[
        bool,
        typer.Option(
            "--on-track",
            help="Also predict the measured creep curve on a tangent rail with the roller's "
            "crown (the modified FASTSIM, as `rollerrig transfer`, which takes other rails "
            "and laws): an 'On track' section in the report and <name>-transfer.csv/.json/.png.",
        ),
    ] = False,
    lenient: LenientOption = False,
    quiet: QuietOption = False,
) -> None:
    """Analyse an adhesion test: phases, corrected CoA with its uncertainty, creep-CoA branches,
    Polach fit, spectrum.

    Recordings faster than 1.5 kHz are analysed at 1 kHz (anti-alias decimation, stated);
    long files are decimated while they are read, never held whole. Writes
    <name>-analysis.json (every result with units), <name>-analysis.nc (the processed channels)
    and a self-contained <name>-report.html with the figures; all three or none.
    """
    require_inputs(
        ("", recording), ("--channels", channels), ("--truth", truth),
        ("--calibration", calibration),
    )  # fmt: skip
    from rollerrig.analysis.adhesion import analyze_test
    from rollerrig.report.analysis import write_analysis

    rig = load_rig(rig_file)
    calibrated, bound = calibration_for(calibration, rig, rig_file, allow_other_rig)
    inputs = {"recording": recording, "truth": truth, "rig": rig_file, "calibration": calibration}
    stem = safe_file_stem(recording.stem)  # one rule for every output name, the run's too
    with command_outputs(
        out,
        run=f"analyze-{stem}",
        inputs=inputs,
        rig=rig,
        channel_map=channels,
        lenient=lenient,
        filter_study=study,
        **bound,
    ) as stage:
        with steps(f"analyze {recording.name}", "opening the recording") as say:
            truth_ds = None if truth is None else load_truth(truth)
            with contextlib.ExitStack() as files:
                # Without a channel map the file's own names are the map: no column is needed
                # by name (the analysis checks its inputs, with their alternatives, and names
                # what is missing), so a column that cannot be read, such as a TDMS channel
                # created but never written, is a note instead of stopping the analysis. With
                # a map, every entry is needed (a mistyped column is an error with close
                # matches).
                needed = () if channels is None else None
                loaded = open_input(recording, channels, lenient, needed, files)
                names = channel_names(loaded)
                if channels is None and "torque" not in names and TWIN_RESULTS_CHANNEL in names:
                    raise twin_results_error(recording, netcdf=False)
                result = analyze_test(
                    loaded, rig, truth=truth_ds, run_study=study, calibration=calibrated,
                    progress=say,
                )  # fmt: skip
            sections = [_calibration_section(calibration, calibrated)]
            if on_track:
                say("the curve on track")
                sections.append(_on_track_section(result, rig, stage.dir, stem))
            say("writing the results and the report (figures)")
            write_analysis(
                result,
                stage.dir,
                stem,
                source=str(recording),
                truth=truth_ds,
                extra_sections=_sections(sections),
                report_folder=stage.out,
            )
    print_analysis(result, f"{stage.out / f'{stem}-analysis.json'}, 'notes'")
    print_written(stage.written)


def _sections(sections):
    """One report hook running every section that is not None (or None without any)."""
    sections = [f for f in sections if f is not None]
    if not sections:
        return None

    def run(rep):
        for section in sections:
            section(rep)

    return run


def _on_track_section(result, rig, out: Path, stem: str):
    """The transfer of the analysis's curve to a tangent rail (written beside the analysis)
    and its report section; a note and no section when the curve cannot be transferred."""
    from rollerrig.analysis.transfer import (
        ContactGeometry,
        RailGeometry,
        curve_from_analysis,
        transfer_curve,
    )
    from rollerrig.report.transfer import transfer_section, write_transfer

    try:
        measured = curve_from_analysis(result, rig)
        transferred = transfer_curve(measured, ContactGeometry.from_rig(rig), RailGeometry())
    except ParameterError as exc:
        note(f"on track: not made ({exc})")
        return None
    write_transfer(transferred, out, stem)
    # On the console too: --on-track had written its files and said nothing of the rail
    note(
        "on track (tangent rail, the roller's crown): peak CoA "
        f"{transferred.peak_coa_text('track')} at creepage [%] "
        f"{transferred.peak_creepage_text('track')}; {transferred.factor_text()} "
        "(rollerrig transfer gives the table and the band)"
    )
    return lambda rep: transfer_section(rep, transferred)


def _calibration_section(path: Path | None, calibrated: dict | None):
    """The report's calibration part (with the fit figure when calibration-fit.nc lies beside
    the calibration.json), or None without a calibration."""
    if path is None or calibrated is None:
        return None
    from rollerrig.report.calibration import calibration_section

    fit = None
    fit_path = path.with_name("calibration-fit.nc")
    if fit_path.is_file():
        import xarray as xr

        try:
            fit = xr.load_dataset(fit_path, engine="h5netcdf")
        except Exception as exc:  # an unreadable side file costs the figure, not the analysis
            note(f"{fit_path}: not read ({type(exc).__name__}); the report shows no fit figure")
    return lambda rep: calibration_section(rep, calibrated, fit)


_FIT_ROWS = (
    ("static_friction", "μ0 [-]"),
    ("limit_ratio", "A [-]"),
    ("friction_decay", "B [s/m]"),
    ("k_adhesion", "kA [-]"),
    ("k_slip", "kS [-]"),
)


def _fit_cell(fit, key: str, truth: dict | None) -> str:
    if fit is None:
        return "–"
    cell = fit.shown(key)  # "(not identifiable)" where the data do not pin it down
    if key in fit.unidentified():
        return cell[:-1] + ", at a bound)" if key in fit.at_bound else cell
    if truth is not None:
        # The fit's own distance: none at a bound of its search (a one-sided interval; A at
        # 1.6e-8 +- 1.7e-6 had read "228827.1 σ") or without a finite standard error.
        sigma = fit.truth_distance(truth)[key]["sigma"]
        if sigma is not None:
            cell += f" ({sigma:.1f} σ)"
        elif key in fit.at_bound:
            cell += " (at a bound)"
    return cell


def print_uncertainty(result) -> None:
    """Per phase: the rig's CoA, the corrected CoA and its expanded uncertainty, what dominates."""
    budget = result.coa_uncertainty
    if budget is None:
        return
    summary = budget.summary()
    k = summary.get("coverage_factor", 2)
    table = Table(
        title=f"CoA per phase: rig, corrected, expanded uncertainty U (k = {k:g})",
        caption="U mean: of the phase mean (systematic terms do not average out); "
        "U sample: median over the phase's samples",
    )
    for name, justify in (
        ("phase", "left"),
        ("time [s]", "right"),
        ("rig CoA [-]", "right"),
        ("corrected [-]", "right"),
        ("U mean [-]", "right"),
        ("U sample [-]", "right"),
        ("dominant term", "left"),
    ):
        table.add_column(Text(name), justify=justify)
    for row in summary.get("phases", []):
        name = row["name"] if row.get("cycle", -1) < 0 else f"{row['name']} {row['cycle'] + 1}"
        cells = [
            f"{row['start [s]']:.2f}-{row['end [s]']:.2f}",
            _number(row.get("rig_coa_mean [-]")),
            _number(row.get("corrected_coa_mean [-]")),
            _number(row.get("U_mean [-]")),
            _number(row.get("U_sample_median [-]")),
            _dominant(row),
        ]
        table.add_row(Text(name), *(Text(c) for c in cells))
    console.print(table)


def _dominant(row: dict) -> str:
    """What dominates the phase mean's U and the typical sample's (once when the same)."""
    mean = str(row.get("dominant_mean", "")).replace("_", " ")
    sample = str(row.get("dominant_sample", "")).replace("_", " ")
    return mean if mean == sample else f"{mean} (mean); {sample} (sample)"


def _number(value) -> str:
    return "–" if value is None else f"{value:.4f}"


def print_analysis(result, full_in: str | None = None) -> None:
    """The analysis on the console; ``full_in`` (the written JSON, its 'notes') is where a
    long note is kept whole (the console cuts it, :func:`rollerrig.cli._console.note`)."""
    print_uncertainty(result)
    truth = result.true_parameters
    table = Table(title="Polach fit to the ascending branches")
    table.add_column("parameter")
    table.add_column("corrected CoA", justify="right")
    table.add_column("rig CoA T56/(r_r S)", justify="right")
    if truth is not None:
        table.add_column("true (twin)", justify="right")
    for key, name in _FIT_ROWS:
        cells = [_fit_cell(fit, key, truth) for fit in (result.fit, result.fit_rig_coa)]
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
        # The caption gives the segments, not where they lie: the window and phase first.
        console.print(result.spectrum_basis(), soft_wrap=True)
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
    print_recording_notes(result.recording)
    warned = warnings_printed()  # a note the analysis also warned of is printed once
    for text in result.notes:
        flat = " ".join(text.split())
        if not text.startswith(tuple(shown)) and not any(flat in w for w in warned):
            note(text, full_in)


def spectrum(
    recordings: Annotated[list[Path], typer.Argument(help="One or more recordings.")],
    channels: ChannelsOption = None,
    channel: Annotated[str, typer.Option(help="Channel to analyse.")] = "torque",
    rig_file: RigOption = None,
    coherence_with: Annotated[
        str | None,
        typer.Option(
            "--coherence",
            help="Second channel: coherence with it at every peak (e.g. a laser displacement).",
        ),
    ] = None,
    out: OutOption = DEFAULT_OUT,
    lenient: LenientOption = False,
    figure_format: FigureFormatOption = FigureFormat.png,
    quiet: QuietOption = False,
) -> None:
    """Spectra whose peaks explain themselves; with several recordings, an order map and the
    lines that stay put at every speed (speed-independent). Settings are chosen from each
    signal and stated; the coupled twin's damped modes at each recording's speed and load are
    among the sources."""
    require_inputs(*(("", p) for p in recordings), ("--channels", channels))
    from rollerrig.analysis.adhesion import fill_short_gaps, recording_facts
    from rollerrig.output import save_figure, write_json
    from rollerrig.recordings.timebase import require_uniform_time
    from rollerrig.report.spectra import (
        coherence_figure,
        order_map_figure,
        shared_log_frequency,
        spectrum_figure,
    )
    from rollerrig.signal.workflow import explain_recordings

    rig = load_rig(rig_file)
    needed = [channel] if coherence_with is None else [channel, coherence_with]
    named_by = {channel: "--channel"}  # a needed channel the file lacks: named by its option
    if coherence_with is not None:
        named_by[coherence_with] = "--coherence"
    stems = unique_file_stems(p.stem for p in recordings)  # "run-1", "run-2": none replaced
    names = [p.name for p in recordings]
    keys = [n if names.count(n) == 1 else str(p) for n, p in zip(names, recordings, strict=True)]
    roles = (
        {"recording": recordings[0]}
        if len(recordings) == 1
        else {f"recording_{i + 1}": p for i, p in enumerate(recordings)}
    )
    summary: dict = {}
    with command_outputs(
        out,
        run="spectrum",
        inputs={**roles, "rig": rig_file},
        rig=rig,
        channel_map=channels,
        channel=channel,
        coherence_with=coherence_with,
        lenient=lenient,
    ) as stage:
        with steps("spectrum", "reading") as say, contextlib.ExitStack() as files:
            loaded = []
            for p in recordings:
                say(f"reading {p.name}")
                rec = open_input(p, channels, lenient, needed, files, named_by)
                if not hasattr(rec, "iter_chunks"):  # a spectrum needs a uniform time base
                    rec, _ = fill_short_gaps(rec)  # jitter, short gaps: interpolated, noted
                    require_uniform_time(rec.time, str(p), "the spectrum")
                loaded.append(derived(rec, rig))
            say("spectra, peaks and their sources" + (" and coherence" if coherence_with else ""))
            with _speed_from_the_map():
                result = explain_recordings(loaded, channel, rig, coherence_with=coherence_with)
        log = shared_log_frequency(result.spectra)  # one axis convention for the set
        for path, stem, key, rec, e in zip(
            recordings, stems, keys, loaded, result.spectra, strict=True
        ):
            if e.roller_speed is None:  # a result too: the notes say what is not attributed
                speed_text = "at rest, rotation orders unattributed"
                fig_title = f"{path.name} (roller at rest)"
            else:
                speed_kmh = e.roller_speed * rig.geometry.roller_radius_x * 3.6
                speed_text = f"{speed_kmh:.1f} km/h"
                fig_title = f"{path.name} ({speed_kmh:.1f} km/h)"
            console.print(
                Text.assemble((path.name, "bold"), f": roller {speed_text}"), soft_wrap=True
            )
            print_recording_notes(rec)
            console.print(e.format_table(), soft_wrap=True)
            for text in e.notes:
                note(text)
            save_figure(
                spectrum_figure(e, title=f"{fig_title}: {channel}", log_frequency=log),
                stage.path(figure_file(f"{stem}-spectrum", figure_format)),
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
                        names=(f"{path.name}: {channel}", coherence_with),
                        log_frequency=log,
                    ),
                    stage.path(figure_file(f"{stem}-coherence", figure_format)),
                )
        fixed = result.speed_independent
        if len(result.spectra) > 1:
            console.print(
                "speed-independent lines [Hz]: " + (", ".join(f"{f:.3f}" for f in fixed) or "none")
            )
            save_figure(
                order_map_figure(
                    result.order_map(),
                    roller_radius=rig.geometry.roller_radius_x,
                    modes=[e.modes for e in result.spectra if e.modes is not None] or None,
                ),
                stage.path(figure_file("order-map", figure_format)),
            )
        summary["speed_independent_lines [Hz]"] = [float(f) for f in fixed]
        # One recording's summary is named by it, as its figures are: a second recording's run
        # into the same --out had replaced the first's spectra.json beside the first's figure.
        write_json(stage.path(f"{stems[0]}-spectra.json" if len(stems) == 1 else "spectra.json"),
                   summary)  # fmt: skip
    print_written(stage.written)


@contextlib.contextmanager
def _speed_from_the_map():
    """A recording without a roller speed: the error in command-line words. The API's ending
    (pass roller_speed=) has no option here: a speed given for a set of recordings would be
    wrong for all but one, and each recording's own speed places its rotation orders."""
    from rollerrig.recordings.recording import RecordingError
    from rollerrig.signal.operating_point import SPEED_ARGUMENT

    try:
        yield
    except RecordingError as exc:
        text = str(exc)
        if not text.endswith(SPEED_ARGUMENT):
            raise
        raise RecordingError(
            text.removesuffix(f", {SPEED_ARGUMENT}")
            + " in a channel map (--channels; spectrum takes no speed option: each recording's "
            "own speed places its rotation orders)"
        ) from None


def filters(
    recording: Annotated[Path, typer.Argument(help="Recording with a torque channel.")],
    channels: ChannelsOption = None,
    channel: Annotated[str, typer.Option(help="Channel to smooth.")] = "torque",
    out: OutOption = DEFAULT_OUT,
    top: Annotated[int, typer.Option(min=1, help="Rows of the ranked table to print.")] = 15,
    lenient: LenientOption = False,
    figure_format: FigureFormatOption = FigureFormat.png,
    quiet: QuietOption = False,
) -> None:
    """The seed's smoothing-filter study as a ranked table and figures (truth-free scoring).

    Reads only the channel it smooths (other map entries missing from the file are noted).
    Recordings faster than 500 Hz are studied at 250 Hz (the seed's rate; anti-alias
    decimation, stated); long files are decimated while they are read, never held whole.
    """
    require_inputs(("", recording), ("--channels", channels))
    from rollerrig.analysis.adhesion import (
        check_channel_values,
        fill_short_gaps,
        recording_facts,
    )
    from rollerrig.output import save_figure, write_json
    from rollerrig.recordings.recording import RecordingError
    from rollerrig.recordings.timebase import require_uniform_time
    from rollerrig.report.filters import savitzky_golay_grid_figure, study_ranking_figure
    from rollerrig.signal.channel_checks import check_varies
    from rollerrig.signal.scoring import (
        prepare_study_signal,
        savitzky_golay_standing,
        study_signal_from_source,
    )

    stem = safe_file_stem(recording.stem)
    with command_outputs(
        out,
        run=f"filters-{stem}",
        inputs={"recording": recording},
        channel_map=channels,
        channel=channel,
        lenient=lenient,
    ) as stage:
        with contextlib.ExitStack() as files:
            rec = open_input(recording, channels, lenient, [channel], files, {channel: "--channel"})
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
                require_uniform_time(rec.time, str(recording), "the filter study")
                signal = prepare_study_signal(rec.time, rec[channel])
                fs = float(f"{rec.sample_rate:.10g}")
            try:  # the spectrum's check: a constant channel has nothing to smooth or score
                check_varies(signal.raw, f"channel {channel!r}", "has nothing to smooth")
            except ParameterError as exc:
                raise RecordingError(f"{recording}: {exc}") from None
            rows = signal.filter_study()
            order, window, grid = signal.tune_savitzky_golay()
            standing = savitzky_golay_standing(grid, rows)
            facts = recording_facts(rec)
        table = Table(
            title=f"Smoothing filters on {recording.name}:{channel} (lower cost is better)"
        )
        for col in ("rank", "filter", "noise left", "peak kept", "lag [ms]", "cost"):
            table.add_column(col, justify="right" if col != "filter" else "left")
        for r in rows[:top]:
            s = r.score
            table.add_row(
                str(r.rank),
                r.label,
                _cell(s.noise_left),
                _cell(s.peak_kept),
                _cell(s.lag * 1e3, 1),  # a fraction of a sample at 250 Hz: ms, not s
                _cell(s.cost),
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
                "cost": standing["cost"],
                "would_rank": standing["would_rank"],
                "of": standing["of"],
                "basis": standing["basis"],
            },
        }
        save_figure(ranking_fig, stage.path(figure_file(f"{stem}-filter-ranking", figure_format)))
        save_figure(grid_fig, stage.path(figure_file(f"{stem}-sg-grid", figure_format)))
        write_json(stage.path(f"{stem}-filters.json"), summary)
    console.print(table)
    console.print(
        f"Savitzky-Golay tuned for this recording: order {order}, window {window} samples at "
        f"{fs:.6g} Hz ({window / fs:.3f} s; tuned at {tuned_at:g} Hz); analyze smooths with it",
        soft_wrap=True,
    )
    note(standing["note"])
    edge = _grid_edge_note(grid)
    if edge is not None:
        note(edge)
    note(rows.basis.note())
    for text in rows.unscored_notes():
        note(text)
    print_recording_notes(rec)
    print_written(stage.written)


def _grid_edge_note(grid) -> str | None:
    """What the user can do where the Savitzky-Golay grid figure says "optimum on the grid
    edge: widen the grid" (None where the lowest cost lies inside the grid): the command's grid
    is fixed, the API's tuning takes any."""
    orders = sorted({r.params["order"] for r in grid})
    windows = sorted({r.params["window"] for r in grid})
    best = grid[0].params  # ranked: the lowest cost first, as the figure's star
    edges = []
    for key, values in (("window", windows), ("order", orders)):
        if best[key] == values[-1]:
            edges.append(f"{key} {best[key]} is the largest tried")
        elif best[key] == values[0]:
            edges.append(f"{key} {best[key]} is the smallest tried")
    if not edges:
        return None
    text = (
        f"Savitzky-Golay grid: the lowest cost lies on its edge ({'; '.join(edges)}), which the "
        f"figure asks to widen; this command tries orders {orders[0]}-{orders[-1]} and windows "
        f"{windows[0]}-{windows[-1]} samples at {grid.basis.analysis_rate:g} Hz, a fixed grid: "
        "a wider one in Python, rollerrig.signal.scoring.tune_savitzky_golay(time, torque, "
        "orders=..., windows=...)"
    )
    if best["order"] == orders[0] and orders[0] <= 2:
        # orders 0 and 1 smooth as the moving average does (a line fitted to a symmetric window
        # has the window's mean at its centre)
        text += "; below order 2 it is the moving average, which the ranking above scores"
    return text


def _cell(value: float, digits: int = 3) -> str:
    """A table cell: the number, or a dash where the recording does not allow the score
    (rounded first, and -0 shown as 0: a lag of -0.2 ms had read "-0.000")."""
    return f"{round(float(value), digits) + 0.0:.{digits}f}" if np.isfinite(value) else "–"
