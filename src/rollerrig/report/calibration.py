"""Figure of a calibration: the recording against the twin before and after the fit."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from rollerrig.report.lines import envelope
from rollerrig.report.twin import MEASURED_STYLE

__all__ = ["calibration_figure", "calibration_section", "torque_residual"]

_ROWS = (
    ("torque", "roller-shaft torque T56 [N·m]"),
    ("roller_speed", "roller speed [rad/s]"),
    ("wheel_speed", "wheel speed [rad/s]"),
)


def _zoom_window(t: np.ndarray, torque: np.ndarray, width: float = 3.0) -> tuple[float, float]:
    """A ``width`` [s] window from just before the steepest fall of the recorded torque (a
    release: where a wrong stiffness or inertia shows as a phase slip of the ringing)."""
    if t.size < 3:
        return float(t[0]), float(t[-1])
    k = int(np.argmin(np.diff(torque)))
    start = max(float(t[0]), float(t[k]) - 0.2 * width)
    return start, min(float(t[-1]), start + width)


def calibration_figure(fit, title: str | None = None):
    """Recorded channels against the twin with the starting and the calibrated parameters.

    Parameters
    ----------
    fit : xarray.Dataset
        ``calibration-fit.nc`` (:meth:`rollerrig.calibrate.Calibration.fit_dataset`): for each
        fitted channel ``<name>_measured``, ``<name>_start`` and ``<name>_fitted`` on ``time``.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
        Left: the whole test; right: 3 s around the steepest torque release; bottom: the
        torque residual before and after as the fit sees it (:func:`torque_residual`: the
        lines removed, its RMS the one ``rollerrig calibrate`` prints), its RMS with the lines
        left in beside it.
    """
    t = np.asarray(fit["time"].values, dtype=float)
    rows = [(name, label) for name, label in _ROWS if f"{name}_measured" in fit]
    fig, axes = plt.subplots(
        len(rows) + 1, 2, figsize=(12, 2.6 * (len(rows) + 1)), sharex="col", squeeze=False
    )
    zoom = _zoom_window(t, np.asarray(fit["torque_measured"].values, dtype=float))
    inside = (t >= zoom[0]) & (t <= zoom[1])
    for i, (name, label) in enumerate(rows):
        measured = np.asarray(fit[f"{name}_measured"].values, dtype=float)
        start = np.asarray(fit[f"{name}_start"].values, dtype=float)
        fitted = np.asarray(fit[f"{name}_fitted"].values, dtype=float)
        for j, keep in enumerate((slice(None), inside)):
            ax = axes[i, j]
            ax.plot(*envelope(t[keep], measured[keep]), **MEASURED_STYLE, label="recorded")
            ax.plot(t[keep], start[keep], color="tab:orange", lw=1.0, ls="--", label="twin, start")
            ax.plot(t[keep], fitted[keep], color="tab:blue", lw=1.2, label="twin, calibrated")
            ax.grid(alpha=0.3)
            if j == 0:
                ax.set_ylabel(label)
        if i == 0:
            axes[i, 0].legend(loc="upper right", fontsize=8)
            axes[i, 0].set_title("whole test")
            axes[i, 1].set_title(f"{zoom[0]:.1f}-{zoom[1]:.1f} s: the steepest release")
    residuals = {which: torque_residual(fit, which) for which in ("start", "fitted")}
    lines = "torque_lines_fitted" in fit
    for j, keep in enumerate((slice(None), inside)):
        ax = axes[-1, j]
        for which, colour in (("start", "tab:orange"), ("fitted", "tab:blue")):
            residual, rms, raw = residuals[which]
            what = "start" if which == "start" else "calibrated"
            text = f"RMS {rms:.3g} N·m; {raw:.3g} with the lines" if lines else f"RMS {rms:.3g} N·m"
            ax.plot(t[keep], residual[keep], color=colour, lw=0.7,
                    label=f"recorded − twin, {what} ({text})")  # fmt: skip
        ax.grid(alpha=0.3)
        ax.set_xlabel("time [s]")
        if j == 0:
            ax.set_ylabel("T56 residual, lines removed [N·m]" if lines else "T56 residual [N·m]")
            ax.legend(loc="upper right", fontsize=8)
    fig.text(
        0.5,
        0.005,
        (
            "Residual as the fit sees it: the motor and order lines fitted to each residual "
            "removed, RMS over the fitted samples (the console's and calibration.json's "
            "rms_before/rms_after)."
            if lines
            else "Residual with the motor and order lines left in (a calibration-fit.nc "
            "without them): larger than the console's RMS, which removes the lines."
        ),
        ha="center",
        va="bottom",
        fontsize=8,
        style="italic",
    )
    fig.suptitle(title or "Calibration: recording against the twin, before and after the fit")
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    return fig


def torque_residual(fit, which: str) -> tuple[np.ndarray, float, float]:
    """The torque residual of ``calibration-fit.nc`` as the fit sees it, and its RMS.

    Parameters
    ----------
    fit : xarray.Dataset
        ``calibration-fit.nc`` (:meth:`rollerrig.calibrate.Calibration.fit_dataset`).
    which : {"start", "fitted"}
        The twin with the starting or the calibrated parameters.

    Returns
    -------
    residual : ndarray
        T56 recorded − twin − the motor and order lines fitted to that difference [N·m]
        (``torque_lines_<which>``; without it, in a file written before they were stored, the
        raw difference).
    rms : float
        Its root mean square over the fitted samples (``torque_in_fit``) [N·m]: the
        ``rms_before`` / ``rms_after`` of ``calibration.json``
        (:data:`rollerrig.calibrate.calibration.RESIDUAL_RMS_MEANING`).
    rms_with_lines : float
        The RMS of the raw difference, the lines left in [N·m].

    Examples
    --------
    >>> import xarray as xr
    >>> ds = xr.Dataset({"torque_measured": ("time", [1.0, 3.0]),
    ...                  "torque_fitted": ("time", [0.0, 0.0]),
    ...                  "torque_lines_fitted": ("time", [1.0, 1.0])})
    >>> _, rms, raw = torque_residual(ds, "fitted")
    >>> float(rms), round(float(raw), 4)
    (1.4142135623730951, 2.2361)
    """
    raw = np.asarray(fit["torque_measured"].values, dtype=float) - np.asarray(
        fit[f"torque_{which}"].values, dtype=float
    )
    lines = fit.get(f"torque_lines_{which}")
    residual = raw if lines is None else raw - np.asarray(lines.values, dtype=float)
    mask = fit.get("torque_in_fit")
    inside = np.ones(raw.size, bool) if mask is None else np.asarray(mask.values) != 0
    rms = float(np.sqrt(np.mean(residual[inside] ** 2)))
    return residual, rms, float(np.sqrt(np.mean(raw[inside] ** 2)))


def calibration_section(rep, calibration: dict, fit=None) -> None:
    """The analysis report's part on the calibration it used: values with their standard
    errors, what was not identified, and the fit figure when its dataset is given.

    Parameters
    ----------
    rep : rollerrig.report.html.HtmlReport
    calibration : dict
        The content of ``calibration.json``.
    fit : xarray.Dataset, optional
        ``calibration-fit.nc`` of the same calibration.
    """
    rep.heading("The calibrated twin this analysis used")
    source = calibration.get("recording") or {}
    where = source.get("source", "") if isinstance(source, dict) else ""
    rep.paragraph(
        "Rig parameters fitted by rollerrig calibrate to a recorded test"
        + (f" ({where})" if where else "")
        + ": their values replace the rig file's and their covariance enters the corrected "
        "CoA's uncertainty. One standard error each, as calibration.json states it "
        "(standard_error_convention there)."
    )
    if calibration.get("valid") is False:
        rep.paragraph(
            "warning: this calibration is NOT VALID ("
            + "; ".join(calibration.get("invalid_reasons") or ["no reason recorded"])
            + "); it was used only because its use was forced.",
            note=True,
        )
    drive = calibration.get("roller_drive")
    if drive:
        rep.paragraph(f"The twin fitted had the roller drive {drive!r}.")
    if calibration.get("standard_errors_conditional_on_model"):
        flag = calibration.get("conditional_on_model") or {}
        rep.paragraph(
            "warning: every standard error is conditional on the model: the calibration's "
            "residuals show structure in "
            + (", ".join(flag.get("structured_channels") or []) or "some channel")
            + " that the fitted model does not explain, so a standard error is what the data "
            "allow if the model were right, not the distance to the truth. The budget keeps the "
            "larger of it and the rig's stated uncertainty."
            + (f" {flag['suggestion']}." if flag.get("suggestion") else ""),
            note=True,
        )
    discrepancy = (calibration.get("model_discrepancy") or {}).get("keys") or {}
    rows = []
    for key, entry in (calibration.get("parameters") or {}).items():
        value, se = entry.get("value"), entry.get("standard_error")
        se_text = "–" if se is None else f"{se:.3g}"
        if se is not None and entry.get("conditional_on_model"):
            se_text += " (conditional on the model)"
        if key in discrepancy:
            se_text += f"; model discrepancy {discrepancy[key]['standard_uncertainty']:.3g}"
        rows.append(
            (
                key,
                "not identified" if value is None else f"{value:.6g}",
                se_text,
                *_error_parts(entry),
                entry.get("unit", ""),
                entry.get("reason") or entry.get("why_null") or "",
            )
        )
    if rows:
        rep.table(
            ("key", "value", "standard error", "of it: from the residuals",
             "from the sensors' classes (the largest input)", "unit", "note"),
            rows,
        )  # fmt: skip
        rep.paragraph(
            "The standard error is the root sum of squares of its two parts: the statistical "
            "one from the fit's residuals (Newey-West) and the systematic one, the shifts the "
            "sensors' stated classes make (each input's for one standard uncertainty, "
            "linearised at the optimum; calibration.json: standard_error_statistical, "
            "standard_error_systematic, systematic). A key whose error is mostly systematic is "
            "known to the sensors' classes, not to the recording's noise.",
            note=True,
        )
    for text in calibration.get("warnings") or []:
        rep.paragraph(f"warning: {text}", note=True)
    if fit is not None:
        rep.figure(calibration_figure(fit), "The calibration's fit: recording against the twin.")


def _error_parts(entry: dict) -> tuple[str, str]:
    """The statistical and systematic parts of a key's standard error as the table shows them:
    ``("0.257", "2.32 (torque_class 1.81)")``; "–" where calibration.json has no split (a key
    not identified, or a file written before the split)."""
    stat, syst = entry.get("standard_error_statistical"), entry.get("standard_error_systematic")
    stat_text = "–" if stat is None else f"{stat:.3g}"
    if syst is None:
        return stat_text, "–"
    shifts = entry.get("systematic") or {}
    largest = max(shifts.items(), key=lambda kv: abs(kv[1] or 0.0), default=None)
    if largest is None or not largest[1]:
        return stat_text, f"{syst:.3g}"
    return stat_text, f"{syst:.3g} ({largest[0]} {abs(largest[1]):.3g})"
