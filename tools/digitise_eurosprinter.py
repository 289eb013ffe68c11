"""Digitise the measured Eurosprinter creep curve from the two figures of CONTACT's user guide.

CONTACT's user guide (section "Calculation of creep force curves", example ``tractcurv.inp``)
shows the traction coefficient F_x/F_n of the Siemens Eurosprinter 127 001 measured by Engel,
Beck & Alders (1998) against the longitudinal creepage ξ, in two MATLAB figures of its
repository, ``doc/fig/eurosprinter6.jpg`` (ξ 0-5 %) and ``doc/fig/eurosprinter5.jpg``
(ξ 0-25 %). This script reads the two figures (JPEG or a lossless PNG of them; no network) and
writes the measured points (the cyan asterisks) as a creep-curve CSV that
:func:`rollerrig.analysis.measured_curve.read_curve_csv` reads with ``creepage="mean"``.

How, per figure:

1. **Axes box from the pixels.** The left axis is the column, the bottom axis the row, with the
   most dark grey pixels; the right and top edges of the box are the outermost light lines that
   run across the whole plot (MATLAB's ``box on``; the grid lines are inside them).
2. **Calibration.** The box edges are the axis limits read on the figure (given per figure,
   :data:`FIGURES`). The tick marks (short dark segments inside the box on the left and bottom
   axes; where the curves hide a tick, its light grey grid line across the box) are then
   located and must fall where the limits and the tick step put them (within
   :data:`TICK_TOLERANCE_PX`); the pixel-to-data map is the least-squares line through the
   ticks found and the box edges. Too few ticks found, or a tick off its place: an error.
3. **Legend.** The legend's rectangle (two long horizontal dark runs with dark vertical sides)
   is found and its inside excluded, so the legend's own asterisk is not a point.
4. **Markers by colour.** Cyan pixels (green and blue above red by more than 70 of 255, green
   and blue within 45 of each other): the asterisks, and nothing else in these figures.
5. **One asterisk as the template.** The connected components of one isolated marker (their
   area within 15 % of the median of the marker-sized components) are averaged about their
   centroids and the mean made symmetric about both axes and the diagonals, as the asterisk
   is: the marker's own shape, width :math:`w` [px].
6. **Centres.** The lines drawn over the markers (curves, the Kalker dashes, black
   annotations) hide parts of them, and near the peak the asterisks overlap. The centres are
   found by matching pursuit: at each step the template position that covers the most
   not-yet-explained cyan pixels, with hidden (line-coloured) and already-explained pixels
   counted as neither for nor against, is accepted when at least
   :data:`MIN_COVER` of the template is cyan, hidden or explained and at least
   :data:`MIN_NEW_CYAN` of it is cyan not yet explained, and it lies at least
   :data:`MIN_SEPARATION_PX` from the centres accepted before; its pixels are then explained. The
   centre is refined to a fraction of a pixel by a parabola through the score. The count per
   connected component is compared with the component's area over one marker's (merged blobs
   split by size): a large difference is reported.
7. **Merge.** Fig. 6 has five times the horizontal resolution: its points make the curve up to
   5 %; fig. 5 adds the points above 5 %. The fig. 5 points below 5 % are dropped as duplicates,
   and used as a check: the nearest fig. 6 point of each isolated one should lie within the
   digitising uncertainty.

The digitising uncertainty stated is half a marker width over the pixel scale, per axis and
figure (a bound for a marker partly hidden or merged; an isolated marker's centre is found to
about a pixel).

Overlays (``--overlays DIR``): each figure with the digitised centres drawn on it, the axes
box, the ticks found and the legend's rectangle; look at them.

Usage::

    python tools/digitise_eurosprinter.py eurosprinter5.png eurosprinter6.png \\
        -o tests/fit/data/eurosprinter_engel1998.csv --overlays /tmp/overlays \\
        --contact-commit d431cdbd125084c79bd59df83b4ac4c63c570ac9
"""

