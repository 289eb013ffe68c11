"""The causal contact-torque estimator (Kalman filter on the roller).

References: the discrete algebraic Riccati equation (scipy.linalg.solve_discrete_are) of the
model discretised independently here (Van Loan's matrix exponential, scipy.linalg.expm, in
physical units); closed-form roller motions (constant contact torque, constant acceleration);
the twin's true contact CoA on a synthetic recording, against the rig's raw CoA and the offline
zero-phase correction (measure.correction). The default tuning was chosen on other recordings
(the estimator module's docstring); these tests use the demo's recording (seed 1).
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from scipy import linalg

from rollerrig._validation import ParameterError
from rollerrig.measure.correction import corrected_adhesion
from rollerrig.measure.estimator import (
    DEFAULT_PROCESS_NOISE,
    ContactEstimate,
    ContactObserver,
    estimate_contact_torque,
    estimate_from_recording,
    estimator_performance,
)
from rollerrig.measure.quantities import derive_quantities
from rollerrig.measure.recording import Recording, RecordingError
from rollerrig.measure.synthetic import synthetic_recording
from rollerrig.rig.parameters import default_rig
from rollerrig.solve.simulation import Simulation

RIG = dict(
    counts_per_rev=10000,
    roller_inertia=45.0,
    bearing_friction=0.007,
    bearing_radius=0.065,
    roller_weight=5000.0,
    roller_radius=0.452,
)
FS = 250.0


def _bearing(load, speed=20.0):
    return 0.007 * 0.065 * (5000.0 + load) * math.tanh(speed / 0.05)


def _online(torque, counts, load, fs=FS, **kw):
    obs = ContactObserver(fs, **{**RIG, **kw})
    loads = np.broadcast_to(load, np.shape(torque))
    out = np.array([obs.update(t, c, n) for t, c, n in zip(torque, counts, loads, strict=True)])
    return obs, out


# ------------------------------------------------------------------ references


def _van_loan(model, fs, J, q, sigma_t, cpr):
    """F, Q, R of the model in physical units, independently of the module's closed forms."""
    h = 1.0 / fs
    n = 3 if model == "random_walk" else 4
    A = np.zeros((n, n))
    A[0, 1] = 1.0
    A[1, 2] = 1.0 / J
    if n == 4:
        A[2, 3] = 1.0
    L = np.zeros((n, 1))
    L[-1, 0] = 1.0
    M = np.zeros((2 * n, 2 * n))
    M[:n, :n] = -A
    M[:n, n:] = q * L @ L.T
    M[n:, n:] = A.T
    E = linalg.expm(M * h)
    F = E[n:, n:].T
    Q = F @ E[:n, n:]
    g = np.zeros(n)
    g[0], g[1] = h * h / (2 * J), h / J  # torque noise, zero-order held
    Q = Q + sigma_t**2 * np.outer(g, g)
    R = (2 * math.pi / cpr) ** 2 / 12
    return F, Q, R


@pytest.mark.parametrize(
    ("model", "q", "fs"),
    [
        ("random_walk", None, 250.0),
        ("random_walk", 1e2, 1000.0),
        ("random_walk", 1e8, 100.0),
        ("integrated_random_walk", None, 250.0),
    ],
)
def test_steady_state_gain_is_the_riccati_equations(model, q, fs):
    t = np.arange(400) / fs
    est = estimate_contact_torque(
        np.zeros(t.size),
        np.floor(20.0 * t * 10000 / (2 * np.pi)),
        4300.0,
        fs,
        model=model,
        process_noise=q,
        **RIG,
    )
    q = DEFAULT_PROCESS_NOISE[model] if q is None else q
    F, Q, R = _van_loan(model, fs, 45.0, q, 1.0, 10000)
    # Scaled for the solver (states of very different sizes), then back.
    S = np.diag([1.0, 1 / fs, 1 / fs**2 / 45.0, 1 / fs**3 / 45.0][: F.shape[0]])
    Si = np.linalg.inv(S)
    Fz, Qz = Si @ F @ S, Si @ Q @ Si.T
    H = np.zeros((1, F.shape[0]))
    H[0, 0] = 1.0
    P = S @ (R * linalg.solve_discrete_are(Fz.T, H.T, Qz / R, np.eye(1))) @ S.T
    K = P[:, 0] / (P[0, 0] + R)
    np.testing.assert_allclose(est.gain, K, rtol=1e-7)
    assert est.settling_samples > 0  # the time-varying gain comes first


