"""Report of an analysed adhesion test: the results files (JSON summary, NetCDF channels) and
the self-contained HTML report (:func:`write_analysis`).

Its parts: the figures (:mod:`~rollerrig.report.analysis_figures`), the report's sections and
their tables (:mod:`~rollerrig.report.analysis_sections`), the channels as the results file's
columns (:mod:`~rollerrig.report.analysis_channels`).
"""

from __future__ import annotations

import os
from pathlib import Path

from rollerrig._display import key_words
from rollerrig.analysis.adhesion import TestAnalysis
from rollerrig.output import json_text, provenance, write_json, write_table
from rollerrig.report.adhesion import adhesion_figure
from rollerrig.report.analysis_channels import (
    analysis_columns,
    channel_attributes,
    uncertainty_columns,
)
from rollerrig.report.analysis_figures import (
    coa_uncertainty_figure,
    overview_figure,
    rig_versus_corrected_figure,
)
from rollerrig.report.analysis_sections import (
    _filter_study_section,
    _fit_honesty_section,
    _fit_rows,
    _recording_section,
    _spectrum_section,
    _uncertainty_section,
    cycle_number,
    phase_words,
)
from rollerrig.report.html import HtmlReport, relative_paths

__all__ = [
    "analysis_columns",
    "channel_attributes",
    "coa_uncertainty_figure",
    "overview_figure",
    "rig_versus_corrected_figure",
    "uncertainty_columns",
    "write_analysis",
]


def write_analysis(
    result: TestAnalysis,
    out: str | os.PathLike,
    stem: str,
    *,
    source: str = "",
    truth=None,
    extra_provenance: dict | None = None,
    extra_sections=None,
    report_folder: str | os.PathLike | None = None,
) -> list[Path]:
    """Write the results (JSON summary, NetCDF channels) and the self-contained HTML report.

    Returns the written paths: ``<stem>-analysis.json`` (the summary, with its provenance),
    ``<stem>-analysis.nc`` (every analysed channel with its unit and long name, CF-1.10,
    written by :func:`rollerrig.output.write_table`; see :func:`analysis_columns`) and
    ``<stem>-report.html`` (self-contained: figures embedded as PNG data URIs). Each file
    replaces one of the same name.

    The report names files relative to ``report_folder`` (default ``out``; the folder the
    report will be read from, when ``out`` is a staging folder moved there afterwards): no
    absolute path, no home directory, in a report that is shared.
    """
    from rollerrig.output.provenance import current_run, run_context

    if current_run() is None and source and Path(source).is_file():
        # Called from Python: the recording named as the source is this run's input (the CLI
        # opens its own context with every input of the command).
        with run_context(inputs={"recording": source}):
            return write_analysis(
                result,
                out,
                stem,
                source=source,
                truth=truth,
                extra_provenance=extra_provenance,
                extra_sections=extra_sections,
                report_folder=report_folder,
            )
    out = Path(out)
    record = provenance(source=source, **(extra_provenance or {}))
    if record["rig"] is None and result.rig_sha256:
        record["rig"] = {"name": result.rig_name, "sha256": result.rig_sha256}
    summary = {"provenance": record, **result.summary()}
    paths = [write_json(out / f"{stem}-analysis.json", summary)]

    facts = summary["recording"]
    rec = result.recording
    name = source or str(rec.metadata.get("source", ""))
    # CF-1.10 NetCDF: units and long_name on every variable; the global attributes are strings
    # (lists as JSON, with the same NaN policy as the JSON summary).
    attrs = {
        "title": f"rollerrig analysis of the adhesion test {name}".strip(),
        "source": source,
        "recording_notes": json_text(facts["notes"]),
        "interpolated": json_text(facts["interpolated"]),
        "gaps": json_text(facts["gaps"]),
        "injected_lines": json_text(facts["injected_lines"]),
        "analysis_notes": json_text(result.notes),
    }
    paths.append(
        write_table(
            out / f"{stem}-analysis.nc",
            {**analysis_columns(rec), **uncertainty_columns(result)},
            time=rec.time,
            provenance=record,
            attrs=attrs,
            overwrite=True,  # like the JSON summary and the report beside it
        )
    )

    report_folder = out if report_folder is None else Path(report_folder)
    rep = HtmlReport(f"Adhesion test analysis: {stem}")
    shown = relative_paths(source, report_folder) or stem
    rep.paragraph(
        f"Recording {shown}: {rec.duration:.2f} s at {rec.sample_rate:.4g} Hz, "
        f"channels {', '.join(sorted(rec.channels))}. Rig: {result.rig_name}."
    )
    _recording_section(rep, result)
    if result.notes:
        for note in result.notes:
            rep.paragraph(note, note=True)
    rep.heading("Phases of the test")
    rep.table(
        ["phase", "cycle", "start [s]", "end [s]"],
        [[phase_words(ph.name), cycle_number(ph.cycle), ph.start, ph.end] for ph in result.phases],
    )
    rep.figure(overview_figure(result), "Torque, speeds and creep; phases shaded.")

    rep.heading("Adhesion: the rig's CoA and the CoA corrected for the rig's dynamics")
    rep.paragraph(
        "The torque sensor sits on the roller shaft, so the rig's CoA = T56/(r_r S) misses the "
        "torque that accelerates the roller and its bearing loss. The corrected CoA adds them: "
        "F_x r_r = T56 + J5·α5 + R05, with α5 the Savitzky–Golay derivative of the roller speed."
    )
    rep.figure(rig_versus_corrected_figure(result, truth), "Rig versus corrected CoA.")
    if result.coa_uncertainty is not None:
        _uncertainty_section(rep, result)
    truth_parameters = result.true_parameters
    header = ["parameter", "fit to corrected CoA", "fit to rig CoA"]
    if truth_parameters is not None:
        header.append("true (twin)")
    rep.table(header, _fit_rows(result, truth_parameters))
    _fit_honesty_section(rep, result)
    if result.truth_errors:
        rep.table(
            ["error against the true contact CoA", "value"],
            [[key_words(k), v] for k, v in result.truth_errors.items()],
        )
    if result.fit is not None:
        rep.figure(
            adhesion_figure(
                rec["creep_smoothed"],
                rec["coa_corrected"],
                result.branches,
                result.fit,
                title="Corrected CoA: ascending (solid) and descending (dashed) branches, fit",
            ),
            "Creep–CoA curve of the corrected CoA with the Polach fit and its residuals.",
        )
    rep.paragraph(
        "The descending branch follows the creep's fast fall after a release (tens of ms); "
        f"a smoothing window of {result.smoothing_window / rec.sample_rate:.2f} s smears it, so "
        "part of the loop between the branches is the filter's, not the contact's (the seed, "
        "§5, attributes the gap of its return curves to filtering as well).",
        note=True,
    )
    rows = []
    for br, h in zip(result.branches, result.hysteresis, strict=True):
        if h is not None:
            rows.append(
                [
                    cycle_number(br.cycle),
                    h.abs_area,
                    h.max_difference,
                    100 * h.creep_at_max_difference,
                ]
            )
    if rows:
        rep.heading("Hysteresis between ascending and descending branches (rig CoA)")
        rep.table(["cycle", "|area|", "largest ΔCoA", "at creep [%]"], rows)

    if result.spectrum is not None:
        _spectrum_section(rep, result)
    if result.study:
        _filter_study_section(rep, result)
    if extra_sections is not None:
        extra_sections(rep)
    rep.provenance(summary["provenance"], relative_to=report_folder)
    paths.append(rep.write(out / f"{stem}-report.html"))
    return paths