from __future__ import annotations

import argparse
import hashlib
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw
from scipy import ndimage as ndi

TICK_TOLERANCE_PX = 1.5
"""Largest distance of a tick mark from where the axis limits put it [px]."""

MIN_COVER = 0.8
"""Least fraction of the template that is cyan, hidden or explained at an accepted centre."""

MIN_NEW_CYAN = 0.12
"""Least fraction of the template that is cyan not yet explained at an accepted centre (low:
a marker under the drawn curves shows little more than the tips of its spokes)."""

MIN_SEPARATION_PX = 3.0
"""Least distance between two centres [px]: closer markers cannot be told apart."""

NORMAL_LOAD = 106.7e3
"""Wheel load of the Eurosprinter case [N] (CONTACT's euro_tractcurv.inp, FN = 106700 N)."""

ROLLING_SPEED = 10.0
"""Speed of the measurements [m/s] (36 km/h; CONTACT's VELOC = 10000 mm/s)."""


@dataclass(frozen=True)
class AxisLimits:
    """What a figure's axes show: limits and tick steps, read on the figure [data units]."""

    x_max: float
    x_step: float
    y_max: float
    y_step: float


FIGURES = {
    "eurosprinter5": AxisLimits(x_max=25.0, x_step=5.0, y_max=0.35, y_step=0.05),
    "eurosprinter6": AxisLimits(x_max=5.0, x_step=0.5, y_max=0.45, y_step=0.05),
}
"""Axis limits of the two figures: ξ [%] from 0 and F_x/F_n [-] from 0."""


@dataclass
class Calibration:
    """Pixel to data: x = (col − col0)·sx, y = (row0 − row)·sy, and what was found."""

    col0: float
    sx: float
    row0: float
    sy: float
    box: tuple[int, int, int, int]  # left, right, top, bottom [px]
    x_ticks: list[tuple[float, int]]  # (value, column)
    y_ticks: list[tuple[float, int]]  # (value, row)
    residual_px: float

    def to_data(self, col, row):
        return (np.asarray(col) - self.col0) * self.sx, (self.row0 - np.asarray(row)) * self.sy


@dataclass
class Digitised:
    """The markers of one figure."""

    name: str
    calibration: Calibration
    legend: tuple[int, int, int, int] | None  # left, right, top, bottom [px]
    cols: np.ndarray
    rows: np.ndarray
    x: np.ndarray
    y: np.ndarray
    isolated: np.ndarray  # the marker is a connected component of its own
    marker_width_px: float
    component_report: list[str]

    @property
    def uncertainty(self) -> tuple[float, float]:
        """Half a marker width in data units (x, y)."""
        half = 0.5 * self.marker_width_px
        return half * self.calibration.sx, half * self.calibration.sy


def read_rgb(path: Path) -> np.ndarray:
    """The image as an (h, w, 3) int array."""
    with Image.open(path) as im:
        return np.asarray(im.convert("RGB")).astype(int)


def _masks(rgb):
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    total = r + g + b
    spread = np.max(rgb, axis=2) - np.min(rgb, axis=2)
    grey = spread < 30
    dark = grey & (total < 330)
    light_line = total < 725  # anything drawn on the white background
    cyan = (np.minimum(g, b) - r > 70) & (np.abs(g - b) < 45)
    # Drawn over the markers: the coloured curves, the blue dashes, black lines and text.
    hidden = ((spread > 80) & ~cyan) | (total < 250)
    hidden = ndi.binary_dilation(hidden, np.ones((3, 3), bool))  # and their blurred edges
    grid = grey & (total >= 550) & (total < 725)  # MATLAB's light grey grid lines
    return dark, light_line, cyan, hidden, grid


def _line_centre(fill, full, last: bool) -> int:
    """The most filled column (row) of the last (first) run of full ones: a line blurred over
    two or three pixels by the JPEG compression."""
    idx = np.flatnonzero(full)
    runs = np.split(idx, np.flatnonzero(np.diff(idx) > 1) + 1)
    run = runs[-1] if last else runs[0]
    return int(run[np.argmax(fill[run])])


