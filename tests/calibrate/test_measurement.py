"""The measured channels of a calibration: speeds from the counts, the quantisation noise
against a Monte Carlo of floored counts, the lines' orders, the replay, clear errors."""

import math

import numpy as np
import pytest

from rollerrig.calibrate.measurement import (
    CHANNELS,
    line_orders,
    prepare_measurement,
    quantisation_noise,
)
from rollerrig.calibrate.problem import replay_protocol_from_recording
from rollerrig.measure.quantities import encoder_speed
from rollerrig.recordings.recording import Recording, RecordingError
from rollerrig.rig.parameters import default_rig


def test_quantisation_noise_against_a_monte_carlo_of_floored_counts():
    # Counts floor(theta CPR/2 pi + phase) of a shaft whose speed sweeps 18-19 rad/s (6 whole
    # counts per sample): the gated speed's error (against the gate mean) has the standard
    # deviation 2 pi/(CPR dt) sqrt(1/6) and lag-1 autocorrelation -1/2. (At one constant speed
    # its variance is (2 pi/(CPR dt))^2 d(1 - d), d the fraction of a count per sample: 1/6 is
    # its mean over d.)
    cpr, dt = 10000, 1 / 250
    t = np.arange(200_000) * dt
    omega = 18.0 + t / t[-1]
    theta = 18.0 * t + 0.5 * t**2 / t[-1]
    counts = np.floor(theta * cpr / (2 * math.pi) + 0.3)
    gate_mean = np.diff(theta) / dt
    error = encoder_speed(counts, t, cpr)[1:] - gate_mean
    assert omega[-1] == pytest.approx(19.0)
    assert np.std(error) == pytest.approx(quantisation_noise(cpr, dt), rel=0.02)
    e = error - error.mean()
    assert float(e[1:] @ e[:-1] / (e @ e)) == pytest.approx(-0.5, abs=0.02)


def test_line_orders_follow_the_pole_pairs():
    rig = default_rig().with_overrides({"induction_motor.pole_pairs": 4})
    orders = {label: (shaft, order) for shaft, order, label in line_orders(rig)}
    assert ("roller", 4) in orders.values() and ("roller", 12) in orders.values()
    assert ("wheel", 22) in orders.values() and ("wheel", 132) in orders.values()


def test_measurement_speeds_from_counts_and_the_replay(altered_recording):
    rec, truth = altered_recording
    rig = default_rig()
    m = prepare_measurement(rec, rig)
    assert m.channels == CHANNELS and m.encoder_counts
    cpr = rig.sensors.encoder_counts_per_revolution
    np.testing.assert_array_equal(
        m.values["roller_speed"], encoder_speed(rec["roller_encoder_counts"], rec.time, cpr)
    )
    assert not m.valid["wheel_speed"][0] and m.valid["torque"][0]
    assert m.normal_load == pytest.approx(4300.0, abs=1.0)
    assert m.roller_speed_start == pytest.approx(30 / 3.6, rel=1e-3)
    assert 1.0 <= m.quiet_until <= 1.1  # the request passes 2 % of its peak at 1.06 s
    # The twin's prediction of a speed from the true angle: the gate mean, within quantisation.
    angle = truth["roller_angle"].values
    predicted = m.predicted(truth["torque_clean"].values, angle, angle, 4300.0)
    gap = (m.values["roller_speed"] - predicted["roller_speed"])[1:]
    assert abs(gap.mean()) < 1e-3 and np.std(gap) < 1.1 * quantisation_noise(cpr, 1 / 250)
    # The replay reproduces the recorded request at every sample, with few breakpoints.
    p = replay_protocol_from_recording(m, 30 / 3.6, "dry", "replay", m.normal_load)
    np.testing.assert_allclose(p.torque_at(m.time), rec["torque_request"], atol=1e-9)
    assert p.torque_time.size < 20 < rec.time.size
    assert p.normal_load_at(5.0) == m.normal_load


def test_recording_problems_name_the_channel_and_what_to_do():
    t = np.arange(100) / 250.0
    base = {"torque": np.zeros(100), "torque_request": np.linspace(0, 100, 100)}
    units = {"torque": "N.m", "torque_request": "N.m"}
    with pytest.raises(RecordingError, match=r"\[channels.wheel_encoder_counts\] or"):
        prepare_measurement(Recording(t, base, units, {"source": "x.csv"}), default_rig())
    full = base | {
        "wheel_encoder_counts": np.arange(100.0) * 150,
        "roller_encoder_counts": np.arange(100.0) * 117,
        "air_spring_pressure": np.full(100, 86e3),
    }
    units = units | {"wheel_encoder_counts": "1", "roller_encoder_counts": "1"}
    units |= {"air_spring_pressure": "Pa"}
    gap = t.copy()
    gap[50:] += 0.1
    with pytest.raises(RecordingError, match="uniform time base"):
        prepare_measurement(Recording(gap, full, units, {"source": "x.csv"}), default_rig())
    flat = full | {"torque_request": np.zeros(100)}
    with pytest.raises(RecordingError, match="zero throughout"):
        prepare_measurement(Recording(t, flat, units, {"source": "x.csv"}), default_rig())
    # A constant load channel is taken as exact: no load channel in the fit.
    m = prepare_measurement(Recording(t, full, units, {"source": "x.csv"}), default_rig())
    assert "normal_load" not in m.channels
    assert any("constant" in n for n in m.notes)


def test_a_time_in_ms_read_as_s_says_what_was_empty_without_a_nan(recwarn):
    n = 100
    t = np.arange(n) * 4.0  # 4 ms steps read as 4 s: no sample in the 2 s before the test
    request = np.where(np.arange(n) < 40, 0.0, 100.0)
    full = {
        "torque": request.copy(),
        "torque_request": request,
        "wheel_encoder_counts": np.arange(n) * 150.0,
        "roller_encoder_counts": np.arange(n) * 117.0,
        "air_spring_pressure": np.full(n, 86e3),
    }
    units = {"torque": "N.m", "torque_request": "N.m", "air_spring_pressure": "Pa"}
    units |= {"wheel_encoder_counts": "1", "roller_encoder_counts": "1"}
    rec = Recording(t, full, units, {"source": "ms.csv"})
    with pytest.raises(RecordingError, match=r"no sample in the 2 s of free rolling") as info:
        prepare_measurement(rec, default_rig())
    assert "nan" not in str(info.value) and 'unit = "ms"' in str(info.value)
    assert not [w for w in recwarn if issubclass(w.category, RuntimeWarning)]


def test_quantisation_noise_refuses_a_zero_negative_or_nan_count_or_gate():
    import re

    from rollerrig._validation import ParameterError

    for cpr, gate, name in [
        (0, 0.004, "counts_per_revolution must be > 0"),
        (-10000, 0.004, "counts_per_revolution must be > 0"),
        (math.nan, 0.004, "counts_per_revolution must be finite"),
        (10000, 0, "interval must be > 0 [s]"),
        (10000, -1, "interval must be > 0 [s]"),
        (10000, math.inf, "interval must be finite [s]"),
    ]:
        with pytest.raises(ParameterError, match=re.escape(name)):
            quantisation_noise(cpr, gate)
