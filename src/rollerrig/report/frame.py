"""Figures of the frame analysis: the deformed shape under the test load and the mode shapes.

Both are 3-D line drawings of the members (through each member's inner FE nodes) over the
undeformed frame in grey. Displacements are magnified; the factor is stated in the title
(``displacements x 2000``) and returned, so a reader can take lengths off the figure. The
axes carry at most four ticks each (labels that never run into each other at the corners of
the box), and a legend says what every mark is: undeformed and deformed frame, supports,
strain gauges, and the forces on the frame as arrows drawn to a stated scale.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.lines import Line2D
from matplotlib.ticker import MaxNLocator

from rollerrig.frame.analysis import FrameResult
from rollerrig.output.figures import crop_when_saved

__all__ = ["auto_scale", "deformed_shape_figure", "frame_study_figure", "mode_shape_figure"]

_FRACTION = 0.12
"""The largest displacement is drawn as this fraction of the frame's largest dimension."""


def _span(result: FrameResult) -> float:
    p = np.array(list(result.frame.nodes.values()), dtype=float)
    return float(np.max(np.ptp(p, axis=0))) or 1.0


def auto_scale(result: FrameResult, translations: np.ndarray) -> float:
    """A round magnification (1, 2 or 5 x 10^k) that draws the largest translation as about
    12 % of the frame's largest dimension [-].

    Examples
    --------
    >>> from rollerrig.frame import default_frame, analyze_frame
    >>> r = analyze_frame(default_frame(), n_modes=1)
    >>> auto_scale(r, r.displacements[:, :3])  # 0.08 mm drawn as 0.16 m
    2000.0
    """
    peak = float(np.max(np.linalg.norm(translations, axis=1)))
    if peak <= 0.0 or not np.isfinite(peak):
        return 1.0
    raw = _FRACTION * _span(result) / peak
    exponent = np.floor(np.log10(raw))
    mantissa = raw / 10**exponent
    step = 5.0 if mantissa >= 5 else 2.0 if mantissa >= 2 else 1.0
    return float(step * 10**exponent)


def _polylines(result: FrameResult) -> dict[str, list[int]]:
    """Member -> the indices (in ``result.nodes``) of its FE nodes, start to end."""
    index = {n: i for i, n in enumerate(result.nodes)}
    out = {}
    for name, m in result.frame.members.items():
        inner = [index[f"{name}~{k}"] for k in range(1, result.elements_per_member)]
        out[name] = [index[m.start], *inner, index[m.end]]
    return out


def _coordinates(result: FrameResult) -> np.ndarray:
    frame = result.frame
    out = np.zeros((len(result.nodes), 3))
    for name, m in frame.members.items():
        a, b = frame.coordinates(m.start), frame.coordinates(m.end)
        for k in range(1, result.elements_per_member):
            out[result.nodes.index(f"{name}~{k}")] = a + (b - a) * k / result.elements_per_member
    for name, p in frame.nodes.items():
        out[result.nodes.index(name)] = p
    return out


def _draw(
    ax,
    result: FrameResult,
    translations: np.ndarray,
    scale: float,
    colour: str,
    *,
    fontsize: float = 8.0,
) -> None:
    xyz = _coordinates(result)
    moved = xyz + scale * translations
    for chain in _polylines(result).values():
        ax.plot(*xyz[chain].T, color="0.75", lw=1.0)
        ax.plot(*moved[chain].T, color=colour, lw=1.8)
    supports = [result.nodes.index(n) for n in result.frame.supports]
    ax.scatter(*xyz[supports].T, marker="s", s=30, color="k", label="support")
    ax.set_xlabel("x [m]", fontsize=fontsize)
    ax.set_ylabel("y [m]", fontsize=fontsize)
    ax.set_zlabel("z [m]", fontsize=fontsize)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):  # few, short tick labels: none overprint
        axis.set_major_locator(MaxNLocator(nbins=3, steps=(1, 2, 5, 10)))
    ax.tick_params(labelsize=fontsize - 1, pad=0)
    lo, hi = xyz.min(axis=0), xyz.max(axis=0)
    ax.set_box_aspect(np.maximum(hi - lo, 0.1 * _span(result)))
    ax.view_init(elev=20, azim=-60)


