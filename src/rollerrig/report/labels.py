"""Peak labels in a band above the data: never on a marker, on the curve or on one another.

A spectrum's peaks crowd where the orders of a slow rotation sit (0.5-15 Hz at 5 km/h), and
a label hung where its peak is would cover its neighbours' markers and the curve. Here every
label is a short vertical text in one row in a *headroom band* at the top of the axes, and
the y-axis is extended so that the highest point of the data (and the markers on it) stays
below the band: no label can cover a marker or the curve. The labels are spread sideways, in
the order of their peaks, just enough not to touch (the least-squares displacement,
:func:`spread`), and each is tied to its peak by a leader line: down from the label, a slanted
step to the peak's frequency, down to just above the marker (the layout of line
identifications in astronomical spectra). Leader lines are drawn above the curve and below
the markers; no label box lies on any leader.

Everything is computed from the rendered sizes of the texts (any font, text or figure size),
without extra dependencies.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from matplotlib.text import Text
from matplotlib.transforms import Bbox

from rollerrig._validation import ParameterError, require_finite, require_nonnegative
from rollerrig.output.figures import crop_when_saved

__all__ = ["LABEL_GID", "LEADER_GID", "PeakLabel", "label_extent", "label_peaks", "spread"]

LABEL_GID = "peak-label"
"""``gid`` of the texts :func:`label_peaks` draws (to find them in a figure)."""

LEADER_GID = "peak-leader"
"""``gid`` of the leader lines :func:`label_peaks` draws."""

_HINTING = 1.1  # rendered text sizes vary by up to ~7 % with the dpi [-]


@dataclass(frozen=True)
class PeakLabel:
    """What to label, in data coordinates.

    Attributes
    ----------
    x : float
        Position of the peak on the x-axis [data units].
    y : float or None
        Height of the peak [data units]; the leader ends just above its marker. ``None``: not a
        peak but a frequency (e.g. a rig mode), and the leader runs down to the bottom of the
        axes.
    text : str
        The label.
    colour : str
        Colour of the text and of the leader.
    linestyle : str
        Line style of the leader.
    """

    x: float
    y: float | None
    text: str
    colour: str = "k"
    linestyle: str = "-"


def label_extent(label: Text, renderer=None) -> Bbox:
    """Display-coordinate box [pixels] of a text (of an annotation: its text only)."""
    renderer = renderer or label.figure.canvas.get_renderer()
    update = getattr(label, "update_positions", None)
    if update is not None:  # an annotation: its text's transform, before any draw
        update(renderer)
    return Text.get_window_extent(label, renderer)


def spread(centres, widths, lo: float, hi: float, pad: float = 0.0) -> np.ndarray:
    """Centres of intervals moved apart: no two overlap, all inside ``[lo, hi]``, order kept.

    Among all placements that keep the intervals in the order of their ``centres``, at least
    ``pad`` apart and inside ``[lo, hi]``, this is the one with the least sum of squared
    displacements (pool-adjacent-violators on the left edges). Intervals that do not touch
    are not moved. When they cannot all fit, they are packed from ``lo`` and overflow ``hi``.

    Parameters
    ----------
    centres : array_like, shape (n,)
        Wanted centres [any length unit, e.g. pixels].
    widths : array_like, shape (n,)
        Widths of the intervals [same unit].
    lo, hi : float
        Room available [same unit].
    pad : float
        Least gap between neighbours [same unit].

    Returns
    -------
    ndarray, shape (n,)
        The centres, in the order given.

    Examples
    --------
    >>> spread([5.0, 5.0], [2.0, 2.0], 0.0, 10.0).tolist()
    [4.0, 6.0]
    >>> spread([0.5, 9.0], [2.0, 2.0], 0.0, 10.0).tolist()  # inside the room, not moved apart
    [1.0, 9.0]
    """
    # Mismatched lengths had reached a bare IndexError, text numpy's ValueError; NaN had
    # given NaN centres and a negative width overlapping labels.
    c = require_finite("centres", centres)
    w = require_nonnegative("widths", widths)
    if c.ndim != 1 or w.shape != c.shape:
        raise ParameterError(
            f"centres (shape {c.shape}) and widths (shape {w.shape}) must be 1-D arrays of the "
            "same length"
        )
    lo = require_finite("lo", lo, single=True)
    hi = require_finite("hi", hi, single=True)
    pad = require_nonnegative("pad", pad, single=True)
    if c.size == 0:
        return c.copy()
    order = np.argsort(c, kind="stable")
    cs, ws = c[order], w[order]
    offset = np.concatenate([[0.0], np.cumsum(ws[:-1] + pad)])  # left edge i = y_i + offset_i
    y = _non_decreasing(cs - ws / 2.0 - offset)  # least squares with y non-decreasing
    total = offset[-1] + ws[-1]
    y = np.clip(y, lo, max(lo, hi - total))
    out = np.empty_like(c)
    out[order] = y + offset + ws / 2.0
    return out


def _non_decreasing(values: np.ndarray) -> np.ndarray:
    """Least-squares non-decreasing fit (pool adjacent violators)."""
    blocks: list[list[float]] = []  # [sum, count]
    for v in values:
        blocks.append([float(v), 1.0])
        while len(blocks) > 1 and blocks[-2][0] / blocks[-2][1] > blocks[-1][0] / blocks[-1][1]:
            s, n = blocks.pop()
            blocks[-1][0] += s
            blocks[-1][1] += n
    return np.concatenate([np.full(int(n), s / n) for s, n in blocks])


def label_peaks(
    ax,
    labels: Sequence[PeakLabel],
    *,
    data_top: float,
    fontsize: float = 7.0,
    marker_size: float = 6.0,
    min_data_fraction: float = 0.5,
    pad: float = 2.0,
) -> list[Text]:
    """Label peaks in one row of vertical texts in a headroom band at the top of ``ax``.

    Sets the top of the y-axis so that ``data_top`` (the highest point of everything drawn in
    the axes' x-range), plus half a marker, lies below the band, and grows the figure's height
    (and re-runs ``tight_layout``) if the data would get less than ``min_data_fraction`` of the
    axes' height. The bottom of the y-axis is kept. Labels are spread sideways in the order of
    their peaks (:func:`spread`); when they cannot all fit side by side the last ones (least
    important) are left out, and their peaks keep their markers.

    Call it last, after ``tight_layout`` and the x-limits: it works on rendered sizes.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes (linear or log y).
    labels : sequence of PeakLabel
        The labels, most important first.
    data_top : float
        Highest value drawn in the axes [data units of y]; > 0 on a log axis.
    fontsize : float
        Size of the label texts [pt].
    marker_size : float
        Size of the peak markers [pt] (the leader stops above them).
    min_data_fraction : float
        Least share of the axes' height left to the data, in (0, 1).
    pad : float
        Gap between neighbouring labels [pixels].

    Returns
    -------
    list of matplotlib.text.Text
        The labels drawn, in the order given (``gid`` :data:`LABEL_GID`; their leaders are
        lines with ``gid`` :data:`LEADER_GID`).

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> fig, ax = plt.subplots()
    >>> _ = ax.plot([4.9, 5.0, 5.1, 5.2, 5.3], [0.1, 1.0, 0.1, 0.8, 0.1])
    >>> _ = ax.set_xlim(0, 10)
    >>> texts = label_peaks(ax, [PeakLabel(5.0, 1.0, "peak A"), PeakLabel(5.2, 0.8, "peak B")],
    ...                     data_top=1.0)
    >>> r = fig.canvas.get_renderer()
    >>> a, b = (label_extent(t, r) for t in texts)
    >>> bool(a.x1 < b.x0)  # side by side, in the order of their peaks
    True
    >>> bool(min(a.y0, b.y0) > ax.transData.transform((5.0, 1.0))[1])  # above the data
    True
    >>> plt.close(fig)
    """
    if not labels:
        return []
    fig = ax.figure
    dpi = fig.dpi
    texts = [
        ax.text(
            lab.x,
            1.0,
            lab.text,
            transform=ax.get_xaxis_transform(),
            rotation=90,
            ha="center",
            va="bottom",
            fontsize=fontsize,
            color=lab.colour,
            zorder=5,
            gid=LABEL_GID,
            clip_on=False,
            bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.85},
        )
        for lab in labels
    ]
    for t in texts:
        t.set_in_layout(False)  # inside the axes once placed: no room to be made for them
    renderer = fig.canvas.get_renderer()
    sizes = [label_extent(t, renderer) for t in texts]
    box_pad = 0.1 * fontsize * dpi / 72.0  # the white box around each text [pixels]
    # Sizes with a margin: font hinting makes a text up to ~7 % larger at another dpi (a
    # figure saved at 150 dpi is laid out at 100).
    widths = _HINTING * np.array([s.width for s in sizes]) + 2 * box_pad
    depth = _HINTING * max(s.height for s in sizes) + 2 * box_pad  # of the row [pixels]
    marker = marker_size * dpi / 72.0  # [pixels]
    stub, top_pad, gap = 3.0, 3.0, 3.0  # [pixels]
    fan = 24.0  # height of the slanted part of the leaders [pixels]
    band = top_pad + depth + stub + fan  # the headroom band [pixels]
    frame = ax.get_window_extent(renderer)
    below = band + marker / 2.0 + gap  # what the data may not enter [pixels]
    if frame.height - below < min_data_fraction * frame.height:
        # Too little room for the data: a taller figure (the texts keep their size).
        grow = below / (1.0 - min_data_fraction) - frame.height
        fig.set_figheight(fig.get_figheight() + grow / dpi)
        fig.tight_layout()
        renderer = fig.canvas.get_renderer()
        frame = ax.get_window_extent(renderer)

    # Labels side by side in the order of their peaks; the least important left out if the
    # row is too long for the axes.
    keep = len(labels)
    while keep > 1 and widths[:keep].sum() + pad * (keep - 1) > frame.width - 2.0:
        keep -= 1
    for t in texts[keep:]:
        t.remove()
    texts, labels, widths = texts[:keep], list(labels)[:keep], widths[:keep]
    px = np.array([ax.transData.transform((lab.x, 1.0))[0] for lab in labels])
    px = np.clip(px, frame.x0, frame.x1)
    centres = spread(px, widths, frame.x0 + 1.0, frame.x1 - 1.0, pad)

    # The y-axis: data_top, plus half a marker and a gap, at the bottom of the band.
    data_height = frame.height - below
    share = data_height / frame.height
    lo = ax.get_ylim()[0]
    if ax.get_yscale() == "log":
        top = 10.0 ** (np.log10(lo) + (np.log10(data_top) - np.log10(lo)) / share)
    else:
        top = lo + (data_top - lo) / share
    ax.set_ylim(lo, top)

    bottom = frame.y1 - top_pad - depth  # of the label boxes [pixels]
    y_text = (bottom + box_pad - frame.y0) / frame.height  # axes fraction
    to_data = ax.transData.inverted()
    for t, lab, xc, xp in zip(texts, labels, centres, px, strict=True):
        x_data = float(to_data.transform((xc, frame.y0))[0])
        t.set_position((x_data, y_text))
        if lab.y is None:
            end = frame.y0
        else:
            end = ax.transData.transform((lab.x, lab.y))[1] + marker / 2.0 + 1.0
        ys = [bottom - 1.0, bottom - stub, bottom - stub - fan, min(end, bottom - stub - fan)]
        xs = [xc, xc, xp, xp]
        pts = to_data.transform(np.column_stack([xs, ys]))
        ax.plot(
            pts[:, 0],
            pts[:, 1],
            color=lab.colour,
            lw=0.7,
            ls=lab.linestyle,
            zorder=3,  # above the curve (2), below the label texts (5) and markers (6)
            gid=LEADER_GID,
            clip_on=False,
            scalex=False,
            scaley=False,
        )
    # the labels are placed after the layout and may reach past the axes: crop to them
    crop_when_saved(ax.figure)
    return texts
