"""Calibration on the command line: ``rollerrig calibrate``."""

from __future__ import annotations

from enum import StrEnum
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
    print_recording_notes,
    print_warning,
    print_written,
)
from rollerrig.cli._options import (
    DEFAULT_OUT,
    ChannelsOption,
    FigureFormat,
    FigureFormatOption,
    Friction,
    LenientOption,
    OutOption,
    RigOption,
    figure_file,
    load_rig,
)
from rollerrig.cli._outputs import command_outputs
from rollerrig.cli.contact import CreepLaw

FIT_FIGURE_NAME = "calibration-fit.png"
"""The figure of the fit: recorded against simulated T56 and speeds, before and after."""

__all__ = [
    "CalibrationDrive",
    "calibrate",
    "print_calibration",
    "print_combinations",
    "print_comparison",
]


class CalibrationDrive(StrEnum):
    """The roller drive of the twin a calibration fits, or ``compare`` for both."""

    induction = "induction"
    induction_dq = "induction_dq"
    compare = "compare"


def calibrate(
    recording: Annotated[
        Path | None,
        typer.Argument(
            help="[required, except with --list-keys] Recording of an adhesion test with the "
            "torque request, the torque sensor, both encoder counts and the air-spring pressure "
            "(or the normal load).",
            show_default=False,
        ),
    ] = None,
    free: Annotated[
        str | None,
        typer.Option(
            "--free",
            help="[required, except with --list-keys] Free parameters, comma-separated dotted "
            "keys of the rig file (e.g. "
            "stiffness.roller_shaft,bearing.friction_coefficient,inertia.roller) or of the "
            "recording's friction law (with --law polach: polach.static_friction, "
            "polach.limit_ratio, polach.friction_decay, polach.k_adhesion, polach.k_slip; with "
            "--law modified-fastsim: fastsim.static_friction, fastsim.limit_ratio, "
            "fastsim.friction_decay, fastsim.k0, fastsim.alpha_inf, fastsim.beta; fastsim and "
            "fastrip: the first three); --list-keys lists them.",
        ),
    ] = None,
    channels: ChannelsOption = None,
    rig_file: RigOption = None,
    friction: Annotated[
        Friction,
        typer.Option(
            help="Polach set the recording's friction law starts from (with a law of the "
            "FASTSIM family its mu0, A, B; modified-fastsim takes k0, alpha_inf, beta of the "
            "Eurosprinter set, as the twin does)."
        ),
    ] = Friction.dry,
    law: Annotated[
        list[CreepLaw] | None,
        typer.Option(
            "--law",
            help="Creep law of the twin the fit replays: polach (Polach 2005; polach.* keys; "
            "the default), modified-fastsim (fastsim.* keys incl. k0, alpha_inf, beta), "
            "fastsim or fastrip (fastsim.static_friction, limit_ratio, friction_decay). The "
            "result names the law and its fitted parameters. With --compare-laws, repeat it "
            "to name the laws compared.",
            show_default=False,
            metavar="<polach|fastsim|modified-fastsim|fastrip>",
        ),
    ] = None,
    torque_noise: Annotated[
        float | None,
        typer.Option(
            "--torque-noise",
            help="Noise of the torque sensor [N.m] for the first weights; default 1/3000 of "
            "sensors.torque_sensor_range of the rig (1 N.m on the bundled rig).",
        ),
    ] = None,
    torque_delay_ms: Annotated[
        float,
        typer.Option(
            "--torque-delay-ms",
            min=-100.0,
            max=100.0,
            help="The torque channel's delay against the encoders [ms] (> 0: the torque is "
            "late; a filter's group delay in its amplifier or DAQ module), removed before the "
            "fit. A calibration whose torque residual a delay explains names the value to give "
            "here.",
        ),
    ] = 0.0,
    max_iterations: Annotated[
        int,
        typer.Option(min=1, help="Most Levenberg-Marquardt iterations per stage [-]."),
    ] = 20,
    roller_drive: Annotated[
        CalibrationDrive,
        typer.Option(
            "--roller-drive",
            help="Roller drive of the twin the fit replays: induction (Thevenin torque with "
            "its first-order lag; induction_motor.response_lag_clp is its free key), "
            "induction_dq (the dq machine under open-loop V/f; the roller_drive_vf.* settings "
            "are free keys too), or compare (both fitted, the one the recording supports "
            "chosen by evidence; as --compare-drives).",
        ),
    ] = CalibrationDrive.induction,
    compare_drives: Annotated[
        bool,
        typer.Option(
            "--compare-drives",
            help="Fit each roller-drive model (the same free keys plus each model's own drive "
            "keys) and report which one the recording supports: residual whiteness, AIC/BIC, "
            "the ringing after each release; writes calibration-compare.json, and the "
            "winner's calibration files only when it is adequate.",
        ),
    ] = False,
    compare_laws: Annotated[
        bool,
        typer.Option(
            "--compare-laws",
            help="Fit each creep law named by --law (default polach and modified-fastsim) and "
            "report which one the recording supports and by how much (residual whiteness, "
            "BIC difference [-]); mu0, A, B are the same keys in every law (polach.* or "
            "fastsim.* alike), each law frees its own shape keys (those named in --free, else "
            "all not starting on a bound). Writes calibration-compare-laws.json, and the "
            "winner's calibration files only when it is adequate. Not with --compare-drives: "
            "compare the drives under one law, then the laws under the winning drive.",
        ),
    ] = False,
    out: OutOption = DEFAULT_OUT,
    lenient: LenientOption = False,
    list_keys: Annotated[
        bool,
        typer.Option(
            "--list-keys",
            help="List the keys --free accepts (with --roller-drive induction_dq the V/f "
            "settings too, with --law its law's keys, with --compare-laws every compared "
            "law's) and exit.",
        ),
    ] = False,
    figure_format: FigureFormatOption = FigureFormat.png,
    quiet: QuietOption = False,
) -> None:
    """Fit the twin's parameters to a recorded test: values with standard errors [SI].

    Replays the recorded wheel-torque request through the twin (fast solver, at the
    recording's load and roller speed) and fits the free parameters so that the simulated
    roller-shaft torque T56 and both encoder speeds match the recording; the weights come from
    the sensor noise, the encoders' quantisation is modelled, the torque's motor and order lines
    are fitted. Writes calibration.json (each value and standard error [SI], correlations,
    residuals before and after, whiteness, warnings for what the recording cannot identify),
    calibrated-rig.toml (a complete rig file for --rig), calibration-fit.nc (recorded against
    simulated channels) and its figure calibration-fit.png; all of them or none. A fit that
    does not converge or ends worse than it started is marked "valid": false and gets no
    calibrated-rig.toml; residuals with structure mark every standard error "conditional on
    the model".
    """
    compare = compare_drives or roller_drive is CalibrationDrive.compare
    roller = "induction_dq" if roller_drive is CalibrationDrive.induction_dq else "induction"
    laws = _laws(law, compare_laws, compare)
    if list_keys:
        from rollerrig.calibrate import free_parameter_catalogue

        catalogue = (
            k
            for lw in laws
            for k in free_parameter_catalogue("induction_dq" if compare else roller, lw)
        )
        for key in dict.fromkeys(catalogue):
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
    from rollerrig.calibrate.problem import check_law_keys, is_law_key

    if compare_laws:
        from rollerrig.calibrate.lawcompare import law_free_keys

        law_free_keys(keys, laws, friction.value)  # a key of none of the laws: its own message
        catalogue = free_parameter_catalogue(roller, laws[0])
        unknown = [k for k in keys if k not in catalogue and not is_law_key(k)]
    else:
        check_law_keys(keys, laws[0])  # a key of another creep law: its own message
        catalogue = free_parameter_catalogue("induction_dq" if compare else roller, laws[0])
        unknown = [k for k in keys if k not in catalogue]
    if unknown:  # before reading anything: one line naming what is accepted
        from rollerrig.calibrate import CalibrationError

        vf = [k for k in unknown if k in free_parameter_catalogue("induction_dq", laws[0])]
        if vf:
            raise CalibrationError(
                f"--free: {vf} are settings of the V/f controller, which only the dq roller "
                f"drive reads; add --roller-drive induction_dq (or --compare-drives), or leave "
                "them out"
            )
        from rollerrig._validation import did_you_mean

        each = "; ".join(f"{k!r}{did_you_mean(k, catalogue, n=3)}" for k in unknown)
        raise CalibrationError(
            f"--free: not a key rollerrig calibrate fits: {each} (--list-keys lists all of them)"
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
        torque_delay_ms=torque_delay_ms,
        max_iterations=max_iterations,
        lenient=lenient,
        roller_drive="compare" if compare else roller,
        law=laws if compare_laws else laws[0],
        compare_laws=compare_laws,
    ) as stage:
        rec = read(recording, channels, lenient)
        _say_compile_stage(dq=compare or roller == "induction_dq")
        comparison = None
        with _progress() as bar:
            task = bar.add_task("calibrating", total=3 * max_iterations, info="replaying")

            def progress(done: int, total: int, text: str) -> None:
                bar.update(task, completed=done, total=total, info=text)

            models: list[str] = []  # compared models in the order their fits report

            def each(model: str, count: int, done: int, total: int, text: str) -> None:
                """One model's progress as its share of all: each fit counts from 0, and the
                bar had run backwards from one model to the next (40 % to 0 %)."""
                if model not in models:
                    models.append(model)
                k = models.index(model)
                share = done / total if total else 0.0
                progress(round(1000 * (k + share) / count), 1000, f"{model}: {text}")

            if compare_laws:
                from rollerrig.calibrate.lawcompare import compare_laws as run_law_comparison

                comparison = run_law_comparison(
                    rec,
                    keys,
                    laws=laws,
                    rig=rig,
                    friction=friction.value,
                    max_iterations=max_iterations,
                    progress=lambda lw, i, n, text: each(lw, len(laws), i, n, text),
                    torque_noise=torque_noise,
                    torque_delay=torque_delay_ms * 1e-3,
                    roller_drive=roller,
                )
                result = comparison.winning_calibration
            elif compare:
                from rollerrig.calibrate.compare import ROLLER_DRIVES
                from rollerrig.calibrate.compare import compare_drives as run_comparison

                comparison = run_comparison(
                    rec,
                    keys,
                    rig=rig,
                    friction=friction.value,
                    max_iterations=max_iterations,
                    progress=lambda d, i, n, text: each(d, len(ROLLER_DRIVES), i, n, text),
                    torque_noise=torque_noise,
                    torque_delay=torque_delay_ms * 1e-3,
                    law=laws[0],
                )
                result = comparison.winning_calibration
            else:
                result = run_calibration(
                    rec,
                    keys,
                    rig=rig,
                    friction=friction.value,
                    max_iterations=max_iterations,
                    progress=progress,
                    torque_noise=torque_noise,
                    torque_delay=torque_delay_ms * 1e-3,
                    roller_drive=roller,
                    law=laws[0],
                )
            bar.update(task, completed=bar.tasks[0].total, info="done")
        if comparison is not None:
            from rollerrig.calibrate.compare import write_comparison

            write_comparison(comparison, stage.dir)
        else:
            write_calibration(result, stage.dir)
        if comparison is None or comparison.adequate:
            from rollerrig.output import save_figure
            from rollerrig.report.calibration import calibration_figure

            title = (
                f"Calibration to {recording.name} ({result.roller_drive} roller drive, "
                f"{result.law} creep law)"
            )
            save_figure(
                calibration_figure(result.fit_dataset(), title=title),
                stage.dir / figure_file(FIT_FIGURE_NAME.removesuffix(".png"), figure_format),
            )
    print_recording_notes(rec)
    from rollerrig.calibrate import CALIBRATION_JSON_NAME

    kept = f"{out / CALIBRATION_JSON_NAME}, 'notes'"  # where a long note is kept whole
    if comparison is not None:
        print_comparison(comparison)
        if comparison.adequate:
            print_calibration(result, kept)
    else:
        print_calibration(result, kept)
    print_written(stage.written)


