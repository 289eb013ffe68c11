"""Shared inputs of the report tests: one analysed adhesion test, built without the twin.

The recording is made in closed form (three ramp-hold-release cycles at 30 km/h on the
bundled rig's radii, CoA from a Polach-shaped curve, a motor line and noise on the torque), so
the analysis runs in well under a second and the report tests need no simulation.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from rollerrig.analysis.adhesion import analyze_test
from rollerrig.recordings.recording import Recording
from rollerrig.rig.parameters import default_rig

FS = 250.0  # [Hz]


def adhesion_test_recording(seed: int = 0) -> Recording:
    """24 s at 250 Hz: three cycles of creep 0 -> 4 % (3 s), hold 0.5 s, release (50 ms)."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(24 * FS)) / FS
    rr, rw, load, v = 0.452, 0.348, 4300.0, 30 / 3.6  # m, m, N, m/s
    creep = np.zeros_like(t)
    for t0 in (2.0, 10.0, 18.0):
        up = (t >= t0) & (t < t0 + 3.0)
        creep[up] = 0.04 * (t[up] - t0) / 3.0
        creep[(t >= t0 + 3.0) & (t < t0 + 3.5)] = 0.04
        rel = (t >= t0 + 3.5) & (t < t0 + 4.0)
        creep[rel] = 0.04 * np.exp(-(t[rel] - t0 - 3.5) / 0.05)
    eps = 40.0 * creep  # Polach's gradient of tangential stress, here in closed form
    coa = 2 * 0.45 / np.pi * (0.6 * eps / (1 + (0.6 * eps) ** 2) + np.arctan(0.3 * eps))
    torque = (
        coa * load * rr + 3.0 * np.sin(2 * np.pi * 14.67 * t) + 2.0 * rng.standard_normal(t.size)
    )
    return Recording(
        t,
        {
            "torque": torque,
            "torque_request": coa * load * rw,
            "wheel_speed": v * (1 + creep) / rw,
            "roller_speed": np.full(t.size, v / rr),
            "normal_load": np.full(t.size, load),
        },
        {
            "torque": "N.m",
            "torque_request": "N.m",
            "wheel_speed": "rad/s",
            "roller_speed": "rad/s",
            "normal_load": "N",
        },
        {"source": "synthetic-test.csv"},
    )


@pytest.fixture(scope="session")
def analysed():
    """:class:`rollerrig.analysis.adhesion.TestAnalysis` of :func:`adhesion_test_recording`."""
    return analyze_test(adhesion_test_recording(), default_rig())


@pytest.fixture(scope="session")
def written(analysed, tmp_path_factory):
    """The files :func:`rollerrig.report.analysis.write_analysis` writes: json, nc, html."""
    from rollerrig.report.analysis import write_analysis

    out = tmp_path_factory.mktemp("analysis")
    return write_analysis(analysed, out, "synthetic", source="synthetic-test.csv")


def _marker_boxes(ax, renderer):
    """Display boxes [pixels] of every marker drawn in ``ax`` (lines with a marker)."""
    from matplotlib.transforms import Bbox

    boxes = []
    for line in ax.get_lines():
        if line.get_marker() in (None, "None", "", " "):
            continue
        half = line.get_markersize() * ax.figure.dpi / 72.0 / 2.0
        xy = np.column_stack([line.get_xdata(), line.get_ydata()]).astype(float)
        for x, y in ax.transData.transform(xy[np.isfinite(xy).all(axis=1)]):
            boxes.append(Bbox.from_extents(x - half, y - half, x + half, y + half))
    return boxes


def _crosses(box, path: np.ndarray) -> bool:
    """Whether the polyline ``path`` [pixels] passes through ``box`` (sampled finely)."""
    for a, b in itertools.pairwise(path):
        s = np.linspace(0.0, 1.0, 200)[:, None]
        pts = a + s * (b - a)
        inside = (
            (pts[:, 0] > box.x0)
            & (pts[:, 0] < box.x1)
            & (pts[:, 1] > box.y0)
            & (pts[:, 1] < box.y1)
        )
        if inside.any():
            return True
    return False


def check_peak_labels(fig, ax=None, *, curve=None) -> list:
    """Assert what a viewer of a labelled spectrum needs, from the renderer's extents.

    The peak labels' boxes (:data:`rollerrig.report.labels.LABEL_GID`) overlap no other label,
    no marker, and lie above every point of ``curve`` (a Line2D; default the first line of the
    axes) within their x-span; they stay inside the axes; every label has its leader, no
    leader passes through another label, leaders are drawn above the curve and below the
    markers. Returns the label boxes.
    """
    from rollerrig.report.labels import LABEL_GID, LEADER_GID

    ax = ax or fig.axes[0]
    fig.canvas.draw()  # as a viewer sees it
    renderer = fig.canvas.get_renderer()
    labels = [t for t in ax.texts if t.get_gid() == LABEL_GID]
    boxes = [t.get_bbox_patch().get_window_extent(renderer) for t in labels]
    frame = ax.get_window_extent(renderer)
    for i, a in enumerate(boxes):
        assert frame.x0 - 0.5 <= a.x0 and a.x1 <= frame.x1 + 0.5, (a, frame)
        assert frame.y0 <= a.y0 and a.y1 <= frame.y1 + 0.5, (a, frame)
        for b in boxes[:i]:
            assert not a.overlaps(b), (labels[i].get_text(), a, b)
    for m in _marker_boxes(ax, renderer):
        for t, b in zip(labels, boxes, strict=True):
            assert not b.overlaps(m), (t.get_text(), b, m)
    curve = curve or ax.get_lines()[0]
    xy = ax.transData.transform(np.column_stack([curve.get_xdata(), curve.get_ydata()]))
    xy = xy[np.isfinite(xy).all(axis=1)]
    for t, b in zip(labels, boxes, strict=True):
        span = (xy[:, 0] >= b.x0) & (xy[:, 0] <= b.x1)
        edges = np.interp([b.x0, b.x1], xy[:, 0], xy[:, 1])
        assert max(xy[span, 1].max(initial=-np.inf), *edges) < b.y0, t.get_text()
    leaders = [ln for ln in ax.get_lines() if ln.get_gid() == LEADER_GID]
    assert len(leaders) == len(labels)
    markers = [ln for ln in ax.get_lines() if ln.get_marker() == "v"]
    for leader in leaders:
        assert curve.get_zorder() < leader.get_zorder()
        assert all(leader.get_zorder() < m.get_zorder() for m in markers)
        assert leader.get_visible() and leader.get_alpha() in (None, 1.0)
    paths = [ax.transData.transform(np.column_stack(ln.get_data())) for ln in leaders]
    for i, b in enumerate(boxes):
        for j, path in enumerate(paths):
            if i != j:
                assert not _crosses(b, path), (labels[i].get_text(), j)
    return boxes


@pytest.fixture(scope="session")
def peak_labels_clear():
    """:func:`check_peak_labels`, for the tests of the labelled figures."""
    return check_peak_labels
