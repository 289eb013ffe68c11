"""Figure of the drive-dynamics study (issue 13): where the twin's slow modes lie with each
roller drive, against the 1.33 Hz line the dissertation measured, and the lag the dq machine
gives against the seed's fitted one."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt

__all__ = ["LINE_HZ", "drive_dynamics_figure", "verdict_text"]

LINE_HZ = 1.33
"""The line Kayaalp 5.1.2 reports in the roller torque at all speeds and conditions [Hz]."""
RING_ZETA = 0.3
"""Damping ratio below which a mode can ring as a line (as in :mod:`rollerrig.rig.linear`)."""


def drive_dynamics_figure(study: dict, *, normal_load_kn: float = 4.3):
    """Modes below 20 Hz (frequency against damping ratio) for every drive and speed at one
    load, and the fitted response lag of the dq machine against speed.

    Parameters
    ----------
    study : dict
        :func:`rollerrig.rig.drive_dynamics.drive_dynamics_study`.
    normal_load_kn : float
        The load whose rows are drawn [kN] (the modes move by < 1 % from 4.3 to 20 kN).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = plt.figure(figsize=(12.5, 8.5))
    grid = fig.add_gridspec(2, 2, width_ratios=(2, 1), height_ratios=(5, 3))
    ax, lag = fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[0, 1])
    text = fig.add_subplot(grid[1, :])
    rows = [*study["thevenin"], *study["dq"]]
    # A drive that acts exactly as one drawn before has its markers: drawn again, in its own
    # colour, they hid that drive's; one colour, both named in the legend.
    same = {v["drive"]: v.get("same_as", []) for v in study.get("verdicts", [])}
    names: dict[str, str] = {}
    for d in dict.fromkeys(r["drive"] for r in rows):
        if not any(o in names for o in same.get(d, [])):
            names[d] = " = ".join([d, *same.get(d, [])])
    drives = list(names)
    speeds = sorted({r["speed [km/h]"] for r in rows})
    markers = dict(zip(speeds, "osD^v<>", strict=False))
    colours = plt.get_cmap("tab10")
    for i, drive in enumerate(drives):
        for r in rows:
            if r["drive"] != drive or abs(r["normal_load [kN]"] - normal_load_kn) > 1e-6:
                continue
            for mode in r["modes below 20 Hz"]:
                ax.plot(mode["frequency [Hz]"], mode["damping_ratio [-]"],
                        marker=markers[r["speed [km/h]"]], ls="none", color=colours(i % 10),
                        ms=6, alpha=0.85)  # fmt: skip
                if mode.get("class") == "unstable":  # a class of its own: ringed in red
                    ax.plot(mode["frequency [Hz]"], mode["damping_ratio [-]"], marker="o",
                            ms=11, mfc="none", mec="red", ls="none")  # fmt: skip
    ax.axvspan(1.2, 1.45, color="0.85", zorder=0)
    ax.axvline(LINE_HZ, color="k", ls=":", lw=1.0)
    ax.axhline(RING_ZETA, color="k", ls="--", lw=0.8)
    ax.axhspan(-0.35, 0.0, color="mistyrose", zorder=0)
    ax.text(19.5, -0.02, "unstable (ζ < 0)", fontsize=8, ha="right", va="top", color="red")
    ax.text(LINE_HZ, 0.02, " 1.33 Hz line\n (Kayaalp 5.1.2)", fontsize=8, va="bottom")
    ax.text(19.5, RING_ZETA, "can ring below", fontsize=8, ha="right", va="bottom")
    ax.set_xscale("log")
    ax.set_xlim(0.5, 20.0)
    ax.set_ylim(-0.35, 1.0)
    ax.set_xticks([0.5, 1, 1.33, 2, 5, 10, 20], ["0.5", "1", "1.33", "2", "5", "10", "20"])
    ax.set_xlabel("damped frequency [Hz]")
    ax.set_ylabel("damping ratio [-]")
    ax.set_title(f"modes below 20 Hz at {normal_load_kn:g} kN, free rolling", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    handles = [plt.Line2D([], [], color=colours(i % 10), marker="s", ls="none",
                          label=names[d]) for i, d in enumerate(drives)]  # fmt: skip
    handles += [plt.Line2D([], [], color="0.3", marker=markers[v], ls="none",
                           label=f"{v:g} km/h") for v in speeds]  # fmt: skip
    ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    held = study["lag_held_speed"]
    lag.plot([h["speed [km/h]"] for h in held], [h["tau [s]"] * 1e3 for h in held], "o-",
             label="dq machine, speed held")  # fmt: skip
    in_rig = study["lag_in_rig"]
    lag.plot([h["speed [km/h]"] for h in in_rig], [h["tau [s]"] * 1e3 for h in in_rig], "s",
             ms=8, label="dq machine in the rig (torque step)")  # fmt: skip
    lag.axhline(study["seed_lag [s]"] * 1e3, color="k", ls="--", lw=1.0,
                label="Kayaalp's fitted lag (c_lp = 2.75)")  # fmt: skip
    lag.set_ylim(0.0, 1.15 * study["seed_lag [s]"] * 1e3)
    lag.set_xlabel("roller speed [km/h]")
    lag.set_ylabel("first-order lag τ [ms]")
    lag.set_title("response lag fitted to the dq machine", fontsize=10)
    lag.grid(True, alpha=0.3)
    lag.legend(fontsize=7, loc="center right")
    text.axis("off")
    text.text(0.0, 1.0, verdict_text(study), fontsize=7.5, va="top", ha="left", wrap=True,
              family="monospace", transform=text.transAxes)  # fmt: skip
    fig.suptitle("The roller drive as a dynamic induction machine under open-loop V/f", fontsize=11)
    fig.tight_layout()
    return fig


def verdict_text(study: dict, width: int = 150) -> str:
    """Each dq drive's verdict about the band and its robustness, one short block per drive
    (what the figure prints under the plots; the full text is in the JSON)."""
    import textwrap

    lo, hi = study.get("band [Hz]", (1.0, 1.7))
    lines = [f"verdicts about {lo:g}-{hi:g} Hz, each checked over its assumptions' ranges:"]
    for v in study.get("verdicts", []):
        rob = v.get("robustness")
        if rob is None:
            tail = "not checked"
        elif rob["holds"]:
            tail = "holds over the assumed ranges"
        else:
            flips = [
                f"{a['label']} at " + ", ".join(f"{x:.3g}" for x in a["flips"])
                for a in rob["assumptions"]
                if a.get("flips")
            ]
            tail = "depends on " + "; ".join(flips)
        lines += textwrap.wrap(f"{v['drive']}: {v['text']} -- {tail}", width,
                               subsequent_indent="    ")  # fmt: skip
    return "\n".join(lines)
