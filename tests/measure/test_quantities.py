"""Physical quantities from raw channels: closed forms (pressure -> force, exact counts -> exact
speed, the encoder resolution, creep and CoA definitions of Kayaalp eqs. 4.21-4.22) and the
twin's own measured CoA reproduced from a synthetic recording without disturbances."""

import numpy as np
import pytest

from rollerrig.measure.quantities import (
    coefficient_of_adhesion,
    creep_and_slip_velocity,
    derive_quantities,
    encoder_speed,
    encoder_speed_resolution,
    normal_force_from_pressure,
    tangential_force,
)
from rollerrig.recordings.recording import Recording, RecordingError
from rollerrig.recordings.synthetic import DisturbanceModel, synthetic_recording
from rollerrig.rig.parameters import default_rig
from rollerrig.solve.simulation import Simulation

RIG = default_rig()


@pytest.fixture(scope="module")
def twin():
    return Simulation(experiment="seed-30kmh-dry").run()


def test_normal_force_from_pressure():
    # 0.86 bar on 0.05 m^2 is the seed's 4.3 kN load (rig file, sensors.air_spring_effective_area).
    assert float(normal_force_from_pressure(0.86e5, 0.05)) == pytest.approx(4300.0, rel=1e-15)
    np.testing.assert_allclose(normal_force_from_pressure([1e5, 2e5], 0.05), [5e3, 1e4])
    with pytest.raises(ValueError, match="effective_area"):
        normal_force_from_pressure(1e5, 0.0)


def test_resolution_closed_form():
    # 10000 counts/rev at 250 Hz: 2 pi / (1e4 x 4 ms) = 0.15708 rad/s.
    assert float(encoder_speed_resolution(10000, 0.004)) == pytest.approx(np.pi / 20, rel=1e-15)
    assert float(encoder_speed_resolution(10000, 0.04)) == pytest.approx(np.pi / 200, rel=1e-15)


@pytest.mark.parametrize("gate", [1, 4, 25])
def test_constant_speed_whole_counts_give_the_exact_speed(gate):
    # 40 counts per sample at 10000 counts/rev and 250 Hz: omega = 40 x 2 pi / 1e4 x 250.
    t = np.arange(500) / 250.0
    counts = 40.0 * np.arange(500)
    omega = 40 * 2 * np.pi / 1e4 * 250
    np.testing.assert_allclose(encoder_speed(counts, t, 10000, gate=gate), omega, rtol=1e-12)
    np.testing.assert_allclose(
        encoder_speed(counts, t, 10000, gate=gate, centred=True), omega, rtol=1e-12
    )


@pytest.mark.parametrize("gate", [1, 5, 20])
def test_quantisation_error_within_the_resolution(gate):
    # 18.43 rad/s (the roller at 30 km/h), not a whole number of counts per sample.
    t = np.arange(2000) / 250.0
    omega = 18.43
    counts = np.floor(omega * t * 1e4 / (2 * np.pi))
    w = encoder_speed(counts, t, 10000, gate=gate)
    res = float(encoder_speed_resolution(10000, gate / 250.0))
    assert np.max(np.abs(w[gate:] - omega)) <= res * (1 + 1e-12)
    assert abs(np.mean(w[gate:]) - omega) < res / 10


def test_centred_gate_removes_the_delay_on_a_ramp():
    # omega = alpha t: the causal gate lags by k dt / 2, the centred one does not.
    fs, k, alpha = 1000.0, 50, 10.0
    t = np.arange(4000) / fs
    counts = np.floor(0.5 * alpha * t**2 * 1e4 / (2 * np.pi))
    res = float(encoder_speed_resolution(10000, k / fs))
    causal = encoder_speed(counts, t, 10000, gate=k)
    centred = encoder_speed(counts, t, 10000, gate=k, centred=True)
    inner = slice(k, -k)
    lag = alpha * k / (2 * fs)
    assert np.mean(alpha * t[inner] - causal[inner]) == pytest.approx(lag, abs=res)
    assert np.max(np.abs(centred[inner] - alpha * t[inner])) <= res * (1 + 1e-9)


def test_gate_must_be_a_positive_integer():
    t = np.arange(10.0)
    with pytest.raises(RecordingError, match="gate"):
        encoder_speed(t, t, 100, gate=0)


def test_creep_slip_force_and_coa_closed_forms():
    # Kayaalp eqs. 4.21-4.22: wheel 1 % faster than the roller at 30 km/h.
    v = 30 / 3.6
    s, w = creep_and_slip_velocity(1.01 * v / 0.348, v / 0.452, 0.348, 0.452)
    # The regularised denominator sqrt(v_r^2 + v_eps^2) changes s by (v_eps / v)^2 / 2 = 1.8e-5.
    assert float(s) == pytest.approx(0.01, rel=2e-5)
    assert float(w) == pytest.approx(0.01 * v, rel=1e-12)
    assert float(tangential_force(904.0, 0.452)) == pytest.approx(2000.0, rel=1e-15)
    assert float(coefficient_of_adhesion(904.0, 0.452, 4000.0)) == pytest.approx(0.5, rel=1e-15)