def deformed_shape_figure(result: FrameResult, *, scale: float | None = None):
    """The frame deformed under the test load (magnified), over the undeformed frame.

    The forces on the frame at its load points are arrows ending at the point they act on,
    drawn to one scale (stated in the legend: 0.1 m of arrow = so many kN); gauges are dots,
    supports squares.

    Returns
    -------
    (matplotlib.figure.Figure, float)
        The figure and the magnification used.
    """
    translations = result.displacements[:, :3]
    scale = auto_scale(result, translations) if scale is None else float(scale)
    fig = plt.figure(figsize=(8.0, 6.5))
    ax = fig.add_subplot(projection="3d")
    _draw(ax, result, translations, scale, "tab:red")
    frame = result.frame
    forces = {
        lp.node: result.normal_load * np.asarray(lp.normal)
        + result.traction_force * np.asarray(lp.traction)
        for lp in frame.load_points.values()
    }
    largest = max((float(np.linalg.norm(f)) for f in forces.values()), default=0.0)
    per_metre = _force_scale(largest, _span(result))  # [N per m of arrow]
    for node, f in forces.items():
        if np.linalg.norm(f) > 0:
            p = frame.coordinates(node)
            d = f / per_metre  # the arrow ends at the point the force acts on
            ax.quiver(*(p - d), *d, color="tab:blue", lw=1.2, arrow_length_ratio=0.3)
    for g in frame.gauges.values():
        m = frame.members[g.member]
        a, b = frame.coordinates(m.start), frame.coordinates(m.end)
        p = a + (b - a) * g.position / frame.length(g.member)
        ax.scatter(*p, color="tab:green", s=25)
        ax.text(*p, f" {g.name}", fontsize=7, color="tab:green")
    arrow = f"force on the frame (arrow 0.1 m = {per_metre * 0.1 / 1e3:g} kN)"
    handles = [
        Line2D([], [], color="0.75", lw=1.0, label="undeformed"),
        Line2D([], [], color="tab:red", lw=1.8, label=f"deformed (displacements x {scale:g})"),
        Line2D([], [], color="tab:blue", lw=1.2, marker=">", ms=6, label=arrow),
        Line2D([], [], color="tab:green", marker="o", ls="none", ms=5, label="strain gauge"),
        Line2D([], [], color="k", marker="s", ls="none", ms=5, label="support (fixed)"),
    ]
    fig.legend(handles=handles, loc="lower center", ncol=3, fontsize=7, frameon=False)
    peak = float(np.max(np.linalg.norm(translations, axis=1)))
    ax.set_title(
        f"{frame.name}: N = {result.normal_load / 1e3:g} kN, F_x = "
        f"{result.traction_force / 1e3:g} kN\n"
        f"displacements x {scale:g} (largest {peak * 1e3:.3f} mm); "
        f"top horizontal {result.top_horizontal_deflection * 1e3:.3f} mm",
        fontsize=9,
    )
    fig.tight_layout(rect=(0.0, 0.07, 1.0, 1.0))  # room for the legend underneath
    crop_when_saved(fig)  # 3D axes: the layout does not see their projected labels
    return fig, scale


def _force_scale(largest: float, span: float) -> float:
    """Newtons per metre of arrow [N/m]: round (0.1 m of arrow = 1, 2 or 5 x 10^k kN) and
    drawing the largest force [N] at about 15 % of the frame's span [m] (at most).

    Examples
    --------
    >>> _force_scale(20e3, 2.2)  # 0.1 m = 10 kN: 20 kN drawn as 0.2 m
    100000.0
    """
    if largest <= 0.0 or not np.isfinite(largest):
        return 1.0
    raw = largest * 0.1 / (0.15 * span)  # [N per 0.1 m]
    exponent = np.floor(np.log10(raw))
    mantissa = raw / 10**exponent
    step = next(m for m in (1.0, 2.0, 5.0, 10.0) if m >= mantissa - 1e-12)
    return float(step * 10**exponent / 0.1)


_MOST_PANELS = 6
"""Most mode panels in one figure [-] (two rows of three): more would shrink each below
reading; beyond, the first modes and the contact's are drawn and the title says which."""


def _mode_numbers(indices) -> str:
    """Mode numbers (from 1) of 0-based ``indices``, runs joined: ``"1-5, 12"``."""
    numbers = sorted(int(i) + 1 for i in indices)
    runs: list[list[int]] = []
    for n in numbers:
        if runs and n == runs[-1][-1] + 1:
            runs[-1].append(n)
        else:
            runs.append([n])
    return ", ".join(f"{r[0]}-{r[-1]}" if len(r) > 2 else ", ".join(map(str, r)) for r in runs)


