"""The calibration figure on a small fit dataset of known content."""

import numpy as np
import xarray as xr

from rollerrig.report.calibration import _zoom_window, calibration_figure


def _fit_dataset():
    t = np.arange(0.0, 10.0, 0.004)
    torque = np.where(t < 5.0, 800.0 * t / 5.0, 0.0)  # a release at 5 s
    data = {}
    for name, measured in (("torque", torque), ("roller_speed", 18.4 + 0 * t)):
        data[f"{name}_measured"] = ("time", measured)
        data[f"{name}_start"] = ("time", measured * 1.1)
        data[f"{name}_fitted"] = ("time", measured + 0.5)
    return xr.Dataset(data, coords={"time": t})


def test_zoom_window_starts_before_the_steepest_fall():
    ds = _fit_dataset()
    start, end = _zoom_window(ds["time"].values, ds["torque_measured"].values)
    assert start < 5.0 < end and end - start <= 3.0 + 1e-9


def test_figure_has_a_row_per_channel_and_the_residual_rms_in_its_legend():
    fig = calibration_figure(_fit_dataset())
    axes = fig.axes
    assert len(axes) == 6  # torque, roller speed (no wheel speed here), residual; x2 columns
    labels = [t.get_text() for t in axes[-2].get_legend().get_texts()]
    assert any("RMS 0.5 N·m" in text for text in labels)  # recorded − fitted = −0.5


def test_the_report_splits_each_standard_error_into_its_two_parts():
    # The analysis report had shown only the total; the bearing friction's 0.0018 is nearly
    # all the torque's zero (6e-6 from the residuals on the tour's recording, 2026-12-03).
    from rollerrig.report.calibration import calibration_section
    from rollerrig.report.html import HtmlReport

    doc = {
        "parameters": {
            "bearing.friction_coefficient": {
                "value": 0.009092, "standard_error": 0.00178, "unit": "1",
                "standard_error_statistical": 6.0e-6, "standard_error_systematic": 0.00178,
                "systematic": {"torque_class": -0.00177, "torque_gain": -0.00016},
            },
            "inertia.roller": {"value": None, "standard_error": None, "unit": "kg.m^2",
                               "why_null": "not identifiable"},
        }
    }  # fmt: skip
    rep = HtmlReport("t")
    calibration_section(rep, doc)
    page = rep.render()
    assert "from the residuals" in page and "6 × 10⁻⁶" in page  # typeset
    assert "0.00178 (torque_class 0.00177)" in page
    assert "not identified" in page  # a key without a split keeps its row
