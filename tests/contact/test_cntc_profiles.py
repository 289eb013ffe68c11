"""A wheel profile on a tangent rail and on a roller, by CONTACT's module 1 (non-Hertzian).

Reference data: ``tests/contact/data/cntc_profiles_rig.json``, CONTACT's *outputs* (E.A.H.
Vollebregt, Vtech CMCC, Apache-2.0, github.com/eve70a/CONTACT, commit d431cdb, revision 2707),
built with gfortran 12 by ``tools/build_contact.sh`` and computed through
:mod:`rollerrig.contact.cntc_profiles` by ``tools/contact_profiles_reference.py`` (which rebuilds
it; the file says how). Inputs: CONTACT's own example profiles (S1002 wheel on UIC60 rail, read
from CONTACT's examples/, never copied here), the default rig's wheel radius (348 mm) and roller
radius (452 mm), 10 kN, Coulomb μ = 0.33. The invariants below come from mechanics, not from the
package's Hertzian model: the roller's patch is shorter along the rolling direction, the force
saturates at μ F_n, the spin is the kinematics of a surface of revolution, and the Hertzian
transfer factor is compared with the recorded one with the difference stated.

The live tests call CONTACT where ``CONTACT_DIR`` names a build (and the example profiles are
in ``$CONTACT_DIR/examples`` or ``$CONTACT_SOURCE/examples``); elsewhere they are skipped.
"""

from __future__ import annotations

import collections
import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from rollerrig._validation import ParameterError
from rollerrig.analysis.transfer_geometry import hertz_ellipse
from rollerrig.contact.cntc import ContactNotAvailable, contact_dir
from rollerrig.contact.cntc_profiles import (
    EXAMPLE_RAIL,
    EXAMPLE_WHEEL,
    example_profile,
    profile_creep_force,
    profile_transfer_factor,
)
from rollerrig.contact.hertz import combined_elastic_constants
from rollerrig.rig.parameters import default_rig

REF = json.loads((Path(__file__).parent / "data" / "cntc_profiles_rig.json").read_text())
INP = REF["input"]
BODIES = ("tangent_rail", "roller")


def _sweep(body, key):
    return np.array(REF["sweep"][body][key])


def _mu_fn(body):
    return INP["friction"] * _sweep(body, "normal_force [N]")


# --------------------------------------------------------------------------------------------
# (i) the recorded CONTACT results (no CONTACT needed)
# --------------------------------------------------------------------------------------------


def test_reference_file_says_where_it_comes_from():
    assert REF["contact"]["commit"].startswith("d431cdb")
    assert REF["contact"]["revision"] == 2707
    assert REF["made_by"] == "tools/contact_profiles_reference.py"
    assert "provenance" in REF
    g = default_rig().geometry
    assert INP["wheel_radius_m"] == g.wheel_radius_x and INP["roller_radius_m"] == g.roller_radius_x
    assert (INP["wheel_profile"], INP["rail_profile"]) == (EXAMPLE_WHEEL, EXAMPLE_RAIL)


def test_the_requested_creepage_was_reached():
    target = np.array(REF["sweep"]["long_creep"])
    for body in BODIES:
        got = _sweep(body, "long_creep [-]")
        assert np.all(np.abs(got - target) <= 1e-3 * np.abs(target) + 1e-8), body


def test_one_patch_carrying_the_load_when_centred():
    """F_n = F_z / cos δ (the prescribed vertical force on the inclined contact) within 0.1 %
    (measured: within 0.08 %, the tangential forces' share of F_z)."""
    for body in BODIES:
        assert np.all(_sweep(body, "n_patches [-]") == 1)
        delta = _sweep(body, "contact_angle [rad]")
        fn = _sweep(body, "normal_force [N]")
        np.testing.assert_allclose(fn, INP["normal_load_N"] / np.cos(delta), rtol=1e-3)


def test_the_rollers_patch_is_shorter_along_the_rolling_direction():
    """The roller curves the running surface along x too: at equal load its patch is shorter
    (measured 3.0 mm against 4.2 mm, 15 against 21 elements of 0.2 mm) and smaller in area;
    across, both span the same tread (measured 16.4 and 16.0 mm)."""
    h = REF["sweep"]["element_size_m"]
    rail, roller = (_sweep(b, "patch_length_x [m]") for b in BODIES)
    assert np.all(roller <= rail - 4 * h)
    assert np.all(
        _sweep("roller", "patch_area [m^2]") < 0.9 * _sweep("tangent_rail", "patch_area [m^2]")
    )
    np.testing.assert_allclose(
        _sweep("roller", "patch_width_y [m]"), _sweep("tangent_rail", "patch_width_y [m]"),
        atol=3 * h,
    )  # fmt: skip
    # Hertz on the rig's geometry says the same direction: a_roller < a_rail
    ratio = roller[0] / rail[0]
    el = _hertz()
    assert ratio < 1 and el["roller"].a / el["tangent_rail"].a < 1


