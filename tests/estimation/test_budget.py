"""Per-phase and per-point tables of the corrected CoA's uncertainty (closed-form test).

References: closed forms (the creep's uncertainty from the radii's tolerances,
(1 + s)·√((t_w/r_w)² + (t_r/r_r)²)/√3); the phase means against the per-sample values.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from rollerrig.estimation.budget import _curve_point_indices, coa_budget, creep_uncertainty
from rollerrig.estimation.uncertainty import corrected_coa_uncertainty
from rollerrig.measure.segmentation import Branches, Phase
from rollerrig.recordings.recording import Recording
from rollerrig.rig.parameters import default_rig
from rollerrig.signal.smoothing import savitzky_golay

RIG = default_rig()
PHASES = [
    Phase("free_rolling", 0.0, 2.0, -1),
    Phase("ramp_up", 2.0, 6.0, 0),
    Phase("hold", 6.0, 7.0, 0),
    Phase("release", 7.0, 7.02, 0),
    Phase("rest", 7.02, 12.0, 0),
]


def _with_smoothed(rec):
    """The channels analyze_test adds that the budget reads (smoothed creep and rig CoA)."""
    w_w = savitzky_golay(rec["wheel_speed"], 51, 2)
    w_r = savitzky_golay(rec["roller_speed"], 51, 2)
    g = RIG.geometry
    creep = w_w * g.wheel_radius_x / (w_r * g.roller_radius_x) - 1
    coa = savitzky_golay(rec["torque"], 51, 2) / (g.roller_radius_x * rec["normal_load"])
    units = {"creep_smoothed": "1", "coa_smoothed": "1"}
    return rec.with_channels(creep_smoothed=creep, coa_smoothed=coa, units=units)


@pytest.fixture(scope="module")
def budget(closed_form_no_arm):
    # A contact that carries the air spring's force (no arm): the sensors' inputs dominate, as
    # this table's closed forms assume (the arm's terms: test_uncertainty).
    rig, rec, mu, release = closed_form_no_arm
    rec = _with_smoothed(rec)
    unc = corrected_coa_uncertainty(
        rec, rig, window=51, releases=[release], quiet=[(0.0, 2.0), (7.02, 12.0)]
    )
    t = rec.time
    branches = [
        Branches(0, np.flatnonzero((t >= 2) & (t < 7)), np.flatnonzero((t >= 7) & (t < 7.5)))
    ]
    creep_u = creep_uncertainty(rec, RIG, 51, 2)
    return coa_budget(unc, rec, PHASES, branches, creep_u=creep_u, true_coa=mu)


def test_one_row_per_phase_with_means_u_and_dominant(budget):
    rows = budget.phases
    assert [r["name"] for r in rows] == [p.name for p in PHASES]
    hold = rows[2]
    assert hold["corrected_coa_mean [-]"] == pytest.approx(0.3, abs=0.003)
    assert hold["dominant_sample"] == "pressure_class" == rows[1]["dominant_mean"]
    # systematic inputs do not average down: the mean's U is close to a (middle) sample's
    ramp = rows[1]
    assert ramp["U_mean [-]"] == pytest.approx(ramp["U_sample_median [-]"], rel=0.2)
    free = rows[0]
    # quantisation does average down: the mean's U is far below a sample's
    assert free["U_mean [-]"] < 0.7 * free["U_sample_median [-]"]
    assert rows[3]["dominant_sample"] == "residual_release"
    for r in rows:
        assert r["mean_covered"] and r["samples_covered [-]"] > 0.9


def test_curve_points_one_per_window_with_monte_carlo(budget):
    pts = budget.points
    times = [p["time [s]"] for p in pts]
    assert times == sorted(times) and len(pts) == 25 + 3  # 5 s ascending, 0.5 s descending
    assert all(p["u_agrees"] for p in pts)
    p = pts[10]
    assert p["mc_low_95 [-]"] < p["corrected_coa [-]"] < p["mc_high_95 [-]"]
    assert p["U [-]"] == pytest.approx(2 * p["u [-]"])


def test_summary_is_json_without_nan(budget):
    text = json.dumps(budget.summary(), allow_nan=False)
    data = json.loads(text)
    assert data["coverage_factor"] == 2.0
    assert data["validation"]["points"] == len(budget.points)
    assert data["typical"]["dominant_all_samples"] in {i["name"] for i in data["inputs"]}
    assert data["truth_coverage"]["samples_covered [-]"] > 0.95


def test_creep_uncertainty_of_the_radii_is_the_closed_form():
    """Exact speeds (no noise): u(s) from the radii's tolerances alone."""
    t = np.arange(500) / 250.0
    g, s = RIG.geometry, RIG.sensors
    w_r = np.full(t.size, 18.4)
    w_w = 1.01 * w_r * g.roller_radius_x / g.wheel_radius_x  # creep 1 %
    rec = Recording(t, {"wheel_speed": w_w, "roller_speed": w_r},
                    {"wheel_speed": "rad/s", "roller_speed": "rad/s"})  # fmt: skip
    u = creep_uncertainty(rec, RIG, 51, 2)
    expected = (
        1.01
        * math.hypot(
            s.wheel_radius_tolerance / g.wheel_radius_x,
            s.roller_radius_tolerance / g.roller_radius_x,
        )
        / math.sqrt(3)
    )
    np.testing.assert_allclose(u, expected, rtol=1e-6)


def test_curve_points_are_spaced_by_the_window_and_sorted():
    br = [Branches(1, np.arange(100, 200), np.arange(200, 230)),
          Branches(0, np.arange(10, 60), np.array([], dtype=int))]  # fmt: skip
    pts = _curve_point_indices(br, 25, 1000)
    assert pts[:, 0].tolist() == [10, 35, 100, 125, 150, 175, 200, 225]
    assert pts[:, 1].tolist() == [0, 0, 1, 1, 1, 1, 1, 1]
    assert pts[:, 2].tolist() == [1, 1, 1, 1, 1, 1, 0, 0]


def test_the_monte_carlo_is_thinned_above_its_cap_and_says_so(closed_form_test, budget):
    rec, _, _ = closed_form_test
    rec = _with_smoothed(rec)
    t = rec.time
    branches = [Branches(0, np.flatnonzero((t >= 2) & (t < 7)), np.array([], dtype=int))]
    thinned = coa_budget(
        budget.uncertainty, rec, PHASES, branches, mc_max_points=5, mc_draws=10_000
    )
    with_mc = [p for p in thinned.points if p["mc_u [-]"] is not None]
    assert len(thinned.points) == 25 and len(with_mc) == 5
    assert all("mc_null_because" in p for p in thinned.points if p["mc_u [-]"] is None)
    assert "one in 5 of the 25" in thinned.summary()["notes"][-1]
    json.dumps(thinned.summary(), allow_nan=False)
