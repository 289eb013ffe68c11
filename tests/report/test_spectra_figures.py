"""Spectrum and coherence figures state their settings, mark the twin's ringing modes, and
draw an empty spectrum with its sentence instead of failing."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pytest

from rollerrig.measure.recording import Recording
from rollerrig.report.spectra import coherence_figure, order_map_figure, spectrum_figure
from rollerrig.rig.parameters import default_rig
from rollerrig.signal.workflow import explain_recording, explain_recordings

RIG = default_rig()
FS = 250.0


def _recording(v_kmh: float, torque=None, seed: int = 0) -> Recording:
    rng = np.random.default_rng(seed)
    t = np.arange(int(60 * FS)) / FS
    w_r = v_kmh / 3.6 / 0.452
    f_r = w_r / (2 * np.pi)
    if torque is None:
        torque = (
            3.0 * np.sin(2 * np.pi * 5 * f_r * t)
            + np.sin(2 * np.pi * 13.78 * t)  # at the roller-shaft mode
            + np.sin(2 * np.pi * 37.0 * t)
            + 0.3 * rng.standard_normal(t.size)
        )
    laser = np.sin(2 * np.pi * f_r * t) + rng.standard_normal(t.size)
    return Recording(
        t,
        {
            "torque": torque,
            "laser": laser,
            "roller_speed": np.full(t.size, w_r),
            "wheel_speed": np.full(t.size, v_kmh / 3.6 / 0.348),
        },
        {"torque": "N.m", "laser": "m", "roller_speed": "rad/s", "wheel_speed": "rad/s"},
    )


@pytest.fixture(scope="module")
def explained():
    return explain_recording(_recording(30.0), "torque", RIG, coherence_with="laser")


def _texts(fig) -> str:
    return " | ".join(t.get_text() for t in fig.axes[0].texts) + fig.axes[0].get_title()


def test_spectrum_figure_states_settings_and_marks_modes(explained, tmp_path):
    fig = spectrum_figure(explained)
    text = _texts(fig)
    s = explained.spectrum
    assert f"{s.nperseg}-sample segments" in text and f"{s.n_segments} segments" in text
    assert "N = 4.3 kN" in text  # the twin's load and where it came from
    assert "mode 13.78 Hz" in text  # the roller-shaft mode can ring: drawn
    assert "rig mode 13.78 Hz" in text  # and labels the peak at it
    assert "unexplained" in text  # the 37 Hz line
    fig.savefig(tmp_path / "s.png")
    plt.close(fig)


def test_empty_spectrum_figure_has_its_sentence():
    rng = np.random.default_rng(1)
    e = explain_recording(_recording(30.0, torque=rng.standard_normal(int(60 * FS))), "torque", RIG)
    assert e.rows == ()
    fig = spectrum_figure(e)
    assert "no peak above the thresholds" in _texts(fig)
    plt.close(fig)


def test_coherence_figure_states_segments(explained):
    coh = explained.coherence
    fig = coherence_figure(
        coh, [r.frequency for r in explained.rows], [r.label for r in explained.rows]
    )
    title = fig.axes[0].get_title()
    assert f"{coh.n_segments} segments" in title and f"{coh.nperseg}-sample" in title
    assert "Δf" in title
    plt.close(fig)


def test_order_map_figure_of_a_spectra_set():
    result = explain_recordings([_recording(v, seed=int(v)) for v in (10.0, 30.0)], "torque", RIG)
    fig = order_map_figure(result.order_map(), roller_radius=0.452)
    assert fig.axes[0].get_xlabel() == "speed [km/h]"
    plt.close(fig)
