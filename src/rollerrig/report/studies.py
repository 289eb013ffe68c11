"""Figures of a study: each metric against the study's parameters, failed points marked.

:func:`study_figures` draws, per metric, what fits the design of the study Dataset
(:mod:`rollerrig.studies.summary` describes its form):

- a **grid** of one axis: the metric against it (a log axis when the grid is log-spaced);
- a grid of two axes: a heat map over both, and one line per level of the second axis;
- a grid of more axes: a heat map over the first two, averaged over the others (the title
  says which), and a main-effect plot: the metric averaged over all other axes against each
  axis, one panel each (a shared y-axis, so that the panels compare);
- **cases**: a horizontal bar per case;
- a **sample**: the metric against each parameter (a scatter panel each), Spearman's rank
  correlation of each parameter, and for a Sobol design the indices S1 and ST with their
  confidence intervals.

A point without a value (failed, pending, or the metric undefined there) is never dropped
silently: on a line or scatter it is a cross at the bottom of the axes, in a heat map a
hatched cell, in a bar chart a cross at zero with its status, and the legend counts them by
status. A categorical parameter (friction, drive) is shown by its categories. Values are
shown in the units an engineer reads (:func:`display_unit`: kN·m/rad, km/h, kN); the
figures are returned, saving them (:func:`rollerrig.output.save_figure`) is the caller's.

The figures of each design are drawn in :mod:`~rollerrig.report.study_grid_figures`,
:mod:`~rollerrig.report.study_case_figure` and :mod:`~rollerrig.report.study_sample_figures`;
what they share (units, quantities as shown, the marks of points without a value) in
:mod:`~rollerrig.report.study_display`.
"""

from __future__ import annotations

from rollerrig.report.study_case_figure import _cases_figure
from rollerrig.report.study_display import MISSING_GID, _quantity, display_unit
from rollerrig.report.study_grid_figures import _grid_figures
from rollerrig.report.study_sample_figures import _sample_figures
from rollerrig.studies.summary import check_metric, design_kind, metric_names

__all__ = ["MISSING_GID", "display_unit", "study_figures"]


def study_figures(ds, metrics=None) -> dict:
    """The figures of a study, per metric, for its design.

    Parameters
    ----------
    ds : xarray.Dataset
        A study (:func:`rollerrig.studies.store.open_study`).
    metrics : str or sequence of str, optional
        The metrics to draw; default every metric of the study.

    Returns
    -------
    dict of str -> matplotlib.figure.Figure
        Keyed ``"<metric>-<kind>"`` (a file stem): for a grid ``-line`` (one axis),
        ``-heatmap`` and ``-lines`` (two axes), ``-heatmap`` and ``-main-effects`` (more);
        for cases ``-cases``; for a sample ``-scatter``, ``-rank-correlation`` and, for a
        Sobol design, ``-sobol`` (a figure saying why when the indices cannot be computed,
        e.g. failed points). The caller saves and closes them.

    Raises
    ------
    ParameterError
        A metric the study does not have (the message lists those it has), or a Dataset
        without the attributes of a study.

    Examples
    --------
    >>> import json, numpy as np, xarray as xr
    >>> import matplotlib.pyplot as plt
    >>> ds = xr.Dataset(
    ...     {"speed": ("point", [5.0, 10.0, 15.0], {"units": "m/s", "long_name": "speed"}),
    ...      "status": ("point", ["ok", "solver failed", "ok"]),
    ...      "peak_coa": ("point", [0.31, np.nan, 0.35], {"units": "1"})},
    ...     attrs={"study": "demo", "design": "grid", "parameters": '["speed"]',
    ...            "metrics": '["peak_coa"]', "grid_shape": "[3]", "grid_scales": '["linear"]'})
    >>> figs = study_figures(ds)
    >>> list(figs), figs["peak_coa-line"].axes[0].get_xlabel()
    (['peak_coa-line'], 'speed [km/h]')
    >>> plt.close("all")
    """
    names = metric_names(ds) if metrics is None else (
        [metrics] if isinstance(metrics, str) else [str(m) for m in metrics])  # fmt: skip
    design = design_kind(ds)
    for m in names:
        check_metric(ds, m)
    figs: dict = {}
    for m in names:
        metric = _quantity(ds, m)
        if design == "grid":
            figs.update(_grid_figures(ds, metric))
        elif design == "cases":
            figs[f"{m}-cases"] = _cases_figure(ds, metric)
        else:
            figs.update(_sample_figures(ds, metric))
    return figs
