"""Analysis cost bounded by what the data can say (issue 23, point 2): one Polach law is never
fitted across two friction conditions without a note, and a fit the data cannot determine
stops early and says so."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from rollerrig.analysis.polach_fits import (
    FRICTION_SLOPE_RATIO,
    _note_friction_change,
    _one_friction_condition,
)
from rollerrig.contact.creep import POLACH_DRY, POLACH_WET
from rollerrig.fit import creep_stiffness_for_rig, fit_polach, polach_coa
from rollerrig.fit.polach import PolachFitWarning
from rollerrig.measure.facts import friction_schedule, true_polach_parameters
from rollerrig.measure.segmentation import Branches
from rollerrig.recordings.recording import Recording
from rollerrig.rig.parameters import default_rig


def _recording(metadata: dict) -> Recording:
    t = np.arange(10) / 10.0
    return Recording(t, {"torque": np.zeros(10)}, {"torque": "N.m"}, metadata)


def _provenance(times, conditions) -> str:
    # the twin's provenance keeps the protocol's lists as their text
    protocol = {"friction_time [s]": str(times), "friction_condition": str(conditions)}
    sets = {"dry": {"static_friction": 0.55}, "wet": {"static_friction": 0.3}}
    return json.dumps({"protocol": protocol, "friction_sets": sets})


def test_the_friction_schedule_is_read_from_the_twins_provenance():
    stored = {"twin_provenance": _provenance([0.0, 6.04], ["dry", "wet"])}
    rec = _recording({"stored_metadata": stored})
    assert friction_schedule(rec) == [(0.0, "dry"), (6.04, "wet")]
    # a real rig's recording says nothing about its friction
    assert friction_schedule(_recording({"source": "rig.tdms"})) is None
    # with several sets, the one the fits used is the truth they are compared with
    params, source = true_polach_parameters(rec, condition="wet")
    assert params == {"static_friction": 0.3} and "'wet' set, the condition the fits used" in source
    assert true_polach_parameters(rec)[0] is None
    one = _recording({"twin_provenance": _provenance([0.0], ["wet"])})
    assert true_polach_parameters(one)[0] == {"static_friction": 0.3}  # (was read letter by letter)


def test_the_fits_keep_the_condition_with_most_points_and_say_so():
    t = np.arange(700) / 100.0
    points = np.arange(0, 700, 2)
    notes: list[str] = []
    kept, condition = _one_friction_condition(t, points, [(0.0, "dry"), (6.04, "wet")], notes)
    assert condition == "dry"
    assert np.all(t[kept] < 6.04) and kept.size == np.sum(t[points] < 6.04)
    (note,) = notes
    assert "changes friction (dry from 0 s, wet from 6.04 s)" in note
    assert f"{kept.size} ascending-branch points under 'dry' only" in note
    assert "never fitted across two friction conditions" in note
    # one condition, or none known: the points as they are, nothing said
    for schedule in (None, [(0.0, "dry")]):
        notes = []
        same, _ = _one_friction_condition(t, points, schedule, notes)
        assert np.array_equal(same, points) and notes == []


def _branches(params_per_cycle, rig, load=4300.0, n=200):
    """Ascending branches of Polach curves, one cycle per parameter set, end to end."""
    k = creep_stiffness_for_rig(load, rig)
    creep, coa, branches = [], [], []
    for c, params in enumerate(params_per_cycle):
        s = np.linspace(2e-4, 0.004, n)
        start = sum(x.size for x in creep)
        creep.append(s)
        coa.append(polach_coa(s, s * 30 / 3.6, load, k, params))
        branches.append(Branches(c, np.arange(start, start + n), np.arange(0)))
    creep, coa = np.concatenate(creep), np.concatenate(coa)
    return branches, creep, coa, np.full(creep.size, load)


def test_a_change_of_friction_the_recording_does_not_state_is_noted():
    rig = default_rig()
    notes: list[str] = []
    _note_friction_change(*_branches([POLACH_DRY, POLACH_DRY, POLACH_WET], rig), rig, notes)
    (note,) = notes
    assert "friction condition probably changed" in note and "one law" in note
    ratio = float(note.split("differ by x", 1)[1].split()[0])
    assert ratio > FRICTION_SLOPE_RATIO
    notes = []
    _note_friction_change(*_branches([POLACH_DRY] * 3, rig), rig, notes)
    assert notes == []


def test_a_fit_the_data_cannot_determine_stops_early_and_says_so():
    # creep far below the peak, one speed: the user guide's notebook case (docs/guide/notebook.rst)
    rig = default_rig()
    k = creep_stiffness_for_rig(4300.0, rig)
    s = np.linspace(2e-4, 0.002, 300)
    rng = np.random.default_rng(0)
    mu = polach_coa(s, s * 30 / 3.6, 4300.0, k, POLACH_DRY) + 0.003 * rng.standard_normal(s.size)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fit = fit_polach(s, mu, 4300.0, k, rolling_speed=30 / 3.6)
    assert not fit.identifiable
    assert "stopped at the optimiser's default tolerances" in fit.message
    text = " ".join(str(w.message) for w in caught if issubclass(w.category, PolachFitWarning))
    assert "not polished, since the data do not determine" in text


def test_a_fit_the_data_determine_is_polished_as_before():
    s = np.tile(np.linspace(0.0005, 0.08, 40), 2)
    v = np.repeat([30 / 3.6, 60 / 3.6], 40)
    k = 1.1295e6
    mu = polach_coa(s, s * v, 4300.0, k, POLACH_DRY)
    fit = fit_polach(s, mu, 4300.0, k, slip_velocity=s * v)
    assert "stopped" not in fit.message
    assert fit.parameters.static_friction == pytest.approx(0.55, abs=1e-6)
    assert fit.parameters.k_slip == pytest.approx(0.4, abs=1e-6)