def test_the_force_saturates_at_mu_fn_and_grows_with_creepage():
    for body in BODIES:
        fx, fy = _sweep(body, "fx [N]"), _sweep(body, "fy [N]")
        mu_fn = _mu_fn(body)
        assert np.all(np.hypot(fx, fy) <= mu_fn * (1 + 1e-6)), body
        assert np.all(np.diff(fx) > 0), body
        assert fx[-1] >= 0.999 * mu_fn[-1], body  # ξ = 1e-2: full slip (measured 0.99996)


def test_the_spin_is_the_kinematics_of_the_two_surfaces():
    """Spin from the contact angle δ: each body turning at ω about an axle at radius r from the
    contact adds ω sin δ / V_ref, and V_w = V_ref (1 + ξ/2), V_r = V_ref (1 - ξ/2) (CONTACT's
    ξ = (V_w - V_r)/V_ref): φ = -sin δ (1 + ξ/2)/r_w on the rail, and the roller, a surface of
    revolution too, adds -sin δ (1 - ξ/2)/r_r. Rolling radii at the contact taken as the nominal
    ones (measured agreement within 0.05 %). Measured: -0.0838 and -0.1507 1/m."""
    rw, rr = INP["wheel_radius_m"], INP["roller_radius_m"]
    for body in BODIES:
        xi = _sweep(body, "long_creep [-]")
        curv = (1 + xi / 2) / rw + ((1 - xi / 2) / rr if body == "roller" else 0.0)
        delta = _sweep(body, "contact_angle [rad]")
        np.testing.assert_allclose(_sweep(body, "spin [1/m]"), -np.sin(delta) * curv, rtol=1e-3)


def test_the_transfer_factor_tends_to_one_at_saturation():
    factor = np.array(REF["sweep"]["transfer_factor"])
    fn_ratio = _sweep("tangent_rail", "normal_force [N]") / _sweep("roller", "normal_force [N]")
    assert abs(factor[-1] - fn_ratio[-1]) < 1e-3
    assert np.all(factor[1:5] > 1.1)  # the transition: the rail is stiffer


def _hertz():
    """The package's Hertz ellipses on the rig's default geometry (roller; tangent rail with the
    roller's crown), 10 kN: what rollerrig.analysis.transfer uses."""
    rig = default_rig()
    g, m = rig.geometry, rig.material
    el = combined_elastic_constants(m.youngs_modulus, m.poisson, m.youngs_modulus, m.poisson)
    nu = float(el.poisson)
    out = {}
    for body, rx in (("roller", g.roller_radius_x), ("tangent_rail", math.inf)):
        out[body] = hertz_ellipse(
            INP["normal_load_N"], g.wheel_radius_x, g.wheel_radius_y, rx, g.roller_radius_y,
            m.youngs_modulus, nu, m.poisson,
        )  # fmt: skip
    return out


def test_small_creepage_factor_against_the_hertzian_one():
    """The factor at small creepage, F_rail/F_roller = ratio of the creep stiffnesses dF/dξ at
    ξ = 0 (central difference at ±1e-4, which removes the spin's force on a patch not symmetric
    across the rolling direction), from CONTACT on the S1002/UIC60 profiles, against Kalker's
    linear theory on the package's Hertz ellipses of the rig's default geometry,
    (a b C11)_rail / (a b C11)_roller = 1.321. Recorded: 1.472 (0.2 mm elements), 1.466
    (0.1 mm), 1.460 extrapolated: 10.6 % above the Hertzian factor. In the transition the
    measured factor (1.267, 1.295, 1.217, 1.134, 1.056 at ξ = 2.5e-4, 5e-4, 1e-3, 1.5e-3, 2e-3)
    lies 4.1, 2.0, 7.9, 14.2, 20.1 % below it, and it is 1.000 from ξ = 3e-3 (saturation)."""
    el = _hertz()
    hertz = (el["tangent_rail"].a * el["tangent_rail"].b * el["tangent_rail"].c11) / (
        el["roller"].a * el["roller"].b * el["roller"].c11
    )
    assert hertz == pytest.approx(1.3209, abs=1e-3)
    s = REF["slope"]
    profiles = s["transfer_factor_extrapolated"]
    assert profiles == pytest.approx(1.4603, abs=1e-3)
    assert (profiles / hertz - 1) * 100 == pytest.approx(10.6, abs=0.1)
    # converged in the element size: halving it moves each stiffness by under 1.5 % (measured
    # 1.0 % and 0.6 %) and the factor by under 0.5 % (measured 0.4 %)
    for body in BODIES:
        coarse, fine = s[body]["creep_stiffness_N"]
        assert abs(fine / coarse - 1) < 0.015
    ratios = [r / q for r, q in zip(*(s[b]["creep_stiffness_N"] for b in BODIES), strict=True)]
    assert abs(ratios[1] / ratios[0] - 1) < 0.005
    # the transition: 2 % to 20 % below the Hertzian small-creepage factor
    factor = np.array(REF["sweep"]["transfer_factor"][1:6])
    assert np.all((factor < 0.99 * hertz) & (factor > 0.79 * hertz))


