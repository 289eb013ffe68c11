"""Frame figures: the deformed shape and the mode shapes, magnification stated."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pytest

from rollerrig.frame import analyze_frame, default_frame

pytest.importorskip("Pynite")

from rollerrig.report.frame import (
    _force_scale,
    auto_scale,
    deformed_shape_figure,
    mode_shape_figure,
)


@pytest.fixture(scope="module")
def result():
    return analyze_frame(default_frame(), 20e3, 2e3, n_modes=3)


def test_deformed_shape_states_the_scale_and_draws_every_member(result):
    fig, scale = deformed_shape_figure(result)
    ax = fig.axes[0]
    title = ax.get_title()
    assert f"displacements x {scale:g}" in title
    assert "N = 20 kN, F_x = 2 kN" in title
    assert f"top horizontal {result.top_horizontal_deflection * 1e3:.3f} mm" in title
    assert ax.get_xlabel() == "x [m]" and ax.get_zlabel() == "z [m]"
    # Two lines per member: undeformed (grey) and deformed.
    assert len(ax.get_lines()) == 2 * len(result.frame.members)
    # The deformed line of a member is the undeformed one moved by scale x displacement.
    m = result.frame.members["top_beam_left"]
    names = list(result.frame.members)
    deformed = ax.get_lines()[2 * names.index("top_beam_left") + 1]
    *_, zs = deformed.get_data_3d()
    tip = result.displacement(m.end)[:3]
    assert zs[-1] == pytest.approx(result.frame.nodes[m.end][2] + scale * tip[2])
    plt.close(fig)
    fig, fixed = deformed_shape_figure(result, scale=100.0)
    assert fixed == 100.0 and "displacements x 100 " in fig.axes[0].get_title()
    plt.close(fig)


def test_mode_shapes_one_panel_per_mode(result):
    fig, scales = mode_shape_figure(result, modes=3)
    titles = [ax.get_title() for ax in fig.axes]
    assert len(titles) == 3 and len(scales) == 3
    for i, (t, s) in enumerate(zip(titles, scales, strict=True)):
        assert t.startswith(f"mode {i + 1}: {result.frequencies[i]:.2f} Hz")
        assert f"shape x {s:g}" in t
    plt.close(fig)


def test_auto_scale_is_round_and_draws_a_visible_shape(result):
    s = auto_scale(result, result.displacements[:, :3])
    mantissa = s / 10 ** np.floor(np.log10(s))
    assert mantissa in (1.0, 2.0, 5.0)
    peak = np.max(np.linalg.norm(result.displacements[:, :3], axis=1))
    assert 0.05 < s * peak / 1.4 <= 0.12 + 1e-12  # 1.4 m: the default frame's largest side
    assert auto_scale(result, np.zeros((3, 3))) == 1.0


def _tick_label_boxes(fig):
    """Display boxes of every visible, non-empty tick label of every axis of ``fig``."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    boxes = []
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis, *((ax.zaxis,) if hasattr(ax, "zaxis") else ())):
            lo, hi = sorted(axis.get_view_interval())
            for tick in axis.get_major_ticks():  # those drawn: inside the axis' range
                label = tick.label1
                if lo <= tick.get_loc() <= hi and label.get_visible() and label.get_text():
                    boxes.append((label.get_text(), label.get_window_extent(renderer)))
    return boxes


@pytest.mark.parametrize("which", ["deformed", "modes"])
def test_no_tick_label_overprints_another(result, which):
    """Issue 23: the 3-D panels ran their tick labels into each other at the box's corners
    (x "0.8" on y "-0.6") and, three panels wide, along whole axes. Checked on the renderer's
    boxes, across panels too."""
    fig = deformed_shape_figure(result)[0] if which == "deformed" else mode_shape_figure(result)[0]
    boxes = _tick_label_boxes(fig)
    assert len(boxes) >= 6
    for i, (text, box) in enumerate(boxes):
        for other, obox in boxes[:i]:
            assert not box.overlaps(obox), (text, other)
    plt.close(fig)


def test_the_legend_says_what_the_arrows_are_and_their_scale(result):
    fig, scale = deformed_shape_figure(result)
    (legend,) = fig.legends
    entries = [t.get_text() for t in legend.get_texts()]
    assert f"deformed (displacements x {scale:g})" in entries
    (arrow,) = [e for e in entries if e.startswith("force on the frame")]
    assert arrow == "force on the frame (arrow 0.1 m = 10 kN)"  # N = 20 kN drawn as 0.2 m
    # The scale is round and draws the largest force (the air spring's 20 kN) at 0.2 m, 14 %
    # of the frame's 1.4 m: visible, and not longer than the frame's members.
    assert _force_scale(20e3, 1.4) == 100e3  # [N per m of arrow]
    assert _force_scale(20e3, 0.5) == 500e3 and _force_scale(0.0, 1.4) == 1.0
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    assert legend.get_window_extent(renderer).y1 <= fig.axes[0].get_window_extent(renderer).y0
    plt.close(fig)


def test_six_modes_in_two_readable_rows_titles_clear_of_the_row_above(result):
    """The review's frame-modes.png was 2753 px wide, four panels in a row, 7-point text: six
    modes are now two rows of three, under 12 inches (1800 px at 150 dpi), and no panel's title
    runs into the tick labels of the row above (tight_layout does not see 3-D labels)."""
    fig, scales = mode_shape_figure(result, modes=6, contact_mode=3)
    assert len(fig.axes) == len(scales) == 6
    assert fig.get_figwidth() <= 12.0
    rows = {round(ax.get_position().y0, 3) for ax in fig.axes}
    assert len(rows) == 2
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    titles = [ax.title.get_window_extent(renderer) for ax in fig.axes]
    for text, box in _tick_label_boxes(fig):
        for title in titles:
            assert not box.overlaps(title), text
    assert "the contact's longitudinal mode" in fig.axes[3].get_title()
    plt.close(fig)


def test_more_modes_than_panels_draw_the_first_and_the_contacts_and_say_so():
    """Of more modes than fit, the first ones and the contact's are drawn; the title names
    them, so that a reader knows which of the modes reported are missing."""
    nine = analyze_frame(default_frame(), 20e3, 2e3, n_modes=9)
    assert len(nine.frequencies) == 9
    fig, scales = mode_shape_figure(nine, modes=[*range(9), 99], contact_mode=7)
    titles = [ax.get_title() for ax in fig.axes]
    assert len(titles) == len(scales) == 6
    assert [t.split(":")[0] for t in titles] == [*(f"mode {i}" for i in range(1, 6)), "mode 8"]
    assert "natural modes 1-5, 8 of 1-9" in fig._suptitle.get_text()
    plt.close(fig)
    fig, _ = mode_shape_figure(nine, modes=[0, 1, 3])
    assert "natural modes\n" in fig._suptitle.get_text()  # all drawn: no list
    plt.close(fig)
