"""Figure of a calibration: the recording against the twin before and after the fit."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from rollerrig.report.lines import envelope
from rollerrig.report.twin import MEASURED_STYLE

__all__ = ["calibration_figure"]

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
        torque residual (recorded − calibrated twin) before and after.
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
    measured = np.asarray(fit["torque_measured"].values, dtype=float)
    for j, keep in enumerate((slice(None), inside)):
        ax = axes[-1, j]
        for which, colour in (("start", "tab:orange"), ("fitted", "tab:blue")):
            residual = measured - np.asarray(fit[f"torque_{which}"].values, dtype=float)
            rms = float(np.sqrt(np.mean(residual**2)))
            what = "start" if which == "start" else "calibrated"
            ax.plot(t[keep], residual[keep], color=colour, lw=0.7,
                    label=f"recorded − twin, {what} (RMS {rms:.3g} N·m)")  # fmt: skip
        ax.grid(alpha=0.3)
        ax.set_xlabel("time [s]")
        if j == 0:
            ax.set_ylabel("T56 residual [N·m]")
            ax.legend(loc="upper right", fontsize=8)
    fig.suptitle(title or "Calibration: recording against the twin, before and after the fit")
    fig.tight_layout()
    return fig