def _laws(law: list[CreepLaw] | None, compare_laws: bool, compare_drives: bool) -> list[str]:
    """The creep law(s) of the run: one without --compare-laws (default polach), at least two
    with it (default :data:`rollerrig.calibrate.lawcompare.DEFAULT_LAWS`)."""
    named = list(dict.fromkeys(lw.value for lw in law or ()))
    if compare_laws and compare_drives:
        raise UserError(
            "--compare-laws and --compare-drives (or --roller-drive compare) together would fit "
            "every drive with every law; run one comparison at a time: compare the drives under "
            "one --law, then the laws under the winning --roller-drive"
        )
    if compare_laws:
        if len(named) == 1:
            raise UserError(
                f"--compare-laws needs at least two creep laws: --law {named[0]} names one; "
                "repeat --law (e.g. --law polach --law modified-fastsim) or leave it out for "
                "polach against modified-fastsim"
            )
        from rollerrig.calibrate.lawcompare import DEFAULT_LAWS

        return named or list(DEFAULT_LAWS)
    if len(named) > 1:
        raise UserError(
            f"--law names one creep law, got {', '.join(named)}; to fit several and compare "
            "them, add --compare-laws"
        )
    return named or ["polach"]


def _number(value: float | None, digits: int = 6) -> str:
    return "–" if value is None else f"{value:.{digits}g}"