def find_box(dark, light_line) -> tuple[int, int, int, int]:
    """Left, right, top, bottom of the axes box [px]."""
    left = int(np.argmax(dark.sum(axis=0)))
    bottom = int(np.argmax(dark.sum(axis=1)))
    column_fill = light_line[:bottom].sum(axis=0)
    right = _line_centre(column_fill, column_fill > 0.5 * bottom, last=True)
    row_fill = light_line[:, left : right + 1].sum(axis=1)
    top = _line_centre(row_fill, row_fill > 0.5 * (right - left), last=False)
    if not (right - left > 100 and bottom - top > 100):
        raise ValueError(
            f"no axes box found (left {left}, right {right}, top {top}, bottom {bottom})"
        )
    return left, right, top, bottom


def _tick_positions(segment_dark) -> np.ndarray:
    """Centres of the runs of True in a 1-D boolean array."""
    idx = np.flatnonzero(segment_dark)
    if idx.size == 0:
        return idx.astype(float)
    runs = np.split(idx, np.flatnonzero(np.diff(idx) > 1) + 1)
    return np.array([r.mean() for r in runs if r.size <= 4])


def calibrate(dark, hidden, grid, box, limits: AxisLimits) -> Calibration:
    """Check the ticks against the limits and fit the pixel-to-data map.

    A tick is a short dark segment perpendicular to the axis, 5 px long here; where a curve
    crosses it, its pixels under the curve count (at least 2 of the 5 must be dark), and it
    must end (not dark 10 px from the axis: not a longer line). Where the curves hide a tick
    altogether (fig. 5's left axis), its grid line, light grey across the box, stands in.
    """
    left, right, top, bottom = box
    seen = dark | hidden
    rows = slice(bottom - 6, bottom - 1)
    cols = slice(left + 3, right - 2)
    band = seen[rows, cols].all(axis=0) & (dark[rows, cols].sum(axis=0) >= 2)
    band &= ~dark[bottom - 10, cols]
    x_found = _tick_positions(band) + left + 3
    rows = slice(top + 3, bottom - 2)
    cols = slice(left + 2, left + 7)
    band = seen[rows, cols].all(axis=1) & (dark[rows, cols].sum(axis=1) >= 2)
    band &= ~dark[rows, left + 10]
    y_found = _tick_positions(band) + top + 3
    inner_rows, inner_cols = slice(top + 10, bottom - 10), slice(left + 10, right - 10)
    grid_cols = np.flatnonzero(grid[inner_rows].mean(axis=0) > 0.5)
    grid_rows = np.flatnonzero(grid[:, inner_cols].mean(axis=1) > 0.5)
    grid_cols = grid_cols[(grid_cols > left + 2) & (grid_cols < right - 2)]
    grid_rows = grid_rows[(grid_rows > top + 2) & (grid_rows < bottom - 2)]
    x_found = np.union1d(x_found, _tick_positions(np.isin(np.arange(right), grid_cols)))
    y_found = np.union1d(y_found, _tick_positions(np.isin(np.arange(bottom), grid_rows)))
    nx = round(limits.x_max / limits.x_step)
    ny = round(limits.y_max / limits.y_step)
    x_ticks, y_ticks = [(0.0, left), (limits.x_max, right)], [(0.0, bottom), (limits.y_max, top)]
    for k in range(1, nx):
        expected = left + k * (right - left) / nx
        near = x_found[np.abs(x_found - expected) <= TICK_TOLERANCE_PX]
        if near.size:
            x_ticks.append((k * limits.x_step, float(near[0])))
    for k in range(1, ny):
        expected = bottom - k * (bottom - top) / ny
        near = y_found[np.abs(y_found - expected) <= TICK_TOLERANCE_PX]
        if near.size:
            y_ticks.append((k * limits.y_step, float(near[0])))
    stray_x = [c for c in x_found if min(abs(c - p) for _, p in x_ticks) > TICK_TOLERANCE_PX]
    stray_y = [r for r in y_found if min(abs(r - p) for _, p in y_ticks) > TICK_TOLERANCE_PX]
    if len(x_ticks) < 4 or len(y_ticks) < 4:
        raise ValueError(
            f"too few tick marks where the limits put them: x {len(x_ticks) - 2} of {nx - 1}, "
            f"y {len(y_ticks) - 2} of {ny - 1} (limits wrong for this figure?)"
        )
    if stray_x:
        raise ValueError(f"tick marks at columns {stray_x} do not fit x_max/x_step")
    if stray_y:
        raise ValueError(f"tick marks at rows {stray_y} do not fit y_max/y_step")
    vx, px = np.array(x_ticks).T
    vy, py = np.array(y_ticks).T
    ax, bx = np.polyfit(vx, px, 1)  # col = bx + ax·value
    ay, by = np.polyfit(vy, py, 1)  # row = by + ay·value (ay < 0)
    res = np.concatenate([px - (bx + ax * vx), py - (by + ay * vy)])
    return Calibration(
        col0=bx, sx=1.0 / ax, row0=by, sy=-1.0 / ay, box=box,
        x_ticks=[(float(v), round(p)) for v, p in x_ticks],
        y_ticks=[(float(v), round(p)) for v, p in y_ticks],
        residual_px=float(np.max(np.abs(res))),
    )  # fmt: skip


