"""Static and modal frame analysis against closed forms, signs and units of loads and stresses.

Closed forms: the cantilever (Euler-Bernoulli: tip deflection P L^3/(3 E I), rotation
P L^2/(2 E I), root stress P L c / I; Timoshenko & Gere, Mechanics of Materials, Table G-1
case 4); the L-shaped cantilever (bending of both legs plus torsion of the first, Castigliano);
the fixed-base portal frame under sway and under a mid-span load (Kleinlogel, Rahmenformeln,
frame I: fixed feet; derived again here by slope-deflection); the first bending frequency of a
cantilever with a tip mass (Rayleigh, Blevins, Formulas for Natural Frequency and Mode Shape,
Table 8-1 case 3: f = (1/2π) sqrt(3 E I / (L^3 (M + 0.2357 m)))); the cantilever's own first
bending frequency (Blevins Table 8-1 case 3 with M = 0: λ = 1.87510) and first torsional
frequency (St Venant torsion of a fixed-free bar: f = sqrt(G J / (ρ I_p)) / (4 L)).
"""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest

from rollerrig._validation import ParameterError
from rollerrig.frame import FrameFileError, analyze_frame, contact_dof

pytest.importorskip("Pynite")

from tests.frame.conftest import IPE200, NU, RHO, E

G = E / (2 * (1 + NU))
I_S, I_W = 1943e-8, 142.4e-8  # IPE 200 strong and weak axis [m^4]
A, J = 28.48e-4, 6.98e-8  # [m^2], [m^4]
H_SEC, B_SEC = 0.2, 0.1  # depth, width [m]


def _cantilever(make_frame, load, *, web=None, length=2.0, gauges=None, masses=None, n=1):
    nodes = {"root": (0, 0, 0), **{f"n{k}": (length * k / n, 0, 0) for k in range(1, n + 1)}}
    members = {}
    chain = ["root", *[f"n{k}" for k in range(1, n + 1)]]
    for k in range(n):
        members[f"m{k}"] = (chain[k], chain[k + 1], None, *([web] if web else []))
    return make_frame(
        nodes,
        members,
        {"root": "fixed"},
        {"tip": (chain[-1], load, (0, 0, 0))},
        gauges=gauges,
        masses=masses,
    )


def test_cantilever_tip_deflection_rotation_and_root_stress(make_frame):
    p, length = 1000.0, 2.0
    gauges = {
        "root_top": ("m0", 0.0, "+z"),
        "root_bottom": ("m0", 0.0, "-z"),
        "mid_top": ("m0", 0.5, "+z"),
    }
    frame = _cantilever(make_frame, (0, 0, -1), gauges=gauges)
    r = analyze_frame(frame, normal_load=p, traction_force=0.0, n_modes=1)
    tip = r.displacement("n1")
    assert tip[2] == pytest.approx(-p * length**3 / (3 * E * I_S), rel=1e-9)
    # A downward tip deflection of a cantilever along +x is a positive rotation about +y.
    assert tip[4] == pytest.approx(p * length**2 / (2 * E * I_S), rel=1e-9)
    # Hogging moment P L at the root: top fibre in tension (> 0), bottom in compression.
    root = p * length * (H_SEC / 2) / I_S
    assert r.gauge_stresses["root_top"] == pytest.approx(root, rel=1e-9)
    assert r.gauge_stresses["root_bottom"] == pytest.approx(-root, rel=1e-9)
    assert r.gauge_stresses["mid_top"] == pytest.approx(p * 1.5 * (H_SEC / 2) / I_S, rel=1e-9)
    # Per-newton coefficients and their units: Pa/N.
    assert r.gauges["root_top"].normal == pytest.approx(root / p, rel=1e-9)
    assert r.gauges["root_top"].traction == 0.0
    # Largest von Mises at the root: σ = P L (h/2 + 0)/I (corner) with the shear P/A_v.
    sigma = p * length * (H_SEC / 2) / I_S
    tau = p / A  # the properties-given section's shear area defaults to its area
    assert r.max_von_mises.value == pytest.approx(math.sqrt(sigma**2 + 3 * tau**2), rel=1e-9)
    assert (r.max_von_mises.member, r.max_von_mises.position) == ("m0", 0.0)
    # Member forces at the root (local axes; the sign follows M = E I κ).
    root_forces = r.member_forces["m0"].start
    assert abs(root_forces["M_strong"]) == pytest.approx(p * length, rel=1e-9)
    assert abs(root_forces["V_y"]) == pytest.approx(p, rel=1e-9)


