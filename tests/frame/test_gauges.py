"""Virtual strain gauges: the stress at each gauge from the twin's force channels."""

from __future__ import annotations

import re

import numpy as np
import pytest

from rollerrig._validation import ParameterError
from rollerrig.frame import analyze_frame, default_frame, gauge_influence, gauge_signals

pytest.importorskip("Pynite")


@pytest.fixture(scope="module")
def result():
    return analyze_frame(default_frame(), 20e3, 2e3, n_modes=2)


def test_signals_are_the_static_result_at_the_test_load(result):
    influence = gauge_influence(result)
    t = np.linspace(0.0, 1.0, 11)
    normal = 20e3 * t
    traction = 2e3 * t
    signals = gauge_signals({"normal_load": normal, "contact_force": traction}, influence)
    for name in influence.names:
        # Linear in the loads: at the test load it is the static analysis' gauge stress.
        assert signals[name][-1] == pytest.approx(result.gauge_stresses[name], rel=1e-12)
        assert signals[name][0] == 0.0
        np.testing.assert_allclose(signals[name], t * result.gauge_stresses[name], rtol=1e-12)
    strains = influence.strains(normal, traction)
    assert strains["top_beam"][-1] == pytest.approx(result.gauge_stresses["top_beam"] / 210e9)
    assert influence.first_frequency == pytest.approx(result.frequencies[0])


def test_signs_of_the_gauges(result):
    g = result.gauges
    # The air spring pushes the top beam up at mid-span: hogging, the top face in tension.
    assert g["top_beam"].normal > 0
    # Traction pushes the pivots towards -x: the rear columns bend, and the gauges on their
    # front faces below the pivots read the opposite sign of braking.
    braking = gauge_influence(result).stresses(0.0, -1.0)
    traction = gauge_influence(result).stresses(0.0, 1.0)
    for name in ("column_rear_left", "column_rear_right"):
        assert traction[name] == pytest.approx(-braking[name])
        assert traction[name] != 0.0


def test_a_missing_channel_is_named(result):
    with pytest.raises(ParameterError, match="no channel 'contact_force'"):
        gauge_signals({"normal_load": np.zeros(3)}, gauge_influence(result))
    with pytest.raises(ParameterError, match="traction_force must be finite"):
        gauge_influence(result).stresses(np.zeros(2), np.array([0.0, np.nan]))


def test_mismatched_force_lengths_name_both():
    """Three normal loads and two traction forces: numpy's bare broadcast ValueError before."""
    influence = gauge_influence(analyze_frame(default_frame(), n_modes=1))
    with pytest.raises(
        ParameterError,
        match=re.escape("normal_load (shape (3,)) and traction_force (shape (2,)) must have"),
    ):
        influence.stresses([1.0, 2.0, 3.0], [1.0, 2.0])
    source = {"normal_load": [1.0, 2.0], "contact_force": [1.0, 2.0, 3.0]}
    with pytest.raises(
        ParameterError,
        match=re.escape(
            "channel 'normal_load' (shape (2,)) and channel 'contact_force' (shape (3,)) must"
        ),
    ):
        gauge_signals(source, influence)


def test_gauge_signals_refuses_text_channels_and_a_source_that_is_no_mapping():
    influence = gauge_influence(analyze_frame(default_frame(), n_modes=1))
    with pytest.raises(
        ParameterError, match=re.escape("channel 'normal_load' must be numbers, got text")
    ):
        gauge_signals({"normal_load": ["a"], "contact_force": [1.0]}, influence)
    with pytest.raises(
        ParameterError,
        match=re.escape("source must be a mapping of channel name -> array (the twin's results"),
    ):
        gauge_signals(None, influence)
