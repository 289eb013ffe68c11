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
from rollerrig.estimation.estimator import (
    DEFAULT_CHAIN_NOISE,
    DEFAULT_CHAIN_TORQUE_NOISE,
    DEFAULT_DRIVE_NOISE,
    DEFAULT_PROCESS_NOISE,
    DEFAULT_SMOOTHER_NOISE,
    DEFAULT_TORQUE_NOISE,
    ContactEstimate,
    ContactObserver,
    RollerChain,
    estimate_contact_torque,
    estimate_from_recording,
    estimator_performance,
    smooth_contact_torque,
    smooth_from_recording,
    smoother_weights,
)
from rollerrig.measure.correction import corrected_adhesion
from rollerrig.measure.quantities import derive_quantities
from rollerrig.recordings.recording import Recording, RecordingError
from rollerrig.recordings.synthetic import synthetic_recording
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
        load_transfer=rig.arm.transfer_ratio,
        dead_weight=rig.arm.dead_weight,
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


# ------------------------------------------------------------------ the smoother


def _chain():
    return RollerChain.from_rig(default_rig())


def _reference_model(model, fs, q, sigma_t, chain=None, q_drive=0.0, J=45.0, cpr=10000):
    """F, G0, G1, Q, H, R, x-names of the smoother's model, built here from the equations.

    Continuous: J ω̇ = d − u (roller alone, u = T56 + R05) or the roller-shaft-rotor-drive
    chain (u = R05, T56 = k φ + b (ω5 − ω6) measured); discretised by matrix exponentials
    (the input linear between samples, Van Loan's integral for the noise).
    """
    irw = model == "integrated_random_walk"
    names = ["theta", "omega"] + ([] if chain is None else ["phi", "omega6"]) + ["d"]
    names += ["slope"] if irw else []
    if chain is not None:
        names += ["ta"] + ([] if chain.drive_slope is None else ["m"])
    i = {name: k for k, name in enumerate(names)}
    n = len(names)
    A, B, L = np.zeros((n, n)), np.zeros(n), []
    A[i["theta"], i["omega"]] = 1.0
    A[i["omega"], i["d"]] = 1.0 / J
    B[i["omega"]] = -1.0 / J
    if irw:
        A[i["d"], i["slope"]] = 1.0
    L.append((i["slope" if irw else "d"], q))
    H = [np.eye(n)[0]]
    R = [(2 * math.pi / cpr) ** 2 / 12]
    if chain is not None:
        k, b, J6 = chain.shaft_stiffness, chain.shaft_damping, chain.rotor_inertia
        w5, w6, phi, ta = i["omega"], i["omega6"], i["phi"], i["ta"]
        # J ω̇5 = d − k φ − b (ω5 − ω6) − R05;  J6 ω̇6 = k φ + b (ω5 − ω6) + T_a
        A[w5, phi], A[w5, w5], A[w5, w6] = -k / J, -b / J, b / J
        A[phi, w5], A[phi, w6] = 1.0, -1.0
        A[w6, phi], A[w6, w5], A[w6, w6], A[w6, ta] = k / J6, b / J6, -b / J6, 1.0 / J6
        if chain.drive_slope is None:
            L.append((ta, q_drive))
        else:  # τ Ṫ_a = κ ω_s − κ ω6 − T_a, m = κ ω_s
            tau, kappa = chain.drive_lag, chain.drive_slope
            A[ta, ta], A[ta, w6], A[ta, i["m"]] = -1 / tau, -kappa / tau, 1 / tau
            L.append((i["m"], q_drive))
        row = np.zeros(n)
        row[phi], row[w5], row[w6] = k, b, -b
        H.append(row)
        R.append(sigma_t**2)
    h = 1.0 / fs
    M = np.zeros((n + 2, n + 2))
    M[:n, :n], M[:n, n], M[n, n + 1] = A * h, B * h, 1.0
    E = linalg.expm(M)
    F, hold, ramp = E[:n, :n], E[:n, n], E[:n, n + 1]
    Qc = np.zeros((n, n))
    for j, qj in L:
        Qc[j, j] = qj
    V = np.zeros((2 * n, 2 * n))
    V[:n, :n], V[:n, n:], V[n:, n:] = -A * h, Qc * h, A.T * h
    EV = linalg.expm(V)
    Q = EV[n:, n:].T @ EV[:n, n:]
    if chain is None:
        Q = Q + sigma_t**2 * np.outer(hold, hold)
    return F, hold - ramp, ramp, 0.5 * (Q + Q.T), np.array(H), np.diag(R), names


