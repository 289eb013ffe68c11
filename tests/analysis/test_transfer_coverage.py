"""Coverage of the transfer's band on data of a model the fit does not share (issue 19 point 4).

The "measured" roller curve is Kalker's exact theory computed by CONTACT (Vollebregt), not
either law: ``tests/contact/data/cntc_exact_rig.json`` (12 creepages 1e-5...1e-2, the bundled
rig's wheel on its 0.452 m roller and on a tangent rail with the roller's crown, 10 kN,
30 km/h, Coulomb μ = 0.33, grid-extrapolated; one load and one geometry only: what the file
holds). The truth on the rail is CONTACT's curve on the rail. Coverage is the fraction of the
11 creepages from 2.5e-4 on where the band holds the truth (at 1e-5 the CoA is 0.002, below
the noise of the noisy cases).

Measured (draws 60, 81 output points, FASTSIM grid 12 x 12, draw seed 0; noise seeds 1-3 of
σ = 0.005 in F/N), creepages covered of 11, and the largest half-width over the rail CoA where
that is 0.1 or more:

================  =====================================  ======================================
law               old band (clipped covariance draws)    this band (measured points)
================  =====================================  ======================================
polach            noise-free 4; noisy 4, 4, 0; 98 %      noise-free 11; noisy 11, 11, 10; 4.9 %
modified-fastsim  noise-free 10; noisy 9, 0, 11; 119 %   noise-free 11; noisy 11, 11, 10; 5.1 %
================  =====================================  ======================================

Over noise seeds 1-10 (draws 100, 161 output points, FASTSIM 12 x 12) the band covers 104 of
110 creepages for each law (0.945, against a nominal 0.95). The old band's lower edge lay near
zero and its upper edge, at a quarter of the creepages, below its own central curve. Pinned
with margin below; each law fails at least one of these tests on the old band. (Seed 3 puts a
3.3 σ error on the point at ξ = 4e-3: a 95 % band need not hold that one.)
"""

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from rollerrig.analysis.transfer import (
    LAW_FACTOR_ERROR,
    ContactGeometry,
    MeasuredCurve,
    rig_creep,
    transfer_curve,
)
from rollerrig.contact.fastsim import fastsim_grid

DATA = Path(__file__).resolve().parents[1] / "contact" / "data" / "cntc_exact_rig.json"
REF = json.loads(DATA.read_text())
INP = REF["input"]
XI = np.array(REF["long_creep"])
LOAD = INP["normal_load_N"]
SPEED = INP["rolling_speed_m_s"]
ROLLER = np.array(REF["contacts"]["roller"]["fx_N_extrapolated"]) / LOAD
RAIL = np.array(REF["contacts"]["tangent_rail"]["fx_N_extrapolated"]) / LOAD
GEO = ContactGeometry(
    INP["wheel_radius_x_m"],
    INP["wheel_radius_y_m"],
    INP["roller_radius_x_m"],
    INP["roller_radius_y_m"],
    INP["youngs_modulus_Pa"],
    INP["poisson_material"],
    2.5e-4,
    2.5e-4,
    0.05,
)
SCORED = XI >= 2.5e-4
NOISE = 0.005  # standard deviation of the noise added to F/N [-]
SEEDS = (1, 2, 3)
LAWS = ("polach", "modified-fastsim")


def _transfer(law, seed):
    y = ROLLER.copy()
    if seed is not None:
        y = y + np.random.default_rng(seed).normal(0.0, NOISE, y.size)
    s = rig_creep(XI)
    m = MeasuredCurve(s, y, s * SPEED, np.full(XI.size, LOAD), np.full(XI.size, SPEED))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the fit says it is not identifiable: that is the case
        return transfer_curve(
            m,
            GEO,
            None,
            law,
            draws=60,
            points=81,
            grid=fastsim_grid(12, 12),
            fit_options={"profile": False} if law != "polach" else None,
        )


def _at_truth(r):
    lo = np.interp(XI, r.creepage, r.track_low)
    hi = np.interp(XI, r.creepage, r.track_high)
    covered = (lo <= RAIL) & (RAIL <= hi)
    return covered[SCORED], ((hi - lo) / 2)[SCORED]


@pytest.fixture(scope="module", params=LAWS)
def runs(request):
    law = request.param
    return law, {seed: _transfer(law, seed) for seed in (None, *SEEDS)}


def test_the_band_covers_contacts_rail_curve_from_its_roller_curve(runs):
    """Noise-free: measured 11/11 for both laws (old band 4/11 Polach, 10/11 modified
    FASTSIM); pinned at 10/11. Noisy (3 seeds, 33 creepages): measured 32/33 for each law
    (old: 8/33 and 20/33); pinned at 0.85."""
    law, results = runs
    covered, _ = _at_truth(results[None])
    assert covered.sum() >= 10, (law, covered)
    noisy = np.concatenate([_at_truth(results[s])[0] for s in SEEDS])
    assert noisy.mean() >= 0.85, (law, noisy.mean())


def test_the_band_is_not_absurdly_wide(runs):
    """Noise-free: half-width under 8 % of CONTACT's rail CoA where it is 0.1 or more
    (measured 4.9 % Polach, 5.1 % modified FASTSIM; old 98 % and 119 %); noisy: under
    7 σ = 0.035 in F/N at every scored creepage (measured 0.018-0.027; a 95 % band of a point's
    noise alone is ±1.96 σ·factor ≈ ±0.013)."""
    law, results = runs
    _, half = _at_truth(results[None])
    big = RAIL[SCORED] >= 0.1
    assert np.max(half[big] / RAIL[SCORED][big]) < 0.08, law
    for seed in SEEDS:
        _, half = _at_truth(results[seed])
        assert np.max(half) < 7 * NOISE, (law, seed)


def test_the_central_curve_is_inside_its_band_and_the_construction_is_said(runs):
    _, results = runs
    for r in results.values():
        assert np.all(r.track_low <= r.track) and np.all(r.track <= r.track_high)
        assert np.all(r.roller_low <= r.roller) and np.all(r.roller <= r.roller_high)
        assert np.all(r.factor_low <= r.factor) and np.all(r.factor <= r.factor_high)
        # a noise-free curve of another law: the fit cannot determine its parameters
        assert r.band["construction"] == "measured points"
        assert (
            "identifiable" in r.band["construction_why"]
            or "structured" in (r.band["construction_why"])
        )
        assert any(n.startswith("band construction: measured points") for n in r.notes)
        assert r.band["plausible_set"]["parameter_sets"] >= 2


def test_on_the_measured_points_the_central_curve_is_measured_times_factor(runs):
    """Noise-free, 12 points: the measured level goes through the points (one per bin), so
    the predicted rail CoA at a measured creepage is CONTACT's roller CoA times the law's factor;
    its error against CONTACT's rail curve is then the law's factor error alone: within
    LAW_FACTOR_ERROR plus 1.5 points (the factor at the fitted, not Kalker's, parameters;
    measured up to 3.8 % Polach, 3.2 % modified FASTSIM)."""
    law, results = runs
    r = results[None]
    level = np.interp(XI, r.creepage, r.roller)
    on = XI >= r.creepage[1]  # the grid's first point is 1e-4 of the range, below the data
    np.testing.assert_allclose(level[on], ROLLER[on], rtol=0.02, atol=2e-4)
    pred = np.interp(XI, r.creepage, r.track)
    assert np.max(np.abs(pred[SCORED] / RAIL[SCORED] - 1)) < LAW_FACTOR_ERROR[law] + 0.015
