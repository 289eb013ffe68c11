"""Spectrum and coherence figures state their settings and units, mark the twin's ringing modes,
keep their peak labels apart (renderer extents), and draw an empty spectrum with its sentence
instead of failing."""

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


def _label_boxes(fig):
    """Display boxes of the peak labels' texts (leader lines excluded), from the renderer."""
    from matplotlib.text import Annotation, Text

    ax = fig.axes[0]
    fig.canvas.draw()  # as a viewer sees it
    renderer = fig.canvas.get_renderer()
    labels = [a for a in ax.texts if isinstance(a, Annotation) and a.arrow_patch is not None]
    return ax, [Text.get_window_extent(a, renderer) for a in labels]


def _assert_apart(ax, boxes, n: int):
    assert len(boxes) == n
    for i, a in enumerate(boxes):
        for b in boxes[:i]:
            assert not a.overlaps(b), (a, b)
    frame = ax.get_window_extent()
    assert all(frame.x0 - 0.5 <= b.x0 and b.x1 <= frame.x1 + 0.5 for b in boxes)


@pytest.fixture(scope="module")
def crowded():
    """A torque with 16 lines, several of them closer than a label's width."""
    rng = np.random.default_rng(0)
    t = np.arange(int(120 * FS)) / FS
    w_r = 30 / 3.6 / 0.452
    f_r = w_r / (2 * np.pi)
    lines = [f_r, 2 * f_r, 3 * f_r, 5 * f_r, 10 * f_r, 1.333, 4.1, 4.6, 7.9, 8.3, 13.78, 14.5,
             20.0, 20.6, 21.3, 37.0]  # fmt: skip
    torque = 0.3 * rng.standard_normal(t.size)
    for k, f in enumerate(lines):
        torque += 3.0 / (1 + 0.2 * k) * np.sin(2 * np.pi * f * t)
    rec = Recording(
        t,
        {"torque": torque, "roller_speed": np.full(t.size, w_r),
         "wheel_speed": np.full(t.size, 30 / 3.6 / 0.348)},
        {"torque": "N.m", "roller_speed": "rad/s", "wheel_speed": "rad/s"},
    )  # fmt: skip
    return explain_recording(rec, "torque", RIG)


def test_spectrum_figure_axes_say_power_in_squared_newton_metres(explained):
    fig = spectrum_figure(explained)
    ax = fig.axes[0]
    assert ax.get_ylabel() == "power [(N.m)²]"  # not N.m², a newton square metre
    assert ax.get_xlabel() == "frequency [Hz]" and ax.get_yscale() == "log"
    entries = [t.get_text() for t in ax.get_legend().get_texts()]
    assert set(entries) == {r.source for r in explained.rows}  # one entry per kind of source
    markers = [ln for ln in ax.get_lines() if ln.get_marker() == "v"]
    assert len(markers) == len(explained.rows)
    plt.close(fig)


def test_peak_labels_of_a_crowded_spectrum_do_not_overlap(crowded):
    assert len(crowded.rows) >= 12
    fig = spectrum_figure(crowded, max_labels=16)
    ax, boxes = _label_boxes(fig)
    _assert_apart(ax, boxes, len(crowded.rows))
    # The most powerful peak keeps the top row.
    strongest = max(crowded.rows, key=lambda r: r.power)
    top = max(ax.texts, key=lambda a: a.xyann[1] if hasattr(a, "xyann") else -1)
    assert top.get_text().startswith(f"{strongest.frequency:.3f} Hz")
    plt.close(fig)


def test_coherence_labels_do_not_overlap(crowded, explained):
    rows = crowded.rows
    fig = coherence_figure(
        explained.coherence, [r.frequency for r in rows], [r.label for r in rows]
    )
    ax, boxes = _label_boxes(fig)
    _assert_apart(ax, boxes, len(rows))
    assert ax.get_ylabel() == "coherence γ² [-]"
    plt.close(fig)


def test_order_map_draws_order_lines_and_peaks():
    result = explain_recordings([_recording(v, seed=int(v)) for v in (10.0, 30.0)], "torque", RIG)
    omap = result.order_map()
    fig = order_map_figure(omap)
    ax = fig.axes[0]
    assert ax.get_xlabel() == "roller speed [rad/s]" and ax.get_ylabel() == "peak frequency [Hz]"
    kinds = list(dict.fromkeys(omap.source.tolist()))
    assert len(ax.get_lines()) == len(omap.lines) + len(kinds)
    assert [t.get_text() for t in ax.get_legend().get_texts()] == [k or "peak" for k in kinds]
    plt.close(fig)
