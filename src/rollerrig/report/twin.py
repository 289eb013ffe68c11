"""Figures of a simulated adhesion experiment (in the spirit of Kayaalp Fig. 40)."""

from __future__ import annotations

import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

__all__ = ["experiment_figure", "sweep_figure"]


def experiment_figure(ds, title: str | None = None):
    """Six panels: torque, CoA-creep, wheel speed, slip velocity, roller speed, forces.

    (a) torque request and PMSM air-gap torque; (b) CoA versus creep, true at the contact and as
    the rig measures it (T56 and encoder creep); (c) wheel and (e) roller peripheral speed;
    (d) slip (creep) velocity; (f) true contact force and the force the rig derives from T56.
    """
    t = ds["time"].values
    prov = json.loads(ds.attrs["provenance"])
    geo = prov["rig"]["geometry"]
    rw, rr = geo["wheel_radius_x"], geo["roller_radius_x"]
    fig, axes = plt.subplots(3, 2, figsize=(12, 10))
    (a, b), (c, d), (e, f) = axes

    a.plot(t, ds.torque_request, color="tab:blue", label="torque request")
    a.plot(t, ds.pmsm_torque, color="tab:orange", lw=0.8, label="PMSM torque (simulated)")
    a.set_ylabel("wheel torque [N·m]")
    a.set_title("(a) torque request and PMSM torque")

    b.plot(
        100 * ds.measured_creep,
        ds.measured_coa,
        ".",
        ms=1.5,
        color="0.6",
        label="measured: T56/(r_r N) vs encoder creep",
    )
    b.plot(100 * ds.creep, ds.coa, color="tab:red", lw=1, label="true: F_x/N vs contact creep")
    b.set_xlabel("creep [%]")
    b.set_ylabel("CoA [-]")
    lim = float(np.nanpercentile(np.abs(100 * ds.creep), 99.5)) * 1.1 + 0.5
    b.set_xlim(-0.5, lim)
    b.set_title("(b) CoA-creep")

    c.plot(t, ds.wheel_speed * rw * 3.6, color="tab:green", label="wheel (tyre)")
    c.plot(t, ds.measured_wheel_speed * rw * 3.6, color="0.5", lw=0.6, label="wheel encoder")
    c.set_ylabel("wheel peripheral speed [km/h]")
    c.set_title("(c) wheel speed")

    d.plot(t, ds.slip_velocity, color="tab:purple", label="true")
    d.plot(t, ds.measured_slip_velocity, color="0.5", lw=0.6, label="from encoders")
    d.set_ylabel("slip velocity [m/s]")
    d.set_title("(d) creep velocity")

    e.plot(t, ds.roller_speed * rr * 3.6, color="tab:brown", label="roller")
    e.plot(t, ds.roller_speed_setpoint * 3.6, color="k", lw=0.8, ls="--", label="set point")
    e.set_ylabel("roller peripheral speed [km/h]")
    e.set_title("(e) roller speed")

    f.plot(t, ds.contact_force, color="tab:red", label="true contact force F_x")
    f.plot(t, ds.measured_force, color="tab:blue", lw=0.8, label="derived from T56: T56/r_r")
    f.axhline(0, color="k", lw=0.5)
    f.set_ylabel("force [N]")
    f.set_title("(f) contact force vs force from the torque sensor")

    for ax in axes.flat:
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="best")
        if ax is not b:
            ax.set_xlabel("time [s]")
    fig.suptitle(title or ds.attrs.get("title", ""), fontsize=11)
    fig.tight_layout()
    return fig


def sweep_figure(values, amplitudes: dict, xlabel: str, title: str):
    """Relative oscillation amplitude versus a swept parameter (Kayaalp Figs. 43b, 47).

    ``values`` are numbers (a line plot) or labels (a bar chart); ``amplitudes`` maps a legend
    label to one relative amplitude [-] per value.
    """
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