def _scales(names, J=45.0, k=43500.0):
    s = {"theta": 1e-4, "omega": 1e-2, "omega6": 1e-2, "phi": 1e-2 / k, "d": 1.0, "ta": 1.0}
    s.update(slope=100.0, m=100.0)
    return np.array([s[name] for name in names])


def _steady(F, Q, H, R, S):
    """Prior and posterior covariance and the smoother gain of the steady state (scaled)."""
    Si = np.diag(1 / S)
    Fz, Qz, Hz = Si @ F @ np.diag(S), Si @ Q @ Si, H @ np.diag(S)
    P = linalg.solve_discrete_are(Fz.T, Hz.T, Qz, R)
    K = P @ Hz.T @ np.linalg.inv(Hz @ P @ Hz.T + R)
    Pf = (np.eye(F.shape[0]) - K @ Hz) @ P
    C = Pf @ Fz.T @ np.linalg.inv(P)
    Ps = linalg.solve_discrete_lyapunov(C, Pf - C @ P @ C.T)
    D = np.diag(S)
    return D @ P @ D, D @ Pf @ D, D @ C @ np.diag(1 / S), D @ Ps @ D


def _case(chain, model="random_walk"):
    defaults = DEFAULT_SMOOTHER_NOISE if chain is None else DEFAULT_CHAIN_NOISE
    q = defaults[model]
    sigma = DEFAULT_TORQUE_NOISE if chain is None else DEFAULT_CHAIN_TORQUE_NOISE["no_lines"]
    return q, sigma, (0.0 if chain is None else DEFAULT_DRIVE_NOISE)


CHAINS = {
    "roller": None,
    "induction": RollerChain(43500.0, 1.0, 6.6, 851.2, 0.3635),
    "unknown_drive": RollerChain(43500.0, 1.0, 6.6, None),
}


@pytest.mark.parametrize(
    ("chain", "model"),
    [
        ("roller", "random_walk"),
        ("roller", "integrated_random_walk"),
        ("induction", "random_walk"),
        ("unknown_drive", "random_walk"),
    ],
)
def test_smoother_gain_and_variance_are_the_steady_state(chain, model):
    """C = P⁺ Fᵀ (P⁻)⁻¹ of the Riccati equation, and the smoothed variance of the Stein
    equation P = P⁺ + C (P − P⁻) Cᵀ in the middle of a long recording."""
    chain = CHAINS[chain]
    q, sigma, q_drive = _case(chain, model)
    F, _, _, Q, H, R, names = _reference_model(model, FS, q, sigma, chain, q_drive)
    _, _, C, Ps = _steady(F, Q, H, R, _scales(names))
    torque, counts, load = _random_inputs(4000, 8)
    est = smooth_contact_torque(torque, counts, load, FS, model=model, chain=chain, **RIG)
    np.testing.assert_allclose(est.smoother_gain, C, rtol=1e-6, atol=1e-9 * np.abs(C).max())
    i = names.index("d")
    assert est.contact_torque_variance[2000] == pytest.approx(Ps[i, i], rel=1e-7)
    assert est.settling_samples > 0
    assert est.smoothed and not estimate_contact_torque(torque, counts, load, FS, **RIG).smoothed


def _exact_rts(F, G0, G1, Q, H, R, y, u, x0, P0):
    """Time-varying Kalman filter and RTS smoother, plain loops (the reference)."""
    n, nx = y.shape[0], F.shape[0]
    xf, Pf = np.empty((n, nx)), np.empty((n, nx, nx))
    xp, Pp = np.empty((n, nx)), np.empty((n, nx, nx))
    x, P = x0, P0
    for k in range(n):
        if k > 0:
            x, P = F @ x + G0 * u[k - 1] + G1 * u[k], F @ P @ F.T + Q
            xp[k], Pp[k] = x, P
            K = P @ H.T @ np.linalg.inv(H @ P @ H.T + R)
            x = x + K @ (y[k] - H @ x)
            IKH = np.eye(nx) - K @ H
            P = IKH @ P @ IKH.T + K @ R @ K.T
        xf[k], Pf[k] = x, P
    xs, Ps = xf.copy(), Pf.copy()
    for k in range(n - 2, -1, -1):
        C = Pf[k] @ F.T @ np.linalg.inv(Pp[k + 1])
        xs[k] = xf[k] + C @ (xs[k + 1] - xp[k + 1])
        Ps[k] = Pf[k] + C @ (Ps[k + 1] - Pp[k + 1]) @ C.T
    return xs, Ps


