"""Greedy label placement: no two label texts overlap, the first keeps its place, labels stay
inside the axes horizontally (renderer extents, not pixels of an image)."""

from __future__ import annotations

import matplotlib.pyplot as plt
from matplotlib.text import Text

from rollerrig.report.labels import label_extent, separate_labels


def _labels(ax, xs):
    kw = {"textcoords": ("data", "axes fraction"), "ha": "center", "va": "top", "fontsize": 8,
          "arrowprops": {"arrowstyle": "-"}}  # fmt: skip
    return [
        ax.annotate(f"{x:.2f} Hz\nlabel {i}", (x, 0.1), xytext=(x, 0.97), **kw)
        for i, x in enumerate(xs)
    ]


def test_labels_on_one_spot_are_stacked_in_order_without_overlap():
    fig, ax = plt.subplots(figsize=(6, 6))
    ax.set_xlim(0, 10)
    labels = _labels(ax, [5.0, 5.1, 4.9, 5.05, 8.0])
    fig.tight_layout()
    separate_labels(ax, labels)
    fig.canvas.draw()  # as a viewer sees it
    renderer = fig.canvas.get_renderer()
    boxes = [Text.get_window_extent(a, renderer) for a in labels]
    for i, a in enumerate(boxes):
        for b in boxes[:i]:
            assert not a.overlaps(b)
    assert labels[0].xyann == (5.0, 0.97)  # the first keeps the top row
    assert labels[4].xyann == (8.0, 0.97)  # one far enough away is not moved
    tops = [b.y1 for b in boxes[:4]]
    assert tops == sorted(tops, reverse=True)  # stacked downwards in the order given
    plt.close(fig)


def test_labels_at_the_edges_are_moved_inside_the_axes():
    fig, ax = plt.subplots(figsize=(4, 3))
    ax.set_xlim(0, 10)
    labels = _labels(ax, [0.0, 10.0])
    separate_labels(ax, labels)
    fig.canvas.draw()
    frame = ax.get_window_extent()
    for a in labels:
        box = label_extent(a)
        assert frame.x0 - 0.5 <= box.x0 and box.x1 <= frame.x1 + 0.5
    assert labels[0].xy == (0.0, 0.1)  # the leader still points at the peak
    plt.close(fig)


def test_no_labels_is_fine():
    fig, ax = plt.subplots()
    separate_labels(ax, [])
    plt.close(fig)