def test_exact_roller_motion_converges_to_the_contact_torque():
    """Constant contact torque d0 and acceleration α: T56 = d0 − J α − R05 (closed form).

    Unquantised counts (θ·CPR/2π as a real number): the model is exact, so the filter's error
    decays to rounding after it settles.
    """
    t = np.arange(int(8 * FS)) / FS
    alpha, w0, d0, load = 1.5, 18.0, 640.0, 4300.0
    counts = (w0 * t + 0.5 * alpha * t**2) * 10000 / (2 * np.pi)
    torque = np.full(t.size, d0 - 45.0 * alpha - _bearing(load))
    est = estimate_contact_torque(torque, counts, load, FS, **RIG)
    late = t > 4.0
    np.testing.assert_allclose(est.contact_torque[late], d0, atol=1e-6)
    np.testing.assert_allclose(est.roller_speed[late], w0 + alpha * t[late], atol=1e-9)
    np.testing.assert_allclose(est.roller_acceleration[late], alpha, atol=1e-7)
    np.testing.assert_allclose(est.coa[late], d0 / (0.452 * load), atol=1e-9)


def test_quantised_counts_converge_within_the_filters_noise():
    t = np.arange(int(20 * FS)) / FS
    alpha, w0, d0, load = -0.8, 18.4, 300.0, 4300.0
    counts = np.floor((w0 * t + 0.5 * alpha * t**2) * 10000 / (2 * np.pi))
    torque = np.full(t.size, d0 - 45.0 * alpha - _bearing(load))
    est = estimate_contact_torque(torque, counts, load, FS, **RIG)
    late = est.contact_torque[t > 2.0]
    # The estimate's noise from quantisation alone is ~10 N.m (module docstring: 0.005 CoA);
    # its mean over 18 s (4500 samples, correlated over ~10) is within a few N.m of d0.
    assert abs(late.mean() - d0) < 3.0
    assert late.std() < 25.0


def test_first_sample_is_the_measured_torque_and_no_speed():
    est = estimate_contact_torque([123.0], [7.0], 4300.0, FS, **RIG)
    # The bearing loss needs a speed: none at the first sample, so no loss either.
    assert est.contact_torque[0] == pytest.approx(123.0, rel=1e-15)
    assert est.roller_speed.tolist() == [0.0]


# ------------------------------------------------------------------ structure


def _random_inputs(n, seed):
    rng = np.random.default_rng(seed)
    torque = 300 + 50 * rng.standard_normal(n)
    counts = np.cumsum(rng.integers(100, 130, n)).astype(float)
    load = 4300 + 20 * rng.standard_normal(n)
    return torque, counts, load


@pytest.mark.parametrize("j", [5, 150, 900])
def test_causal_a_later_sample_changes_no_earlier_output(j):
    torque, counts, load = _random_inputs(1200, 3)
    base = estimate_contact_torque(torque, counts, load, FS, **RIG)
    for changed in (
        (np.where(np.arange(1200) == j, torque + 500.0, torque), counts, load),
        (torque, np.where(np.arange(1200) >= j, counts + 40.0, counts), load),
        (torque, counts, np.where(np.arange(1200) == j, 9000.0, load)),
    ):
        other = estimate_contact_torque(*changed, FS, **RIG)
        for name in ("contact_torque", "roller_speed", "coa"):
            a, b = getattr(base, name), getattr(other, name)
            assert np.array_equal(a[:j], b[:j]), name
        assert other.coa[j] != base.coa[j]


@pytest.mark.parametrize("model", ["random_walk", "integrated_random_walk"])
def test_online_equals_batch(model):
    torque, counts, load = _random_inputs(3000, 5)
    est = estimate_contact_torque(torque, counts, load, FS, model=model, **RIG)
    obs, online = _online(torque, counts, load, model=model)
    assert est.settling_samples < 3000  # the batch's steady-state recursion is exercised
    np.testing.assert_allclose(online, est.contact_torque, rtol=0, atol=1e-8)
    assert obs.samples == 3000
    assert obs.roller_speed == pytest.approx(est.roller_speed[-1], abs=1e-10)
    assert obs.coa == pytest.approx(est.coa[-1], abs=1e-12)
    assert obs.roller_acceleration == pytest.approx(est.roller_acceleration[-1], abs=1e-9)
    obs.reset()
    assert obs.update(torque[0], counts[0], load[0]) == est.contact_torque[0]