def find_legend(dark, box) -> tuple[int, int, int, int] | None:
    """The legend's rectangle inside the box, or None."""
    left, right, top, bottom = box
    min_run = 0.2 * (right - left)
    runs = []  # (row, start, end)
    for row in range(top + 3, bottom - 3):
        idx = np.flatnonzero(dark[row, left + 2 : right - 1]) + left + 2
        if idx.size < min_run:
            continue
        for run in np.split(idx, np.flatnonzero(np.diff(idx) > 1) + 1):
            if run.size >= min_run:
                runs.append((row, int(run[0]), int(run[-1])))
    for i, (r1, s1, e1) in enumerate(runs):
        for r2, s2, e2 in runs[i + 1 :]:
            if r2 - r1 < 20 or abs(s1 - s2) > 3 or abs(e1 - e2) > 3:
                continue
            sides = dark[r1:r2, s1 - 1 : s1 + 2].any(axis=1).mean() > 0.9
            sides &= dark[r1:r2, e1 - 1 : e1 + 2].any(axis=1).mean() > 0.9
            if sides:
                return s1, e1, r1, r2
    return None


def marker_template(cyan) -> np.ndarray:
    """The mean shape of the isolated markers, a boolean (2h+1, 2h+1) array."""
    lab, n = ndi.label(cyan, structure=np.ones((3, 3)))
    objects = ndi.find_objects(lab)
    areas = np.asarray(ndi.sum(cyan, lab, range(1, n + 1)))
    sizes = np.array([[s[0].stop - s[0].start, s[1].stop - s[1].start] for s in objects])
    marker_sized = (sizes.max(axis=1) <= 16) & (sizes.min(axis=1) >= 8)
    area = float(np.median(areas[marker_sized]))
    single = marker_sized & (np.abs(areas - area) <= 0.15 * area)
    h = 7
    patches = []
    for k in np.flatnonzero(single):
        cy, cx = ndi.center_of_mass(lab == k + 1)
        cy, cx = round(cy), round(cx)
        patch = lab[cy - h : cy + h + 1, cx - h : cx + h + 1] == k + 1
        if patch.shape == (2 * h + 1, 2 * h + 1):
            patches.append(patch)
    if len(patches) < 5:
        raise ValueError(f"only {len(patches)} isolated markers to learn the marker's shape from")
    mean = np.mean(patches, axis=0)
    # The asterisk is symmetric about both axes and the diagonals: so is its template (this
    # also removes the half-pixel bias of centring each patch on a rounded centroid).
    mean = (mean + mean[::-1] + mean[:, ::-1] + mean[::-1, ::-1]) / 4.0
    return (mean + mean.T) / 2.0 >= 0.5


