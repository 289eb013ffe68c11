"""Figures of a simulated adhesion experiment (in the spirit of Kayaalp Fig. 40)."""

from __future__ import annotations

import json
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from rollerrig.report.lines import envelope

__all__ = [
    "EXPERIMENT_FIGURE_DPI",
    "MEASURED_STYLE",
    "TRUE_STYLE",
    "experiment_figure",
    "sweep_figure",
]

MEASURED_STYLE = {"color": "0.72", "lw": 0.6, "zorder": 1}
"""How a trace the rig measures (encoder staircase, torque sensor) is drawn: thin, light, behind."""

TRUE_STYLE = {"lw": 1.5, "zorder": 3}
"""How the twin's truth is drawn: a strong colour (given per panel), on top of the measurement."""


EXPERIMENT_FIGURE_SIZE = (12.0, 10.0)
"""Size of the six-panel experiment figure [in]."""

EXPERIMENT_FIGURE_DPI = 100
"""Resolution the experiment figure is saved at [dots per inch]: 1200 x 1000 pixels, every
label readable at 100 % on a screen; ``rollerrig simulate`` writes it so, with no re-render to
crop it (its layout is fixed, see :data:`_EXPERIMENT_MARGINS`)."""

_EXPERIMENT_MARGINS = {
    "left": 0.85 / EXPERIMENT_FIGURE_SIZE[0],
    "right": 1 - 0.15 / EXPERIMENT_FIGURE_SIZE[0],
    "bottom": 0.55 / EXPERIMENT_FIGURE_SIZE[1],
    "top": 1 - 0.7 / EXPERIMENT_FIGURE_SIZE[1],
    "wspace": 0.2,
    "hspace": 0.36,
}
"""The experiment figure's layout, fixed: margins in inches over the figure's size (left 0.85
for tick labels of five characters and the y label, top 0.7 for the title and the panels'
titles), the gaps as fractions of a panel. What ``tight_layout`` found for the bundled
experiments, with room to spare; fixed, the figure is drawn once when saved, not three times
(layout, tight bounding box, the image)."""


def _measured_and_true(ax, t, measured, true, colour: str, what: str, how: str) -> None:
    """Draw ``measured`` behind ``true`` on ``ax``, with legend entries saying which is which."""
    ax.plot(*envelope(t, np.asarray(measured)), **MEASURED_STYLE, label=f"measured: {how}")
    ax.plot(*envelope(t, np.asarray(true)), color=colour, **TRUE_STYLE, label=f"true: {what}")


def _new_figure(size):
    """A figure of pyplot's when pyplot is imported, so that ``plt.show()``, notebooks and
    sphinx-gallery (which collects pyplot's figures) see it; otherwise one on an Agg canvas of
    its own, with no pyplot to import (0.1-0.2 s of a fresh ``rollerrig simulate``)."""
    pyplot = sys.modules.get("matplotlib.pyplot")
    if pyplot is not None:
        return pyplot.figure(figsize=size)
    fig = Figure(figsize=size)
    FigureCanvasAgg(fig)
    return fig