@pytest.mark.parametrize("chain", ["roller", "induction", "unknown_drive"])
def test_smoother_is_the_exact_rts_smoother(chain):
    """The steady-state gains after the exact transient, run by lfilter forward and backward,
    give the time-varying Kalman filter and RTS smoother's estimate and variance."""
    chain = CHAINS[chain]
    q, sigma, q_drive = _case(chain)
    F, G0, G1, Q, H, R, names = _reference_model("random_walk", FS, q, sigma, chain, q_drive)
    n = 1500
    torque, counts, load = _random_inputs(n, 9)
    theta = counts * 2 * np.pi / 10000
    speed = np.diff(theta, prepend=theta[0]) * FS
    speed[0] = speed[1]
    bearing = 0.007 * 0.065 * (5000.0 + load) * np.tanh(speed / 0.05)
    u = torque + bearing if chain is None else bearing
    y = theta[:, None] if chain is None else np.c_[theta, torque]
    # The start: the first sample's angle; the speed and the acceleration unknown (1000 rad/s,
    # 10 rad/s²); the rest as in the steady state.
    i = {name: k for k, name in enumerate(names)}
    S = _scales(names)
    _, Pf, _, _ = _steady(F, Q, H, R, S)
    P0 = Pf.copy()
    P0[0, :] = P0[:, 0] = 0.0
    P0[0, 0] = R[0, 0]
    v, a = np.zeros(len(names)), np.zeros(len(names))
    v[i["omega"]] = 1e3
    a[i["d"]] = 10.0 * 45.0
    x0 = np.zeros(len(names))
    x0[0], x0[i["d"]] = theta[0], u[0] + (0.0 if chain is None else torque[0])
    if chain is None:
        P0[1, :] = P0[:, 1] = 0.0
    else:
        v[i["omega6"]] = 1e3
        a[i["ta"]] = 10.0 * 6.6
        x0[i["phi"]], x0[i["ta"]] = torque[0] / 43500.0, -torque[0]
        if "m" in i:
            v[i["m"]], a[i["m"]], x0[i["m"]] = 1e3 * 851.2, 10.0 * 6.6, -torque[0]
    P0 = P0 + np.outer(v, v) + np.outer(a, a)
    xs, Ps = _exact_rts(F, G0, G1, Q, H, R, y, u, x0, P0)
    est = smooth_contact_torque(torque, counts, load, FS, chain=chain, **RIG)
    assert est.settling_samples < n - 200  # the steady-state recursions are exercised
    # The reference loses digits in its first samples (a covariance of 1e6 (rad/s)² beside
    # one of 1e-8 rad²), and the gains switch to the steady state's within 1e-9: the two
    # agree to 1e-8 of the signal (these inputs jump by hundreds of rad/s² from sample to
    # sample).
    d_ref = xs[:, i["d"]]
    np.testing.assert_allclose(est.contact_torque, d_ref, rtol=1e-5)
    np.testing.assert_allclose(est.contact_torque[50:], d_ref[50:], atol=1e-8 * np.abs(d_ref).max())
    np.testing.assert_allclose(est.roller_speed[50:], xs[50:, 1], rtol=0, atol=1e-8)
    np.testing.assert_allclose(est.contact_torque_variance, Ps[:, i["d"], i["d"]], rtol=1e-5)
    if chain is None:  # at the last sample the smoother is the filter (no bearing at sample 0)
        est0 = smooth_contact_torque(torque, counts, load, FS, **{**RIG, "bearing_friction": 0})
        causal = estimate_contact_torque(torque, counts, load, FS, **{**RIG, "bearing_friction": 0})
        assert est0.contact_torque[-1] == pytest.approx(causal.contact_torque[-1], abs=1e-6)


