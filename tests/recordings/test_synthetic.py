"""Synthetic DAQ recordings: closed forms (lines at known frequencies and amplitudes, exact
encoder counts at constant speed, the anti-alias filter's attenuation), determinism, and the
twin's clean channels carried through unchanged when the disturbances are off."""

import json
from dataclasses import replace

import numpy as np
import pytest
import xarray as xr

from rollerrig.recordings.recording import CANONICAL_CHANNELS
from rollerrig.recordings.synthetic import LINE_NAMES, DisturbanceModel, synthetic_recording
from rollerrig.rig.parameters import default_rig
from rollerrig.solve.simulation import Simulation

RIG = default_rig()
CPR = RIG.sensors.encoder_counts_per_revolution  # 2500 lines x4 = 10000


def _constant_speed_dataset(rate, duration, omega_wheel, omega_roller, t56=0.0, load=4300.0):
    """A hand-made twin dataset at constant speeds, with the default rig in its provenance."""
    t = np.arange(round(duration * rate) + 1) / rate
    ones = np.ones_like(t)
    ds = xr.Dataset(
        {
            "t56": ("time", t56 * ones),
            "normal_load": ("time", load * ones),
            "wheel_disc_speed": ("time", omega_wheel * ones),
            "wheel_speed": ("time", omega_wheel * ones),
            "roller_speed": ("time", omega_roller * ones),
            "torque_request": ("time", 0.0 * ones),
        },
        coords={"time": t},
    )
    ds.attrs["provenance"] = json.dumps({"rig": RIG.to_dict()})
    return ds


def _only(**kwargs):
    """No disturbances but those given."""
    return replace(DisturbanceModel.none(), **kwargs)


def _line_amplitude(x, fs, f):
    """Amplitude of the sine at f [Hz] in x (whole number of periods, rectangular window)."""
    n = x.size
    k = round(f * n / fs)
    assert abs(k - f * n / fs) < 1e-9, "the line must sit on an FFT bin"
    return 2.0 * np.abs(np.fft.rfft(x - x.mean()))[k] / n


@pytest.fixture(scope="module")
def twin():
    return Simulation(experiment="seed-30kmh-dry").run()


def test_constant_speed_counts_are_exact_closed_form():
    # 2 rev/s on the roller, 1.5 rev/s on the wheel: counts = floor(f t CPR), exactly.
    ds = _constant_speed_dataset(250.0, 4.0, 2 * np.pi * 1.5, 2 * np.pi * 2.0)
    rec, _ = synthetic_recording(ds, DisturbanceModel.none())
    t = rec.time
    np.testing.assert_array_equal(rec["roller_encoder_counts"], np.floor(2.0 * t * CPR + 1e-9))
    np.testing.assert_array_equal(rec["wheel_encoder_counts"], np.floor(1.5 * t * CPR + 1e-9))


def test_am_line_frequency_and_amplitude_closed_form():
    # Roller at 3 rev/s, p_AM = 5 (Kayaalp Table 2): the line sits at 15 Hz with 3 N.m.
    ds = _constant_speed_dataset(250.0, 8.0, 2 * np.pi * 2.0, 2 * np.pi * 3.0)
    rec, truth = synthetic_recording(ds, _only(am_line_amplitudes=(3.0, 0.0, 0.0)))
    x = rec["torque"][:-1]  # 8 s exactly: whole periods
    assert _line_amplitude(x, 250.0, 15.0) == pytest.approx(3.0, rel=1e-9)
    assert (
        np.max(
            np.abs(x - 3.0 * np.sin(2 * np.pi * 15.0 * rec.time[:-1] + truth.line_phase.values[0]))
        )
        < 1e-9
    )
    np.testing.assert_allclose(truth.line_frequency.sel(line="am_h1"), 15.0)
    np.testing.assert_allclose(truth.line_frequency.sel(line="pmsm_h1"), 22 * 2.0)