def test_long_recording_runs_and_matches_online_at_its_end():
    """An hour at 250 Hz (900 000 samples) through the steady-state recursion."""
    n = int(3600 * FS)
    t = np.arange(n) / FS
    omega = 18.4 + 0.5 * np.sin(2 * np.pi * 0.01 * t)
    counts = np.floor(np.cumsum(omega) / FS * 10000 / (2 * np.pi))
    torque = 400.0 + 100.0 * np.sin(2 * np.pi * 0.1 * t)
    est = estimate_contact_torque(torque, counts, 4300.0, FS, **RIG)
    assert np.all(np.isfinite(est.contact_torque))
    # An online filter started 3000 samples before the end agrees once it has settled.
    tail = slice(n - 3000, n)
    _, online = _online(torque[tail], counts[tail], 4300.0)
    np.testing.assert_allclose(online[-500:], est.contact_torque[tail][-500:], atol=1e-6)


# ------------------------------------------------------------------ validation


def test_inputs_are_validated_with_clear_errors():
    torque, counts, load = _random_inputs(50, 1)
    bad = torque.copy()
    bad[7] = np.nan
    with pytest.raises(RecordingError, match=r"torque has 1 NaN/inf.*index 7"):
        estimate_contact_torque(bad, counts, load, FS, **RIG)
    with pytest.raises(RecordingError, match=r"roller_counts has 49 samples and torque 50"):
        estimate_contact_torque(torque, counts[:-1], load, FS, **RIG)
    with pytest.raises(RecordingError, match=r"normal_load has 3 samples"):
        estimate_contact_torque(torque, counts, load[:3], FS, **RIG)
    with pytest.raises(RecordingError, match=r"normal_load must be > 0.*sample 4"):
        estimate_contact_torque(torque, counts, np.where(np.arange(50) == 4, 0.0, load), FS, **RIG)
    with pytest.raises(RecordingError, match="no samples"):
        estimate_contact_torque([], [], 4300.0, FS, **RIG)
    with pytest.raises(RecordingError, match="1-D"):
        estimate_contact_torque(np.zeros((2, 3)), np.zeros((2, 3)), 4300.0, FS, **RIG)
    for rate in (0.0, -250.0, np.nan, "fast"):
        with pytest.raises(ParameterError, match=r"sample_rate must be .*\[Hz\]"):
            estimate_contact_torque(torque, counts, load, rate, **RIG)
    with pytest.raises(ParameterError, match=r"roller_inertia must be finite and > 0"):
        estimate_contact_torque(torque, counts, load, FS, **{**RIG, "roller_inertia": 0.0})
    with pytest.raises(ParameterError, match=r"process_noise must be finite and > 0"):
        estimate_contact_torque(torque, counts, load, FS, process_noise=-1.0, **RIG)
    with pytest.raises(ParameterError, match="model must be one of"):
        estimate_contact_torque(torque, counts, load, FS, model="kalman", **RIG)
    obs = ContactObserver(FS, **RIG)
    obs.update(1.0, 0.0, 4300.0)
    with pytest.raises(RecordingError, match=r"sample 1: counts is nan"):
        obs.update(1.0, np.nan, 4300.0)
    with pytest.raises(RecordingError, match=r"sample 1: load must be > 0"):
        obs.update(1.0, 3.0, -5.0)
    assert obs.samples == 1  # a refused sample leaves the filter as it was
    with pytest.raises(RecordingError, match="same length"):
        estimator_performance(np.zeros(5), np.zeros(6), FS)
    with pytest.raises(ParameterError, match="max_lag"):
        estimator_performance(np.zeros(5), np.zeros(5), FS, max_lag=0.0)