def test_cantilever_weak_axis_lateral_load_and_axial_load(make_frame):
    f, length = 500.0, 2.0
    gauges = {"root_left": ("m0", 0.0, "+y"), "root_top": ("m0", 0.0, "+z")}
    frame = _cantilever(make_frame, (0, 0, 0), gauges=gauges)
    lateral = make_frame(
        {"root": (0, 0, 0), "n1": (2, 0, 0)},
        {"m0": ("root", "n1")},
        {"root": "fixed"},
        {"tip": ("n1", (1, 0, 0), (0, 1, 0))},
        gauges=gauges,
    )
    r = analyze_frame(lateral, normal_load=0.0, traction_force=f, n_modes=1)
    assert r.displacement("n1")[1] == pytest.approx(f * length**3 / (3 * E * I_W), rel=1e-9)
    # A tip load along +y bends the beam towards +y: the +y face at the root is in compression.
    assert r.gauge_stresses["root_left"] == pytest.approx(-f * length * (B_SEC / 2) / I_W, rel=1e-9)
    assert r.gauge_stresses["root_top"] == pytest.approx(0.0, abs=1e-6)
    # The normal pattern pulls along the axis: σ = N / A everywhere, tension positive.
    r = analyze_frame(lateral, normal_load=2000.0, traction_force=0.0, n_modes=1)
    assert r.gauge_stresses["root_top"] == pytest.approx(2000.0 / A, rel=1e-9)
    assert r.displacement("n1")[0] == pytest.approx(2000.0 * length / (E * A), rel=1e-9)
    assert frame.members["m0"].web == (0.0, 0.0, 1.0)


def test_web_direction_turns_the_section(make_frame):
    # Web along y: the vertical load now bends the weak axis.
    frame = _cantilever(make_frame, (0, 0, -1), web=(0, 1, 0))
    r = analyze_frame(frame, normal_load=1000.0, traction_force=0.0, n_modes=1)
    assert r.displacement("n1")[2] == pytest.approx(-1000.0 * 8 / (3 * E * I_W), rel=1e-9)


def test_l_shaped_cantilever_bending_and_torsion(make_frame):
    """Leg 1 along x (length a), leg 2 along y (length b), tip load P down at the end of leg
    2: δ = P b^3/(3 E I) + P a^3/(3 E I) + P b^2 a/(G J) (Castigliano; the first leg twists
    under the torque P b)."""
    a, b, p = 1.5, 1.0, 800.0
    frame = make_frame(
        {"root": (0, 0, 0), "corner": (a, 0, 0), "tip": (a, b, 0)},
        {"leg1": ("root", "corner"), "leg2": ("corner", "tip")},
        {"root": "fixed"},
        {"load": ("tip", (0, 0, -1), (0, 0, 0))},
    )
    r = analyze_frame(frame, normal_load=p, traction_force=0.0, n_modes=1)
    expected = p * b**3 / (3 * E * I_S) + p * a**3 / (3 * E * I_S) + p * b**2 * a / (G * J)
    assert r.displacement("tip")[2] == pytest.approx(-expected, rel=1e-9)
    forces = r.member_forces["leg1"].start
    assert abs(forces["T"]) == pytest.approx(p * b, rel=1e-9)
    # von Mises at leg 1's root: corner σ from M = P a (strong axis) + the shear P/A + P b/W_t
    # (W_t = J / (min(h, b)/2) for a section given by its properties).
    sigma = p * a * (H_SEC / 2) / I_S
    tau = p / A + p * b / (J / (B_SEC / 2))
    assert r.max_von_mises.value == pytest.approx(math.sqrt(sigma**2 + 3 * tau**2), rel=1e-9)


