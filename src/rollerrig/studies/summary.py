"""Tables of a study: one row per point, the spread of each metric, the points that failed.

Every function takes the study Dataset (:func:`rollerrig.studies.store.open_study`): dimension
``point``; one variable per varied quantity (listed in the JSON attribute ``parameters``, SI
units in their ``units``, or text for a categorical one), ``label``, ``status``
(``"ok"``, ``"solver failed"``, ``"invalid parameters"``, ``"pending"``), ``reason`` and one
float variable per metric (listed in ``metrics``; NaN where the point has no value). The
tables are lists of dicts, ready for :func:`rollerrig.output.write_table` or JSON: a missing
value is ``None``, never NaN, and the row says why (status, reason, or the metric's
``nan_meaning``).

Examples
--------
>>> import json, numpy as np, xarray as xr
>>> ds = xr.Dataset(
...     {"speed": ("point", [5.0, 10.0, 15.0], {"units": "m/s"}),
...      "label": ("point", ["v = 18", "v = 36", "v = 54"]),
...      "status": ("point", ["ok", "solver failed", "ok"]),
...      "reason": ("point", ["", "step size below 1e-12 s at t = 2.1 s", ""]),
...      "peak_coa": ("point", [0.31, np.nan, 0.35], {"units": "1"})},
...     attrs={"study": "demo", "design": "grid", "parameters": json.dumps(["speed"]),
...            "metrics": json.dumps(["peak_coa"]), "grid_shape": "[3]",
...            "grid_scales": '["linear"]'})
>>> metric_table(ds, "peak_coa")[1]["peak_coa [-]"] is None
True
>>> [(r["metric"], r["with value"], r["failed"], r["max"]) for r in metric_summary(ds)]
[('peak_coa', 2, 1, 0.35)]
>>> failures(ds)[0]["status"]
'solver failed'
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence

import numpy as np

from rollerrig._validation import ParameterError, did_you_mean

__all__ = [
    "STATUS_OK",
    "STATUS_PENDING",
    "check_metric",
    "design_kind",
    "failures",
    "grid_shape",
    "is_numeric",
    "json_attribute",
    "metric_names",
    "metric_summary",
    "metric_table",
    "missing_counts",
    "study_name",
    "text_values",
    "varied_parameters",
    "warned_points",
]

STATUS_OK = "ok"
"""Status of a point that ran and was measured."""
STATUS_PENDING = "pending"
"""Status of a point not run yet (an interrupted study)."""
WARNING_PREFIX = "warning: "
"""Start of an ``ok`` point's reason that holds the domain warnings of its setup."""

PERCENTILES = (5.0, 50.0, 95.0)
"""Percentiles [%] of a metric that :func:`metric_summary` gives for a sampled design."""


# --------------------------------------------------------------------------------------------
# Reading the study Dataset (shared by the analysis and the figures of a study)
# --------------------------------------------------------------------------------------------


def study_name(ds) -> str:
    """The study's name from its Dataset (``"(unnamed)"`` when it has none)."""
    return str(ds.attrs.get("study", "") or "(unnamed)")


def json_attribute(ds, key: str, default=None):
    """A JSON attribute of the study, decoded; ``default`` when absent."""
    if key not in ds.attrs:
        if default is not None:
            return default
        raise ParameterError(
            f"study {study_name(ds)!r}: the Dataset has no attribute {key!r}; open the study "
            "with rollerrig.studies.store.open_study (it writes the attributes a study needs)"
        )
    value = ds.attrs[key]
    if isinstance(value, str):
        try:
            return json.loads(value)
        except json.JSONDecodeError as exc:
            raise ParameterError(
                f"study {study_name(ds)!r}: attribute {key!r} is not JSON text: {value[:80]!r}"
            ) from exc
    return value


def design_kind(ds) -> str:
    """The study's design: ``"grid"``, ``"sample"`` or ``"cases"`` (checked)."""
    design = str(ds.attrs.get("design", ""))
    if design not in ("grid", "sample", "cases"):
        raise ParameterError(
            f"study {study_name(ds)!r}: attribute 'design' must be 'grid', 'sample' or "
            f"'cases', got {design!r}"
        )
    return design


def varied_parameters(ds) -> list[str]:
    """The varied quantities, in design order; each must be a variable of the Dataset."""
    keys = [str(k) for k in json_attribute(ds, "parameters", [])]
    missing = [k for k in keys if k not in ds.variables]
    if missing:
        raise ParameterError(
            f"study {study_name(ds)!r}: parameters {missing} are listed in attrs 'parameters' "
            "but have no variable in the Dataset"
        )
    return keys