def _refine(score, r, c):
    """Sub-pixel offset of a peak by a parabola in each direction."""
    out = []
    for d0, d1 in (((r - 1, c), (r + 1, c)), ((r, c - 1), (r, c + 1))):
        lo, mid, hi = score[d0], score[r, c], score[d1]
        den = lo - 2 * mid + hi
        out.append(0.0 if den >= 0 else float(np.clip(0.5 * (lo - hi) / den, -0.5, 0.5)))
    return out


def _correlate_window(mask, template, r0, r1, c0, c1):
    """Correlation of ``mask`` with ``template`` on rows r0:r1, columns c0:c1 only."""
    h = template.shape[0] // 2
    padded = np.pad(mask, h)
    sub = padded[r0 : r1 + 2 * h, c0 : c1 + 2 * h].astype(float)
    return ndi.correlate(sub, template.astype(float), mode="constant")[h:-h, h:-h]


def find_centres(cyan, hidden, template, region):
    """Matching pursuit of the template over the cyan mask (see the module's docstring).

    Returns the centres as (column, row) [px], and the score maps are updated only near each
    accepted centre.
    """
    size = float(template.sum())
    h = template.shape[0] // 2
    unexplained = cyan & region
    explained = np.zeros_like(cyan)
    neutral = hidden & ~cyan
    footprint = ndi.binary_dilation(template, np.ones((3, 3), bool))  # with its blurred edge
    full = (0, cyan.shape[0], 0, cyan.shape[1])
    new = _correlate_window(unexplained, template, *full) / size
    cover = _correlate_window(unexplained | explained | neutral, template, *full) / size
    centres = []
    sep = int(MIN_SEPARATION_PX)
    yy, xx = np.mgrid[-sep : sep + 1, -sep : sep + 1]
    disc = np.hypot(yy, xx) <= MIN_SEPARATION_PX
    taken = np.zeros_like(cyan)
    while True:
        ok = (cover >= MIN_COVER) & (new >= MIN_NEW_CYAN) & region & ~taken
        if not ok.any():
            break
        score = new + 0.5 * cover
        r, c = np.unravel_index(int(np.argmax(np.where(ok, score, -1.0))), score.shape)
        dr, dc = _refine(score, r, c)
        centres.append((c + dc, r + dr))
        taken[max(r - sep, 0) : r + sep + 1, max(c - sep, 0) : c + sep + 1] |= disc
        window = (slice(r - h, r + h + 1), slice(c - h, c + h + 1))
        covered = footprint & (cyan[window] | explained[window])
        explained[window] |= covered
        unexplained[window] &= ~covered
        r0, r1 = max(r - 2 * h, 0), min(r + 2 * h + 1, cyan.shape[0])
        c0, c1 = max(c - 2 * h, 0), min(c + 2 * h + 1, cyan.shape[1])
        new[r0:r1, c0:c1] = _correlate_window(unexplained, template, r0, r1, c0, c1) / size
        cover[r0:r1, c0:c1] = (
            _correlate_window(unexplained | explained | neutral, template, r0, r1, c0, c1) / size
        )
    return np.array(centres).reshape(-1, 2)


