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
