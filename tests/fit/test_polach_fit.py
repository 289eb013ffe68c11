"""Polach fitting: exact recovery from exact data (Polach 2005 dry set at two speeds, and the
twin's own contact channels), tolerances with noise (pinned from measured errors with margin),
and the uncertainty model (stderr proportional to the noise; 95 % intervals cover the truth)."""

import json
import warnings

import numpy as np
import pytest

from rollerrig.contact.creep import POLACH_DRY, PolachParameters
from rollerrig.contact.curves import polach_creep_curve
from rollerrig.fit import (
    PARAMETER_NAMES,
    PolachFitWarning,
    creep_stiffness_for_rig,
    fit_polach,
    polach_coa,
)
from rollerrig.solve.simulation import Simulation

LOAD = 4300.0  # [N], the seed's load
K = float(creep_stiffness_for_rig(LOAD))  # G a b c11 of the default rig's contact at 4.3 kN
SPEEDS = np.array([10.0, 30.0, 60.0]) / 3.6  # [m/s]
# An interior set (no parameter at a bound) for the coverage test; Polach's dry set has kA = 1.
INTERIOR = PolachParameters(0.5, 0.4, 0.6, 0.8, 0.3, name="interior")


def _points(params, speeds=SPEEDS, n=60, max_creep=0.1):
    s = np.tile(np.linspace(5e-4, max_creep, n), len(speeds))
    w = s * np.repeat(speeds, n)
    return s, w, polach_coa(s, w, LOAD, K, params)


def _rel_errors(fit, truth):
    return np.abs(np.array(fit.parameters.as_tuple()) / np.array(truth.as_tuple()) - 1)


def test_exact_data_exact_recovery():
    s, w, mu = _points(POLACH_DRY, speeds=SPEEDS[1:])  # two speeds
    fit = fit_polach(s, mu, LOAD, K, slip_velocity=w)
    np.testing.assert_allclose(fit.parameters.as_tuple(), POLACH_DRY.as_tuple(), rtol=1e-6)
    assert fit.rmse < 1e-9
    assert "k_adhesion" in fit.at_bound  # Polach's dry kA = 1 is the bound
    # The same with rolling_speed instead of slip_velocity, per point.
    v = np.repeat(SPEEDS[1:], 60)
    fit2 = fit_polach(s, mu, LOAD, K, rolling_speed=v, initial=INTERIOR)
    np.testing.assert_allclose(fit2.parameters.as_tuple(), POLACH_DRY.as_tuple(), rtol=1e-6)


def test_noisy_three_speeds_within_tolerance():
    # sigma = 0.005 in CoA, 180 points. Measured over 50 seeds: max errors mu0 0.9 %, A 16 %,
    # B 13 %, kA 6.6 %, kS 3.8 %. Pinned with margin: mu0 2 %, kA and kS 10 %, A and B 35 %.
    s, w, mu = _points(POLACH_DRY)
    rng = np.random.default_rng(11)
    fit = fit_polach(s, mu + 0.005 * rng.standard_normal(mu.size), LOAD, K, slip_velocity=w)
    err = _rel_errors(fit, POLACH_DRY)
    assert err[0] < 0.02
    assert err[3] < 0.10 and err[4] < 0.10
    assert err[1] < 0.35 and err[2] < 0.35
    assert fit.rmse == pytest.approx(0.005, rel=0.15)
    assert fit.parameters.k_slip <= fit.parameters.k_adhesion <= 1.0
    assert fit.residuals.shape == mu.shape
    np.testing.assert_allclose(np.diag(fit.correlation), 1.0)


def test_twin_contact_channels_recover_the_dry_set():
    ds = Simulation(experiment="seed-30kmh-dry").run()
    prov = json.loads(ds.attrs["provenance"])
    s, w, q = ds.creep.values, ds.slip_velocity.values, ds.normal_load.values
    k = creep_stiffness_for_rig(q, prov["rig_parameters"])
    sel = np.abs(s) > 1e-4  # the ramps, holds and releases
    # One rolling speed: A and B are strongly correlated, hence the warning; but the data are
    # exact, so the recovery is too.
    with pytest.warns(PolachFitWarning, match="limit_ratio and friction_decay"):
        fit = fit_polach(s[sel], ds.coa.values[sel], q[sel], k[sel], slip_velocity=w[sel])
    dry = prov["friction_sets"]["dry"]
    expected = [dry[name] for name in PARAMETER_NAMES]
    np.testing.assert_allclose(fit.parameters.as_tuple(), expected, rtol=1e-6)