def digitise(path: Path, limits: AxisLimits) -> Digitised:
    """The markers of one figure, in pixels and data units."""
    rgb = read_rgb(path)
    dark, light_line, cyan, hidden, grid = _masks(rgb)
    box = find_box(dark, light_line)
    cal = calibrate(dark, hidden, grid, box, limits)
    legend = find_legend(dark, box)
    left, right, top, bottom = box
    region = np.zeros_like(cyan)
    region[top + 1 : bottom, left + 1 : right] = True
    if legend is not None:
        ll, lr, lt, lb = legend
        region[lt - 1 : lb + 2, ll - 1 : lr + 2] = False
    cyan &= region
    template = marker_template(cyan)
    cols_t = np.flatnonzero(template.any(axis=0))
    width = float(cols_t[-1] - cols_t[0] + 1)
    centres = find_centres(cyan, hidden, template, region)
    cols, rows = centres[:, 0], centres[:, 1]
    # Count per connected component against its area (merged blobs split by size).
    lab, n = ndi.label(cyan, structure=np.ones((3, 3)))
    areas = np.asarray(ndi.sum(cyan, lab, range(1, n + 1)))
    one = float(template.sum())
    at = lab[np.clip(np.round(rows).astype(int), 0, lab.shape[0] - 1),
             np.clip(np.round(cols).astype(int), 0, lab.shape[1] - 1)]  # fmt: skip
    counts = np.bincount(at, minlength=n + 1)
    isolated = np.array([counts[k] == 1 and abs(areas[k - 1] - one) < 0.25 * one for k in at])
    report = []
    for k in range(1, n + 1):
        by_area = areas[k - 1] / one
        if areas[k - 1] >= 0.5 * one and abs(counts[k] - by_area) > max(1.5, 0.35 * by_area):
            ys, xs = np.nonzero(lab == k)
            report.append(
                f"component at column {xs.mean():.0f}, row {ys.mean():.0f}: {counts[k]} centres, "
                f"area {by_area:.1f} markers"
            )
    x, y = cal.to_data(cols, rows)
    order = np.argsort(x)
    return Digitised(
        name=path.stem, calibration=cal, legend=legend, cols=cols[order], rows=rows[order],
        x=x[order], y=y[order], isolated=isolated[order], marker_width_px=width,
        component_report=report,
    )  # fmt: skip


def overlay(path: Path, d: Digitised, out: Path) -> None:
    """The figure with the box, the ticks, the legend and the digitised centres drawn on it."""
    with Image.open(path) as im:
        im = im.convert("RGB").resize((im.width * 2, im.height * 2), Image.NEAREST)
    draw = ImageDraw.Draw(im)
    left, right, top, bottom = d.calibration.box
    draw.rectangle([2 * left, 2 * top, 2 * right, 2 * bottom], outline=(0, 200, 0))
    for _, c in d.calibration.x_ticks:
        draw.line([2 * c, 2 * bottom + 4, 2 * c, 2 * bottom + 16], fill=(0, 200, 0), width=2)
    for _, r in d.calibration.y_ticks:
        draw.line([2 * left - 16, 2 * r, 2 * left - 4, 2 * r], fill=(0, 200, 0), width=2)
    if d.legend is not None:
        ll, lr, lt, lb = d.legend
        draw.rectangle([2 * ll, 2 * lt, 2 * lr, 2 * lb], outline=(255, 0, 255), width=2)
    for c, r, iso in zip(d.cols, d.rows, d.isolated, strict=True):
        x, y = 2 * c + 1, 2 * r + 1
        colour = (200, 0, 200) if iso else (255, 0, 0)
        draw.line([x - 3, y, x + 3, y], fill=colour, width=1)
        draw.line([x, y - 3, x, y + 3], fill=colour, width=1)
    im.save(out)