def grid_shape(ds, keys: list[str]) -> tuple[int, ...]:
    """``grid_shape`` of a grid study, checked against its axes and points."""
    shape = tuple(int(s) for s in json_attribute(ds, "grid_shape"))
    if len(shape) != len(keys) or int(np.prod(shape)) != ds.sizes["point"]:
        raise ParameterError(
            f"study {study_name(ds)!r}: grid_shape {list(shape)} does not fit the "
            f"{len(keys)} axes {keys} and {ds.sizes['point']} points (C order over the axes)"
        )
    return shape


def metric_names(ds) -> list[str]:
    """The metrics of the study, in the order of attrs ``metrics``."""
    return [str(m) for m in json_attribute(ds, "metrics", [])]


def check_metric(ds, metric: str) -> str:
    """``metric`` if the study has it, else a :class:`ParameterError` listing those it has."""
    names = metric_names(ds)
    if metric in names and metric in ds.variables:
        return metric
    hint = did_you_mean(str(metric), names)
    raise ParameterError(
        f"study {study_name(ds)!r} has no metric {metric!r}{hint}; its metrics: "
        f"{', '.join(repr(m) for m in names) or 'none'}. Choose one of them, or add it to "
        "[outputs] metrics of the study file and run the study again"
    )


def _metric_values(ds, metric: str) -> np.ndarray:
    """Values of a metric per point [its unit], float, NaN where there is none."""
    return np.asarray(ds[check_metric(ds, metric)].values, dtype=float)


def text_values(ds, name: str) -> np.ndarray:
    """A text variable per point (``status``, ``label``, ``reason``) as str; '' if absent."""
    n = ds.sizes["point"]
    if name not in ds.variables:
        return np.full(n, STATUS_OK if name == "status" else "", dtype=object)
    return np.asarray([str(v) for v in np.asarray(ds[name].values).ravel()], dtype=object)


def _unit(ds, name: str) -> str:
    return str(ds[name].attrs.get("units", "")) if name in ds.variables else ""


def is_numeric(values: np.ndarray) -> bool:
    return np.asarray(values).dtype.kind in "biuf"


def _column(name: str, unit: str) -> str:
    """A column name with its unit: ``"speed [m/s]"``; ``[-]`` for a dimensionless one."""
    if unit in ("1", "-"):
        return f"{name} [-]"
    return f"{name} [{unit}]" if unit else name


def _python(value):
    """A table cell: a Python float/int/str, None for None, NaN or inf."""
    if value is None:
        return None
    if isinstance(value, str | np.str_):
        return str(value)
    if isinstance(value, bool | np.bool_):
        return bool(value)
    if isinstance(value, int | np.integer):
        return int(value)
    v = float(value)
    return v if math.isfinite(v) else None


def _parameter_columns(ds) -> list[tuple[str, np.ndarray]]:
    """(column name with unit, values per point) of each varied quantity."""
    return [
        (_column(k, _unit(ds, k)), np.asarray(ds[k].values).ravel()) for k in varied_parameters(ds)
    ]


def missing_counts(ds, values: np.ndarray) -> dict[str, int]:
    """Points without a value, by why: their status, or "metric undefined" where the point
    ran but the metric has no value there [points]."""
    status = text_values(ds, "status")
    bad = ~np.isfinite(values)
    counts: dict[str, int] = {}
    for s in status[bad]:
        counts[s] = counts.get(s, 0) + 1
    if STATUS_OK in counts:  # ran, but the metric is undefined there
        counts["metric undefined"] = counts.pop(STATUS_OK)
    return counts


def _describe_missing(counts: dict[str, int]) -> str:
    return ", ".join(f"{status}: {n}" for status, n in sorted(counts.items()))


# --------------------------------------------------------------------------------------------
# Tables
# --------------------------------------------------------------------------------------------