@pytest.mark.parametrize("chain", ["roller", "induction"])
@pytest.mark.parametrize("slope", [0.0, 40.0])
def test_smoother_converges_to_a_constant_or_ramping_contact_torque(chain, slope):
    """Closed form: the roller at constant speed, the contact torque constant or a ramp
    (40 N.m/s), T56 = F_x r_r − R05 (the shaft and the drive in their steady state).
    Unquantised counts: the smoother is exact inside the recording, where the causal filter
    lags a ramp by ~1 N.m; with quantised counts its error is below the filter's."""
    chain = CHAINS[chain]
    t = np.arange(int(12 * FS)) / FS
    contact = 300.0 + slope * t
    torque = contact - _bearing(4300.0, 18.0)
    exact = 18.0 * t * 10000 / (2 * np.pi)
    inside = (t > 2.0) & (t < 10.0)
    for counts, tol in ((exact, 1e-5), (np.floor(exact), None)):
        smooth = smooth_contact_torque(torque, counts, 4300.0, FS, chain=chain, **RIG)
        causal = estimate_contact_torque(torque, counts, 4300.0, FS, **RIG)
        e_s = np.abs(smooth.contact_torque - contact)[inside]
        e_f = np.abs(causal.contact_torque - contact)[inside]
        if tol is not None:
            assert e_s.max() < tol
            if slope:
                assert e_f.min() > 1.0  # the filter's lag behind the ramp
            np.testing.assert_allclose(smooth.roller_speed[inside], 18.0, atol=1e-8)
            np.testing.assert_allclose(smooth.roller_acceleration[inside], 0.0, atol=1e-6)
        else:
            assert np.sqrt(np.mean(e_s**2)) < np.sqrt(np.mean(e_f**2))


def test_smoother_removes_order_lines_of_the_torque():
    """Lines at orders 1 and 5 of the roller's rotation (3 and 2 N.m) on a constant torque are
    found and removed by the chain model; the contact torque is then within the quantisation
    noise, where without the fit the lines pass into it."""
    t = np.arange(int(20 * FS)) / FS
    theta = 18.4 * t
    contact = np.full(t.size, 250.0)
    lines = 3.0 * np.sin(theta + 0.3) + 2.0 * np.sin(5 * theta + 1.1)
    torque = contact - _bearing(4300.0, 18.4) + lines
    counts = np.floor(theta * 10000 / (2 * np.pi))
    chain = CHAINS["induction"]
    fitted = smooth_contact_torque(
        torque, counts, 4300.0, FS, chain=chain, roller_orders=(1, 2, 5), **RIG
    )
    plain = smooth_contact_torque(torque, counts, 4300.0, FS, chain=chain, **RIG)
    inside = (t > 1.0) & (t < 19.0)
    assert np.sqrt(np.mean((fitted.torque_lines - lines)[inside] ** 2)) < 0.2
    assert np.all(plain.torque_lines == 0.0)
    err_fit = np.sqrt(np.mean((fitted.contact_torque - contact)[inside] ** 2))
    err_plain = np.sqrt(np.mean((plain.contact_torque - contact)[inside] ** 2))
    assert err_fit < 0.5 * err_plain
    # The wheel's lines need the wheel's counts.
    wheel = np.floor(1.3 * theta * 10000 / (2 * np.pi))
    with_wheel = smooth_contact_torque(
        torque + 1.5 * np.sin(1.3 * theta * 22),
        counts,
        4300.0,
        FS,
        chain=chain,
        roller_orders=(1, 5),
        wheel_counts=wheel,
        wheel_orders=(22,),
        **RIG,
    )
    assert np.sqrt(np.mean((with_wheel.contact_torque - contact)[inside] ** 2)) < err_plain


@pytest.mark.parametrize("chain", ["roller", "induction"])
def test_smoother_weights_reproduce_the_smoother(chain):
    """Away from the ends the smoother is the linear filter of smoother_weights."""
    chain = CHAINS[chain]
    n = 4000
    torque, counts, load = _random_inputs(n, 4)
    est = smooth_contact_torque(torque, counts, load, FS, chain=chain, **RIG)
    w = smoother_weights(
        FS, counts_per_rev=10000, roller_inertia=45.0, chain=chain, tolerance=1e-14
    )
    theta = counts * 2 * np.pi / 10000
    speed = np.diff(theta, prepend=theta[0]) * FS
    speed[0] = speed[1]
    bearing = 0.007 * 0.065 * (5000.0 + load) * np.tanh(speed / 0.05)
    half = (w.lags.size - 1) // 2
    assert np.array_equal(w.lags, np.arange(half, -half - 1, -1))
    for k in (1500, 2000, 2500):
        window = slice(k - half, k + half + 1)  # samples k − j for j = lags = half .. −half
        value = (
            w.torque @ torque[window]
            + w.angle @ (theta[window] - theta[k])
            + w.bearing @ bearing[window]
        )
        assert value == pytest.approx(est.contact_torque[k], abs=1e-6)
    # The white-noise variance of the weights is the smoother's noise on a steady roller.
    assert w.noise_variance(1.0, 10000) > 0.0