def test_all_lines_at_their_frequencies():
    ds = _constant_speed_dataset(1000.0, 4.0, 2 * np.pi * 2.0, 2 * np.pi * 1.5)
    rec, truth = synthetic_recording(
        ds,
        DisturbanceModel(torque_noise=0.0, fixed_line_frequency=1.25, fixed_line_amplitude=2.0),
        sample_rate=1000.0,
    )
    x = rec["torque"][:-1]
    expected = {  # [Hz]: p_AM = 5 and p_PMSM = 22 (Kayaalp Tables 1-2)
        "am_h1": 7.5, "am_h2": 15.0, "am_h3": 22.5, "pmsm_h1": 44.0, "pmsm_h6": 264.0,
        "wheel_1x": 2.0, "wheel_2x": 4.0, "roller_1x": 1.5, "roller_2x": 3.0, "fixed": 1.25,
    }  # fmt: skip
    for name, f in expected.items():
        assert float(truth.line_frequency.sel(line=name)[0]) == pytest.approx(f)
        amp = float(truth.line_amplitude.sel(line=name))
        assert _line_amplitude(x, 1000.0, f) == pytest.approx(amp, rel=1e-6), name


def test_anti_alias_filter_removes_lines_above_nyquist():
    # PMSM 6th harmonic at 6 x 22 x 2.5 = 330 Hz; DAQ at 250 Hz (Nyquist 125 Hz).
    fast = _constant_speed_dataset(2000.0, 8.0, 2 * np.pi * 2.5, 2 * np.pi * 2.0)
    model = _only(pmsm_ripple_6th_amplitude=10.0)
    rec, truth = synthetic_recording(fast, model, sample_rate=250.0)
    assert rec.sample_rate == pytest.approx(250.0)
    assert "Butterworth" in rec.metadata["anti_alias"]
    alias = float(truth.line_alias_frequency.sel(line="pmsm_h6")[0])
    assert alias == pytest.approx(80.0)  # |330 - 250|
    # Filter response squared (zero-phase) at 330 Hz for order 8 at 100 Hz: ~1e-8.
    assert np.max(np.abs(rec["torque"][200:-200])) < 1e-3 * 10.0
    # The same line sampled at the DAQ rate without a filter aliases to 80 Hz at full amplitude.
    slow = _constant_speed_dataset(250.0, 8.0, 2 * np.pi * 2.5, 2 * np.pi * 2.0)
    rec2, _ = synthetic_recording(slow, model)
    assert "alias" in rec2.metadata["anti_alias"]
    assert _line_amplitude(rec2["torque"][:-1], 250.0, alias) == pytest.approx(10.0, rel=1e-6)


def test_pressure_is_load_over_area_and_noise_levels():
    ds = _constant_speed_dataset(250.0, 40.0, 20.0, 18.0, t56=100.0)
    model = _only(torque_noise=2.0, pressure_noise=300.0)
    rec, _ = synthetic_recording(ds, model, seed=3)
    area = RIG.sensors.air_spring_effective_area
    p = rec["air_spring_pressure"]
    assert np.mean(p) == pytest.approx(4300.0 / area, abs=4 * 300.0 / np.sqrt(p.size))
    assert np.std(p) == pytest.approx(300.0, rel=0.05)  # 10001 samples: std error ~0.7 %
    assert np.std(rec["torque"]) == pytest.approx(2.0, rel=0.05)
    assert np.mean(rec["torque"]) == pytest.approx(100.0, abs=0.1)


def test_deterministic_for_a_seed():
    ds = _constant_speed_dataset(250.0, 2.0, 20.0, 18.0)
    a, ta = synthetic_recording(ds, seed=7)
    b, tb = synthetic_recording(ds, seed=7)
    c, _ = synthetic_recording(ds, seed=8)
    for name in a.channels:
        np.testing.assert_array_equal(a[name], b[name])
    np.testing.assert_array_equal(ta.line_phase, tb.line_phase)
    assert not np.array_equal(a["torque"], c["torque"])


def test_sample_rate_above_twin_rate_is_refused():
    ds = _constant_speed_dataset(250.0, 1.0, 20.0, 18.0)
    with pytest.raises(ValueError, match="sample_rate"):
        synthetic_recording(ds, sample_rate=1000.0)