def test_the_spin_pushes_both_patches_the_same_way():
    """At ξ = ±1e-4 the forces are not opposite: the spin's own F_x (half the difference of
    |F|, measured 250 N on the rail, 270 N on the roller) is of the order of the force at
    ξ = 1e-4, so a transfer factor at ξ -> 0 from one point is wrong (0.96 at ξ = 1e-5)."""
    for body in BODIES:
        lo, hi = REF["slope"][f"{body}_0.2mm"]["fx [N]"]
        assert (hi + lo) / 2 > 200
    assert REF["sweep"]["transfer_factor"][0] < 1


def test_a_lateral_shift_moves_the_patch_and_lowers_the_spin():
    """y_ws = 0, 3, 6 mm: one patch, moving across the rail head towards its centre with a
    smaller contact angle, hence less spin; the factor stays within 1.18-1.23 at ξ = 1e-3."""
    for body in BODIES:
        rows = REF["lateral"][body]
        assert all(r["n_patches [-]"] == 1 for r in rows)
        spin = [abs(np.ravel(r["spin [1/m]"])[0]) for r in rows]
        assert spin[0] > spin[1] > spin[2]
    fx = {b: [np.ravel(r["fx [N]"])[0] for r in REF["lateral"][b]] for b in BODIES}
    factor = np.array(fx["tangent_rail"]) / np.array(fx["roller"])
    assert np.all((factor > 1.18) & (factor < 1.23))


# --------------------------------------------------------------------------------------------
# (ii) against a live CONTACT (skipped without one)
# --------------------------------------------------------------------------------------------


def _profiles_or_skip():
    if contact_dir() is None:
        pytest.skip("CONTACT_DIR is not set: no CONTACT build to call (tools/build_contact.sh)")
    try:
        return example_profile(EXAMPLE_WHEEL), example_profile(EXAMPLE_RAIL)
    except ContactNotAvailable as exc:
        pytest.skip(f"CONTACT's example profiles are not reachable: {exc}")


def _kwargs(wheel, rail):
    return dict(
        wheel_profile=wheel,
        rail_profile=rail,
        normal_load=INP["normal_load_N"],
        wheel_radius=INP["wheel_radius_m"],
        friction=INP["friction"],
        shear_modulus=INP["shear_modulus_Pa"],
        poisson=INP["poisson"],
        rolling_speed=INP["rolling_speed_m_s"],
        element_size=REF["sweep"]["element_size_m"],
    )


def _slope(body, key, element="0.2mm"):
    """The recorded solutions at ξ = -1e-4 and +1e-4 (element 0.2 mm, the sweep's)."""
    return np.array(REF["slope"][f"{body}_{element}"][key])


def test_live_backend_reproduces_the_recorded_transfer():
    wheel, rail = _profiles_or_skip()
    assert REF["sweep"]["element_size_m"] == 2e-4 and REF["slope"]["long_creep"] == [-1e-4, 1e-4]
    r = profile_transfer_factor(
        [1e-4], roller_radius=INP["roller_radius_m"], **_kwargs(wheel, rail)
    )
    for body, plus, minus in (("tangent_rail", r.rail, r.rail_reversed),
                              ("roller", r.roller, r.roller_reversed)):  # fmt: skip
        # each creepage hit within 1e-3 of itself from another starting guess: F_x within 1e-4
        # of the recorded value at ±1e-4 (the smaller of the two, the rail's at -1e-4, 1e-3)
        fx = _slope(body, "fx [N]")
        assert plus.fx[0] == pytest.approx(fx[1], rel=1e-4)
        assert minus.fx[0] == pytest.approx(fx[0], rel=1e-3, abs=0.1)
    odd = {b: (_slope(b, "fx [N]")[1] - _slope(b, "fx [N]")[0]) / 2 for b in BODIES}
    assert r.factor[0] == pytest.approx(odd["tangent_rail"] / odd["roller"], rel=1e-3)