def merge(fig5: Digitised, fig6: Digitised):
    """Fig. 6's points, and fig. 5's above 5 % (x: ξ [%], y: F_x/F_n [-]); the check of the
    fig. 5 points below 5 % against fig. 6 (offsets of the isolated ones, data units)."""
    x_max6 = FIGURES["eurosprinter6"].x_max
    ux5, uy5 = fig5.uncertainty
    keep5 = fig5.x > x_max6
    # A fig. 5 point just above 5 % that fig. 6 also shows (near its right edge): a duplicate.
    near_edge = keep5 & (fig5.x <= x_max6 + ux5)
    for i in np.flatnonzero(near_edge):
        d = np.hypot((fig6.x - fig5.x[i]) / ux5, (fig6.y - fig5.y[i]) / uy5)
        if d.size and d.min() <= 1.0:
            keep5[i] = False
    x = np.concatenate([fig6.x, fig5.x[keep5]])
    y = np.concatenate([fig6.y, fig5.y[keep5]])
    source = np.array(["fig6"] * fig6.x.size + ["fig5"] * int(keep5.sum()))
    order = np.argsort(x, kind="stable")
    below = np.flatnonzero((fig5.x <= x_max6 - ux5) & fig5.isolated)
    offsets = []
    for i in below:
        d = np.hypot((fig6.x - fig5.x[i]) / ux5, (fig6.y - fig5.y[i]) / uy5)
        j = int(np.argmin(d))
        offsets.append((fig6.x[j] - fig5.x[i], fig6.y[j] - fig5.y[i]))
    return x[order], y[order], source[order], np.array(offsets).reshape(-1, 2)