@settings(max_examples=40, deadline=None)
@given(
    data=st.data(),
    n=st.integers(1, 400),
    fs=st.floats(10.0, 2000.0),
    q=st.floats(1.0, 1e10),
    model=st.sampled_from(["random_walk", "integrated_random_walk"]),
)
def test_any_finite_input_gives_finite_causal_output(data, n, fs, q, model):
    finite = {"allow_nan": False, "allow_infinity": False}
    torque = data.draw(hnp.arrays(float, n, elements=st.floats(-1e4, 1e4, **finite)))
    steps = data.draw(hnp.arrays(float, n, elements=st.floats(-1e3, 1e3, **finite)))
    load = data.draw(hnp.arrays(float, n, elements=st.floats(1.0, 1e5, **finite)))
    counts = np.cumsum(np.round(steps))
    est = estimate_contact_torque(torque, counts, load, fs, process_noise=q, model=model, **RIG)
    assert isinstance(est, ContactEstimate)
    for name in ("contact_torque", "roller_speed", "roller_acceleration", "coa"):
        values = getattr(est, name)
        assert values.shape == (n,)
        assert np.all(np.isfinite(values)), name
    assert est.contact_torque[0] == pytest.approx(torque[0], rel=1e-15, abs=1e-300)
    # Causality on the prefix: the first half alone gives the same first half.
    half = max(1, n // 2)
    first = estimate_contact_torque(
        torque[:half], counts[:half], load[:half], fs, process_noise=q, model=model, **RIG
    )
    np.testing.assert_array_equal(first.contact_torque, est.contact_torque[:half])


# ------------------------------------------------------------------ performance


def test_performance_of_a_delayed_copy():
    t = np.arange(4000) / FS
    truth = 300.0 * np.sin(2 * np.pi * 0.4 * t) + 100.0 * np.sin(2 * np.pi * 1.3 * t)
    for delay in (0.0, 0.01, 0.012, 0.1):  # 0, 2.5, 3 and 25 samples
        late = 300.0 * np.sin(2 * np.pi * 0.4 * (t - delay)) + 100.0 * np.sin(
            2 * np.pi * 1.3 * (t - delay)
        )
        p = estimator_performance(late + 2.0, truth, FS)
        assert p["lag [s]"] == pytest.approx(delay, abs=2e-4)
        assert p["samples"] == 4000
        if delay == 0.0:
            assert p["bias [N.m]"] == pytest.approx(2.0, rel=1e-12)
            assert p["rms_error [N.m]"] == pytest.approx(2.0, rel=1e-12)
    p = estimator_performance(np.full(10, 3.0), np.full(10, 1.0), FS, unit="-")
    assert p["lag [s]"] is None and "no variation" in p["lag_note"]
    assert p["rms_error [-]"] == pytest.approx(2.0)
    assert p["max_abs_error [-]"] == pytest.approx(2.0)


# ------------------------------------------------------------------ the twin's truth


@pytest.fixture(scope="module")
def demo_recording():
    """The demo's recording: 30 km/h, 4.3 kN, dry, three ramps past the adhesion peak."""
    rig = default_rig()
    ds = Simulation(rig, "seed-30kmh-dry", output_rate=1000.0).run()
    rec, truth = synthetic_recording(ds, sample_rate=250.0, seed=1)
    return rig, rec, truth


def test_online_estimate_against_the_rig_and_the_offline_correction(demo_recording):
    rig, rec, truth = demo_recording
    fs = rec.sample_rate
    est = estimate_from_recording(rec, rig)
    measured = derive_quantities(rec, rig)
    b = rig.bearing
    offline, _ = corrected_adhesion(
        measured["torque"],
        measured["roller_speed"],
        measured["normal_load"],
        fs,
        roller_radius=rig.geometry.roller_radius_x,
        roller_inertia=rig.inertia.roller,
        bearing_friction=b.friction_coefficient,
        bearing_radius=b.roller_bearing_radius,
        roller_weight=b.roller_subsystem_weight,
        regularisation_speed=b.regularisation_speed,
        window=51,
        order=4,
    )
    true = truth["coa"].values
    raw = estimator_performance(measured["coa"], true, fs, unit="-")
    off = estimator_performance(offline, true, fs, unit="-")
    online = estimator_performance(est.coa, true, fs, unit="-")
    # Measured (module docstring): raw 79.5 ms / 0.0383, offline 2.4 ms / 0.0088,
    # online 29.1 ms / 0.0162.
    assert online["rms_error [-]"] < raw["rms_error [-]"] / 2
    assert online["lag [s]"] < raw["lag [s]"] / 2
    assert 0.012 < online["rms_error [-]"] < 0.020
    assert 0.015 < online["lag [s]"] < 0.040
    # Causality costs: the zero-phase offline correction is better where it can be used.
    assert off["rms_error [-]"] < online["rms_error [-]"]
    assert abs(off["lag [s]"]) < online["lag [s]"]
    # As a torque, against the twin's F_x r_r.
    torque = estimator_performance(
        est, truth["contact_force"].values * rig.geometry.roller_radius_x, fs
    )
    assert torque["rms_error [N.m]"] < 40.0
    # The recording's pressure gives the same load (and estimate) as its derived normal load.
    loaded = Recording(
        rec.time,
        {**rec.channels, "normal_load": measured["normal_load"]},
        {**rec.units, "normal_load": "N"},
    )
    np.testing.assert_allclose(
        estimate_from_recording(loaded, rig).contact_torque, est.contact_torque, rtol=1e-12
    )
