"""Peak labels in a headroom band: spread apart in the order of their peaks (least-squares
displacement), above the data (no marker, no curve under a label), each tied to its peak by a
visible leader (renderer extents, not pixels of an image)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rollerrig.report.labels import LABEL_GID, PeakLabel, label_peaks, spread


def test_spread_keeps_apart_intervals_where_they_are():
    assert spread([1.0, 5.0, 9.0], [2.0, 2.0, 2.0], 0.0, 10.0).tolist() == [1.0, 5.0, 9.0]
    assert spread([], [], 0.0, 1.0).size == 0


def test_spread_moves_a_cluster_symmetrically_and_inside_the_room():
    out = spread([5.0, 5.0, 5.0], [2.0, 2.0, 2.0], 0.0, 10.0, pad=1.0)
    assert out.tolist() == [2.0, 5.0, 8.0]  # least squares: centred on the cluster
    out = spread([0.0, 0.1], [2.0, 2.0], 0.0, 10.0)  # at the edge: pushed inside
    assert out.tolist() == [1.0, 3.0]


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.floats(0.0, 100.0), min_size=1, max_size=30),
    st.floats(0.5, 5.0),
)
def test_spread_never_overlaps_and_keeps_the_order(centres, width):
    widths = np.full(len(centres), width)
    out = spread(centres, widths, 0.0, 200.0, pad=0.5)
    order = np.argsort(np.asarray(centres), kind="stable")
    placed = out[order]
    assert np.all(np.diff(placed) >= width + 0.5 - 1e-9)  # no overlap, order kept
    assert placed[0] - width / 2 >= -1e-9 and placed[-1] + width / 2 <= 200.0 + 1e-9


def _spectrum(ax, peaks):
    """A spiky log spectrum on 0-100 with lines at ``peaks`` [Hz]."""
    f = np.linspace(0.0, 100.0, 2001)
    p = np.full(f.size, 1e-4)
    for k, fc in enumerate(peaks):
        p[np.argmin(abs(f - fc))] = 10.0 / (1 + k)
    ax.semilogy(f, p, color="0.3", zorder=2)
    ax.set_xlim(0.0, 100.0)
    ax.set_ylim(1e-5, 100.0)
    heights = [10.0 / (1 + k) for k in range(len(peaks))]
    for x, y in zip(peaks, heights, strict=True):
        ax.plot(x, y, "v", ms=6, zorder=6)
    return heights


@pytest.mark.parametrize("size", [(9.0, 4.5), (5.0, 2.5)])
def test_crowded_labels_clear_markers_curve_and_each_other(size, peak_labels_clear):
    fig, ax = plt.subplots(figsize=size)
    peaks = [1.0, 1.2, 1.4, 2.0, 2.1, 30.0, 30.5, 99.5]
    heights = _spectrum(ax, peaks)
    fig.tight_layout()
    labels = [
        PeakLabel(x, y, f"{x:.2f} Hz\nsource {i}")
        for i, (x, y) in enumerate(zip(peaks, heights, strict=True))
    ]
    texts = label_peaks(ax, labels, data_top=max(heights))
    assert len(texts) == len(peaks)
    boxes = peak_labels_clear(fig, ax)
    # Side by side in the order of their peaks.
    assert [b.x0 for b in boxes] == sorted(b.x0 for b in boxes)
    plt.close(fig)


def test_a_small_figure_grows_to_keep_room_for_the_data():
    fig, ax = plt.subplots(figsize=(6.0, 1.6))
    heights = _spectrum(ax, [10.0, 50.0])
    fig.tight_layout()
    label_peaks(ax, [PeakLabel(10.0, heights[0], "a long label\nat 10 Hz")], data_top=10.0)
    frame = ax.get_window_extent()
    top_of_data = ax.transData.transform((10.0, 10.0))[1]
    assert fig.get_figheight() > 1.6
    assert top_of_data - frame.y0 >= 0.49 * frame.height  # the data keep half the axes
    plt.close(fig)


def test_labels_that_do_not_fit_side_by_side_are_left_out_least_important_first():
    fig, ax = plt.subplots(figsize=(3.0, 3.0))
    heights = _spectrum(ax, [50.0])
    fig.tight_layout()
    labels = [PeakLabel(50.0, heights[0], f"label number {i}\nsecond line") for i in range(40)]
    texts = label_peaks(ax, labels, data_top=heights[0])
    assert 1 <= len(texts) < 40
    assert [t.get_text() for t in texts] == [lab.text for lab in labels[: len(texts)]]
    assert len([t for t in ax.texts if t.get_gid() == LABEL_GID]) == len(texts)
    plt.close(fig)


def test_a_frequency_without_a_peak_gets_a_line_to_the_axis():
    fig, ax = plt.subplots()
    _spectrum(ax, [20.0])
    fig.tight_layout()
    label_peaks(ax, [PeakLabel(40.0, None, "mode 40 Hz", "tab:brown", ":")], data_top=10.0)
    (leader,) = [ln for ln in ax.get_lines() if ln.get_gid() == "peak-leader"]
    assert leader.get_linestyle() == ":"
    assert leader.get_ydata()[-1] == pytest.approx(ax.get_ylim()[0])  # down to the axis
    plt.close(fig)


def test_no_labels_is_fine():
    fig, ax = plt.subplots()
    assert label_peaks(ax, [], data_top=1.0) == []
    plt.close(fig)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (([1.0, 2.0, 3.0], [1.0, 2.0], 0.0, 10.0), r"centres \(shape \(3,\)\) and widths"),
        ((["ab"], [1.0], 0.0, 10.0), "centres must be numbers, got text"),
        (([np.nan], [1.0], 0.0, 10.0), "centres must be finite"),
        (([1.0], [-1.0], 0.0, 10.0), "widths must be >= 0"),
        (([1.0], [1.0], np.nan, 10.0), "lo must be finite"),
        (([1.0], [1.0], 0.0, 10.0, -1.0), "pad must be >= 0"),
    ],
)
def test_spread_refuses_bad_input_naming_it(args, message):
    """Mismatched lengths had been a bare IndexError, text numpy's ValueError; NaN gave NaN
    centres and a negative width overlapping labels."""
    from rollerrig._validation import ParameterError

    with pytest.raises(ParameterError, match=message):
        spread(*args)
