"""Tables of a study: one row per point, the spread of each metric, the failed points; never a
NaN in a row (None, with the reason beside it).

The studies are synthetic Datasets in the form the study store writes (plan11.md).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

from rollerrig._validation import ParameterError
from rollerrig.studies.summary import failures, metric_summary, metric_table


def _study(design: str = "grid", **attrs) -> xr.Dataset:
    """Six points over stiffness x friction (3 x 2): one failed, one pending, one where the
    release overshoot is undefined."""
    k = np.repeat([43.5e3, 83.5e3, 143.5e3], 2)  # [N.m/rad]
    friction = np.tile(["dry", "wet"], 3)
    status = ["ok", "solver failed", "ok", "ok", "pending", "ok"]
    reason = ["", "step size below 1e-12 s at t = 2.1 s", "", "", "", ""]
    overshoot = np.array([0.30, np.nan, 0.21, np.nan, np.nan, 0.12])
    peak = np.array([0.40, np.nan, 0.38, 0.36, np.nan, 0.31])
    data = {
        "stiffness.roller_shaft": ("point", k, {"units": "N.m/rad", "long_name": "k56"}),
        "friction": ("point", friction),
        "label": ("point", [f"k56 = {v / 1e3:.1f} kN·m/rad, {f}"
                            for v, f in zip(k, friction, strict=True)]),
        "status": ("point", status),
        "reason": ("point", reason),
        "release_overshoot": ("point", overshoot,
                              {"units": "1", "nan_meaning": "no torque release to measure"}),
        "peak_coa": ("point", peak, {"units": "1"}),
    }  # fmt: skip
    base = {
        "study": "synthetic",
        "design": design,
        "parameters": json.dumps(["stiffness.roller_shaft", "friction"]),
        "metrics": json.dumps(["release_overshoot", "peak_coa"]),
        "grid_shape": "[3, 2]",
        "grid_scales": '["list", "list"]',
    }
    return xr.Dataset(data, attrs=base | attrs)


def _no_nan(rows):
    for row in rows:
        for v in row.values():
            assert v is None or isinstance(v, str | int) or np.isfinite(v), row
    json.dumps(rows, allow_nan=False)


def test_metric_table_has_one_row_per_point_with_reasons():
    rows = metric_table(_study(), "release_overshoot")
    _no_nan(rows)
    assert len(rows) == 6
    assert list(rows[0]) == [
        "point", "label", "stiffness.roller_shaft [N.m/rad]", "friction",
        "release_overshoot [-]", "status", "reason",
    ]  # fmt: skip
    assert rows[0]["release_overshoot [-]"] == 0.30
    assert rows[0]["stiffness.roller_shaft [N.m/rad]"] == 43.5e3 and rows[1]["friction"] == "wet"
    assert rows[1]["release_overshoot [-]"] is None and rows[1]["status"] == "solver failed"
    assert rows[1]["reason"].startswith("step size")
    # Ran, but the metric is undefined: the metric's nan_meaning says why.
    assert rows[3]["status"] == "ok" and rows[3]["reason"] == "no torque release to measure"
    assert rows[4]["status"] == "pending" and rows[4]["release_overshoot [-]"] is None


def test_metric_summary_counts_and_spread():
    rows = metric_summary(_study())
    _no_nan(rows)
    over, peak = rows
    assert over["metric"] == "release_overshoot" and over["unit"] == "1"
    assert (over["points"], over["with value"], over["failed"], over["pending"]) == (6, 3, 1, 1)
    assert over["undefined"] == 1
    v = np.array([0.30, 0.21, 0.12])
    assert over["min"] == 0.12 and over["max"] == 0.30
    assert over["mean"] == pytest.approx(v.mean()) and over["std"] == pytest.approx(v.std(ddof=1))
    assert "p50" not in over  # percentiles only for sampled designs
    assert peak["with value"] == 4 and peak["undefined"] == 0


def test_metric_summary_of_a_sample_has_percentiles():
    rows = metric_summary(_study("sample"), ["peak_coa"])
    _no_nan(rows)
    (peak,) = rows
    v = np.array([0.40, 0.38, 0.36, 0.31])
    # numpy's default (linear) percentile: p50 of four values is the mean of the middle two.
    assert peak["p50"] == pytest.approx(0.37)
    assert peak["p5"] == pytest.approx(np.percentile(v, 5)) and peak["p95"] <= 0.40


def test_metric_summary_without_values_is_none():
    ds = _study()
    ds["peak_coa"].values[:] = np.nan
    (peak,) = metric_summary(ds.assign_attrs(design="sample"), ["peak_coa"])
    _no_nan([peak])
    assert peak["with value"] == 0
    assert all(peak[k] is None for k in ("min", "mean", "max", "std", "p5", "p50", "p95"))


def test_failures_lists_the_failed_points_not_the_pending():
    rows = failures(_study())
    _no_nan(rows)
    assert [r["point"] for r in rows] == [1]
    assert rows[0]["status"] == "solver failed" and rows[0]["friction"] == "wet"
    assert rows[0]["stiffness.roller_shaft [N.m/rad]"] == 43.5e3


def test_unknown_metric_is_a_clear_error():
    with pytest.raises(ParameterError, match=r"no metric 'overshoot'.*'release_overshoot'"):
        metric_table(_study(), "overshoot")
    with pytest.raises(ParameterError, match=r"no metric 'settling_time'"):
        metric_summary(_study(), ["settling_time"])


def test_a_dataset_without_the_study_attributes_is_a_clear_error():
    ds = _study()
    ds.attrs["design"] = "anything"
    with pytest.raises(ParameterError, match=r"'design' must be 'grid', 'sample' or 'cases'"):
        metric_summary(ds)
    ds = _study(parameters='["stiffness.roller_shaft", "load"]')
    with pytest.raises(ParameterError, match=r"\['load'\] are listed"):
        failures(ds)