def _portal(make_frame, k, *, load, midspan=False, stiff_area=True):
    """Columns of height h at x = 0 and x = l (web along x: in-plane bending on the strong
    axis), beam between their tops with I_2 = k I_1 l / h; areas x 1e4 (no axial strain)."""
    h, span = 2.0, 3.0
    scale = 1e4 if stiff_area else 1.0
    col = {**IPE200, "area": {"value": 28.48 * scale, "unit": "cm^2", "source": "test"}}
    beam = {
        **IPE200,
        "area": {"value": 28.48 * scale, "unit": "cm^2", "source": "test"},
        "second_moment_strong": {"value": 1943.0 * k * span / h, "unit": "cm^4", "source": "test"},
    }
    nodes = {"a": (0, 0, 0), "b": (0, 0, h), "c": (span, 0, h), "d": (span, 0, 0)}
    members = {"col_left": ("a", "b", "col"), "col_right": ("d", "c", "col")}
    if midspan:
        nodes["m"] = (span / 2, 0, h)
        members |= {"beam_left": ("b", "m", "beam"), "beam_right": ("m", "c", "beam")}
    else:
        members["beam"] = ("b", "c", "beam")
    gauges = {"mid_bottom": ("beam_left", span / 2, "-z")} if midspan else None
    frame = make_frame(
        nodes,
        members,
        {"a": "fixed", "d": "fixed"},
        {"p": load},
        sections={"col": col, "beam": beam},
        gauges=gauges,
    )
    return frame, h, span


@pytest.mark.parametrize("k", [1.0, 0.25, 1e4])
def test_fixed_base_portal_under_sway(make_frame, k):
    """Kleinlogel frame I (fixed feet), horizontal load H at the girder: with
    k = I2 h / (I1 l), sway Δ = H h^3 (3k + 2) / (12 E I1 (6k + 1)) and base moment
    M_A = H h (3k + 1) / (2 (6k + 1)). Limits: k -> ∞, two guided fixed-fixed columns
    (H h^3 / (24 E I)); k -> 0, two cantilevers (H h^3 / (6 E I))."""
    force = 10e3
    frame, h, _ = _portal(make_frame, k, load=("b", (0, 0, 0), (1, 0, 0)))
    r = analyze_frame(frame, normal_load=0.0, traction_force=force, n_modes=1)
    sway = force * h**3 * (3 * k + 2) / (12 * E * I_S * (6 * k + 1))
    assert r.displacement("b")[0] == pytest.approx(sway, rel=2e-4)
    assert r.displacement("c")[0] == pytest.approx(sway, rel=2e-4)
    base = force * h * (3 * k + 1) / (2 * (6 * k + 1))
    assert abs(r.member_forces["col_left"].start["M_strong"]) == pytest.approx(base, rel=2e-4)
    assert abs(r.member_forces["col_right"].start["M_strong"]) == pytest.approx(base, rel=2e-4)
    # The top deflection is the largest horizontal displacement of the highest nodes.
    assert r.top_horizontal_deflection == pytest.approx(sway, rel=2e-4)


@pytest.mark.parametrize("k", [1.0, 3.0])
def test_fixed_base_portal_under_a_midspan_load(make_frame, k):
    """Symmetric load P at mid-span (slope-deflection, = Kleinlogel frame I): corner moment
    M_B = P l / (4 (k + 2)), base moment M_A = M_B / 2, mid-span moment P l / 4 - M_B,
    mid-span deflection P l^3/(48 E I2) - M_B l^2/(8 E I2)."""
    p = 20e3
    frame, h, span = _portal(make_frame, k, load=("m", (0, 0, -1), (0, 0, 0)), midspan=True)
    r = analyze_frame(frame, normal_load=p, traction_force=0.0, n_modes=1)
    i2 = I_S * k * span / h
    corner = p * span / (4 * (k + 2))
    assert abs(r.member_forces["col_left"].end["M_strong"]) == pytest.approx(corner, rel=2e-4)
    assert abs(r.member_forces["col_left"].start["M_strong"]) == pytest.approx(corner / 2, rel=2e-4)
    deflection = p * span**3 / (48 * E * i2) - corner * span**2 / (8 * E * i2)
    assert r.displacement("m")[2] == pytest.approx(-deflection, rel=2e-4)
    # Sagging at mid-span: the bottom fibre in tension.
    mid = p * span / 4 - corner
    assert r.gauge_stresses["mid_bottom"] == pytest.approx(mid * (H_SEC / 2) / i2, rel=2e-4)
    assert r.displacement("m")[0] == pytest.approx(0.0, abs=1e-12)  # symmetric: no sway


