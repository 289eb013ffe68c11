"""Figures of the contact report: creep-adhesion curves and contact size versus roller radius."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.contact.creep import PolachParameters
from rollerrig.contact.curves import CreepCurve, polach_creep_curve
from rollerrig.contact.roller import RollerRailComparison

__all__ = ["contact_size_figure", "creep_curve_figure"]

_COLOURS = {"dry": "tab:red", "wet": "tab:blue"}


def creep_curve_figure(
    parameter_sets: dict[str, PolachParameters],
    normal_load: float,
    rolling_speed: float,
    wheel_radius_x: float,
    wheel_radius_y: float,
    roller_radius_x: float,
    roller_radius_y: float,
    youngs_modulus: float = 210e9,
    poisson: float = 0.3,
    max_creep: float = 0.06,
):
    """Creep-adhesion curves on the roller (solid) and on a tangent rail (dashed).

    Returns the figure and the computed curves ``{(condition, "roller"|"tangent"): CreepCurve}``.
    """
    creep = np.linspace(0.0, max_creep, 601)
    curves: dict[tuple[str, str], CreepCurve] = {}
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    for name, params in parameter_sets.items():
        colour = _COLOURS.get(name)
        for where, rx, style in (("roller", roller_radius_x, "-"), ("tangent", np.inf, "--")):
            c = polach_creep_curve(
                creep,
                normal_load,
                rolling_speed,
                wheel_radius_x,
                wheel_radius_y,
                rx,
                roller_radius_y,
                params,
                youngs_modulus,
                poisson,
            )
            curves[(name, where)] = c
            label = f"{name}, " + (
                f"roller r = {roller_radius_x * 1e3:.0f} mm"
                if where == "roller"
                else "tangent rail"
            )
            line = ax.plot(100 * creep, c.adhesion_coefficient, style, color=colour, label=label)[0]
            if where == "roller":
                s_pk, mu_pk = c.peak
                ax.plot(100 * s_pk, mu_pk, "o", color=line.get_color(), ms=4)
        # Kalker's linear theory for reference: the slope Polach starts from (kA = kS = 1).
        lin = curves[(name, "roller")]
        s_lin = creep[creep * lin.creep_stiffness / normal_load <= 1.1 * lin.peak[1]]
        ax.plot(
            100 * s_lin,
            s_lin * lin.creep_stiffness / normal_load,
            ":",
            color=colour,
            lw=1,
            label=f"{name}, Kalker linear theory" if name == next(iter(parameter_sets)) else None,
        )
    ax.set_xlabel("creep s [%]")
    ax.set_ylabel("adhesion coefficient F/N [-]")
    ax.set_title(
        f"Polach creep curves, N = {normal_load / 1e3:g} kN, v = {rolling_speed * 3.6:g} km/h"
    )
    ax.set_xlim(0, 100 * max_creep)
    ax.set_ylim(0, None)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    return fig, curves


def contact_size_figure(comparison: RollerRailComparison, rig_roller_radius: float | None = None):
    """Contact semi-axes and area versus roller radius (Kayaalp Figs. 12-13), log radius axis."""
    if not isinstance(comparison, RollerRailComparison):  # None: a bare AttributeError
        raise ParameterError(
            "comparison must be a RollerRailComparison (contact_versus_roller_radius), got a "
            f"value of type {type(comparison).__name__}"
        )
    r_mm = comparison.roller_radius_x * 1e3
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.3))
    ax1.semilogx(r_mm, comparison.semi_axis_x * 1e3, color="tab:green", label="a (rolling)")
    ax1.semilogx(r_mm, comparison.semi_axis_y * 1e3, color="tab:purple", label="b (lateral)")
    ax1.axhline(comparison.tangent_semi_axis_x * 1e3, color="tab:green", ls="--", lw=1)
    ax1.axhline(comparison.tangent_semi_axis_y * 1e3, color="tab:purple", ls="--", lw=1)
    ax1.set_xlabel("roller longitudinal radius [mm]")
    ax1.set_ylabel("semi-axis [mm]")
    ax1.set_title("Contact ellipse (dashed: tangent rail)")
    ax2.semilogx(r_mm, comparison.area * 1e6, color="k", label="roller")
    ax2.axhline(comparison.tangent_area * 1e6, color="k", ls="--", lw=1, label="tangent rail")
    ax2.set_xlabel("roller longitudinal radius [mm]")
    ax2.set_ylabel("contact area [mm²]")
    ax2.set_title("Contact area")
    if rig_roller_radius is not None:
        for ax in (ax1, ax2):
            ax.axvline(rig_roller_radius * 1e3, color="tab:orange", lw=1, label="rig roller")
    for ax in (ax1, ax2):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    return fig
