"""Figure and files of a roller-to-track transfer (:mod:`rollerrig.analysis.transfer`)."""

from __future__ import annotations

import os
import textwrap
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only
import matplotlib.pyplot as plt
import numpy as np

from rollerrig.analysis.transfer import TransferResult, kalker_creepage

__all__ = ["transfer_figure", "write_transfer"]

_SCATTER = 600


def transfer_figure(result: TransferResult):
    """Measured points, the fitted curve on the roller and the predicted curve on the rail,
    each with its 95 % band (left); the transfer factor F_track/F_roller with its band (right).

    Parameters
    ----------
    result : TransferResult

    Returns
    -------
    matplotlib.figure.Figure
    """
    xi = 100 * result.creepage
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.8), gridspec_kw={"width_ratios": [3, 2]})
    m = result.measured
    if m is not None:
        step = max(1, int(np.ceil(m.creep.size / _SCATTER)))
        ax.plot(
            100 * kalker_creepage(m.creep[::step]),
            m.coa[::step],
            ".",
            ms=2.5,
            color="0.6",
            label="measured on the roller (points fitted)",
        )
    r_mm = result.geometry.roller_radius_x * 1e3
    on_points = result.band.get("construction") == "measured points"
    ax.fill_between(xi, result.roller_low, result.roller_high, color="tab:blue", alpha=0.25, lw=0)
    ax.plot(
        xi,
        result.roller,
        color="tab:blue",
        label=(
            f"measured level on the roller r = {r_mm:.0f} mm ({result.law} fit + its residuals)"
            if on_points
            else f"{result.law} fit, roller r = {r_mm:.0f} mm"
        ),
    )
    ax.fill_between(xi, result.track_low, result.track_high, color="tab:red", alpha=0.25, lw=0)
    ax.plot(
        xi,
        result.track,
        color="tab:red",
        label="predicted on the rail (95 % band)"
        + (": measured level × the law's factor" if on_points else ""),
    )
    for name, colour in (("roller", "tab:blue"), ("track", "tab:red")):
        pk = result.peaks[name]
        if pk.get("inside_measured_range", True):
            ax.plot(100 * pk["creepage [-]"], pk["coa [-]"], "o", color=colour, ms=4)
        else:  # no peak in the range: the curve's largest CoA, an open marker
            m = pk.get("curve_maximum", pk)
            ax.plot(100 * m["creepage [-]"], m["coa [-]"], "o", mfc="none", color=colour, ms=5)
    ax.set_xlabel("creepage ξ (Kalker: referred to the mean rolling speed) [%]")
    ax.set_ylabel("CoA F/N [-]")
    # the transfer's one speed, as the console and the files state it (V = ... km/h (what))
    speed, what = result.speed_text().split(" (", 1)
    ax.set_title(
        f"Roller to rail: N = {result.normal_load / 1e3:.3g} kN, {speed}\n"
        f"(V on roller and rail: {what}",
        fontsize=11,
    )
    ax.set_xlim(0, xi[-1])
    ax.set_ylim(0, None)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    bx.fill_between(xi, result.factor_low, result.factor_high, color="tab:purple", alpha=0.25, lw=0)
    bx.plot(xi, result.factor, color="tab:purple", label="F_rail / F_roller (95 % band)")
    bx.axhline(
        result.stiffness_ratio,
        color="k",
        ls="--",
        lw=1,
        label=f"ratio of G·a·b·C11: {result.stiffness_ratio:.3f}",
    )
    bx.axhline(1.0, color="0.5", ls=":", lw=1, label="1: saturation at μN on both")
    bx.set_xlabel("creepage ξ [%]")
    bx.set_ylabel("transfer factor at equal creepage [-]")
    bx.set_title("What the geometry changes")
    bx.set_xlim(0, xi[-1])
    bx.grid(True, alpha=0.3)
    bx.legend(fontsize=8, loc="center right")  # the curve falls at the left: free there
    inputs = (
        "the measured points' noise, the factor over the parameters that fit them about as "
        "well as the best (Beale's region)"
        if on_points
        else "Monte Carlo of the fit's covariance"
    )
    why = result.band.get("construction_why")
    footnote = (
        "Surface parameters (slope reduction, μ0, A, B) carried over from the roller as "
        "measured: an assumption. "
        + (f"Band on the measured points, since {why}: " if on_points and why else "Band: ")
        + inputs
        + ", the geometry's stated uncertainty"
        + (
            ", the law's error bound in the factor (against Kalker's exact theory)"
            if any("law's error" in str(i.get("name", "")) for i in result.band.get("inputs", []))
            else ""
        )
        + (
            " and the measured CoA's systematic error."
            if any("systematic" in str(i.get("name", "")) for i in result.band.get("inputs", []))
            else " (not the measured CoA's systematic error)."
        )
    )
    # wrapped to the figure's width and set on the bottom edge: the figure is saved at its own
    # size (rollerrig.output.figures.crop_to_drawing), so a longer line would be cut
    fig.text(
        0.01, 0.005, "\n".join(textwrap.wrap(footnote, 190)), fontsize=7, color="0.3",
        va="bottom",
    )  # fmt: skip
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    return fig


