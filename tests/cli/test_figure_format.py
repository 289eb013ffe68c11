"""``--figure-format png|svg|pdf``: one option on every command that writes figures, the files
in the format asked for, each with the run's provenance (issue 23, point 4)."""

from __future__ import annotations

import numpy as np
import pytest

from rollerrig.cli import app
from rollerrig.cli._options import FigureFormat, figure_file
from rollerrig.output import figure_provenance
from rollerrig.output.figures import FIGURE_FORMATS

COMMANDS = (
    "simulate",
    "spectrum",
    "filters",
    "contact",
    "frame",
    "transfer",
    "calibrate",
    "study run",
    "study show",
    "study frame",
    "study drive-dynamics",
    "demo",
)


def _flat(text: str) -> str:
    return " ".join(text.split())


def test_the_choices_are_the_formats_that_carry_provenance():
    assert tuple(f.value for f in FigureFormat) == FIGURE_FORMATS
    assert figure_file("order-map") == "order-map.png"  # the default
    assert figure_file("order-map", "pdf") == "order-map.pdf"


@pytest.mark.parametrize("command", COMMANDS)
def test_every_figure_command_offers_the_option(command, runner):
    result = runner.invoke(app, [*command.split(), "--help"])
    assert result.exit_code == 0, result.output
    text = _flat(result.output)
    assert "--figure-format <png|svg|pdf>" in text and "[default: png]" in text


def _free_rolling_csv(path, v_kmh: float, seed: int):
    """60 s at 250 Hz of free rolling at ``v_kmh``: a roller order and an 83 Hz line."""
    from rollerrig.recordings.recording import Recording
    from rollerrig.recordings.writers import write_recording

    rng = np.random.default_rng(seed)
    t = np.arange(int(60 * 250.0)) / 250.0
    w_r = v_kmh / 3.6 / 0.452
    torque = 3 * np.sin(w_r * t) + np.sin(2 * np.pi * 83.0 * t) + 0.3 * rng.standard_normal(t.size)
    channels = {
        "torque": torque,
        "roller_speed": np.full(t.size, w_r),
        "wheel_speed": np.full(t.size, v_kmh / 3.6 / 0.348),
        "normal_load": np.full(t.size, 4300.0),
    }
    units = {"torque": "N.m", "roller_speed": "rad/s", "wheel_speed": "rad/s", "normal_load": "N"}
    return write_recording(Recording(t, channels, units), path)


def test_spectrum_writes_svg_figures_with_their_provenance(tmp_path, runner):
    recordings = [
        _free_rolling_csv(tmp_path / f"free-{v}kmh.csv", v, seed) for v, seed in ((5, 1), (30, 2))
    ]
    out = tmp_path / "out"
    args = ["spectrum", *map(str, recordings), "--figure-format", "SVG", "--out", str(out)]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    figures = sorted(p.name for p in out.iterdir() if p.suffix in (".png", ".svg", ".pdf"))
    assert figures == ["free-30kmh-spectrum.svg", "free-5kmh-spectrum.svg", "order-map.svg"]
    for name in figures:
        record = figure_provenance(out / name)
        assert record["command"][1] == "spectrum", name
        assert (out / name).read_text().lstrip().startswith("<?xml")


def test_a_wrong_format_is_one_usage_error(tmp_path, runner):
    result = runner.invoke(app, ["contact", "--figure-format", "jpg", "--out", str(tmp_path)])
    assert result.exit_code == 2, result.output
    assert "Invalid value for '--figure-format'" in result.output
    assert list(tmp_path.iterdir()) == []