def test_derive_quantities_reproduces_the_twins_measured_coa(twin):
    rec, truth = synthetic_recording(twin, DisturbanceModel.none())
    out = derive_quantities(rec)  # rig from the recording's metadata
    # CoA = T56 / (r_r S) with S = p A_eff, the air spring's force (not the contact's load,
    # which the arm changes): the twin's measured_coa, to rounding.
    np.testing.assert_allclose(out["coa"], twin.measured_coa, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(out["normal_load"], twin.air_spring_force, rtol=1e-12)
    np.testing.assert_allclose(out["tangential_force"], twin.measured_force, rtol=1e-12)
    assert out.units["coa"] == "1" and out.units["slip_velocity"] == "m/s"
    # Counts over one sample come from the trapezoid angle, whose increment is the mean of the
    # end speeds: the derived speed matches it within one count's resolution.
    res = float(encoder_speed_resolution(10000, 1 / 250))
    for name in ("roller_speed", "wheel_disc_speed"):
        w = truth[name].values
        mean = 0.5 * (w[1:] + w[:-1])
        derived = out["roller_speed" if name == "roller_speed" else "wheel_speed"][1:]
        assert np.max(np.abs(derived - mean)) <= res * (1 + 1e-9)
    # A longer, centred gate tracks the true creep far better than one sample.
    fine = derive_quantities(rec, RIG, gate=25, centred=True)
    steady = (truth.time.values > 2.5) & (truth.time.values < 4.9)
    err1 = np.abs(out["creep"] - truth.creep.values)[steady]
    err25 = np.abs(fine["creep"] - truth.creep.values)[steady]
    assert np.max(err25) < 0.25 * np.max(err1)


def test_derive_quantities_needs_the_rig():
    t = np.arange(3.0)
    rec = Recording(t, {"torque": t}, {"torque": "N.m"})
    with pytest.raises(RecordingError, match="rig"):
        derive_quantities(rec)
    out = derive_quantities(rec, RIG)
    np.testing.assert_allclose(out["tangential_force"], t / 0.452)
    assert "coa" not in out  # no normal force recorded


@pytest.mark.parametrize("time", [[0, 1, 2, 3, 4], [0, 1, 1, 3, 4], [0, 2, 1, 3, 4]])
def test_encoder_speed_refuses_time_that_does_not_move_on(time):
    """Out of order it had given a negative speed, a repeated stamp an infinite one."""
    from rollerrig.recordings.recording import RecordingError

    counts = [0, 100, 200, 300, 400]
    if np.all(np.diff(time) > 0):
        assert np.allclose(encoder_speed(counts, time, 1000), 2 * np.pi * 0.1)
        return
    with pytest.raises(RecordingError, match="time must be strictly increasing"):
        encoder_speed(counts, time, 1000)


@pytest.mark.parametrize(
    ("section", "key", "value"),
    [
        ("geometry", "wheel_radius_x", -0.348),  # every sample's creep had been -2.03
        ("geometry", "roller_radius_x", float("nan")),  # and NaN
        ("sensors", "encoder_pulses_per_revolution", 0.0),
        ("sensors", "air_spring_effective_area", -0.05),
    ],
)
def test_derive_quantities_refuses_a_rig_mapping_without_a_rig(section, key, value):
    from rollerrig._validation import ParameterError

    t = np.arange(4) / 250.0
    rec = Recording(
        t,
        {"wheel_speed": np.full(4, 24.0), "roller_speed": np.full(4, 18.0)},
        {"wheel_speed": "rad/s", "roller_speed": "rad/s"},
    )
    rig = {
        "geometry": {"wheel_radius_x": 0.348, "roller_radius_x": 0.452},
        "sensors": {"encoder_pulses_per_revolution": 2500, "encoder_quadrature_factor": 4,
                    "air_spring_effective_area": 0.05},
    }  # fmt: skip
    assert np.isfinite(derive_quantities(rec, rig)["creep"]).all()
    rig[section][key] = value
    with pytest.raises(ParameterError, match=rf"{section}\.{key} must be"):
        derive_quantities(rec, rig)


def test_coefficient_of_adhesion_refuses_arrays_of_different_lengths_naming_them():
    """Torque and normal force of different lengths had given numpy's bare broadcast error."""
    import re

    from rollerrig._validation import ParameterError

    with pytest.raises(ParameterError, match=re.escape(
        "torque (shape (5,)) and normal_force (shape (3,)) must have the same shape, or one of "
        "them be a single number"
    )):  # fmt: skip
        coefficient_of_adhesion(np.full(5, 904.0), 0.452, np.full(3, 4000.0))
    coa = coefficient_of_adhesion(np.full(5, 904.0), 0.452, 4000.0)  # a single load still goes
    np.testing.assert_allclose(coa, np.full(5, 0.5), rtol=1e-15)