def test_the_factor_is_the_ratio_of_the_odd_parts(monkeypatch):
    """A stand-in for CONTACT, F_x = k ξ + push (a spin push that keeps its sign): the factor
    is k_rail / k_roller at every creepage, whatever the pushes; the plain ratio is not."""
    import rollerrig.contact.cntc_profiles as cp

    def fake(long_creep, *, roller_radius=None, **kwargs):
        xi = np.atleast_1d(np.asarray(long_creep, dtype=float))
        k, push = (3.0e6, 250.0) if roller_radius is None else (2.0e6, 280.0)
        fields = {f.name: np.zeros(xi.shape) for f in dataclasses.fields(cp.ProfileContact)}
        return cp.ProfileContact(**{**fields, "long_creep": xi, "fx": k * xi + push})

    monkeypatch.setattr(cp, "profile_creep_force", fake)
    xi = np.array([1e-5, 1e-4, 1e-3])
    r = cp.profile_transfer_factor(xi, roller_radius=0.452)
    np.testing.assert_allclose(r.factor, 1.5, rtol=1e-12)
    np.testing.assert_allclose(r.rail_fx_odd, 3.0e6 * xi, rtol=1e-12)
    assert abs(r.rail.fx[0] / r.roller.fx[0] - 1.5) > 0.3  # the plain ratio at 1e-5


def test_live_an_unreadable_profile_is_one_error_line(tmp_path):
    wheel, _ = _profiles_or_skip()
    bad = tmp_path / "garbage.prr"
    bad.write_text("this is not a profile\n")
    with pytest.raises(ParameterError, match="rail_profile: CONTACT could not read") as info:
        profile_creep_force(1e-3, **_kwargs(wheel, bad))
    assert "\n" not in str(info.value)


# --------------------------------------------------------------------------------------------
# (iii) validation and the missing backend (no CONTACT needed)
# --------------------------------------------------------------------------------------------


@pytest.fixture
def two_files(tmp_path):
    w, r = tmp_path / "w.prw", tmp_path / "r.prr"
    w.write_text("x\n")
    r.write_text("x\n")
    return w, r


@pytest.mark.parametrize(
    ("change", "match"),
    [
        ({"normal_load": -1.0}, r"normal_load"),
        ({"wheel_radius": 0.0}, r"wheel_radius"),
        ({"roller_radius": float("nan")}, r"roller_radius"),
        ({"lateral_position": 0.2}, r"lateral_position must lie within"),
        ({"poisson": 0.5}, r"poisson must lie in"),
        ({"element_size": 1.0}, r"element_size must lie in"),
        ({"friction": 0.0}, r"friction"),
        ({"long_creep": 0.6}, r"long_creep must lie in \(-0.5, 0.5\)"),
        ({"wheel_profile": "/nonexistent/w.prw"}, r"wheel_profile: no such file"),
    ],
)
def test_bad_input_is_one_error_line_before_contact(monkeypatch, two_files, change, match):
    monkeypatch.delenv("CONTACT_DIR", raising=False)
    monkeypatch.delenv("CONTACTDIR", raising=False)
    kw = _kwargs(*two_files) | {"long_creep": 1e-3, **change}
    with pytest.raises(ParameterError, match=match) as info:
        profile_creep_force(**kw)
    assert "\n" not in str(info.value)


def test_transfer_factor_refuses_zero_creepage(two_files):
    with pytest.raises(ParameterError, match="non-zero"):
        profile_transfer_factor([0.0, 1e-3], roller_radius=0.452, **_kwargs(*two_files))


def test_without_contact_one_message(monkeypatch, two_files):
    monkeypatch.delenv("CONTACT_DIR", raising=False)
    monkeypatch.delenv("CONTACTDIR", raising=False)
    monkeypatch.delenv("CONTACT_SOURCE", raising=False)
    with pytest.raises(ContactNotAvailable, match=r"^CONTACT_DIR is not set\. ") as info:
        profile_creep_force(1e-3, **_kwargs(*two_files))
    assert "\n" not in str(info.value)
    with pytest.raises(ContactNotAvailable, match="CONTACT_SOURCE") as info:
        example_profile(EXAMPLE_WHEEL)
    assert "\n" not in str(info.value)


