"""Figures for the FASTSIM-family creep laws: creep curves and the traction distribution."""

from __future__ import annotations

from collections.abc import Mapping

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.contact.curves import CreepCurve
from rollerrig.contact.fastsim import fastsim_grid

__all__ = ["law_curve_figure", "traction_figure"]

_LAW_NAMES = {
    "polach": "Polach (2005)",
    "fastsim": "FASTSIM (Kalker 1982)",
    "modified-fastsim": "modified FASTSIM (Spiryagin et al. 2013)",
    "fastrip": "FaStrip (Sichani et al. 2016)",
}


def law_curve_figure(rows: dict, law: str, roller_radius_x: float, max_creep: float = 0.10):
    """Creep-adhesion curves of one law: roller (solid) and tangent rail (dashed), each set.

    Parameters
    ----------
    rows : dict
        ``{"roller" | "tangent rail": {set name: CreepCurve}}``.
    law : str
        Name of the law (for the title).
    roller_radius_x : float
        Roller radius [m] (for the legend).
    max_creep : float
        Upper end of the creep axis [-].

    Returns
    -------
    matplotlib.figure.Figure
    """
    if not isinstance(rows, Mapping) or not all(
        isinstance(rows.get(w), Mapping) for w in ("roller", "tangent rail")
    ):  # a str had been a bare TypeError (string indices)
        raise ParameterError(
            'rows must be a dict {"roller": {set name: CreepCurve}, "tangent rail": {...}}, got '
            f"{rows!r:.60}"
        )
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, name in enumerate(rows["roller"]):
        for where, style in (("roller", "-"), ("tangent rail", "--")):
            c: CreepCurve = rows[where][name]
            keep = c.creep <= max_creep
            label = f"{name}, " + (
                f"roller r = {roller_radius_x * 1e3:.0f} mm" if where == "roller" else where
            )
            ax.plot(
                100 * c.creep[keep],
                c.adhesion_coefficient[keep],
                style,
                color=colours[k % len(colours)],
                label=label,
            )
    ax.set_xlabel("creep s [%]")
    ax.set_ylabel("adhesion coefficient F/N [-]")
    ax.set_title(f"Creep curves by {_LAW_NAMES.get(law, law)}")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def traction_figure(curve: CreepCurve, law: str, poisson: float, creep: float | None = None):
    """Traction distribution p_x over the contact ellipse, with adhesion and slip zones.

    Parameters
    ----------
    curve : CreepCurve
        A curve of the law (gives the contact, the load, the speed and the friction set).
    law : str
        A FASTSIM-family law name.
    poisson : float
        Combined Poisson's ratio ν of the contact [-].
    creep : float, optional
        Creep of the distribution [-]; default half the creep at the curve's peak (partial
        slip: both zones visible).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from rollerrig.contact.laws import creep_force

    if not isinstance(curve, CreepCurve):  # None: a bare AttributeError
        raise ParameterError(
            f"curve must be a CreepCurve, got a value of type {type(curve).__name__}"
        )
    s_peak = curve.peak[0]
    s = 0.5 * s_peak if creep is None else float(creep)
    a = float(curve.contact.semi_axis_x)
    b = float(curve.contact.semi_axis_y)
    g = curve.creep_stiffness / (a * b * curve.c11)
    nu = float(poisson)
    r = creep_force(
        law,
        s,
        abs(s) * curve.rolling_speed,
        curve.normal_load,
        a,
        b,
        g,
        nu,
        curve.parameters,
        grid=fastsim_grid(48, 48),
        tractions=True,
    )
    t = r.tractions
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10.5, 4.4))
    px = np.where(t.state[0] > 0, t.px[0], np.nan) / 1e6
    im = ax1.scatter(
        1e3 * t.x.ravel(), 1e3 * t.y.ravel(), c=px.ravel(), s=6, marker="s", cmap="viridis"
    )
    slip = t.state[0] == 2
    ax1.scatter(1e3 * t.x[slip], 1e3 * t.y[slip], s=1, color="white", label="slip")
    fig.colorbar(im, ax=ax1, label="p_x [MPa]")
    ax1.set_xlabel("x (rolling; leading edge right) [mm]")
    ax1.set_ylabel("y [mm]")
    ax1.set_title("adhesion (colour), slip (white dots)")
    ax1.set_aspect("equal")
    mid = t.x.shape[0] // 2
    ax2.plot(1e3 * t.x[mid], t.px[0, mid] / 1e6, "-", label="p_x")
    ax2.plot(1e3 * t.x[mid], t.bound[0, mid] / 1e6, "--", label="bound mu p_n")
    ax2.set_xlabel("x [mm]")
    ax2.set_ylabel("traction [MPa]")
    ax2.set_title(f"centre strip y = {1e3 * t.y[mid, 0]:.2f} mm")
    ax2.grid(True, alpha=0.3)
    ax2.legend(fontsize=8)
    fig.suptitle(
        f"{_LAW_NAMES.get(law, law)}: s = {100 * s:.3g} %, N = {curve.normal_load / 1e3:g} kN, "
        f"F/N = {float(r.fx[0]) / curve.normal_load:.3f}"
    )
    fig.tight_layout()
    return fig
