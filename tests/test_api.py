"""The notebook-level functions of rollerrig (src/rollerrig/_api.py and the top-level names)."""

from __future__ import annotations

import pytest

import rollerrig as rr


def test_a_missing_recording_is_the_package_error_and_a_file_not_found(tmp_path):
    missing = tmp_path / "missing.tdms"
    for call in (lambda: rr.read_recording(missing), lambda: rr.analyze(missing)):
        with pytest.raises(rr.ParameterError, match="recording file not found") as info:
            call()
        assert isinstance(info.value, FileNotFoundError)


def test_simulation_says_which_argument_a_protocol_belongs_to():
    protocol = rr.Protocol.from_steps(
        "p", [rr.Hold(1.0)], normal_load=4300.0, roller_speed=30 / 3.6
    )
    with pytest.raises(rr.ParameterError, match="pass the experiment as experiment="):
        rr.Simulation(protocol)


def test_analyze_and_read_recording_name_the_channel_map_alike():
    import inspect

    assert "channel_map" in inspect.signature(rr.analyze).parameters
    assert "channel_map" in inspect.signature(rr.explain_recording).parameters
    assert "channel_map" in inspect.signature(rr.read_recording).parameters


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"validate": "strikt"}, "validate must be one of ('strict', 'lenient'), got 'strikt'"),
        ({"rig": 5}, "rig must be RigParameters, the path of a rig TOML file or None"),
        ({"truth": 3.0}, "truth: must be an xarray.Dataset or the path of a NetCDF file"),
        ({"calibration": ["x"]}, "calibration: "),
    ],
)  # fmt: skip
def test_analyze_checks_its_arguments_before_reading_anything(kwargs, message):
    # A validate it does not know had been ignored for a Recording; a rig or a recording of
    # the wrong type had raised a bare TypeError or AttributeError.
    with pytest.raises(rr.ParameterError, match=re_escape(message)):
        rr.analyze(object(), **kwargs)
    with pytest.raises(rr.ParameterError, match="recording must be a Recording or the path"):
        rr.analyze(5)
    with pytest.raises(rr.ParameterError, match="recording must be a Recording or the path"):
        rr.explain_recording(5)


def test_analyze_loads_truth_and_calibration_as_the_command_does(tmp_path):
    import numpy as np
    import xarray as xr

    not_nc = tmp_path / "truth.nc"
    not_nc.write_text("this is not NetCDF")
    with pytest.raises(rr.ParameterError, match=re_escape(f"truth {not_nc}: not a NetCDF file")):
        rr.analyze(object(), truth=not_nc)
    # An analysis' own output has a 'coa' (the measured one): it had been taken as the truth.
    zeros = ("time", np.zeros(10))
    analysis = xr.Dataset({"coa": zeros, "coa_corrected": zeros}, coords={"time": np.arange(10.0)})
    with pytest.raises(rr.ParameterError, match="truth: an analysis' output"):
        rr.analyze(object(), truth=analysis)
    not_json = tmp_path / "calibration.json"
    not_json.write_text("{")
    with pytest.raises(rr.ParameterError, match=re_escape(f"calibration {not_json}: not a JSON")):
        rr.analyze(object(), calibration=not_json)


def test_analyze_refuses_a_calibration_made_on_another_rig_unless_allowed():
    from rollerrig.calibrate.binding import rig_binding

    made_on = rr.default_rig()
    value = {
        "value": 50000.0,
        "standard_error": 500.0,
        "unit": "N.m/rad",
        "initial": 43500.0,
        "identified": True,
        "relative_standard_error": 0.01,
        "at_upper_bound": False,
    }
    doc = {
        "parameters": {"stiffness.roller_shaft": value},
        "values": {"stiffness.roller_shaft": 50000.0},
        "rig": rig_binding(made_on, {"stiffness.roller_shaft": (50000.0, 500.0, 43500.0)}),
    }
    other = made_on.with_overrides({"stiffness.am_mount": 2.0e5})
    with pytest.raises(rr.ParameterError, match="calibration: rig: made on another rig"):
        rr.analyze(object(), rig=other, calibration=doc)
    # Allowed: a warning, then the recording is looked at (here: not one).
    with (
        pytest.warns(UserWarning, match="made on another rig"),
        pytest.raises(rr.ParameterError, match="recording must be a Recording"),
    ):
        rr.analyze(object(), rig=other, calibration=doc, allow_other_rig=True)


def re_escape(text: str) -> str:
    import re

    return re.escape(text)