class _AbortingContact:
    """A stand-in for CONTACT's library: the creepage follows the wheel's angular velocity
    (ξ = 2 (ω − k)/(ω + k), k = V/r_w as the solver's first guess), F_x = 3e6 ξ; the case at
    ``abort_at`` ends in ierror -26 in this process, however often it is started afresh."""

    def __init__(self, abort_at, k):
        self.abort_at, self.k, self.xi, self.starts = abort_at, k, 0.0, 0

    def __getattr__(self, name):  # every setter of the configuration: accepted
        return lambda *args, **kwargs: None

    def initialize(self, *args):
        self.starts += 1

    def getprofilevalues(self, *args):
        return np.zeros(1)

    def setwheelsetvelocity(self, ire, e, values):
        omega = -values[5]
        self.xi = 2 * (omega - self.k) / (omega + self.k)

    def calculate(self, ire):
        return -26 if abs(self.xi - self.abort_at) < 1e-9 else 0

    def getnumcontactpatches(self, ire):
        return 1

    def getcontactpatchareas(self, ire, icp):
        return [50.0]

    def getcreepages(self, ire, icp):
        return [self.xi, 0.0, 0.0]

    def getreferencevelocity(self, ire, icp):
        return 1e4

    def getcontactforces(self, ire, p):
        return [1e4, -3e6 * self.xi, 0.0]

    def gettractions(self, ire, icp):
        return [np.ones((3, 4))]

    def getgriddiscretization(self, ire, icp):
        return [0.2, 0.2]

    def getcontactlocation(self, ire, icp):
        return np.zeros(6)


def test_a_case_contact_aborts_here_is_solved_in_a_fresh_process(monkeypatch, tmp_path):
    """The gfortran build sometimes ends a case in NaN (ierror -26) after many cases in one
    process, also after fresh starts of the result element, and solves it in another process:
    that case goes to a fresh process, the others stay here, each row where it belongs."""
    import rollerrig.contact.cntc_profiles as cp

    fake = _AbortingContact(abort_at=6e-3, k=1e4 / 348.0)
    monkeypatch.setattr(cp, "_library", lambda: (fake, collections.defaultdict(int)))
    monkeypatch.setitem(cp._state, "outdir", str(tmp_path) + "/")
    fresh = []

    def solve_fresh(settings, xt, et):
        fresh.append(xt)
        return {"long_creep": xt, "fx": 1.0, "normal_force": 1e4, "n_patches": 1, "solves": 1}

    monkeypatch.setattr(cp, "_solve_fresh", solve_fresh)
    for name in ("wheel.prw", "rail.prr"):
        (tmp_path / name).write_text("profile")
    r = cp.profile_creep_force(
        [1e-3, 6e-3, 3e-3], wheel_profile=tmp_path / "wheel.prw",
        rail_profile=tmp_path / "rail.prr", normal_load=1e4, wheel_radius=0.348, friction=0.3,
        shear_modulus=8e10, poisson=0.3,
    )  # fmt: skip
    assert fresh == [6e-3]
    assert fake.starts == 1 + cp._RETRIES  # tried afresh here first
    np.testing.assert_allclose(r.fx, [3e3, 1.0, 9e3])
    np.testing.assert_allclose(r.long_creep, [1e-3, 6e-3, 3e-3])


def test_live_a_fresh_process_gives_the_same_solution():
    """The fresh-process path (a new interpreter, CONTACT loaded anew, the case alone) solves a
    case as this process does."""
    import rollerrig.contact.cntc_profiles as cp

    wheel, rail = _profiles_or_skip()
    kw = _kwargs(wheel, rail)
    here = profile_creep_force([1e-3], **kw)
    settings = dict(
        roller_mm=0.0, wheel=str(wheel), rail=str(rail), rw_mm=kw["wheel_radius"] * 1e3,
        fz=kw["normal_load"], mu=kw["friction"], gg=kw["shear_modulus"] * 1e-6,
        nu=kw["poisson"], dx_mm=kw["element_size"] * 1e3, y_ws=0.0, v=kw["rolling_speed"] * 1e3,
    )  # fmt: skip
    row = cp._solve_fresh(settings, 1e-3, 0.0)
    assert row["fx"] == pytest.approx(here.fx[0], rel=1e-6)
    assert row["long_creep"] == pytest.approx(1e-3, rel=1e-3)