def write_transfer(
    result: TransferResult, out: str | os.PathLike, stem: str, figure_format: str = "png"
) -> list[Path]:
    """Write ``<stem>-transfer.csv`` (the curves, units on every column, metadata sidecar),
    ``<stem>-transfer.json`` (the summary) and ``<stem>-transfer.png`` (the figure; ``.svg`` or
    ``.pdf`` for that ``figure_format``), each with the run's provenance, atomically, through
    :mod:`rollerrig.output`.

    Returns
    -------
    list of Path
        The written files.
    """
    from rollerrig.output import save_figure, write_json, write_table

    out = Path(out)
    summary = result.summary()
    paths = [
        write_table(
            out / f"{stem}-transfer.csv",
            result.columns(),
            attrs={
                "law": result.law,
                "normal_load [N]": result.normal_load,
                "rolling_speed": result.speed_text(),
                "assumptions": result.assumptions,
            },
            overwrite=True,
        ),
        write_json(out / f"{stem}-transfer.json", summary),
    ]
    fig = transfer_figure(result)
    try:
        paths.append(save_figure(fig, out / f"{stem}-transfer.{figure_format}"))
    finally:
        plt.close(fig)
    return paths


def transfer_section(rep, result: TransferResult) -> None:
    """The report's "On track" section (:class:`rollerrig.report.html.HtmlReport`): the curve
    measured on the roller predicted on the rail, its band, the assumptions and the figure."""
    pr, pt = result.peaks["roller"], result.peaks["track"]
    rep.heading("On track: the measured curve predicted on the rail")
    rep.paragraph(
        f"Law {result.law}, fitted on the roller and evaluated on the rail at the same normal "
        f"load ({result.normal_load / 1e3:.3g} kN) and rolling speed "
        f"{result.speed_text()}; creepage ξ referred to the mean rolling "
        "speed (Kalker), converted from the rig's creep (Kayaalp eq. 4.21)."
    )
    lo, hi = result.elastic["ratio_track_over_roller"]["creep_stiffness_95"]
    inside = pr.get("inside_measured_range", True) and pt.get("inside_measured_range", True)
    largest = [result.curve_maximum_text(name) for name in ("roller", "track")]
    maxima = (
        [["curve's largest CoA at ξ", *(m or "–" for m in largest), "–"]]
        if any(m is not None for m in largest)
        else []
    )
    rep.table(
        ["quantity", "roller", "rail", "rail / roller"],
        [
            [
                "peak CoA (95 %)",
                result.peak_coa_text("roller"),
                result.peak_coa_text("track"),
                f"{pt['coa [-]'] / pr['coa [-]']:.3f}" if inside else "–",
            ],
            [
                "peak creepage ξ [%] (95 %)",
                result.peak_creepage_text("roller"),
                result.peak_creepage_text("track"),
                f"{pt['creepage [-]'] / pr['creepage [-]']:.3f}" if inside else "–",
            ],
            *maxima,
            [
                "creep stiffness G·a·b·C11 (95 %)",
                "",
                "",
                f"{result.stiffness_ratio:.3f} ({lo:.3f}–{hi:.3f})",
            ],
        ],
    )
    rep.paragraph(result.factor_text(), note=True)
    for line in result.assumptions:
        rep.paragraph(line, note=True)
    fig = transfer_figure(result)
    try:
        rep.figure(fig, "The curve measured on the roller and predicted on the rail, with the "
                   "95 % band; right: the transfer factor at equal creepage.")  # fmt: skip
    finally:
        plt.close(fig)