def mode_shape_figure(result: FrameResult, modes=3, *, contact_mode: int | None = None):
    """Mode shapes, one panel each, with frequency and magnification.

    Mode shapes are mass-normalised (φᵀ M φ = 1 kg); each is drawn with its own magnification.
    The panels are laid out in rows of at most three; of more than six modes asked for, the
    first ones and the contact's are drawn, and the title says which of them.

    Parameters
    ----------
    result : FrameResult
    modes : int or sequence of int
        The first ``modes`` modes, or the indices (from 0) of the modes to draw.
    contact_mode : int, optional
        Index of the mode that dominates the contact's flexibility
        (:func:`rollerrig.frame.contact_dof`): its panel says so.

    Returns
    -------
    (matplotlib.figure.Figure, list of float)
        The figure and the magnification of each panel drawn, in the order drawn (ascending
        mode).
    """
    count = len(result.frequencies)
    if np.ndim(modes) == 0:
        chosen = list(range(max(1, min(int(modes), count))))
    else:
        chosen = sorted({int(i) for i in modes if 0 <= int(i) < count}) or [0]
    drawn = chosen
    if len(chosen) > _MOST_PANELS:
        keep = [contact_mode] if contact_mode in chosen else []
        others = [i for i in chosen if i != contact_mode][: _MOST_PANELS - len(keep)]
        drawn = sorted([*others, *keep])
    n = len(drawn)
    columns = 2 if n == 4 else min(n, 3)
    rows = -(-n // columns)
    # About 3.8 in a panel: six make a figure 1700 px wide at 150 dpi, its text legible when
    # shown whole on a screen.
    fig = plt.figure(figsize=(3.8 * columns + 0.4, 4.6 * rows + 1.5))
    scales = []
    for panel, i in enumerate(drawn):
        ax = fig.add_subplot(rows, columns, panel + 1, projection="3d")
        translations = result.mode_shapes[i][:, :3]
        scale = auto_scale(result, translations)
        scales.append(scale)
        colour = "tab:red" if i == contact_mode else "tab:purple"
        _draw(ax, result, translations, scale, colour, fontsize=9.0)
        role = "\nthe contact's longitudinal mode" if i == contact_mode else ""
        ax.set_title(
            f"mode {i + 1}: {result.frequencies[i]:.2f} Hz{role}\nshape x {scale:g}",
            fontsize=10,
        )
    which = "" if drawn == chosen else f" {_mode_numbers(drawn)} of {_mode_numbers(chosen)}"
    fig.suptitle(
        f"{result.frame.name}: natural modes{which}\n"
        "(shapes mass-normalised, m/sqrt(kg), each magnified as titled)",
        fontsize=11,
    )
    handles = [
        Line2D([], [], color="0.75", lw=1.0, label="undeformed"),
        Line2D([], [], color="tab:purple", lw=1.8, label="mode shape (magnified as titled)"),
    ]
    if contact_mode in drawn:
        handles.append(
            Line2D([], [], color="tab:red", lw=1.8, label="the contact's longitudinal mode")
        )
    handles.append(Line2D([], [], color="k", marker="s", ls="none", ms=5, label="support (fixed)"))
    fig.legend(handles=handles, loc="lower center", ncol=4, fontsize=9, frameon=False)
    # By hand, not tight_layout: it does not see the projected tick labels of 3-D axes, and
    # put one row's panel titles on the tick labels of the row above. In inches: 1.0 for the
    # title, 0.5 for the legend, 0.7 between rows.
    height = fig.get_figheight()
    fig.subplots_adjust(
        left=0.02,
        right=0.95,
        bottom=0.5 / height,
        top=1.0 - 1.0 / height,
        wspace=0.15,
        hspace=0.7 / ((height - 1.5) / rows - 0.7),
    )
    crop_when_saved(fig)  # 3D axes: the layout does not see their projected labels
    return fig, scales


def frame_study_figure(study):
    """The frame study (:func:`rollerrig.studies.frame.frame_study`): T56 spectra of the rest
    after the release for each frame, with the frames' frequencies marked, and the release
    overshoots side by side.

    Returns
    -------
    matplotlib.figure.Figure
    """
    colours = ("black", "tab:blue", "tab:red")
    fig, (ax, bars) = plt.subplots(
        1, 2, figsize=(12.0, 4.6), gridspec_kw={"width_ratios": (2.2, 1.0)}
    )
    for case, colour in zip(study.cases, colours, strict=False):
        f, amplitude = case.spectrum
        band = (f > 0.5) & (f <= 80.0)
        label = case.label + (f" ({case.frequency:.1f} Hz)" if np.isfinite(case.frequency) else "")
        ax.semilogy(f[band], np.maximum(amplitude[band], 1e-6), color=colour, lw=1.1, label=label)
        if np.isfinite(case.frequency):
            ax.axvline(case.frequency, color=colour, ls=":", lw=1.0)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("T56 amplitude after the release [N·m]")
    ax.set_title("T56 spectrum of the rest after the release\n(dotted: the frame's frequency)",
                 fontsize=10)  # fmt: skip
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    x = np.arange(len(study.cases))
    measured = [c.metrics["release_overshoot"] for c in study.cases]
    true = [c.metrics["true_release_overshoot"] for c in study.cases]
    bars.bar(x - 0.2, measured, 0.4, label="T56 / r_r (what the rig reports)", color="tab:blue")
    bars.bar(x + 0.2, true, 0.4, label="true F_x", color="tab:orange")
    for xi, value in zip(x, measured, strict=True):
        bars.annotate(f"{value:.3f}", (xi - 0.2, value), ha="center", va="bottom", fontsize=8)
    bars.set_xticks(x, [c.label for c in study.cases], fontsize=8, rotation=15)
    bars.set_ylabel("overshoot below zero after the release [-]")
    bars.set_title("release overshoot", fontsize=10)
    bars.legend(fontsize=8, loc="lower right")
    bars.grid(True, axis="y", alpha=0.3)
    verdict = "the frame matters" if study.matters else "the frame does not matter"
    fig.suptitle(f"Frame study on {study.experiment}: {verdict}", fontsize=11)
    fig.tight_layout()
    return fig