def test_smoother_long_recording_runs_and_is_local():
    """An hour at 250 Hz with the chain model; in its middle the smoother equals the smoother
    of a 40 s window around it (its weights decay within ~6 s)."""
    n = int(3600 * FS)
    t = np.arange(n) / FS
    omega = 18.4 + 0.5 * np.sin(2 * np.pi * 0.01 * t)
    counts = np.floor(np.cumsum(omega) / FS * 10000 / (2 * np.pi))
    torque = 400.0 + 100.0 * np.sin(2 * np.pi * 0.1 * t)
    chain = CHAINS["induction"]
    est = smooth_contact_torque(torque, counts, 4300.0, FS, chain=chain, **RIG)
    assert np.all(np.isfinite(est.contact_torque))
    assert np.all(est.contact_torque_variance > 0.0)
    window = slice(n // 2 - 5000, n // 2 + 5000)
    part = smooth_contact_torque(torque[window], counts[window], 4300.0, FS, chain=chain, **RIG)
    mid = slice(3500, 6500)
    np.testing.assert_allclose(part.contact_torque[mid], est.contact_torque[window][mid], atol=1e-6)


def test_smoother_inputs_are_validated_like_the_filter():
    torque, counts, load = _random_inputs(50, 1)
    bad = torque.copy()
    bad[7] = np.nan
    cases = [
        ((bad, counts, load, FS), {}, RecordingError, r"torque has 1 NaN/inf.*index 7"),
        ((torque, counts[:-1], load, FS), {}, RecordingError, r"roller_counts has 49 samples"),
        ((torque, counts, load[:3], FS), {}, RecordingError, r"normal_load has 3 samples"),
        (
            (torque, counts, np.where(np.arange(50) == 4, 0.0, load), FS),
            {},
            RecordingError,
            r"normal_load must be > 0.*sample 4",
        ),
        (([], [], 4300.0, FS), {}, RecordingError, "no samples"),
        ((np.zeros((2, 3)), np.zeros((2, 3)), 4300.0, FS), {}, RecordingError, "1-D"),
        ((torque, counts, load, 0.0), {}, ParameterError, r"sample_rate must be .*\[Hz\]"),
        ((torque, counts, load, "fast"), {}, ParameterError, r"sample_rate must be .*\[Hz\]"),
        (
            (torque, counts, load, FS),
            {"roller_inertia": 0.0},
            ParameterError,
            r"roller_inertia must be finite and > 0",
        ),
        (
            (torque, counts, load, FS),
            {"process_noise": -1.0},
            ParameterError,
            r"process_noise must be finite and > 0",
        ),
        ((torque, counts, load, FS), {"model": "kalman"}, ParameterError, "model must be one of"),
    ]
    for args, kw, error, message in cases:
        for function in (estimate_contact_torque, smooth_contact_torque):
            with pytest.raises(error, match=message):
                function(*args, **{**RIG, **kw})
    # The smoother's own options.
    chain = CHAINS["induction"]
    with pytest.raises(ParameterError, match="chain must be a RollerChain"):
        smooth_contact_torque(torque, counts, load, FS, chain="induction", **RIG)
    with pytest.raises(ParameterError, match="need chain=RollerChain"):
        smooth_contact_torque(torque, counts, load, FS, roller_orders=(5,), **RIG)
    with pytest.raises(ParameterError, match="wheel_orders need wheel_counts"):
        smooth_contact_torque(torque, counts, load, FS, chain=chain, wheel_orders=(22,), **RIG)
    with pytest.raises(RecordingError, match="wheel_counts has 49 samples"):
        smooth_contact_torque(
            torque, counts, load, FS, chain=chain, wheel_orders=(1,), wheel_counts=counts[1:], **RIG
        )
    with pytest.raises(ParameterError, match=r"roller_orders must be finite and > 0"):
        smooth_contact_torque(torque, counts, load, FS, chain=chain, roller_orders=(0,), **RIG)
    with pytest.raises(ParameterError, match=r"torque_noise must be finite and > 0"):
        smooth_contact_torque(torque, counts, load, FS, chain=chain, torque_noise=0.0, **RIG)
    with pytest.raises(ParameterError, match=r"drive_noise must be finite and > 0"):
        smooth_contact_torque(torque, counts, load, FS, chain=chain, drive_noise=-1.0, **RIG)
    with pytest.raises(ParameterError, match=r"shaft_stiffness must be finite and > 0"):
        RollerChain(0.0, 1.0, 6.6, None)
    with pytest.raises(ParameterError, match=r"drive_slope must be finite and > 0"):
        RollerChain(43500.0, 1.0, 6.6, -2.0)
    with pytest.raises(ParameterError, match="drive must be"):
        RollerChain.from_rig(default_rig(), drive="servo")


def test_roller_chain_from_the_rig():
    from rollerrig.drives.induction import lag_time_constant_from_clp, thevenin_from_nameplate

    rig = default_rig()
    chain = RollerChain.from_rig(rig)
    am = rig.induction_motor
    circuit = thevenin_from_nameplate(stator_resistance=am.stator_resistance)
    assert chain.drive_slope == pytest.approx(circuit.small_slip_slope(), rel=1e-12)
    assert chain.drive_lag == pytest.approx(lag_time_constant_from_clp(2.75), rel=1e-12)
    assert (chain.shaft_stiffness, chain.shaft_damping, chain.rotor_inertia) == (43500.0, 1.0, 6.6)
    assert RollerChain.from_rig(rig, drive="unknown").drive_slope is None


@settings(max_examples=30, deadline=None)
@given(
    data=st.data(),
    n=st.integers(1, 300),
    fs=st.floats(10.0, 2000.0),
    q=st.floats(1.0, 1e8),
    chain=st.sampled_from(["roller", "induction", "unknown_drive"]),
)
def test_any_finite_input_gives_finite_smoothed_output(data, n, fs, q, chain):
    finite = {"allow_nan": False, "allow_infinity": False}
    torque = data.draw(hnp.arrays(float, n, elements=st.floats(-1e4, 1e4, **finite)))
    steps = data.draw(hnp.arrays(float, n, elements=st.floats(-1e3, 1e3, **finite)))
    load = data.draw(hnp.arrays(float, n, elements=st.floats(1.0, 1e5, **finite)))
    counts = np.cumsum(np.round(steps))
    est = smooth_contact_torque(
        torque, counts, load, fs, process_noise=q, chain=CHAINS[chain], **RIG
    )
    for name in (
        "contact_torque",
        "roller_speed",
        "roller_acceleration",
        "coa",
        "contact_torque_variance",
    ):
        values = getattr(est, name)
        assert values.shape == (n,)
        assert np.all(np.isfinite(values)), name
    assert np.all(est.contact_torque_variance > 0.0)


def test_smoother_against_the_rig_the_offline_correction_and_the_filter(demo_recording):
    """The demo's recording (seed 1; the smoother's defaults were chosen on other recordings).

    Measured (module docstring), RMS / largest error of the CoA against the twin's contact
    CoA: rig 0.0383 / 0.28, offline correction 0.0088 / 0.11, causal filter 0.0162 / 0.29,
    smoother on the roller 0.0058 / 0.084, on the chain 0.0031 / 0.064, with the order lines
    0.0021 / 0.048 (the target: 1/8 of the rig's error, 0.0048)."""
    rig, rec, truth = demo_recording
    fs, true = rec.sample_rate, truth["coa"].values
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
        load_transfer=rig.arm.transfer_ratio,
        dead_weight=rig.arm.dead_weight,
    )

    def rms(x):
        return float(np.sqrt(np.mean((x - true) ** 2)))

    raw, off = rms(measured["coa"]), rms(offline)
    causal = rms(estimate_from_recording(rec, rig).coa)
    roller = smooth_from_recording(rec, rig, chain=None)
    plain = smooth_from_recording(rec, rig, chain="induction", lines=False)
    best = smooth_from_recording(rec, rig, chain="induction")
    assert 0.0050 < rms(roller.coa) < 0.0066
    assert 0.0026 < rms(plain.coa) < 0.0036
    assert 0.0017 < rms(best.coa) < 0.0025
    assert rms(best.coa) < rms(plain.coa) < rms(roller.coa) < off < causal < raw
    assert rms(best.coa) <= raw / 8  # the target
    assert np.max(np.abs(best.coa - true)) < 0.06
    assert np.all(roller.torque_lines == 0.0) and np.any(best.torque_lines != 0.0)
    perf = estimator_performance(best.coa, true, fs, unit="-")
    assert abs(perf["lag [s]"]) < 0.002  # two-sided: no lag
    # The smoother's variance: conservative with the rig's own chain (|z| < 2 at > 95 %).
    sd = np.sqrt(best.contact_torque_variance) / (
        rig.geometry.roller_radius_x * measured["normal_load"]
    )
    assert np.mean(np.abs(best.coa - true) < 2 * sd) > 0.95