def test_stderr_scales_with_the_noise():
    s, w, mu = _points(INTERIOR)
    e = np.random.default_rng(5).standard_normal(mu.size)
    f1 = fit_polach(s, mu + 0.002 * e, LOAD, K, slip_velocity=w)
    f2 = fit_polach(s, mu + 0.004 * e, LOAD, K, slip_velocity=w)
    for name in PARAMETER_NAMES:
        assert f2.stderr[name] / f1.stderr[name] == pytest.approx(2.0, rel=0.1), name


def test_95_percent_intervals_cover_the_truth():
    s, w, mu = _points(INTERIOR)
    rng = np.random.default_rng(2024)
    truth = dict(zip(PARAMETER_NAMES, INTERIOR.as_tuple(), strict=True))
    covered = {name: 0 for name in PARAMETER_NAMES}
    n_fits = 50
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PolachFitWarning)
        for _ in range(n_fits):
            fit = fit_polach(s, mu + 0.005 * rng.standard_normal(mu.size), LOAD, K, slip_velocity=w)
            for name, (lo, hi) in fit.confidence_interval(0.95).items():
                covered[name] += lo <= truth[name] <= hi
    # Measured: 49, 47, 49, 44, 47 of 50 for (mu0, A, B, kA, kS).
    for name, c in covered.items():
        assert c / n_fits >= 0.8, (name, c)


def test_robust_loss_resists_outliers():
    s, w, mu = _points(POLACH_DRY)
    rng = np.random.default_rng(3)
    y = mu + 0.003 * rng.standard_normal(mu.size)
    bad = rng.choice(mu.size, 12, replace=False)  # 7 % gross outliers (sensor spikes)
    y[bad] += rng.choice([-1, 1], bad.size) * 0.2
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PolachFitWarning)  # outliers blur A and B
        plain = fit_polach(s, y, LOAD, K, slip_velocity=w)
    robust = fit_polach(s, y, LOAD, K, slip_velocity=w, loss="soft_l1", f_scale=0.01)
    assert _rel_errors(robust, POLACH_DRY)[0] < 0.02
    assert robust.identifiable  # covariance on the inliers: outliers do not inflate it
    assert _rel_errors(robust, POLACH_DRY)[0] < _rel_errors(plain, POLACH_DRY)[0]


def test_single_low_speed_warns_about_a_and_b():
    # 5 km/h and creep up to 2 %: slip velocity below 0.03 m/s, mu(w) hardly bends.
    s, w, mu = _points(POLACH_DRY, speeds=np.array([5 / 3.6]), max_creep=0.02)
    y = mu + 0.002 * np.random.default_rng(0).standard_normal(mu.size)
    with pytest.warns(PolachFitWarning):
        fit = fit_polach(s, y, LOAD, K, slip_velocity=w)
    assert not fit.identifiable


def test_curve_reproduces_the_creep_curve_of_the_fitted_set():
    s, w, mu = _points(POLACH_DRY, speeds=SPEEDS[1:])
    fit = fit_polach(s, mu, LOAD, K, slip_velocity=w)
    grid = np.linspace(0, 0.06, 61)
    ref = polach_creep_curve(grid, LOAD, SPEEDS[2], 0.348, 0.291, 0.452, 1.890, POLACH_DRY)
    np.testing.assert_allclose(
        fit.curve(grid, rolling_speed=SPEEDS[2]), ref.adhesion_coefficient, atol=1e-8
    )


def test_creep_curve_as_contact_description():
    s, w, mu = _points(POLACH_DRY, speeds=SPEEDS[1:])
    curve = polach_creep_curve([0.0], LOAD, 8.0, 0.348, 0.291, 0.452, 1.890)
    fit = fit_polach(s, mu, LOAD, curve, slip_velocity=w)
    np.testing.assert_allclose(fit.parameters.as_tuple(), POLACH_DRY.as_tuple(), rtol=1e-6)


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="at least 6"):
        fit_polach([0.01] * 3, [0.3] * 3, LOAD, K, rolling_speed=8.0)
    with pytest.raises(ValueError, match="slip_velocity"):
        fit_polach(np.linspace(0, 0.1, 10), np.zeros(10), LOAD, K)


def test_adhesion_figure_with_fit_and_residuals():
    from rollerrig.report.adhesion import adhesion_figure

    s, w, mu = _points(POLACH_DRY, speeds=SPEEDS[1:])
    fit = fit_polach(s, mu, LOAD, K, slip_velocity=w)
    fig = adhesion_figure(s, mu, fit=fit, title="dry")
    assert len(fig.axes) == 2


