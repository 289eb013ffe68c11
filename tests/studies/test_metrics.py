"""Metrics of one run against closed forms on synthetic channels."""

import numpy as np
import pytest

from rollerrig.experiment import load_protocol
from rollerrig.studies.metrics import METRICS, RunChannels, compute_metrics, release_overshoots

RR = 0.2  # roller radius [m] of the synthetic runs
LOAD = 4300.0  # [N]


@pytest.fixture(scope="module")
def protocol():
    return load_protocol("release-test")  # release at 3.5 s (0.02 s long), rest to 6.52 s


def _ringing_run(protocol, amplitude, frequency, decay, rate=1000.0, before=500.0):
    """T56 follows the request, then after the release rings as a decaying cosine that starts
    at -amplitude: a shaft mode of known frequency [Hz], decay time [s] and amplitude [N.m]."""
    t = np.arange(0.0, protocol.duration, 1 / rate)
    t56 = np.where(t <= 3.5, before * np.clip((t - 1.0) / 2.0, 0, 1), 0.0)
    after = t > 3.5
    s = t[after] - 3.5
    t56[after] = -amplitude * np.exp(-s / decay) * np.cos(2 * np.pi * frequency * s)
    force = t56 / RR * 0.5  # the true force: half the sensor's swing
    return RunChannels(t, t56, force, np.full(t.size, LOAD), RR)


def test_release_overshoot_is_the_first_minimum_over_the_force_before(protocol):
    run = _ringing_run(protocol, amplitude=200.0, frequency=14.0, decay=0.3)
    m = compute_metrics(run, protocol, ["release_overshoot", "true_release_overshoot"])
    # The minimum is the first sample of the ringing (1 ms after the release), against 500 N.m
    # before: 200 e^(-0.001/0.3) cos(2π 14 0.001) / 500.
    first = 200.0 * np.exp(-0.001 / 0.3) * np.cos(2 * np.pi * 14.0 * 0.001) / 500.0
    assert m["release_overshoot"] == pytest.approx(first, rel=1e-9)
    assert m["true_release_overshoot"] == pytest.approx(0.5 * first, rel=1e-9)


def test_settling_time_of_an_exponential_envelope(protocol):
    # |T56| <= 200 e^(-s/0.3) drops below 5 % of 500 N.m (25 N.m) at s = 0.3 ln(8) = 0.624 s;
    # the last excursion outside the band is the last peak of the cosine before that.
    run = _ringing_run(protocol, amplitude=200.0, frequency=14.0, decay=0.3)
    settle = compute_metrics(run, protocol, ["settling_time"])["settling_time"]
    assert 0.624 - 1 / 14.0 <= settle <= 0.624 + 1e-3


def test_settling_time_is_nan_when_the_ringing_outlasts_the_rest(protocol):
    run = _ringing_run(protocol, amplitude=200.0, frequency=14.0, decay=30.0)
    assert np.isnan(compute_metrics(run, protocol, ["settling_time"])["settling_time"])


def test_the_ringing_line_frequency_and_amplitude(protocol):
    # A steady cosine (no decay) of 120 N.m at 13.8 Hz over the rest: the Hann-windowed,
    # amplitude-corrected spectrum gives 120 N.m at 13.8 Hz (within the zero-padded bin).
    run = _ringing_run(protocol, amplitude=120.0, frequency=13.8, decay=1e9)
    m = compute_metrics(run, protocol, ["t56_line_frequency", "t56_line_amplitude"])
    assert m["t56_line_frequency"] == pytest.approx(13.8, abs=0.05)
    assert m["t56_line_amplitude"] == pytest.approx(120.0, rel=0.02)


def test_coa_bias_against_the_closed_form(protocol):
    t = np.arange(0.0, protocol.duration, 1e-3)
    force = 1000.0 * np.sin(t)  # true F_x [N]
    bias = 0.01 * np.sign(np.sin(3 * t))  # reported minus true CoA: ±0.01
    t56 = (force + bias * LOAD) * RR
    run = RunChannels(t, t56, force, np.full(t.size, LOAD), RR)
    m = compute_metrics(run, protocol, ["coa_bias_rms", "coa_bias_peak", "peak_true_coa"])
    assert m["coa_bias_rms"] == pytest.approx(0.01, rel=1e-3)
    assert m["coa_bias_peak"] == pytest.approx(0.01, rel=1e-9)
    assert m["peak_true_coa"] == pytest.approx(1000.0 / LOAD, rel=1e-4)


