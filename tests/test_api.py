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
