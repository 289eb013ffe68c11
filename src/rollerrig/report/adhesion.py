"""Creep-CoA figures of a test: the branches of each cycle, a fitted Polach curve, residuals."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np

from rollerrig._validation import ParameterError

__all__ = ["adhesion_figure"]


def adhesion_figure(creep, coa, branches=None, fit=None, title: str = ""):
    """Creep-CoA curve with ascending/descending branches, a fitted curve and its residuals.

    Parameters
    ----------
    creep, coa : array_like, shape (n,)
        Creep [-] and CoA [-] of the test.
    branches : list of Branches, optional
        From :func:`rollerrig.measure.segmentation.adhesion_branches`; ascending branches are
        drawn solid, descending dashed. Without them all points are drawn.
    fit : PolachFit, optional
        From :func:`rollerrig.fit.polach.fit_polach`: its curve is drawn and a second panel shows
        its residuals against creep.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    s = np.asarray(creep, dtype=float)
    mu = np.asarray(coa, dtype=float)
    if s.ndim != 1 or s.shape != mu.shape:  # matplotlib's "x and y must have same first dimension"
        raise ParameterError(
            f"creep (shape {s.shape}) and coa (shape {mu.shape}) must be 1-D arrays of the same "
            "length"
        )
    if fit is None:
        fig, ax = plt.subplots(figsize=(7.5, 4.8))
        axes = [ax]
    else:
        fig, axes = plt.subplots(
            2, 1, figsize=(7.5, 6.4), sharex=True, gridspec_kw={"height_ratios": [3, 1]}
        )
        ax = axes[0]
    if branches:
        for i, b in enumerate(branches):
            ax.plot(100 * s[b.ascending], mu[b.ascending], "-", color="tab:blue",
                    label="ascending" if i == 0 else None)  # fmt: skip
            ax.plot(100 * s[b.descending], mu[b.descending], "--", color="tab:orange",
                    label="descending" if i == 0 else None)  # fmt: skip
    else:
        ax.plot(100 * s, mu, ".", ms=2, color="0.4", label="measured")
    if fit is not None:
        grid = np.linspace(0.0, float(np.nanmax(np.abs(fit.creep))), 400)
        p = fit.parameters
        ax.plot(100 * grid, fit.curve(grid), "k-", lw=1.5,
                label=f"Polach fit: μ0={p.static_friction:.3f}, A={p.limit_ratio:.2f}, "
                f"B={p.friction_decay:.2f} s/m, kA={p.k_adhesion:.2f}, kS={p.k_slip:.2f}"
                + (" (A, B not identifiable)" if fit.unidentified() else ""))  # fmt: skip
        axes[1].plot(100 * fit.creep, fit.residuals, ".", ms=2, color="tab:red")
        axes[1].axhline(0.0, color="k", lw=0.8)
        axes[1].set_ylabel("residual [-]")
        axes[1].set_title(f"RMSE {fit.rmse:.2g}", fontsize="small")
    ax.set_ylabel("coefficient of adhesion [-]")
    axes[-1].set_xlabel("creep [%]")
    ax.legend(fontsize="small")
    ax.grid(alpha=0.3)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return fig