def test_metrics_without_a_release_are_nan_and_say_why():
    from rollerrig.experiment import Hold, Protocol, RampTorque

    p = Protocol.from_steps("ramp", [Hold(1.0), RampTorque(300.0, 1.0)], normal_load=LOAD,
                            roller_speed=5.0)  # fmt: skip
    t = np.arange(0.0, p.duration, 1e-3)
    run = RunChannels(t, p.torque_at(t), p.torque_at(t) / RR, np.full(t.size, LOAD), RR)
    m = compute_metrics(run, p, ["release_overshoot", "settling_time", "t56_line_frequency"])
    assert all(np.isnan(v) for v in m.values())
    for name in m:
        assert "release" in METRICS[name].nan_meaning


def test_every_metric_has_units_and_a_meaning_for_nan():
    for name, metric in METRICS.items():
        assert metric.name == name and metric.units and metric.long_name and metric.nan_meaning


def _swing_run(protocol, amplitude, frequency, decay, ripple=0.0, rate=1000.0, before=500.0):
    """After the release T56 swings as -A e^(-s/decay) sin(2π f s) (the slow mode's half-swing
    below zero), with a 13.8 Hz ripple of ``ripple`` × A on it (the roller-shaft ringing)."""
    t = np.arange(0.0, protocol.duration, 1 / rate)
    t56 = np.where(t <= 3.5, before * np.clip((t - 1.0) / 2.0, 0, 1), 0.0)
    after = t > 3.5
    s = t[after] - 3.5
    t56[after] = -amplitude * np.exp(-s / decay) * np.sin(2 * np.pi * frequency * s)
    t56[after] += ripple * amplitude * np.sin(2 * np.pi * 13.8 * s)
    return RunChannels(t, t56, t56 / RR, np.full(t.size, LOAD), RR)


@pytest.mark.parametrize(("frequency", "decay"), [(0.78, 0.64), (1.6, 1.0)])
@pytest.mark.parametrize("ripple", [0.0, 0.1])
def test_release_minimum_time_and_ringing_frequency_of_a_damped_swing(
    protocol, frequency, decay, ripple
):
    # Closed form of -A e^(-σs) sin(ωs): its first minimum where tan(ωs) = ω/σ,
    # s_min = arctan(ω/σ)/ω, the next maximum π/ω later: 1/(2 Δt) = ω/2π, the damped
    # frequency. A 13.8 Hz ripple (the shaft mode) must not move either.
    run = _swing_run(protocol, 300.0, frequency, decay, ripple)
    m = compute_metrics(run, protocol, ["release_minimum_time", "release_ringing_frequency"])
    w, sigma = 2 * np.pi * frequency, 1.0 / decay
    assert m["release_minimum_time"] == pytest.approx(np.arctan(w / sigma) / w, abs=0.004)
    assert m["release_ringing_frequency"] == pytest.approx(frequency, rel=0.02)
    rows = release_overshoots(run, protocol)
    assert rows[0]["time_to_minimum [s]"] == m["release_minimum_time"]


def test_no_swing_back_gives_no_ringing_frequency(protocol):
    # An overdamped return (-A s e^(-s/τ), one minimum at s = τ, no maximum after it within
    # the window above zero): the minimum is timed, the frequency is NaN.
    t = np.arange(0.0, protocol.duration, 1e-3)
    t56 = np.where(t <= 3.5, 500.0 * np.clip((t - 1.0) / 2.0, 0, 1), 0.0)
    s = np.clip(t - 3.5, 0.0, None)
    t56 = np.where(t > 3.5, -300.0 * (s / 0.2) * np.exp(1.0 - s / 0.2), t56)
    run = RunChannels(t, t56, t56 / RR, np.full(t.size, LOAD), RR)
    m = compute_metrics(run, protocol, ["release_minimum_time", "release_ringing_frequency"])
    # (the centred moving average moves the flat, asymmetric minimum by a few ms)
    assert m["release_minimum_time"] == pytest.approx(0.2, abs=0.005)
    assert np.isnan(m["release_ringing_frequency"])


def test_compute_metrics_names_an_unknown_metric_and_refuses_a_string():
    import re

    from rollerrig._validation import ParameterError

    protocol = load_protocol("release-test")
    t = np.arange(0, protocol.duration, 1e-3)
    torque = protocol.torque_at(t) * 0.99
    run = RunChannels(t, torque, torque / 0.2, np.full(t.size, 4300.0), 0.2)
    with pytest.raises(ParameterError, match=re.escape("(did you mean 'release_overshoot'?)")):
        compute_metrics(run, protocol, ["release_overshot"])
    with pytest.raises(ParameterError, match=re.escape("must be a list of names")):
        compute_metrics(run, protocol, "release_overshoot")
    for window in (0.0, -1.0, float("nan")):
        with pytest.raises(ParameterError, match=re.escape("window must")):
            release_overshoots(run, protocol, window)