def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def write_csv(out: Path, x, y, source, fig5, fig6, paths, commit, check) -> None:
    """The CSV with its header comment block."""
    ux5, uy5 = fig5.uncertainty
    ux6, uy6 = fig6.uncertainty
    n5 = int(np.sum(source == "fig5"))
    n6 = int(np.sum(source == "fig6"))
    med = np.median(np.abs(check), axis=0) if check.size else (np.nan, np.nan)
    lines = [
        "# Measured creep curve of the Siemens Eurosprinter 127 001 (one wheel, traction on",
        "# tangent track, pure longitudinal creepage, 36 km/h = 10 m/s), digitised from the",
        "# figures of CONTACT's user guide.",
        "#",
        "# Source of the measurements: B. Engel, H.P. Beck, J. Alders, 'Verschleissreduzierende",
        "#   Radschlupfregelung mit hoher Kraftschlussausnutzung', Elektrische Bahnen 96 (1998)",
        "#   201-209. Figures: E.A.H. Vollebregt, CONTACT user guide, section 'Calculation of",
        "#   creep force curves', doc/fig/eurosprinter6.jpg (creepage 0-5 %) and",
        "#   doc/fig/eurosprinter5.jpg (0-25 %) of https://github.com/eve70a/CONTACT at commit",
        f"#   {commit}. sha256 of the images read:",
        f"#   {paths[1].name} {_sha256(paths[1])},",
        f"#   {paths[0].name} {_sha256(paths[0])}",
        "#   (lossless PNG conversions of the JPEGs give the same pixels and the same points).",
        "#   The case's inputs (CONTACT testbank/examples_temp/euro_tractcurv.inp): wheel radius",
        "#   625 mm, 106.7 kN per wheel, V = 10 m/s, Hertz a/b = 0.5, G = 82 GPa, nu = 0.28.",
        "#",
        "# Digitised by tools/digitise_eurosprinter.py from the pixels: axes box and tick marks",
        "#   located and checked against the axis limits (fig. 6: 0-5 %, 0-0.45; fig. 5: 0-25 %,",
        "#   0-0.35; largest tick residual of the linear pixel-to-data map "
        f"{max(fig5.calibration.residual_px, fig6.calibration.residual_px):.2f} px),",
        "#   legend box excluded, the cyan asterisks isolated by colour and their centres found",
        "#   by matching a template of one marker (learnt from the isolated ones; overlapping",
        "#   markers and markers partly hidden by the drawn curves separated by matching",
        "#   pursuit). Overlays of the centres on the figures were checked by eye.",
        f"#   Points: {n6} from fig. 6 (creepage up to 5 %) and {n5} from fig. 5 (above 5 %);",
        "#   fig. 5's points below 5 % are the same measurements and were dropped. Markers",
        "#   drawn exactly on top of each other cannot be told apart: the measurement may have",
        "#   more points than this file.",
        "# Digitising uncertainty (half a marker width over the pixel scale; a bound, an isolated",
        f"#   marker's centre is found to about 1 px): fig. 6 creepage {ux6:.3f} %, F_x/F_n",
        f"#   {uy6:.4f}; fig. 5 creepage {ux5:.3f} %, F_x/F_n {uy5:.4f}. Check: the isolated",
        "#   fig. 5 points below 5 % lie from their fig. 6 counterparts by a median",
        f"#   {med[0]:.3f} % in creepage and {med[1]:.4f} in F_x/F_n ({len(check)} points).",
        "#",
        "# Columns: 'creep [%]' is Kalker's longitudinal creepage xi (slip velocity over the",
        "#   rolling speed, as the figure's 'Longitudinal creepage xi'), NOT the rig's creep:",
        "#   read with rollerrig.analysis.measured_curve.read_curve_csv(path, creepage='mean').",
        "#   'coa [-]' is the traction coefficient F_x/F_n. 'normal_load' and 'rolling_speed'",
        "#   are the test's (the same for every point); 'slip_velocity [m/s]' = xi * 10 m/s, as",
        "#   CONTACT computes the slip of this case. 'figure' names the figure a point is from.",
        "creep [%],coa [-],slip_velocity [m/s],normal_load [kN],rolling_speed [km/h],figure",
    ]
    for xi, mu, src in zip(x, y, source, strict=True):
        lines.append(
            f"{xi:.4f},{mu:.4f},{xi / 100 * ROLLING_SPEED:.6f},{NORMAL_LOAD / 1e3:.1f},"
            f"{ROLLING_SPEED * 3.6:.1f},{src}"
        )
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(lines) + "\n", encoding="utf-8")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("fig5", type=Path, help="eurosprinter5 image (creepage 0-25 %%)")
    parser.add_argument("fig6", type=Path, help="eurosprinter6 image (creepage 0-5 %%)")
    parser.add_argument("-o", "--output", type=Path, required=True, help="CSV to write")
    parser.add_argument("--overlays", type=Path, help="folder for the overlay PNGs")
    parser.add_argument("--contact-commit", default="(not stated)",
                        help="CONTACT commit the figures came from")  # fmt: skip
    args = parser.parse_args(argv)
    fig5 = digitise(args.fig5, FIGURES["eurosprinter5"])
    fig6 = digitise(args.fig6, FIGURES["eurosprinter6"])
    for d in (fig5, fig6):
        cal = d.calibration
        ux, uy = d.uncertainty
        print(
            f"{d.name}: box {cal.box}, {len(cal.x_ticks) - 2} x and {len(cal.y_ticks) - 2} y "
            f"ticks found, fit residual {cal.residual_px:.2f} px; legend {d.legend}; marker "
            f"{d.marker_width_px:.0f} px wide; {d.x.size} markers ({int(d.isolated.sum())} "
            f"isolated); uncertainty x {ux:.4f} %, y {uy:.4f}"
        )
        for line in d.component_report:
            print("  count differs from area:", line)
    x, y, source, check = merge(fig5, fig6)
    write_csv(args.output, x, y, source, fig5, fig6, (args.fig5, args.fig6),
              args.contact_commit, check)  # fmt: skip
    if check.size:
        print(
            f"check, fig. 5 below 5 % vs fig. 6 ({len(check)} isolated points): median offset "
            f"{np.median(check[:, 0]):+.4f} % / {np.median(check[:, 1]):+.4f}, median |offset| "
            f"{np.median(np.abs(check[:, 0])):.4f} % / {np.median(np.abs(check[:, 1])):.4f}"
        )
    print(f"{x.size} points written to {args.output}")
    if args.overlays:
        args.overlays.mkdir(parents=True, exist_ok=True)
        for path, d in ((args.fig5, fig5), (args.fig6, fig6)):
            overlay(path, d, args.overlays / f"{d.name}-overlay.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