def test_cantilever_with_tip_mass_rayleigh(make_frame):
    length = 1.5
    m_beam = RHO * A * length
    tip = 5.0 * m_beam
    frame = _cantilever(make_frame, (0, 0, 0), length=length, masses={"tip": ("n1", tip)})
    r = analyze_frame(frame, normal_load=0.0, traction_force=0.0, n_modes=4)

    def rayleigh(i):
        return math.sqrt(3 * E * i / (length**3 * (tip + 0.2357 * m_beam))) / (2 * math.pi)

    # The first mode bends the weak axis, the second the strong axis.
    assert r.frequencies[0] == pytest.approx(rayleigh(I_W), rel=3e-3)
    assert r.frequencies[1] == pytest.approx(rayleigh(I_S), rel=3e-3)
    assert r.frame_mass == pytest.approx(m_beam + tip, rel=1e-12)
    shape = r.mode_shapes[0][r.nodes.index("n1")]
    assert abs(shape[1]) > 10 * max(abs(shape[0]), abs(shape[2]))  # lateral (y) bending


def test_cantilever_own_bending_and_torsion_frequencies(make_frame):
    """No tip mass: bending λ1 = 1.87510 (Blevins Table 8-1), f = λ² / (2π L²) sqrt(E I /
    (ρ A)); torsion of a fixed-free bar, f = sqrt(G J / (ρ I_p)) / (4 L) (St Venant; the rotary
    inertia is the polar moment, not J)."""
    length = 2.0
    frame = _cantilever(make_frame, (0, 0, 0), length=length)
    r = analyze_frame(frame, 0.0, 0.0, n_modes=6, elements_per_member=8)
    bending = 1.87510**2 / (2 * math.pi * length**2) * math.sqrt(E * I_W / (RHO * A))
    assert r.frequencies[0] == pytest.approx(bending, rel=1e-3)
    torsion = math.sqrt(G * J / (RHO * (I_S + I_W))) / (4 * length)
    assert np.min(np.abs(r.frequencies / torsion - 1)) < 5e-3


def test_contact_stiffness_is_the_work_conjugate_flexibility(make_frame):
    """A unit traction pattern at a cantilever tip: k = 3 E I / L^3; one dominant mode."""
    length, tip = 2.0, 200.0
    frame = make_frame(
        {"root": (0, 0, 0), "n1": (0, 0, length)},
        {"col": ("root", "n1")},
        {"root": "fixed"},
        {"wheel": ("n1", (0, 0, 0), (-1, 0, 0))},
        masses={"m": ("n1", tip)},
    )
    r = analyze_frame(frame, 0.0, 1000.0, n_modes=4)
    k = 3 * E * I_S / length**3  # the column's web is along x: strong axis
    assert r.longitudinal_stiffness_at_contact == pytest.approx(k, rel=1e-9)
    dof = contact_dof(r)
    assert dof.stiffness == pytest.approx(k, rel=1e-9)
    m_beam = RHO * A * length
    # The mode in x: Rayleigh's mass at the tip, M + 0.2357 m (a 0.2 % approximation here).
    assert dof.modal_mass == pytest.approx(tip + 0.2357 * m_beam, rel=5e-3)
    assert dof.participation == pytest.approx(1.0, abs=0.01)
    assert dof.equivalent_mass == pytest.approx(k / (2 * math.pi * dof.frequency) ** 2)
    assert dof.modal_stiffness >= dof.stiffness * 0.999
    # The traction pattern pushes the tip towards -x: the conjugate displacement is positive.
    assert r.displacement("n1")[0] < 0 < r.contact_flexibility


def test_test_loads_superpose(make_frame):
    frame = _cantilever(make_frame, (0, 0, -1), gauges={"g": ("m0", 0.0, "+z")})
    frame_t = make_frame(
        {"root": (0, 0, 0), "n1": (2, 0, 0)},
        {"m0": ("root", "n1")},
        {"root": "fixed"},
        {"tip": ("n1", (0, 0, -1), (1, 0, 0))},
        gauges={"g": ("m0", 0.0, "+z")},
    )
    both = analyze_frame(frame_t, 3000.0, 500.0, n_modes=1)
    only_n = analyze_frame(frame, 3000.0, 0.0, n_modes=1)
    assert both.gauge_stresses["g"] == pytest.approx(
        only_n.gauge_stresses["g"] + 500.0 / A, rel=1e-9
    )