def metric_table(ds, metric: str) -> list[dict]:
    """One row per point: its parameters, label, status, the metric's value and the reason.

    Parameters
    ----------
    ds : xarray.Dataset
        A study (see the module's docstring).
    metric : str
        One of the study's metrics (attrs ``metrics``).

    Returns
    -------
    list of dict
        In point order, with keys ``point``, ``label``, one ``"<key> [<unit>]"`` per varied
        quantity (SI, as stored; a categorical one as its text), ``"<metric> [<unit>]"`` (None
        where the point has no value), ``status`` and ``reason`` (for a point that ran but
        where the metric is undefined, the metric's ``nan_meaning``).

    Raises
    ------
    ParameterError
        The study has no such metric (the message lists those it has).
    """
    y = _metric_values(ds, metric)
    unit = _unit(ds, metric)
    meaning = str(ds[metric].attrs.get("nan_meaning", "the metric is undefined at this point"))
    params = _parameter_columns(ds)
    labels, status, reason = (
        text_values(ds, "label"),
        text_values(ds, "status"),
        text_values(ds, "reason"),
    )
    name = _column(metric, unit)
    rows = []
    for i in range(y.size):
        row: dict = {"point": i, "label": labels[i]}
        row.update({col: _python(values[i]) for col, values in params})
        value = _python(y[i])
        row[name] = value
        row["status"] = status[i]
        why = reason[i]
        if value is None and status[i] == STATUS_OK and not why:
            why = meaning
        row["reason"] = why
        rows.append(row)
    return rows


def metric_summary(ds, metrics: Sequence[str] | None = None) -> list[dict]:
    """The spread of each metric over the points that have a value.

    Parameters
    ----------
    ds : xarray.Dataset
        A study.
    metrics : sequence of str, optional
        Default: every metric of the study.

    Returns
    -------
    list of dict
        One row per metric: ``metric``, ``unit``, ``points`` (all), ``with value``,
        ``failed`` (status neither ok nor pending), ``pending`` (not run yet), ``undefined``
        (ran, but the metric has no value there: its ``nan_meaning``), and over the points
        with a value ``min``, ``mean``, ``max``, ``std`` (sample standard deviation,
        ``ddof = 1``) [the metric's unit]; for a sampled design also ``p5``, ``p50``, ``p95``
        (percentiles, linear interpolation between order statistics) [the metric's unit]. A
        statistic without enough values is None.

    Notes
    -----
    For a Sobol design every point of SALib's Saltelli sample is a draw from the joint input
    distribution (each row mixes columns of two independent samples), so all of them enter
    the spread; for a grid or cases the statistics are over the points as designed, with
    equal weights.
    """
    names = metric_names(ds) if metrics is None else [str(m) for m in metrics]
    sampled = design_kind(ds) == "sample"
    status = text_values(ds, "status")
    rows = []
    for metric in names:
        y = _metric_values(ds, metric)
        ok = np.isfinite(y)
        v = y[ok]
        row = {
            "metric": metric,
            "unit": _unit(ds, metric),
            "points": int(y.size),
            "with value": int(ok.sum()),
            "failed": int(np.sum(~ok & (status != STATUS_OK) & (status != STATUS_PENDING))),
            "pending": int(np.sum(~ok & (status == STATUS_PENDING))),
            "undefined": int(np.sum(~ok & (status == STATUS_OK))),
            "min": _python(v.min()) if v.size else None,
            "mean": _python(v.mean()) if v.size else None,
            "max": _python(v.max()) if v.size else None,
            "std": _python(v.std(ddof=1)) if v.size > 1 else None,
        }
        if sampled:
            pct = np.percentile(v, PERCENTILES) if v.size else [np.nan] * len(PERCENTILES)
            row.update({f"p{q:g}": _python(p) for q, p in zip(PERCENTILES, pct, strict=True)})
        rows.append(row)
    return rows


def warned_points(ds) -> list[dict]:
    """The points that ran ``ok`` with a domain warning of their setup (a shaft too stiff to
    resolve, a torque beyond the drive): ``point``, ``label`` and ``reason``, in point order."""
    status = text_values(ds, "status")
    reason = text_values(ds, "reason")
    labels = text_values(ds, "label")
    return [
        {"point": int(i), "label": labels[i], "reason": reason[i]}
        for i in range(status.size)
        if status[i] == STATUS_OK and reason[i].startswith(WARNING_PREFIX)
    ]


def failures(ds) -> list[dict]:
    """The points that ran and failed (status neither ``"ok"`` nor ``"pending"``).

    Returns
    -------
    list of dict
        In point order: ``point``, ``label``, one ``"<key> [<unit>]"`` per varied quantity,
        ``status`` and ``reason``. Empty when every point ran (or is still pending).
    """
    status = text_values(ds, "status")
    bad = np.flatnonzero((status != STATUS_OK) & (status != STATUS_PENDING))
    params = _parameter_columns(ds)
    labels, reason = text_values(ds, "label"), text_values(ds, "reason")
    rows = []
    for i in bad:
        row: dict = {"point": int(i), "label": labels[i]}
        row.update({col: _python(values[i]) for col, values in params})
        row.update({"status": status[i], "reason": reason[i]})
        rows.append(row)
    return rows