def test_twin_without_disturbances_keeps_the_clean_channels(twin):
    rec, _ = synthetic_recording(twin, DisturbanceModel.none())
    np.testing.assert_array_equal(rec.time, twin.time.values)
    np.testing.assert_array_equal(rec["torque"], twin.t56.values)
    np.testing.assert_array_equal(rec["torque_request"], twin.torque_request.values)
    area = RIG.sensors.air_spring_effective_area
    # The DAQ sees the air spring's force S, not the contact's load (the arm adds σ(h/l) F_x).
    np.testing.assert_allclose(rec["air_spring_pressure"] * area, twin.air_spring_force, rtol=1e-14)
    assert set(rec.channels) <= set(CANONICAL_CHANNELS)
    for name, unit in rec.units.items():
        assert unit == CANONICAL_CHANNELS[name][0]
    # Counts never decrease while both shafts turn forward.
    assert np.all(np.diff(rec["wheel_encoder_counts"]) >= 0)
    assert np.all(np.diff(rec["roller_encoder_counts"]) >= 0)


def test_twin_with_disturbances_is_clean_plus_lines_plus_noise(twin):
    rec, truth = synthetic_recording(twin, seed=2)
    noise = rec["torque"] - truth.torque_clean.values - truth.torque_lines.values
    assert np.std(noise) == pytest.approx(DisturbanceModel().torque_noise, rel=0.05)
    assert abs(np.mean(noise)) < 0.05
    # The AM line follows the roller speed: f = p_AM * omega_r / (2 pi).
    np.testing.assert_allclose(
        truth.line_frequency.sel(line="am_h1"), 5 * truth.roller_speed / (2 * np.pi)
    )
    assert list(truth.line.values) == list(LINE_NAMES)
    md = rec.metadata
    assert md["seed"] == 2
    assert md["disturbances"]["fixed_line_frequency"] == 1.333
    # The hand-injected speed-independent line is off by default, and nothing claims it.
    assert md["disturbances"]["fixed_line_amplitude"] == 0.0
    assert md["injected_lines"] == [] and md["notes"] == []
    assert float(truth.line_amplitude.sel(line="fixed")) == 0.0
    # The twin's Polach set of the test (dry, Polach 2005 Table 2) for the fit's truth check.
    assert md["true_polach_parameters"]["dry"]["limit_ratio"] == 0.4
    assert json.loads(md["twin_provenance"])["rig_parameters"]["sensors"]["daq_rate"] == 250.0


def test_injected_line_is_disclosed_with_frequency_and_amplitude():
    ds = _constant_speed_dataset(250.0, 2.0, 20.0, 18.0)
    model = _only(fixed_line_amplitude=2.0, fixed_line_frequency=1.333)
    rec, truth = synthetic_recording(ds, model)
    (line,) = rec.metadata["injected_lines"]
    assert line["frequency [Hz]"] == 1.333 and line["amplitude [N.m]"] == 2.0
    (text,) = rec.metadata["notes"]
    assert "1.333 Hz" in text and "2 N.m" in text and "INJECTED" in text
    assert json.loads(truth.attrs["injected_lines"]) == rec.metadata["injected_lines"]
    # Off: nothing injected, nothing said.
    rec0, truth0 = synthetic_recording(ds, _only(fixed_line_frequency=1.333))
    assert (
        rec0.metadata["injected_lines"] == [] and json.loads(truth0.attrs["injected_lines"]) == []
    )


def test_what_is_not_a_twin_simulation_is_named():
    # A protocol's name had raised AttributeError: 'str' object has no attribute 'attrs'.
    import re

    from rollerrig._validation import ParameterError
    from rollerrig.recordings.recording import RecordingError

    with pytest.raises(ParameterError, match=r"ds must be a twin simulation, .* got str"):
        synthetic_recording("seed-30kmh-dry")
    partial = xr.Dataset({"t56": ("time", [0.0, 1.0])}, coords={"time": [0.0, 0.004]})
    with pytest.raises(RecordingError, match=re.escape(
        "the twin dataset lacks ['normal_load', 'roller_speed', 'wheel_disc_speed']"
    )):  # fmt: skip
        synthetic_recording(partial)
