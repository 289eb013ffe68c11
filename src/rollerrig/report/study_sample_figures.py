"""Figures of a sampled study: the metric against each parameter, Spearman's rank correlations,
and for a Sobol design the indices S1 and ST with their confidence intervals.

:func:`rollerrig.report.studies.study_figures` calls :func:`_sample_figures` for a study of
design ``"sample"``. When the correlations or indices cannot be computed (failed points, a
constant parameter), a figure says why instead.
"""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.lines import Line2D

from rollerrig._validation import ParameterError
from rollerrig.report.study_display import (
    _MISSING_COLOUR,
    MISSING_GID,
    _footnote,
    _level_ticks,
    _log_x,
    _mark_missing,
    _missing_handle,
    _missing_text,
    _Quantity,
    _quantity,
    _room_for_missing,
    _say_no_values,
    _title,
)
from rollerrig.studies.summary import json_attribute, varied_parameters

__all__: list[str] = []


def _scatter_figure(ds, metric: _Quantity, qs, spec: dict):
    y = metric.values
    ok = np.isfinite(y)
    d = len(qs)
    ncols = min(d, 3)
    nrows = math.ceil(d / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(4.2 * ncols, 3.6 * nrows), sharey=True,
                             squeeze=False)  # fmt: skip
    dists = spec.get("parameters", {}) if isinstance(spec.get("parameters"), dict) else {}
    ms = 4.0 if y.size <= 500 else 2.0
    alpha = 0.8 if y.size <= 2000 else 0.35
    for i, (q, ax) in enumerate(zip(qs, axes.flat, strict=False)):
        dist = dists.get(q.key, {}) if isinstance(dists.get(q.key), dict) else {}
        if q.numeric:
            x = q.values
        else:  # a choice: its categories side by side, spread sideways to show how many
            cats = [str(c) for c in dist.get("values", [])]
            cats += [c for c in dict.fromkeys(q.values) if c not in cats]
            x = np.array([cats.index(v) for v in q.values], dtype=float)
            x += 0.3 * ((np.arange(x.size) * 0.6180339887) % 1.0 - 0.5)  # golden-ratio jitter
            _level_ticks(ax, len(cats), cats)
            ax.set_xlim(-0.5, len(cats) - 0.5)
        ax.plot(x[ok], y[ok], ".", ms=ms, alpha=alpha, color="tab:blue", zorder=3)
        if (~ok).any():
            _mark_missing(ax, x[~ok])
            _room_for_missing(ax, lower=False)
        if str(dist.get("distribution", "")) == "loguniform" and q.numeric and np.all(x > 0):
            _log_x(ax, None)
        ax.set_xlabel(q.label, fontsize=9)
        ax.grid(True, alpha=0.3)
        if i == 0:  # one label for the shared y-axis: one per row would overlap the next
            ax.set_ylabel(metric.label, fontsize=9)
    for ax in list(axes.flat)[d:]:
        ax.set_visible(False)
    if (~ok).any():  # the y-axis is shared: lowered once
        lo, hi = axes.flat[0].get_ylim()
        axes.flat[0].set_ylim(lo - 0.12 * (hi - lo), hi)
    for ax in list(axes.flat)[:d]:
        _say_no_values(ax, y)
    handles = [Line2D([], [], ls="none", marker=".", ms=8, color="tab:blue",
                      label="point with a value")]  # fmt: skip
    if (~ok).any():
        handles.append(_missing_handle(_missing_text(ds, y)))
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=8, frameon=False)
    method = spec.get("method", "?")
    fig.suptitle(_title(ds, f"{metric.name} against each parameter ({method} sample)\n"
                            f"{_footnote(ds, y)}", 40 * ncols), fontsize=10)  # fmt: skip
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    return fig


def _message_figure(ds, title: str, message: str):
    fig, ax = plt.subplots(figsize=(7.5, 2.4))
    ax.axis("off")
    ax.text(0.5, 0.5, message, ha="center", va="center", wrap=True, fontsize=9,
            color=_MISSING_COLOUR, transform=ax.transAxes, gid=MISSING_GID)  # fmt: skip
    ax.set_title(_title(ds, title), fontsize=10)
    fig.tight_layout()
    return fig


def _short_names(qs) -> list[str]:
    return [q.name if len(q.name) <= 28 else q.key for q in qs]