def experiment_figure(ds, title: str | None = None):
    """Six panels: torque, CoA-creep, wheel speed, slip velocity, roller speed, forces.

    (a) torque request and PMSM air-gap torque; (b) CoA versus creep, true at the contact and as
    the rig measures it (T56 and encoder creep); (c) wheel and (e) roller peripheral speed;
    (d) slip velocity [m/s] (the difference of the peripheral speeds at the contact); (f) true
    contact force and the force the rig derives from T56.

    In every panel that holds both, what the rig measures (quantised encoder speeds, the torque
    sensor) is drawn thin and light grey behind (:data:`MEASURED_STYLE`), the twin's truth in
    colour on top (:data:`TRUE_STYLE`); the legends start with "true:" and "measured:".

    Parameters
    ----------
    ds : xarray.Dataset
        Result of :meth:`rollerrig.solve.simulation.Simulation.run` (truth beside the measured
        channels; the rig's radii in the ``provenance`` attribute).
    title : str, optional
        Figure title (e.g. naming the variant:
        :func:`rollerrig.cli.twin.variant_title`); default the dataset's ``title`` attribute.
        One line; a long one is set smaller to fit the figure's width.

    Returns
    -------
    matplotlib.figure.Figure
        :data:`EXPERIMENT_FIGURE_SIZE`, laid out already (fixed margins): save it with
        ``save_figure(fig, path, dpi=EXPERIMENT_FIGURE_DPI, tight=False)``, drawn once. One of
        pyplot's figures when pyplot is imported (a notebook, a gallery), else on an Agg canvas
        of its own.
    """
    t = ds["time"].values
    prov = json.loads(ds.attrs["provenance"])
    geo = (prov.get("rig_parameters") or prov["rig"])["geometry"]  # "rig": before 0.1.0
    rw, rr = geo["wheel_radius_x"], geo["roller_radius_x"]
    fig = _new_figure(EXPERIMENT_FIGURE_SIZE)
    axes = fig.subplots(3, 2, gridspec_kw=_EXPERIMENT_MARGINS)
    (a, b), (c, d), (e, f) = axes

    a.plot(*envelope(t, ds.pmsm_torque.values), color="tab:orange", lw=1.5, zorder=2,
           label="PMSM air-gap torque (simulated)")  # fmt: skip
    a.plot(*envelope(t, ds.torque_request.values), color="k", lw=0.9, ls="--", zorder=3,
           label="torque request")  # fmt: skip
    a.set_ylabel("wheel torque [N·m]")
    # Titles at a fixed height (y=1.0, where matplotlib would put them: no axis has tick labels
    # on top): placed automatically, each is fitted against its axis's bounding box at every
    # draw, 15-20 % of drawing this figure (0.36 s against 0.45, 2026-12-01).
    a.set_title("(a) torque request and PMSM torque", y=1.0)

    b.plot(
        100 * ds.measured_creep.values,
        ds.measured_coa.values,
        ".",
        ms=1.5,
        color=MEASURED_STYLE["color"],
        zorder=MEASURED_STYLE["zorder"],
        label="measured: T56/(r_r S) vs encoder creep",
    )
    b.plot(100 * ds.creep.values, ds.coa.values, color="tab:red", **TRUE_STYLE,
           label="true: F_x/N vs contact creep")  # fmt: skip
    b.set_xlabel("creep [%]")
    b.set_ylabel("CoA [-]")
    lim = float(np.nanpercentile(np.abs(100 * ds.creep.values), 99.5)) * 1.1 + 0.5
    b.set_xlim(-0.5, lim)
    b.set_title("(b) CoA-creep", y=1.0)
    undefined = int(np.count_nonzero(~np.isfinite(ds.measured_creep.values)))
    if undefined:  # NaN policy: an undrawn sample is said so, with why
        why = ds.measured_creep.attrs.get("nan_meaning", "measured creep undefined")
        b.text(
            0.01,
            0.01,
            textwrap.fill(f"measured creep not drawn at {undefined} samples: {why}", 70),
            transform=b.transAxes,
            fontsize=8,
            color="0.3",
            va="bottom",
        )

    _measured_and_true(c, t, ds.measured_wheel_speed.values * rw * 3.6,
                       ds.wheel_speed.values * rw * 3.6, "tab:green",
                       "wheel tyre (twin)", "wheel encoder (quantised)")  # fmt: skip
    c.set_ylabel("wheel peripheral speed [km/h]")
    c.set_title("(c) wheel speed", y=1.0)

    _measured_and_true(d, t, ds.measured_slip_velocity.values, ds.slip_velocity.values,
                       "tab:purple", "at the contact (twin)", "from the encoders")  # fmt: skip
    d.set_ylabel("slip velocity [m/s]")
    d.set_title("(d) slip velocity", y=1.0)

    if "measured_roller_speed" in ds:
        _measured_and_true(e, t, ds.measured_roller_speed.values * rr * 3.6,
                           ds.roller_speed.values * rr * 3.6, "tab:brown",
                           "roller (twin)", "roller encoder (quantised)")  # fmt: skip
    else:
        e.plot(*envelope(t, ds.roller_speed.values * rr * 3.6), color="tab:brown",
               **TRUE_STYLE, label="true: roller (twin)")  # fmt: skip
    e.plot(*envelope(t, ds.roller_speed_setpoint.values * 3.6), color="k", lw=0.8, ls="--",
           zorder=4, label="set point")  # fmt: skip
    e.set_ylabel("roller peripheral speed [km/h]")
    e.set_title("(e) roller speed", y=1.0)

    _measured_and_true(f, t, ds.measured_force.values, ds.contact_force.values, "tab:red",
                       "contact force F_x (twin)", "from T56: T56/r_r")  # fmt: skip
    f.axhline(0, color="k", lw=0.5, zorder=2)
    f.set_ylabel("force [N]")
    f.set_title("(f) contact force vs force from the torque sensor", y=1.0)

    for ax in axes.flat:
        ax.grid(True, alpha=0.3)
        if ax is b:
            ax.legend(fontsize=8.5, loc="best")
            continue
        # Headroom above the traces for the legend, so that it hides none of them (its text
        # legible where the figure is shown at two thirds of its size, as in the docs).
        lo, hi = ax.get_ylim()
        ax.set_ylim(lo, hi + 0.35 * (hi - lo))
        ax.legend(fontsize=8.5, loc="upper left", ncol=2)
        ax.set_xlabel("time [s]")
    _fitted_title(fig, title or ds.attrs.get("title", ""))
    return fig


def _fitted_title(fig, text: str) -> None:
    """The figure's title in one line within the figure's width: 11 pt, smaller (down to
    7 pt) for a long one (a title naming a variant), so it fits the fixed top margin."""
    sup = fig.suptitle(text, fontsize=11)
    renderer = fig.canvas.get_renderer()
    size = 11.0
    while size > 7.0 and sup.get_window_extent(renderer).width > 0.98 * fig.bbox.width:
        size -= 0.5
        sup.set_fontsize(size)


def sweep_figure(values, amplitudes: dict, xlabel: str, title: str):
    """Relative oscillation amplitude versus a swept parameter (Kayaalp Figs. 43b, 47).

    ``values`` are numbers (a line plot) or labels (a bar chart); ``amplitudes`` maps a legend
    label to one relative amplitude [-] per value.
    """
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.2))
    labels = [str(v) for v in values]
    numeric = all(isinstance(v, int | float | np.floating | np.integer) for v in values)
    for k, (name, amp) in enumerate(amplitudes.items()):
        if numeric:
            ax.plot(values, 100 * np.asarray(amp), "o-", label=name)
        else:
            y = np.arange(len(values)) + (k - 0.5) * 0.38
            ax.barh(y, 100 * np.asarray(amp), height=0.36, label=name)
    if not numeric:
        ax.set_yticks(np.arange(len(values)), labels, fontsize=8)
        ax.invert_yaxis()
        ax.set_xlabel("overshoot below zero [% of the force before release]")
    else:
        ax.set_xlabel(xlabel)
        ax.set_ylabel("overshoot below zero [%]")
    ax.set_title(title, fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig
