"""Roller-to-track transfer (issue 19 point 4): invariants, the issue's numbers, CSV inputs."""

import dataclasses
import math
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rollerrig._validation import ParameterError
from rollerrig.analysis.transfer import (
    ContactGeometry,
    MeasuredCurve,
    RailGeometry,
    kalker_creepage,
    read_curve_csv,
    rig_creep,
    transfer_curve,
)
from rollerrig.contact import law_creep_curve, polach_creep_curve
from rollerrig.contact.fastsim import fastsim_grid

RIG = dict(wx=0.348, wy=0.291, rx=0.452, ry=1.890)
GEO = ContactGeometry(0.348, 0.291, 0.452, 1.890, 210e9, 0.3, 2.5e-4, 2.5e-4, 0.05)
GRID = fastsim_grid(16, 16)


def _measured(law="polach", load=4300.0, speed=30 / 3.6, smax=0.08, n=60):
    s = np.linspace(smax / n, smax, n)
    from rollerrig.contact.laws import parameter_set

    p = parameter_set("polach-dry" if law == "polach" else "eurosprinter-modified-fastsim")
    c = law_creep_curve(law, kalker_creepage(s), load, speed, RIG["wx"], RIG["wy"], RIG["rx"],
                        RIG["ry"], p, grid=GRID)  # fmt: skip
    noise = np.random.default_rng(1).normal(0, 0.002, n)
    return MeasuredCurve(s, c.adhesion_coefficient + noise, s * speed, np.full(n, load),
                         np.full(n, speed))  # fmt: skip


def _run(m, rail=None, law="polach", **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        options = {"profile": False} if law != "polach" else None
        return transfer_curve(m, GEO, rail, law, draws=60, grid=GRID, fit_options=options, **kw)


def test_progress_is_told_each_stage():
    said = []
    _run(_measured(), progress=said.append)
    assert said[0].startswith("fitting polach to 60 points")
    assert "60 draws of the geometry and the parameters" in said
    assert said[-1] == "the peaks and their intervals"


def test_creepage_conversion_round_trip():
    s = np.array([0.0, 0.001, 0.05, 0.3])
    assert np.allclose(rig_creep(kalker_creepage(s)), s)
    assert kalker_creepage(0.01) == pytest.approx(0.01 / 1.005)


@pytest.mark.parametrize("law", ["polach", "modified-fastsim"])
def test_same_geometry_is_identity(law):
    # A rail whose longitudinal radius equals the roller's: R / sin(gamma) = 0.452 m.
    gamma = 0.5
    rail = RailGeometry(curve_radius=0.452 * math.sin(gamma), contact_angle=gamma)
    r = _run(_measured(law), rail, law)
    assert r.stiffness_ratio == pytest.approx(1.0, rel=1e-9)
    assert np.allclose(r.factor, 1.0, atol=1e-9)
    assert np.allclose(r.track, r.roller, atol=1e-12)


@pytest.mark.parametrize("law", ["polach", "modified-fastsim"])
def test_small_creep_factor_is_stiffness_ratio_and_saturation_unchanged(law):
    r = _run(_measured(law, smax=0.3, n=80), None, law)
    e = r.elastic
    ratio = (
        e["track"]["creep_stiffness G a b C11 [N]"] / e["roller"]["creep_stiffness G a b C11 [N]"]
    )
    assert r.stiffness_ratio == pytest.approx(ratio)
    # The factor tends to G a b C11 (track / roller) at small creepage ...
    assert r.factor[0] == pytest.approx(ratio, rel=0.03)
    # ... and to 1 where both contacts slide (saturation at mu N on both).
    assert r.factor[-1] == pytest.approx(1.0, abs=0.01)
    assert np.all(r.track_low <= r.track + 1e-12) and np.all(r.track <= r.track_high + 1e-12)


def test_issue_numbers_creep_stiffness_and_polach_peak():
    """Issue 19: on the 0.452 m roller G a b C11 is 24 % below the tangent rail's (same crown),
    and the Polach peak sits at 16 % larger creep. Reproduced: 0.757 (24.3 % lower) at any
    load (Hertz scaling keeps a/b), and 15.2 % with Polach's dry set at 30 km/h (4.3 and 10 kN;
    grid 1e-5): the issue's 16 % is this number rounded on a coarser creep grid or another
    speed."""
    s = np.linspace(0, 0.1, 10001)
    for load in (4.3e3, 10e3):
        roll = polach_creep_curve(s, load, 30 / 3.6, RIG["wx"], RIG["wy"], RIG["rx"], RIG["ry"])
        rail = polach_creep_curve(s, load, 30 / 3.6, RIG["wx"], RIG["wy"], np.inf, RIG["ry"])
        assert roll.creep_stiffness / rail.creep_stiffness == pytest.approx(0.757, abs=0.001)
        assert roll.peak[0] / rail.peak[0] == pytest.approx(1.152, abs=0.005)
    # The transfer on a dry Polach curve measured on the roller gives the same factor.
    r = _run(_measured("polach"))
    assert 1 / r.stiffness_ratio == pytest.approx(0.757, abs=0.001)
    assert r.peaks["creepage_ratio roller/track [-]"] == pytest.approx(1.15, abs=0.04)


def test_summary_states_what_is_carried_over():
    r = _run(_measured())
    s = r.summary()
    assert "carried over" in s["carried_over_as_measured"]["assumption"]
    assert "Kayaalp eq. 4.21" in s["creepage"]["rig"]
    assert s["band"]["method"].startswith("Monte Carlo")
    assert set(r.columns()) >= {"creep", "creepage_kalker", "coa_track", "factor_low95"}


def test_laws_without_slope_reduction_are_refused():
    with pytest.raises(ParameterError, match="modified-fastsim"):
        transfer_curve(_measured(), GEO, law="fastsim")


def _csv(tmp_path, text, name="c.csv"):
    p = tmp_path / name
    p.write_text(text)
    return p


GOOD = "creep [%],coa [-]\n" + "\n".join(f"{0.3 * i},{0.04 * i}" for i in range(1, 13))


@pytest.mark.parametrize(
    "text, match",
    [
        ("", "empty"),
        ("creep,coa [-]\n0.1,0.1\n", "has no unit"),
        ("creep [mm],coa [-]\n0.1,0.1\n", "not accepted"),
        ("coa [-]\n0.1\n", "missing"),
        (GOOD.replace("0.3,0.04", "nan,0.04"), "not finite"),
        (GOOD.replace("0.3,0.04", "x,0.04"), "not a number"),
        (GOOD.replace("0.6,0.08", "0.1,0.08"), "non-monotonic"),
        (GOOD.replace("0.3,0.04", "-0.3,0.04"), "negative creep"),
        (GOOD.replace("[%]", "[-]").replace("3.5999999999999996", "120"), "per cent"),
        ("creep [-],coa [-]\n" + "\n".join(f"{0.001 * i},{3.0}" for i in range(1, 13)), "2"),
    ],
)
def test_csv_errors_name_the_problem(tmp_path, text, match):
    with pytest.raises(ParameterError, match=match):
        read_curve_csv(_csv(tmp_path, text), normal_load=4300.0, rolling_speed=8.3)


def test_csv_needs_load_and_speed(tmp_path):
    with pytest.raises(ParameterError, match="normal_load"):
        read_curve_csv(_csv(tmp_path, GOOD), rolling_speed=8.3)
    c = read_curve_csv(_csv(tmp_path, GOOD), normal_load=4300.0, rolling_speed=8.3,
                       creepage="mean")  # fmt: skip
    assert c.creep[-1] == pytest.approx(rig_creep(0.036))


cells = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.text(alphabet=st.characters(blacklist_categories=("Cs",)), max_size=6),
)


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    header=st.sampled_from(
        [
            "creep [-],coa [-]",
            "creep [%],coa [-],normal_load [kN]",
            "creep,coa",
            "coa [-],creep [-]",
            "x [1]",
        ]
    ),
    rows=st.lists(st.lists(cells, min_size=1, max_size=3), max_size=14),
)
def test_hostile_csv_is_refused_cleanly_or_read(tmp_path, header, rows):
    text = header + "\n" + "\n".join(",".join(r) for r in rows)
    p = _csv(tmp_path, text, "h.csv")
    try:
        c = read_curve_csv(p, normal_load=4300.0 if "normal_load" not in header else None,
                           rolling_speed=8.3)  # fmt: skip
    except ParameterError:
        return
    assert np.all(np.isfinite(c.creep)) and np.all(np.diff(c.creep) >= 0)


def test_the_points_stated_uncertainty_enters_the_band_by_default():
    """A curve that carries its standard uncertainty (an analysis's) widens the band by it
    unless the user gives coa_systematic; without it the band is the fit's alone."""
    from rollerrig.analysis.transfer import _stated_systematic

    creep = np.linspace(0.001, 0.03, 40)
    coa = 0.4 * np.tanh(creep / 0.004)
    curve = MeasuredCurve(
        creep=creep,
        coa=coa,
        slip_velocity=creep * 8.0,
        normal_load=np.full(40, 5000.0),
        rolling_speed=np.full(40, 8.0),
        coa_uncertainty=0.03 * coa,
    )
    assert _stated_systematic(curve) == pytest.approx(0.03)
    assert (
        _stated_systematic(dataclasses.replace(curve, coa_uncertainty=np.full(40, np.nan))) is None
    )


def test_the_polach_transfer_factor_against_the_strip_theory():
    """FaStrip is within 0.003 of μN of CONTACT's exact theory (tests/contact/test_strip.py,
    tractcurv.ref_out cases 1-11): its factor F_rail/F_roller at equal creepage stands in for
    the exact one. Polach's factor agrees at small creepage (the ratio of G·a·b·C11) and
    differs by up to 3.6 % in the transition; against CONTACT's exact theory it is 3.1 %
    (LAW_FACTOR_ERROR, tests/contact/test_cntc.py): the issue's target of 2 % is not met by the
    closed-form law, which the transfer says and puts in its band."""
    from rollerrig.analysis.transfer import LAW_FACTOR_ERROR
    from rollerrig.contact.laws import law_creep_curve, parameter_set
    from rollerrig.fit.polach import PolachParameters

    creep = np.linspace(1e-5, 0.03, 300)
    geometry = (0.348, 0.291, 0.452, 1.89)  # the bundled rig's wheel and roller radii [m]
    rail = (0.348, 0.291, 1e9, 1.89)  # a tangent rail with the roller's crown
    coulomb = PolachParameters(
        0.33, 1.0, 0.0, 1.0, 1.0, name="coulomb", source="test"
    )  # as the set

    def factor(law, params):
        on = [law_creep_curve(law, creep, 5000.0, 30 / 3.6, *g, params) for g in (rail, geometry)]
        return on[0].adhesion_coefficient / on[1].adhesion_coefficient

    strip = factor("fastrip", parameter_set("eurosprinter-coulomb"))
    polach = factor("polach", coulomb)
    rel = np.abs(polach / strip - 1.0)
    assert rel[0] < 0.002
    assert 0.025 < rel.max() < 0.045
    assert 0.02 < LAW_FACTOR_ERROR["polach"] < rel.max()


def test_the_law_error_widens_the_band_where_the_curve_has_left_its_linear_part():
    """The law's factor error (LAW_FACTOR_ERROR, measured against CONTACT) is a bound on the
    band's edges, scaled by the roller curve's rise: nothing at ξ → 0, where every law's factor
    is the ratio of the creep stiffnesses, the full ±LAW_FACTOR_ERROR past the onset (edges
    times 1 ∓ e: the half-width over the factor grows by e·(mid-band / factor) ≥ 0.95 e)."""
    from rollerrig.analysis.transfer import LAW_FACTOR_ERROR

    m = _measured()
    with_error, without = _run(m, seed=3), _run(m, seed=3, law_error=False)

    def half_width(r):
        return (r.factor_high - r.factor_low) / 2 / r.factor

    e = LAW_FACTOR_ERROR["polach"]
    widened = half_width(with_error) - half_width(without)
    assert abs(widened[0]) < 0.02 * e
    late = with_error.roller >= 0.5 * with_error.roller.max()
    assert np.all(widened[late] > 0.95 * e) and np.all(widened[late] < 1.1 * e)
    assert any("law's error in the transfer factor" in i["name"] for i in with_error.band["inputs"])
    assert "the law's error in the transfer factor" in without.band["not_included"]


def test_a_measured_curve_refuses_a_negative_or_infinite_uncertainty():
    """A negative standard uncertainty had been taken as it was; NaN stays: a point without
    a stated uncertainty (the transfer leaves it out, test above)."""
    import re

    creep = np.linspace(0.001, 0.03, 40)
    coa = 0.4 * np.tanh(creep / 0.004)
    kw = {"creep": creep, "coa": coa, "slip_velocity": creep * 8.0,
          "normal_load": np.full(40, 5000.0), "rolling_speed": np.full(40, 8.0)}  # fmt: skip
    u = 0.03 * coa
    u[5] = -0.01
    with pytest.raises(ParameterError, match=re.escape(
        "coa_uncertainty must be >= 0 and finite [-] (NaN where a point has none stated), got "
        "-0.01 at index 5 (1 of 40 values)"
    )):  # fmt: skip
        MeasuredCurve(**kw, coa_uncertainty=u)
    u[5] = np.inf
    with pytest.raises(ParameterError, match=re.escape("got inf at index 5")):
        MeasuredCurve(**kw, coa_uncertainty=u)
    with pytest.raises(ParameterError, match=re.escape(
        "coa_uncertainty (shape (3,)) must have the shape of coa (shape (40,))"
    )):  # fmt: skip
        MeasuredCurve(**kw, coa_uncertainty=np.full(3, 0.01))
    u[5] = np.nan
    assert MeasuredCurve(**kw, coa_uncertainty=u).coa_uncertainty is u


def test_the_peak_the_factor_line_and_the_curve_written_agree():
    # transfer of the demo's analysis printed "peak creepage ≥ 4.71 (still rising)", "peak CoA
    # ≥ 0.455" and "factor at the roller's peak 1.000", while the CSV's coa_roller peaked at
    # 0.4602 at 3.38 %: the law's fitted shape placed the peak, the curve written is the
    # measured level.
    import copy
    import io

    from rich.console import Console

    from rollerrig.cli.transfer import _table

    r = _run(_measured(smax=0.01))  # the law still rises at the largest creepage
    for name, curve in (("roller", r.roller), ("track", r.track)):
        p = r.peaks[name]
        k = int(np.argmax(curve))  # the curve written (the CSV's column) and its largest
        assert p["curve_maximum"]["creepage [-]"] == r.creepage[k]
        assert p["curve_maximum"]["coa [-]"] == pytest.approx(curve[k])
        if not p["inside_measured_range"]:
            assert p["coa [-]"] >= curve[k]  # a bound: at least the curve's largest

    # The demo's case: the law's shape places no peak, the measured level has its largest
    # inside the range.
    peaks = copy.deepcopy(r.peaks)
    k = r.creepage.size // 2
    largest = {"creepage [-]": float(r.creepage[k]), "coa [-]": 0.4602}
    for name in ("roller", "track"):
        peaks[name].update(
            {"creepage [-]": float(r.creepage[-1]), "coa [-]": 0.4602,
             "inside_measured_range": False, "located_by": "the law's fitted shape",
             "curve_maximum": {**largest, "inside_measured_range": True}}
        )  # fmt: skip
    demo = dataclasses.replace(r, peaks=peaks)
    at = f"{100 * r.creepage[k]:.2f} %"
    assert demo.peak_creepage_text("roller").endswith("(law's shape still rising)")
    assert demo.peak_coa_text("roller").startswith("≥ 0.460")
    assert demo.curve_maximum_text("roller") == f"0.460 at {at}"
    line = demo.factor_text()
    assert "at the roller's peak" not in line and "no roller peak in the range" in line
    assert f"at the roller curve's largest CoA (ξ {at}) {demo.factor_at(r.creepage[k]):.3f}" in line
    factor = demo.summary()["transfer_factor"]
    assert factor["at_roller_peak [-]"] is None
    assert factor["at_roller_curve_maximum [-]"] == pytest.approx(demo.factor_at(r.creepage[k]))
    out = io.StringIO()
    Console(file=out, width=200).print(_table(demo))
    text = " ".join(out.getvalue().split())
    assert "curve's largest CoA at ξ" in text and f"0.460 at {at}" in text
    assert "law's shape still rising" in text and line in text
    # A peak the law's shape places inside the range is said to be the law's
    for name in ("roller", "track"):
        peaks[name].update({"creepage [-]": float(r.creepage[k + 5])})
        peaks[name]["inside_measured_range"] = True
    inside = dataclasses.replace(r, peaks=peaks)
    assert inside.peak_creepage_text("roller").endswith(", law's shape")
    assert "at the roller's peak (law's shape)" in inside.factor_text()
    assert inside.curve_maximum_text("roller") == f"0.460 at {at}"  # the curve's own, elsewhere
