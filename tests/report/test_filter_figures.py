"""Filter-study figures say at which rate their windows count samples, and long signals are
drawn as their envelope (bounded points, every excursion kept)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from rollerrig.report.analysis import _params_at
from rollerrig.report.filters import (
    envelope,
    filter_comparison_figure,
    savitzky_golay_grid_figure,
    study_ranking_figure,
)
from rollerrig.signal.scoring import prepare_study_signal, seed_like_torque


def test_envelope_keeps_every_excursion_within_the_point_budget():
    rng = np.random.default_rng(0)
    t = np.arange(1_000_003) / 1000.0
    y = rng.standard_normal(t.size)
    y[123_457], y[987_654] = 40.0, -40.0  # single-sample spikes
    xs, ys = envelope(t, y, 2000)
    assert ys.size <= 2004 and np.all(np.diff(xs) > 0)  # time order, no duplicates
    assert ys.max() == 40.0 and ys.min() == -40.0
    assert xs[0] == t[0] and xs[-1] == t[-1]  # spans the whole signal
    short = np.arange(10.0)
    assert envelope(short, short, 2000)[1] is short  # short lines drawn as they are


def test_figures_of_a_decimated_study_say_the_rate_of_their_windows():
    sig = seed_like_torque(sample_rate=2000.0, duration=20.0)
    study = prepare_study_signal(sig.time, sig.raw)  # 2 kHz -> 250 Hz
    _, _, grid = study.tune_savitzky_golay(orders=[2, 4], windows=[33, 111])
    fig = savitzky_golay_grid_figure(grid)
    assert fig.axes[0].get_xlabel() == (
        "window [samples at 250 Hz, the recording's 2000 Hz decimated]"
    )
    plt.close(fig)
    rows = study.filter_study([("moving_average", {"window": 33})])
    fig = study_ranking_figure(rows)
    assert "samples at 250 Hz" in fig.axes[0].get_title()
    plt.close(fig)
    # A study row's window at 250 Hz is the same span at the signal's 2 kHz (made odd).
    assert _params_at(rows[0], 2000.0)["window"] == 257
    assert _params_at(rows[0], 250.0)["window"] == 33


def test_comparison_figure_of_a_long_signal_draws_bounded_points():
    t = np.arange(600_000) / 1000.0
    raw = np.sin(t) + 0.1 * np.cos(50 * t)
    fig = filter_comparison_figure(
        t, raw, {"smooth": np.sin(t)}, steady_window=(10.0, 12.0), transient_window=(300, 301)
    )
    counts = [line.get_xdata().size for ax in fig.axes for line in ax.get_lines()]
    assert max(counts) <= 20_004
    zoom = fig.axes[1].get_lines()[0].get_xdata()
    assert zoom.min() >= 9.99 and zoom.max() <= 12.01  # a zoom holds only its window
    plt.close(fig)