def print_calibration(result, full_in: str | None = None) -> None:
    """The fitted values, the channels' residuals, the warnings and notes of a calibration;
    ``full_in`` (the written calibration.json, its 'notes') is where a long note is kept whole
    (the console cuts it, :func:`rollerrig.cli._console.note`)."""
    if not result.valid:
        print_warning(
            "NOT A VALID CALIBRATION: "
            + "; ".join(result.invalid_reasons)
            + '. calibration.json says "valid": false; no calibrated-rig.toml was written and '
            "rollerrig analyze --calibration refuses it."
        )
    title = (
        f"Calibrated parameters, {result.roller_drive} roller drive, {result.law} creep law "
        "(one standard error: the residuals' (Newey-West) and the sensors' stated classes"
        + (", CONDITIONAL ON THE MODEL)" if result.conditional else ")")
    )
    table = Table(title=title)
    for col in (
        "parameter", "value", "± standard error", "residuals / sensors", "unit", "start",
        "rel. error",
    ):  # fmt: skip
        # folded, not cut: the dotted keys (what --free takes) had been shown as
        # "stiffness.roller_s…" at any terminal width
        whole = col == "parameter"
        table.add_column(
            col,
            justify="left" if col in ("parameter", "unit") else "right",
            overflow="fold",
            no_wrap=whole,
            min_width=(
                max(map(len, (*result.parameters, *result.nuisance)))
                if whole
                else len("not identified")
                if col == "value"
                else None
            ),
        )
    rows = [*result.parameters.values(), *result.nuisance.values()]
    numbered = {c["expression"]: n for n, c in enumerate(result.combinations, start=1)}
    for p in rows:
        rel = p.relative_standard_error
        se = _number(p.standard_error, 3)
        combination = result.combination_of(p.key)
        if combination is not None:  # its own error is the shadow of the combination's
            se, rel = f"– (combination {numbered[combination['expression']]})", None
        parts = "–"  # the error's two parts: the residuals' and the sensors' stated classes
        if combination is None and p.standard_error_statistical is not None:
            parts = (
                f"{_number(p.standard_error_statistical, 2)} / "
                f"{_number(p.standard_error_systematic, 2)}"
            )
        table.add_row(
            p.key,
            _number(p.value) if p.identified else "not identified",
            f"{se} (conditional on the model)" if p.conditional_on_model else se,
            parts,
            p.unit,
            _number(p.initial),
            "–" if rel is None else f"{100 * rel:.3g} %",
        )
    console.print(table)
    if result.combinations:
        print_combinations(result.combinations)
    fit = Table(
        title="Residuals of the fitted channels (RMS over the fitted samples, the torque's motor "
        "and order lines removed: as calibration-fit.png plots them)"
    )
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
        if not text.startswith("NOT A VALID CALIBRATION"):  # said first
            print_warning(text)
    for text in result.notes:
        note(text, full_in)


