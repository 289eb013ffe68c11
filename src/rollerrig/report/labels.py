"""Peak labels that do not overlap: greedy placement in display coordinates.

The spectrum and coherence figures hang one label per peak from the top of the axes, each with
a leader line to its peak. Neighbouring peaks would put their labels on top of each other;
:func:`separate_labels` moves each label, most important first, down below every label it
would overlap, and inside the axes horizontally. It works on the rendered sizes of the texts
(so any font, label length or figure size), without extra dependencies.
"""

from __future__ import annotations

from collections.abc import Sequence

from matplotlib.text import Annotation, Text
from matplotlib.transforms import Bbox

__all__ = ["label_extent", "separate_labels"]


def label_extent(label: Annotation, renderer=None) -> Bbox:
    """Display-coordinate box [pixels] of the text of ``label`` (its leader line excluded)."""
    renderer = renderer or label.figure.canvas.get_renderer()
    label.update_positions(renderer)  # the text's transform, before any draw
    return Text.get_window_extent(label, renderer)


def separate_labels(ax, labels: Sequence[Annotation], *, pad: float = 2.0) -> None:
    """Move ``labels`` so that no two of their texts overlap, in the given order of priority.

    Each label is placed, in turn, where it is unless it sticks out of the axes (then it is
    shifted sideways inside them) or overlaps a label placed before it: then it moves down
    below the lowest of those, by that label's depth plus ``pad``, until it overlaps none. The
    first labels keep the top row, so give them most important first.

    The labels must be annotations whose text position is in ``textcoords=("data", "axes
    fraction")`` (x at the peak, y as a fraction of the axes' height). Call this after the
    figure's layout is final (after ``tight_layout``): the placement uses rendered sizes.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes the labels belong to.
    labels : sequence of matplotlib.text.Annotation
        The labels, most important first.
    pad : float
        Gap between stacked labels [pixels].

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> fig, ax = plt.subplots()
    >>> ax.set_xlim(0, 10)
    (0.0, 10.0)
    >>> kw = dict(textcoords=("data", "axes fraction"), ha="center", va="top")
    >>> a = ax.annotate("peak A", (5.0, 0.5), xytext=(5.0, 0.97), **kw)
    >>> b = ax.annotate("peak B", (5.2, 0.5), xytext=(5.2, 0.97), **kw)
    >>> separate_labels(ax, [a, b])
    >>> r = fig.canvas.get_renderer()
    >>> bool(label_extent(b, r).y1 < label_extent(a, r).y0)
    True
    >>> plt.close(fig)
    """
    if not labels:
        return
    renderer = ax.figure.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    height = frame.height or 1.0
    placed: list[Bbox] = []
    for label in labels:
        box = label_extent(label, renderer)
        # Inside the axes horizontally: shift by the overhang, in data units of x.
        shift = max(frame.x0 - box.x0, 0.0) or min(frame.x1 - box.x1, 0.0)
        x, y = label.xyann
        if shift:
            x_px = ax.transData.transform((x, 0.0))[0] + shift
            x = float(ax.transData.inverted().transform((x_px, 0.0))[0])
        drop = 0.0  # how far down [pixels]
        while True:
            moved = Bbox.from_extents(box.x0 + shift, box.y0 - drop, box.x1 + shift, box.y1 - drop)
            hits = [p for p in placed if moved.overlaps(p)]
            if not hits:
                break
            drop += moved.y1 - min(p.y0 for p in hits) + pad
        label.xyann = (x, y - drop / height)
        placed.append(moved)