# ------------------------------------------------------------------ which smoother to trust


def _rms(est, truth):
    return float(np.sqrt(np.mean((est.coa - truth["coa"].values) ** 2)))


def test_the_innovations_of_the_right_model_are_consistent(demo_recording):
    """On the twin's own recording the roller alone predicts the encoder angle to its stated
    variance (quantisation and torque noise): the innovations over their prediction have a
    variance near 1 (measured 1.10; the uniform rounding error is not Gaussian) and no lag-1
    correlation, so a chain must match that to be used."""
    rig, rec, _ = demo_recording
    w = smooth_from_recording(rec, rig, chain=None).innovations["angle"]
    assert 0.9 < w["variance"] < 1.3
    assert abs(w["lag1_autocorrelation"]) < 0.15


def test_the_drive_noise_by_maximum_likelihood_maximises_the_likelihood(demo_recording):
    rig, rec, truth = demo_recording
    ml = smooth_from_recording(rec, rig, chain="induction", drive_noise="ml")
    ll = ml.innovations["log_likelihood_per_sample"]
    for factor in (0.2, 5.0):
        other = smooth_from_recording(
            rec, rig, chain="induction", drive_noise=ml.drive_noise * factor
        )
        assert other.innovations["log_likelihood_per_sample"] < ll
    # The lag model holds on the twin's own recording: tens of times the default, no worse.
    assert 1e2 < ml.drive_noise < 1e5
    default = smooth_from_recording(rec, rig, chain="induction")
    assert _rms(ml, truth) < 1.1 * _rms(default, truth)


