"""The drive-dynamics figure carries the mode classes and the verdicts (synthetic study)."""

from __future__ import annotations

import matplotlib.pyplot as plt

from rollerrig.report.drive_dynamics import drive_dynamics_figure, verdict_text


def _study():
    row = {
        "drive": "dq slip comp 1.5, 0.05 s",
        "speed [km/h]": 10.0,
        "normal_load [kN]": 4.3,
        "modes below 20 Hz": [
            {"frequency [Hz]": 1.55, "damping_ratio [-]": -0.013, "class": "unstable"},
            {"frequency [Hz]": 3.96, "damping_ratio [-]": 0.38, "class": "damped"},
        ],
    }
    verdicts = [
        {
            "drive": "dq slip comp 1.5, 0.05 s",
            "text": "unstable at 10 km/h",
            "robustness": {
                "holds": False,
                "assumptions": [
                    {"label": "rotor-resistance estimate", "flips": [0.8]},
                    {"label": "R_s", "flips": []},
                ],
            },
        },
        {"drive": "dq default", "text": "no lightly damped mode", "robustness": {"holds": True}},
    ]
    return {
        "thevenin": [],
        "dq": [row],
        "band [Hz]": [1.0, 1.7],
        "verdicts": verdicts,
        "seed_lag [s]": 0.3635,
        "lag_held_speed": [{"speed [km/h]": 10.0, "tau [s]": 0.05}],
        "lag_in_rig": [],
    }


def test_the_figure_rings_unstable_modes_and_prints_the_verdicts():
    fig = drive_dynamics_figure(_study())
    ax = fig.axes[0]
    rings = [
        line
        for line in ax.get_lines()
        if line.get_markeredgecolor() == "red" and line.get_xdata()[0] == 1.55
    ]
    assert len(rings) == 1  # only the ζ < 0 mode
    assert ax.get_ylim()[0] < -0.013  # the unstable half-plane is on the plot
    texts = " ".join(t.get_text() for a in fig.axes for t in a.texts)
    assert "unstable at 10 km/h -- depends on rotor-resistance estimate at 0.8" in texts
    assert "dq default: no lightly damped mode -- holds over the assumed ranges" in texts
    plt.close(fig)


def test_verdict_text_without_verdicts_is_just_the_heading():
    assert verdict_text({}).startswith("verdicts about 1-1.7 Hz")


def test_drives_that_act_alike_share_one_colour_and_one_legend_entry():
    """Review: two equivalent drives were drawn in two colours at the same points, the second
    hiding the first; now the first is drawn, its legend entry naming both."""
    study = _study()
    twin = {**study["dq"][0], "drive": "dq twin"}
    study["dq"] = [study["dq"][0], twin]
    study["verdicts"][0]["same_as"] = ["dq twin"]
    study["verdicts"].append(
        {"drive": "dq twin", "text": "x", "same_as": ["dq slip comp 1.5, 0.05 s"]}
    )
    fig = drive_dynamics_figure(study)
    ax = fig.axes[0]
    at = [line for line in ax.get_lines() if list(line.get_xdata()) == [3.96]]
    assert len(at) == 1  # drawn once, not once per drive
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "dq slip comp 1.5, 0.05 s = dq twin" in labels
    assert not any(label.startswith("dq twin") for label in labels)
    plt.close(fig)