def print_combinations(combinations) -> None:
    """The combinations of strongly correlated keys that a calibration determines
    (:func:`rollerrig.calibrate.diagnostics.identified_combinations`), one row each."""
    table = Table(
        title="Correlated keys: the combination the recording determines (one standard error)"
    )
    for col in ("", "combination", "value", "± standard error", "unit", "rel. error",
                "hardly determined (rel. error)"):  # fmt: skip
        table.add_column(col, justify="right" if col in ("value", "± standard error",
                         "rel. error") else "left", overflow="fold")  # fmt: skip
    for n, c in enumerate(combinations, start=1):
        loose = c["undetermined"]
        table.add_row(
            str(n),
            c["expression"],
            _number(c["value"]),
            _number(c["standard_error"], 3),
            c["unit"],
            f"{100 * c['relative_standard_error']:.3g} %",
            f"{loose['expression']} ({100 * loose['relative_standard_error']:.3g} %)",
        )
    console.print(table)


def print_comparison(comparison) -> None:
    """The evidence of :func:`rollerrig.calibrate.compare.compare_drives` or
    :func:`rollerrig.calibrate.lawcompare.compare_laws`, one row per model."""
    table = Table(title=f"{comparison.MODEL.capitalize()}s fitted to the recording")
    cols = (
        "model",
        "adequate",
        "valid",
        "BIC",
        "ΔBIC",
        "torque RMS [N.m]",
        "torque r1",
        "torque LB p",
        "structured",
    )
    for col in cols:
        table.add_column(col, justify="left" if col in ("model", "structured") else "right")
    best = min(e["information_criteria"]["BIC"] for e in comparison.evidence.values())
    for drive, ev in comparison.evidence.items():
        torque = ev["channels"].get("torque", {})
        bic = ev["information_criteria"]["BIC"]
        table.add_row(
            drive + (" (winner)" if drive == comparison.winner else ""),
            "yes" if ev["adequate"] else "no",
            "yes" if ev["valid"] else "no",
            f"{bic:.7g}",
            f"{bic - best:.4g}",
            _number(torque.get("rms_after"), 4),
            _number(torque.get("lag1_autocorrelation"), 2),
            _number(torque.get("ljung_box_p"), 2),
            ", ".join(ev["structured_channels"]) or "–",
        )
    console.print(table)
    if comparison.ringing:
        ring = Table(title="Ringing after each release: first minimum of T56 after it, frequency")
        ring.add_column("release [s]", justify="right")
        ring.add_column("source")
        ring.add_column("first minimum after [s]", justify="right")
        ring.add_column("ringing [Hz]", justify="right")
        for entry in comparison.ringing:
            for name in ("measured", *comparison.evidence):
                item = entry.get(name) or {}
                ring.add_row(
                    f"{entry['release [s]']:.3f}",
                    name,
                    _number(item.get("first_minimum_after_release [s]"), 4),
                    _number(item.get("ringing_frequency [Hz]"), 4),
                )
        console.print(ring)
    for key, item in (comparison.discrepancy.get("keys") or {}).items():
        note(
            f"model discrepancy of {key}: half-width {item['half_width']:.3g} {item['unit']} "
            f"(rectangular, u = {item['standard_uncertainty']:.3g}) between the adequate models"
        )
    (note if comparison.adequate else print_warning)(comparison.verdict())
    # Why a model's fit is not valid: the table says only "no" (a fit that did not converge
    # within the iterations had been judged invalid with its reason in the JSON alone).
    slow = False
    for model, ev in comparison.evidence.items():
        if ev["valid"]:
            continue
        reasons = [
            (w.partition(": ")[2] or w).split(": no calibrated rig")[0]
            for w in comparison.calibrations[model].warnings
            if w.startswith("NOT A VALID CALIBRATION")
        ]
        slow = slow or any("did not converge" in r for r in reasons)
        print_warning(f"{model}: not a valid fit: {'; '.join(reasons) or 'see the JSON'}")
    if slow:
        note("a fit that did not converge may converge with more iterations (--max-iterations)")
    if not comparison.adequate:
        return  # the losers' advice would name the winner, itself not adequate
    for model in getattr(comparison, "losers", ()):
        advice = comparison.calibrations[model].suggestion
        if advice:
            note(advice)