def test_inputs_that_cannot_be_fitted_are_refused_naming_the_parameter():
    """A slip velocity (or load, stiffness, speed) of another length had given numpy's bare
    broadcast error; all-zero creep a ZeroDivisionError in the diagnostics; f_scale = 0 and an
    unknown loss scipy's own errors (or, f_scale = 0 with the linear loss, a fit)."""
    import re

    from rollerrig._validation import ParameterError

    s, w, mu = _points(POLACH_DRY, speeds=SPEEDS[1:], n=10)
    with pytest.raises(ParameterError, match=re.escape(
        "creep (shape (20,)) and slip_velocity (shape (7,)) must have the same shape"
    )):  # fmt: skip
        fit_polach(s, mu, LOAD, K, slip_velocity=w[:7])
    for name, kw in (
        ("normal_load", {"normal_load": np.full(3, LOAD)}),
        ("creep_stiffness", {"creep_stiffness": np.full(3, K)}),
        ("rolling_speed", {"slip_velocity": None, "rolling_speed": np.full(3, 8.0)}),
    ):
        args = {"normal_load": LOAD, "creep_stiffness": K, "slip_velocity": w, **kw}
        with pytest.raises(ParameterError, match=re.escape(f"and {name} (shape (3,))")):
            fit_polach(s, mu, **args)
    with pytest.raises(ParameterError, match=r"creep must be nonzero \[-\] at 6 points.*got 0 of"):
        fit_polach(np.zeros(20), mu, LOAD, K, rolling_speed=8.0)
    for f_scale in (0.0, -1.0, np.nan):
        with pytest.raises(ParameterError, match=r"f_scale must be (> 0|finite) \[-\]"):
            fit_polach(s, mu, LOAD, K, slip_velocity=w, loss="huber", f_scale=f_scale)
    with pytest.raises(ParameterError, match=r"f_scale must be > 0 \[-\], got 0"):
        fit_polach(s, mu, LOAD, K, slip_velocity=w, f_scale=0)
    with pytest.raises(ParameterError, match=re.escape(
        "loss must be one of 'linear', 'soft_l1', 'huber', 'cauchy', 'arctan'"
    )):  # fmt: skip
        fit_polach(s, mu, LOAD, K, slip_velocity=w, loss="bogus")
    with pytest.raises(ParameterError, match=re.escape("got 'Huber' (did you mean 'huber'?)")):
        fit_polach(s, mu, LOAD, K, slip_velocity=w, loss="Huber")
    # One value for all points, or one per point, still go.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PolachFitWarning)  # ten points a speed: k_A ~ k_S
        fit = fit_polach(s, mu, np.full(s.size, LOAD), K, slip_velocity=w, loss="soft_l1")
    assert fit.parameters.static_friction == pytest.approx(POLACH_DRY.static_friction, rel=1e-3)


def test_a_parameter_the_data_do_not_see_has_no_finite_standard_error():
    """A wet-like curve without a friction fall at one speed: the fit ends with A at 1, where
    B no longer changes the curve (a zero Jacobian column). The pseudo-inverse used to leave
    B a standard error of 1e-16, and the analysis then reported B "± 6e-18 ... (3e16 σ)" from
    the truth; B is undetermined: infinite standard error, no correlation, no σ distance."""
    truth = PolachParameters(0.36, 1.0, 0.0, 0.27, 0.08)
    s = np.linspace(5e-4, 0.02, 200)
    w = s * 10 / 3.6
    y = polach_coa(s, w, LOAD, K, truth) + 0.002 * np.random.default_rng(1).standard_normal(s.size)
    with pytest.warns(PolachFitWarning, match="friction_decay is not determined at all"):
        fit = fit_polach(s, y, LOAD, K, slip_velocity=w)
    assert fit.parameters.limit_ratio > 1 - 1e-6  # at its bound: B unseen
    assert fit.stderr["friction_decay"] == np.inf
    b = list(PARAMETER_NAMES).index("friction_decay")
    assert np.all(np.isnan(fit.correlation[b]))
    row = fit.truth_distance(PolachParameters(0.36, 0.4, 0.2, 0.27, 0.08))["friction_decay"]
    assert row["sigma"] is None and not row["beyond_warn_sigma"]
    # What the data do see keeps its finite standard error.
    assert np.isfinite(fit.stderr["static_friction"]) and np.isfinite(fit.stderr["k_adhesion"])