def test_default_frame_is_as_firm_as_the_dissertation_found():
    """Kayaalp 4.4.3: the top of the frame moves about 0.04 mm under 20 kN + 2 kN (SolidWorks,
    real dimensions); the bundled frame's dimensions are assumptions, so only the order of
    magnitude is pinned: between a quarter and four times that."""
    from rollerrig.frame import default_frame

    r = analyze_frame(default_frame(), 20e3, 2e3, n_modes=6)
    assert 0.01e-3 < r.top_horizontal_deflection < 0.16e-3
    assert np.all(np.diff(r.frequencies) > 0) and r.frequencies[0] > 5.0
    dof = contact_dof(r)
    # The longitudinal (x) sway of the frame carries most of the contact's flexibility.
    shape = r.mode_shapes[dof.mode][r.nodes.index("pivot_left")]
    assert abs(shape[0]) > 5 * abs(shape[1])
    assert 0.5 < dof.participation <= 1.0
    # Low stresses (Kayaalp 4.4.3: 'quite low even for the most stressed places').
    assert r.max_von_mises.value < 50e6
    assert r.gauge_stresses["top_beam"] > 0  # the air spring bends the top beam upwards


def test_sparse_eigensolvers_agree_with_dense_lapack(monkeypatch):
    """The stability check and the modes are solved sparse (ARPACK shift-invert) above
    ``_DENSE_BELOW`` free DOFs: on the bundled frame (~700 DOFs) they agree with LAPACK's dense
    solution of the same matrices, and a frame that size on rollers is still a mechanism."""
    from rollerrig.frame import default_frame, modes

    frame = default_frame()
    sparse = analyze_frame(frame, 20e3, 2e3, n_modes=6)
    monkeypatch.setattr(modes, "_DENSE_BELOW", 10**9)
    dense = analyze_frame(frame, 20e3, 2e3, n_modes=6)
    np.testing.assert_allclose(sparse.frequencies, dense.frequencies, rtol=1e-7)
    np.testing.assert_allclose(sparse.mode_shapes, dense.mode_shapes, atol=1e-6)
    monkeypatch.setattr(modes, "_DENSE_BELOW", 0)
    rolling = dataclasses.replace(
        frame, supports={n: (False, False, True, False, False, False) for n in frame.supports}
    )
    with pytest.raises(FrameFileError, match="the frame is a mechanism"):
        analyze_frame(rolling, 1.0, 1.0, n_modes=1)


@pytest.mark.parametrize(
    ("kw", "message"),
    [
        ({"normal_load": 1e300}, "normal_load must be finite and at most 1e+07 N"),
        ({"traction_force": -math.inf}, "traction_force must be finite"),
        ({"elements_per_member": 0}, "elements_per_member must be in [1, 64]"),
        ({"elements_per_member": 64}, "more than the 800 elements the analysis takes"),
    ],
)
def test_absurd_analysis_arguments_never_reach_the_solver(kw, message):
    from rollerrig.frame import default_frame

    with pytest.raises(ParameterError) as info:
        analyze_frame(default_frame(), **kw)
    assert message in str(info.value)


def test_no_traction_pattern_is_one_clear_error(make_frame):
    """Load points with traction [0, 0, 0] everywhere give no contact coordinate: a clear
    error, not a division by zero (found with a 200-member frame file, issue 24)."""
    frame = make_frame(
        {"a": (0, 0, 0), "b": (0, 0, 2)},
        {"col": ("a", "b")},
        {"a": "fixed"},
        {"p": ("b", (0, 0, -1), (0, 0, 0))},
    )
    r = analyze_frame(frame, 1e3, 0.0, n_modes=2)
    with pytest.raises(FrameFileError, match="every load point's traction is"):
        contact_dof(r)


