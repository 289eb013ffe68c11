"""Spectrum and coherence figures state their settings and units, mark the twin's ringing modes,
keep their peak labels apart (renderer extents), and draw an empty spectrum with its sentence
instead of failing."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pytest

from rollerrig.recordings.recording import Recording
from rollerrig.report.labels import LABEL_GID
from rollerrig.report.spectra import (
    coherence_figure,
    frequency_limit,
    log_frequency_axis,
    order_map_figure,
    source_name,
    spectrum_figure,
)
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
    # One entry per kind of source, in words (not identifiers such as "roller_order").
    assert set(entries) == {source_name(r.source) for r in explained.rows}
    assert all("_" not in e for e in entries)
    markers = [ln for ln in ax.get_lines() if ln.get_marker() == "v"]
    assert sum(ln.get_xdata().size for ln in markers) == len(explained.rows)
    plt.close(fig)


def test_the_legend_stands_outside_the_axes(explained):
    fig = spectrum_figure(explained)
    fig.canvas.draw()
    ax = fig.axes[0]
    assert ax.get_legend().get_window_extent().x0 >= ax.get_window_extent().x1
    plt.close(fig)


def test_peak_labels_of_a_crowded_spectrum_clear_markers_curve_and_each_other(
    crowded, peak_labels_clear
):
    assert len(crowded.rows) >= 12
    fig = spectrum_figure(crowded, max_labels=16)
    boxes = peak_labels_clear(fig)
    modes = [m for m in crowded.modes.ringing if m.frequency <= fig.axes[0].get_xlim()[1]]
    assert len(boxes) == len(crowded.rows) + len(modes)  # every peak and mode labelled
    fig.set_dpi(150)  # as saved: text sizes do not scale exactly with the dpi (hinting)
    peak_labels_clear(fig)
    plt.close(fig)


def test_labels_of_the_seed_like_spectrum_clear_the_peaks(explained, peak_labels_clear):
    fig = spectrum_figure(explained)
    peak_labels_clear(fig)
    texts = [t.get_text() for t in fig.axes[0].texts if t.get_gid() == LABEL_GID]
    assert "mode 13.78 Hz" in texts  # the mode's name in the label row, not on the trace
    plt.close(fig)


def test_coherence_labels_clear_markers_curve_and_each_other(crowded, explained, peak_labels_clear):
    rows = crowded.rows
    fig = coherence_figure(
        explained.coherence, [r.frequency for r in rows], [r.label for r in rows]
    )
    boxes = peak_labels_clear(fig)
    assert len(boxes) == len(rows)
    assert fig.axes[0].get_ylabel() == "coherence γ² [-]"
    plt.close(fig)


def _with_high_line(v_kmh: float = 5.0) -> Recording:
    """A slow recording with the orders low and one strong line at 100 Hz (as the PMSM's
    sixth electrical order at 5-10 km/h): the axis must reach it."""
    rec = _recording(v_kmh)
    t = rec.time
    f_r = v_kmh / 3.6 / 0.452 / (2 * np.pi)
    torque = (
        2.0 * np.sin(2 * np.pi * f_r * t)
        + 3.0 * np.sin(2 * np.pi * 5 * f_r * t)
        + 2.0 * np.sin(2 * np.pi * 100.0 * t)
        + 0.3 * np.random.default_rng(3).standard_normal(t.size)
    )
    return Recording(t, {**rec.channels, "torque": torque}, rec.units)


def test_the_frequency_axis_shows_every_listed_peak_by_default():
    e = explain_recording(_with_high_line(), "torque", RIG)
    highest = max(r.frequency for r in e.rows)
    assert highest > 99.0
    fig = spectrum_figure(e)
    ax = fig.axes[0]
    lo, hi = ax.get_xlim()
    # every listed peak and every twin mode inside the spectrum's band
    modes = [m.frequency for m in e.modes.ringing if m.frequency <= FS / 2]
    assert modes and hi == pytest.approx(
        frequency_limit([r.frequency for r in e.rows] + modes, FS / 2)
    )
    assert hi >= 1.1 * max(modes) - 1e-9 or hi == FS / 2
    assert lo <= min(r.frequency for r in e.rows) and highest <= hi <= FS / 2
    markers = [ln for ln in ax.get_lines() if ln.get_marker() == "v"]
    assert sum(ln.get_xdata().size for ln in markers) == len(e.rows)  # every peak marked
    plt.close(fig)
    fig = coherence_figure(e.coherence or _coherence(), [r.frequency for r in e.rows])
    assert fig.axes[0].get_xlim()[1] >= highest
    plt.close(fig)


def _coherence():
    from rollerrig.signal.spectra import coherence

    rng = np.random.default_rng(0)
    x = rng.standard_normal(int(60 * FS))
    return coherence(x, x + rng.standard_normal(x.size), FS, 1024)


def test_a_given_frequency_limit_names_the_peaks_it_hides():
    e = explain_recording(_with_high_line(), "torque", RIG)
    fig = spectrum_figure(e, max_frequency=60.0)
    ax = fig.axes[0]
    assert ax.get_xlim()[1] == 60.0
    small_print = " ".join(t.get_text() for t in ax.texts).replace("\n", " ")
    hidden = [r for r in e.rows if r.frequency > 60.0]
    assert (
        f"{len(hidden)} listed peak" in small_print and f"{hidden[0].frequency:.2f}" in small_print
    )
    # The legend lists only kinds with a marker drawn.
    entries = {t.get_text() for t in ax.get_legend().get_texts()}
    assert entries == {source_name(r.source) for r in e.rows if r.frequency <= 60.0}
    plt.close(fig)


def test_frequency_axis_policy():
    assert frequency_limit([83.8], 300.0) == pytest.approx(92.18)
    assert frequency_limit([167.5], 150.0) == 150.0  # capped at Nyquist
    assert frequency_limit([2.0], 300.0) == 30.0  # at least a tenth of Nyquist
    assert frequency_limit([], 300.0) == 300.0
    assert log_frequency_axis([0.49, 0.63, 83.6]) and not log_frequency_axis([2.9, 83.8])


def test_a_wide_span_of_peaks_gets_a_log_axis_with_plain_numbers():
    e = explain_recording(_with_high_line(), "torque", RIG)
    fig = spectrum_figure(e)
    ax = fig.axes[0]
    assert ax.get_xscale() == "log"  # 0.5 Hz orders next to a 100 Hz line
    fig.canvas.draw()
    ticks = [t.get_text() for t in ax.get_xticklabels() if t.get_text()]
    assert "1" in ticks and "10" in ticks and not any("$" in t for t in ticks)
    plt.close(fig)
    fig = spectrum_figure(e, log_frequency=False)
    assert fig.axes[0].get_xscale() == "linear" and fig.axes[0].get_xlim()[0] == 0.0
    plt.close(fig)


def _order_map_with(kinds: dict[float, str], speeds=(5.0, 10.0, 20.0, 30.0)):
    """An order map of the orders at ``speeds`` [km/h], peaks attributed as ``kinds``
    (multiple of the roller's rotation frequency -> source kind); wheel/roller ratio 1.3."""
    import dataclasses

    from rollerrig.signal.spectra import order_map

    entries, sources = [], []
    for v in speeds:
        w_r = v / 3.6 / 0.452
        f_r = w_r / (2 * np.pi)
        entries.append((w_r, 1.3 * w_r, [m * f_r for m in kinds]))
        sources += list(kinds.values())
    omap = order_map(entries)
    return dataclasses.replace(omap, source=np.array(sources, dtype=object))


def test_order_map_draws_a_line_for_every_attributed_order():
    # The wheel's second order (2 x 1.3 f_r) and the PMSM's sixth (6 x 22 x 1.3 f_r) have no
    # line of their own in the order map's defaults.
    kinds = {1.0: "roller_order", 1.3: "wheel_order", 2.6: "wheel_order", 171.6: "pmsm_electrical"}
    omap = _order_map_with(kinds)
    assert not any(ln.label == "wheel order ×2" for ln in omap.lines)
    fig = order_map_figure(omap, roller_radius=0.452)
    ax = fig.axes[0]
    names = [t.get_text() for t in ax.texts]
    assert "wheel order ×2" in names and "PMSM electrical ×6" in names
    drawn = [ln for ln in ax.get_lines() if ln.get_gid() == "order-line"]
    assert len(drawn) == len(omap.lines) + 2
    plt.close(fig)


def test_order_map_names_its_lines_outside_the_axes_clear_of_points():
    kinds = {1.0: "roller_order", 1.3: "wheel_order", 2.0: "roller_order", 2.6: "wheel_order",
             5.0: "am_electrical", 10.0: "am_electrical", 28.6: "pmsm_electrical"}  # fmt: skip
    fig = order_map_figure(_order_map_with(kinds), roller_radius=0.452)
    ax = fig.axes[0]
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    names = [t.get_window_extent(renderer) for t in ax.texts]
    assert names
    for i, box in enumerate(names):
        assert box.x0 >= frame.x1 or box.y0 >= frame.y1  # right of or above the axes
        for other in names[:i]:
            assert not box.overlaps(other)
    legend = ax.get_legend().get_window_extent(renderer)
    assert legend.y1 <= frame.y0  # below the axes
    entries = [t.get_text() for t in ax.get_legend().get_texts()]
    assert entries == ["roller order", "wheel order", "AM electrical", "PMSM electrical"]
    assert ax.get_yscale() == "log"  # 0.5 Hz orders next to a 90 Hz motor line
    plt.close(fig)


def test_order_map_draws_order_lines_and_peaks():
    result = explain_recordings([_recording(v, seed=int(v)) for v in (10.0, 30.0)], "torque", RIG)
    omap = result.order_map()
    fig = order_map_figure(omap)
    ax = fig.axes[0]
    assert ax.get_xlabel() == "roller speed [rad/s]" and ax.get_ylabel() == "peak frequency [Hz]"
    kinds = list(dict.fromkeys(omap.source.tolist()))
    drawn = [ln for ln in ax.get_lines() if ln.get_gid() == "order-line"]
    assert len(drawn) >= len(omap.lines) and len(ax.get_lines()) == len(drawn) + len(kinds)
    assert [t.get_text() for t in ax.get_legend().get_texts()] == [source_name(k) for k in kinds]
    top = max(omap.frequency)
    assert ax.get_ylim()[1] == pytest.approx(1.1 * top)  # every peak shown
    plt.close(fig)


def test_order_map_with_a_given_limit_names_the_peaks_it_hides():
    omap = _order_map_with({1.0: "roller_order", 171.6: "pmsm_electrical"})
    fig = order_map_figure(omap, roller_radius=0.452, max_frequency=60.0)
    title = fig.axes[0].get_legend().get_title().get_text()
    hidden = sorted(f for f in omap.frequency if f > 60.0)
    assert title.startswith(f"{len(hidden)} listed peaks above the 60 Hz shown")
    assert f"{hidden[0]:.2f}" in title
    plt.close(fig)


def test_a_one_segment_coherence_is_not_drawn():
    """One segment gives γ² = 1 at every frequency: the figure draws neither the curve nor
    values at the peaks, and says why (the console and the tables withhold it too)."""
    from dataclasses import replace

    one = replace(_coherence(), n_segments=1)
    fig = coherence_figure(one, [14.67, 29.3], ["AM electrical ×1", "AM electrical ×2"])
    ax = fig.axes[0]
    assert ax.get_lines() == []  # no curve, no markers at γ² = 1
    text = _texts(fig)
    assert "γ² not estimated: one segment" in text and "γ² = 1.00" not in text
    assert "1 segment: γ² not estimated" in ax.get_title()
    plt.close(fig)
