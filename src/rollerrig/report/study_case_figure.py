"""The figure of a study of cases: a horizontal bar per case, a case without a value marked with
its status and the reason it failed.

:func:`rollerrig.report.studies.study_figures` calls :func:`_cases_figure` for a study of design
``"cases"``.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.lines import Line2D

from rollerrig.report.study_display import (
    _MISSING_COLOUR,
    MISSING_GID,
    _cell_status,
    _fmt,
    _footnote,
    _missing_text,
    _Quantity,
    _title,
)
from rollerrig.studies.summary import text_values

__all__: list[str] = []


def _cases_figure(ds, metric: _Quantity):
    y = metric.values
    n = y.size
    labels = list(text_values(ds, "label"))
    labels = [lab or f"case {i}" for i, lab in enumerate(labels)]
    status, reason = _cell_status(ds, y), text_values(ds, "reason")
    fig, ax = plt.subplots(figsize=(8.5, max(2.6, 0.38 * n + 1.4)))
    pos = np.arange(n)
    ok = np.isfinite(y)
    ax.barh(pos[ok], y[ok], height=0.6, color="tab:blue", zorder=3)
    span = float(np.max(np.abs(y[ok]))) if ok.any() else 1.0
    for i in pos[ok]:
        ax.text(y[i] + 0.01 * span * np.sign(y[i] or 1.0), i, _fmt(y[i]), va="center",
                ha="left" if y[i] >= 0 else "right", fontsize=8)  # fmt: skip
    if (~ok).any():
        ax.plot(np.zeros((~ok).sum()), pos[~ok], ls="none", marker="x", ms=9, mew=2,
                color=_MISSING_COLOUR, zorder=5, gid=MISSING_GID)  # fmt: skip
        for i in pos[~ok]:
            why = f"{status[i]}: {reason[i]}" if reason[i] else str(status[i])
            why = why if len(why) <= 70 else why[:69] + "…"
            ax.text(0.02 * span, i, why, va="center", ha="left", fontsize=8,
                    color=_MISSING_COLOUR, style="italic")  # fmt: skip
    ax.set_yticks(pos, labels, fontsize=8)
    ax.set_ylim(n - 0.5, -0.5)  # the first case on top
    ax.axvline(0.0, color="k", lw=0.6)
    lo = min(0.0, float(y[ok].min()) if ok.any() else 0.0)
    hi = max(0.0, float(y[ok].max()) if ok.any() else 1.0)
    pad = 0.15 * (hi - lo or 1.0)
    ax.set_xlim(lo - (pad if lo < 0 else 0.0), hi + pad)
    ax.set_xlabel(metric.label)
    ax.grid(True, axis="x", alpha=0.3)
    if (~ok).any():
        ax.legend(handles=[Line2D([], [], ls="none", marker="x", ms=9, mew=2,
                                  color=_MISSING_COLOUR, label=_missing_text(ds, y))],
                  fontsize=8, loc="lower right")  # fmt: skip
    ax.set_title(_title(ds, f"{metric.name} per case\n{_footnote(ds, y)}"), fontsize=10)
    fig.tight_layout()
    return fig