def test_auto_takes_the_roller_alone_until_the_shaft_is_calibrated(demo_recording):
    rig, rec, truth = demo_recording
    uncalibrated = smooth_from_recording(rec, rig)
    assert uncalibrated.drive_noise is None  # the roller alone
    assert "not calibrated" in uncalibrated.choice
    calibrated = smooth_from_recording(rec, rig, shaft_calibrated=True)
    assert calibrated.drive_noise is not None  # the chain
    assert "maximum likelihood" in calibrated.choice and "holds" in calibrated.choice
    assert _rms(calibrated, truth) < 0.5 * _rms(uncalibrated, truth)


def test_a_chain_that_predicts_the_encoder_worse_is_not_trusted(demo_recording):
    """choose_smoother compares the angle innovations' variance over their prediction."""
    import dataclasses

    from rollerrig.estimation.estimator import CHAIN_CONSISTENCY, choose_smoother

    rig, rec, _ = demo_recording
    alone = smooth_from_recording(rec, rig, chain=None)
    chained = smooth_from_recording(rec, rig, chain="induction", drive_noise="ml")
    v = alone.innovations["angle"]["variance"]
    worse = dict(chained.innovations, angle={"variance": 1.01 * CHAIN_CONSISTENCY * v})
    got = choose_smoother(alone, dataclasses.replace(chained, innovations=worse), True)
    assert got.drive_noise is None and "worse than the roller alone" in got.choice
    fine = dict(chained.innovations, angle={"variance": 0.99 * CHAIN_CONSISTENCY * v})
    got = choose_smoother(alone, dataclasses.replace(chained, innovations=fine), True)
    assert got.drive_noise == chained.drive_noise
    got = choose_smoother(alone, "k56 missing", True)
    assert got.drive_noise is None and "k56 missing" in got.choice


def test_drive_noise_ml_is_refused_where_no_recording_is_given():
    with pytest.raises(ParameterError, match="drive_noise"):
        smoother_weights(
            250.0,
            counts_per_rev=10000,
            roller_inertia=45.0,
            chain=RollerChain.from_rig(default_rig()),
            drive_noise="ml",
        )
    with pytest.raises(ParameterError, match="maximum likelihood"):
        smooth_contact_torque(
            np.zeros(100),
            np.arange(100.0),
            4300.0,
            250.0,
            chain=RollerChain.from_rig(default_rig()),
            drive_noise="most likely",
            **RIG,
        )
