"""The order map as a Campbell diagram (the twin's coupled modes with their damping, and the
speeds where an order line crosses a mode), and one frequency-axis convention for the spectra
of one set (issue 23, point 4)."""

from __future__ import annotations

from types import SimpleNamespace as NS

import matplotlib.pyplot as plt
import numpy as np
import pytest

from rollerrig.recordings.recording import Recording
from rollerrig.report.spectra import (
    coherence_figure,
    log_frequency_axis,
    order_map_figure,
    resonance_speeds,
    shared_log_frequency,
    spectrum_figure,
)
from rollerrig.rig.linear import coupled_modes
from rollerrig.rig.parameters import default_rig
from rollerrig.signal.spectra import order_map
from rollerrig.signal.workflow import explain_recordings

RIG = default_rig()
R_ROLLER = 0.452  # [m], Kayaalp's roller
FS = 250.0  # [Hz]


@pytest.fixture(scope="module")
def modes():
    return coupled_modes(RIG, 30 / 3.6, 4.3e3)


def _omap():
    """Order map of two recordings (5 and 30 km/h) with the AM lines x1..x3 (p = 5)."""
    entries = []
    for v in (5.0, 30.0):
        w_r = v / 3.6 / R_ROLLER
        entries.append((w_r, 1.3 * w_r, [5 * w_r / (2 * np.pi)]))
    return order_map(entries)


def test_the_am_line_crosses_the_shaft_mode_at_the_closed_form_speed(modes):
    """An AM harmonic k is f = k p ω_r / 2π (p = 5 pole pairs; the electrical frequency is p
    times the rotation's, Kayaalp section 4.5.2.4): it meets a mode at f_m at
    ω_r = 2π f_m / (k p). The roller-shaft mode (13.78 Hz on the bundled rig) is met by AM x1
    at 28.2 km/h, x2 at 14.1 km/h, x3 at 9.4 km/h."""
    shaft = next(md for md in modes.ringing if 13.0 < md.frequency < 14.5)
    found = {r.line: r for r in resonance_speeds(_omap(), modes) if r.mode_frequency > 13.0}
    for k in (1, 2, 3):
        expected = 2 * np.pi * shaft.frequency / (k * 5)  # [rad/s]
        r = found[f"AM electrical ×{k}"]
        assert r.speed == pytest.approx(expected, rel=1e-12)
        assert r.damping_ratio == (shaft.damping_ratio, shaft.damping_ratio)
    assert found["AM electrical ×1"].speed * 3.6 * R_ROLLER == pytest.approx(28.2, abs=0.05)
    # A crossing beyond the map's speed range (AM x1 at 110.8 Hz: 227 km/h) is not one.
    assert all(r.speed <= _omap().speed_grid[-1] for r in resonance_speeds(_omap(), modes))


def test_a_mode_matched_over_operating_points_states_its_damping_range():
    low = NS(ringing=(NS(frequency=13.775, damping_ratio=0.0022),))
    high = NS(ringing=(NS(frequency=13.779, damping_ratio=0.0039),))
    (r, *_) = resonance_speeds(_omap(), [low, high])
    assert r.mode_frequency == pytest.approx(13.777)  # the median of the points
    assert r.damping_ratio == (0.0022, 0.0039)


def test_the_campbell_diagram_draws_modes_with_damping_and_circles_the_crossings(modes):
    omap = _omap()
    fig = order_map_figure(omap, roller_radius=R_ROLLER, modes=modes)
    ax = fig.axes[0]
    assert ax.get_title().startswith("Campbell diagram")
    mode_lines = [ln for ln in ax.get_lines() if ln.get_gid() == "mode"]
    top = ax.get_ylim()[1]
    drawn = [md for md in modes.ringing if md.frequency <= top]
    assert len(mode_lines) == len(drawn) >= 2  # 0.81 and 13.78 Hz; 110.8 Hz is above
    assert [ln.get_ydata()[0] for ln in mode_lines] == pytest.approx([md.frequency for md in drawn])
    names = [t.get_text() for t in ax.texts]
    for md in drawn:
        assert f"mode {md.frequency:.2f} Hz, ζ {md.damping_ratio:.2g}" in names
    (circles,) = [ln for ln in ax.get_lines() if ln.get_gid() == "resonance"]
    expected = [r for r in resonance_speeds(omap, modes) if r.mode_frequency <= top]
    assert circles.get_xdata() == pytest.approx([r.speed * 3.6 * R_ROLLER for r in expected])
    small = ax.get_legend().get_title().get_text().replace("\n", " ")
    assert "AM electrical ×1 28.2" in small  # km/h, the closed form above
    assert "twin modes outside the range shown: 110.79 Hz, ζ 0.028" in small  # the one above, named
    entries = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "twin mode (ζ: damping ratio)" in entries and "order line crosses a mode" in entries
    plt.close(fig)


def test_without_modes_the_map_is_an_order_map():
    fig = order_map_figure(_omap(), roller_radius=R_ROLLER)
    ax = fig.axes[0]
    assert ax.get_title().startswith("order map")
    assert not [ln for ln in ax.get_lines() if ln.get_gid() in ("mode", "resonance")]
    plt.close(fig)


def _free_rolling(v: float, seed: int) -> Recording:
    """A roller order and an 83 Hz motor line at ``v`` [km/h], 60 s at 250 Hz."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(60 * FS)) / FS
    w_r = v / 3.6 / R_ROLLER
    torque = 3 * np.sin(w_r * t) + np.sin(2 * np.pi * 83.0 * t) + 0.3 * rng.standard_normal(t.size)
    laser = np.sin(w_r * t) + rng.standard_normal(t.size)
    return Recording(
        t,
        {"torque": torque, "laser": laser, "roller_speed": np.full(t.size, w_r),
         "wheel_speed": np.full(t.size, v / 3.6 / 0.348)},
        {"torque": "N.m", "laser": "m", "roller_speed": "rad/s", "wheel_speed": "rad/s"},
        {"source": f"free-rolling-{v:g}kmh.csv"},
    )  # fmt: skip


def test_the_spectra_of_one_set_share_one_frequency_axis():
    """At 5 km/h the roller order (0.49 Hz) and the 83 Hz line span a factor 170 (log on its
    own); at 30 km/h 2.9 to 83 Hz (linear on its own). Side by side both are logarithmic."""
    result = explain_recordings(
        [_free_rolling(5.0, 1), _free_rolling(30.0, 2)], "torque", RIG, coherence_with="laser"
    )
    alone = [log_frequency_axis([r.frequency for r in e.rows]) for e in result.spectra]
    assert alone == [True, False]  # the mixed report of issue 23
    log = shared_log_frequency(result.spectra)
    assert log is True
    for e in result.spectra:
        fig = spectrum_figure(e, log_frequency=log)
        assert fig.axes[0].get_xscale() == "log"
        assert fig.axes[0].get_title().startswith(f"{e.source}, torque")  # names the recording
        plt.close(fig)
        fig = coherence_figure(e.coherence, [r.frequency for r in e.rows], log_frequency=log)
        assert fig.axes[0].get_xscale() == "log"
        plt.close(fig)
    fast = [e for e in result.spectra if e.roller_speed > 10]
    assert shared_log_frequency(fast) is False  # a set that needs none gets none