def _sobol_figure(ds, metric: _Quantity, qs):
    from rollerrig.studies.sensitivity import sobol_indices

    try:
        r = sobol_indices(ds, metric.key)
    except ParameterError as exc:
        return _message_figure(ds, f"Sobol indices of {metric.name}: not computed",
                               _wrap(str(exc)))  # fmt: skip
    d = len(r.names)
    fig, ax = plt.subplots(figsize=(max(6.0, 1.3 * d + 2.5), 4.4))
    x = np.arange(d)
    w = 0.38
    err = {"capsize": 4, "error_kw": {"lw": 1.2}}
    ax.bar(x - w / 2, r.S1, w, yerr=r.S1_conf, color="tab:blue", label="first order S1", **err)
    ax.bar(x + w / 2, r.ST, w, yerr=r.ST_conf, color="tab:orange", label="total ST", **err)
    ax.axhline(0.0, color="k", lw=0.6)
    top = float(np.nanmax(np.concatenate([r.S1 + r.S1_conf, r.ST + r.ST_conf, [1.0]])))
    bottom = float(np.nanmin(np.concatenate([r.S1 - r.S1_conf, [0.0]])))
    ax.set_ylim(min(bottom, 0.0) - 0.03, top + 0.05)
    names = _short_names(qs)
    ax.set_xticks(x, names, fontsize=8)
    if max(len(s) for s in names) > 12:
        plt.setp(ax.get_xticklabels(), rotation=20, ha="right")
    ax.set_ylabel("share of the variance [-]")
    ax.grid(True, axis="y", alpha=0.3)
    ax.legend(fontsize=8, title=f"error bars: {100 * r.conf_level:g} % bootstrap interval",
              title_fontsize=8, loc="upper right")  # fmt: skip
    for xs, values, conf in ((x - w / 2, r.S1, r.S1_conf), (x + w / 2, r.ST, r.ST_conf)):
        for xi, v, c in zip(xs, values, conf, strict=True):
            if np.isfinite(v):  # above the error bar
                top = v + (c if np.isfinite(c) else 0.0)
                ax.text(xi, max(top, 0.0) + 0.01, f"{v:.2f}", ha="center", va="bottom",
                        fontsize=8, zorder=5)  # fmt: skip
    what = (
        f"Sobol indices of {metric.name}\nN = {r.n_base} base rows, {metric.values.size} "
        "points (SALib, Saltelli 2010 estimators)"
    )
    ax.set_title(_title(ds, what), fontsize=10)
    fig.tight_layout()
    return fig


def _rank_figure(ds, metric: _Quantity, qs):
    from rollerrig.studies.sensitivity import rank_correlations

    try:
        r = rank_correlations(ds, metric.key)
    except ParameterError as exc:
        return _message_figure(ds, f"rank correlations of {metric.name}: not computed",
                               _wrap(str(exc)))  # fmt: skip
    d = len(r.names)
    fig, ax = plt.subplots(figsize=(7.5, max(2.4, 0.45 * d + 1.5)))
    pos = np.arange(d)
    rho = np.nan_to_num(r.rho)
    ax.barh(pos, rho, height=0.6, color="tab:blue", zorder=3)
    for i in range(d):
        if np.isfinite(r.rho[i]):
            text = f"ρ = {r.rho[i]:+.2f}, p = {r.pvalue[i]:.2g}"
        elif not qs[i].numeric:
            text = "categorical: no rank correlation"
        else:
            text = "undefined (constant)"
        ax.text(0.02 if rho[i] < 0 else -0.02, i, text, va="center",
                ha="left" if rho[i] < 0 else "right", fontsize=8)  # fmt: skip
    ax.set_yticks(pos, _short_names(qs), fontsize=8)
    ax.set_ylim(d - 0.5, -0.5)
    ax.set_xlim(-1.05, 1.05)
    ax.axvline(0.0, color="k", lw=0.6)
    ax.set_xlabel(f"Spearman rank correlation ρ with {metric.name} [-]")
    ax.grid(True, axis="x", alpha=0.3)
    ax.set_title(_title(ds, f"rank correlation with {metric.name}\n{r.note}"), fontsize=10)
    fig.tight_layout()
    return fig


def _wrap(text: str, width: int = 90) -> str:
    import textwrap

    return "\n".join(textwrap.wrap(text, width))


def _sample_figures(ds, metric: _Quantity) -> dict:
    keys = varied_parameters(ds)
    qs = [_quantity(ds, k) for k in keys]
    spec = json_attribute(ds, "sample", {})
    spec = spec if isinstance(spec, dict) else {}
    figs = {f"{metric.key}-scatter": _scatter_figure(ds, metric, qs, spec)}
    figs[f"{metric.key}-rank-correlation"] = _rank_figure(ds, metric, qs)
    if spec.get("method") == "sobol":
        figs[f"{metric.key}-sobol"] = _sobol_figure(ds, metric, qs)
    return figs