@pytest.mark.parametrize(
    ("kw", "message"),
    [
        ({"n_modes": 0}, "n_modes must be a whole number >= 1 [-], got 0"),
        ({"n_modes": -3}, "n_modes must be a whole number >= 1 [-], got -3"),
        ({"n_modes": 2.5}, "n_modes must be a whole number >= 1 [-], got 2.5"),
        ({"n_modes": "3"}, "n_modes must be a whole number >= 1 [-], got '3'"),
        ({"n_modes": math.nan}, "n_modes must be a whole number >= 1 [-], got nan"),
        ({"elements_per_member": 2.5}, "elements_per_member must be a whole number in [1, 64]"),
        ({"elements_per_member": True}, "elements_per_member must be in [1, 64], got True"),
        ({"elements_per_member": None}, "elements_per_member must be in [1, 64], got None"),
        ({"normal_load": "a"}, "normal_load must be a single number [N], got 'a'"),
        ({"normal_load": None}, "normal_load must be finite [N], got nan"),
        ({"traction_force": [1.0, 2.0]}, "traction_force must be a single number [N], got [1.0"),
    ],
)
def test_counts_and_loads_of_wrong_kind_are_refused(kw, message):
    """n_modes 0, -3, 2.5 and "3" and elements_per_member 2.5 and True ran an analysis
    silently (0 modes became 1); NaN, None, text and lists were bare exceptions."""
    from rollerrig.frame import default_frame

    with pytest.raises(ParameterError, match=re.escape(message)):
        analyze_frame(default_frame(), **kw)


def test_displacement_of_an_unknown_node_names_the_nodes():
    """A bare ValueError "'top_rear_lft' is not in list" before."""
    from rollerrig.frame import default_frame

    r = analyze_frame(default_frame(), n_modes=1)
    with pytest.raises(
        ParameterError,
        match=re.escape(
            "node 'top_rear_lft' is not a node of the frame (did you mean 'top_rear_left'?)"
        ),
    ):
        r.displacement("top_rear_lft")


@pytest.mark.parametrize("n_modes", [1, 2, 3, 6])
def test_the_contacts_dominant_mode_is_the_same_whatever_modes_are_asked_for(n_modes):
    """Review: with 2 modes asked for, contact_dof named mode 2 (37.8 Hz, 8.5e6 kg, share
    0.0002) where 6 gave mode 4 (48.1 Hz, 1551 kg, share 0.71). analyze_frame now computes
    modes until they establish the dominant one, and returns them all."""
    from rollerrig.frame import default_frame

    r = analyze_frame(default_frame(), 20e3, 2e3, n_modes=n_modes)
    assert len(r.frequencies) >= max(n_modes, 4)
    dof = contact_dof(r)
    assert dof.mode == 3
    assert dof.frequency == pytest.approx(48.12, abs=0.01)
    assert dof.modal_mass == pytest.approx(1551.0, rel=1e-3)
    assert dof.participation == pytest.approx(0.7098, abs=1e-3)


def test_too_few_modes_to_establish_the_dominant_one_is_an_error_not_a_wrong_mode():
    """A result cut to its first two modes (a FrameResult built by hand, or too few modes
    computed): they carry 0.02 % of the contact's flexibility, so any mode above them may carry
    more; contact_dof says so rather than naming mode 2."""
    from rollerrig.frame import default_frame
    from rollerrig.frame.reduction import contact_shares, dominant_is_established

    r = analyze_frame(default_frame(), 20e3, 2e3, n_modes=6)
    cut = dataclasses.replace(
        r,
        frequencies=r.frequencies[:2],
        mode_shapes=r.mode_shapes[:2],
        contact_participation=r.contact_participation[:2],
    )
    with pytest.raises(ParameterError, match=r"dominant mode is not established: the 2 modes"):
        contact_dof(cut)
    shares = contact_shares(r.frequencies, r.contact_participation, r.contact_flexibility)
    assert dominant_is_established(shares) and not dominant_is_established(shares[:3])
    assert dominant_is_established(shares[:4])  # mode 4: 71 %, the rest at most 29 %


def test_the_shares_of_every_mode_sum_to_one(make_frame):
    """The modal expansion K⁻¹ = Σ φ φᵀ / ω² over all the modes: the shares sum to 1, which is
    what lets the modes left out be bounded."""
    from rollerrig.frame.reduction import contact_shares

    frame = make_frame(
        {"root": (0, 0, 0), "n1": (1, 0, 0), "n2": (2, 0, 0)},
        {"m0": ("root", "n1"), "m1": ("n1", "n2")},
        {"root": "fixed"},
        {"tip": ("n2", (0, 0, 0), (1.0, 0.3, -0.5))},
    )
    r = analyze_frame(frame, 0.0, 1.0, n_modes=1000, elements_per_member=2)
    assert len(r.frequencies) == 6 * 4  # every free DOF of 4 nodes
    shares = contact_shares(r.frequencies, r.contact_participation, r.contact_flexibility)
    assert np.sum(shares) == pytest.approx(1.0, rel=1e-9)
