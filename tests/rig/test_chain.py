"""Torsional chain: assembly, invariants and modes against closed forms and opentorsion.

References: the two-inertia and single-inertia closed forms (e.g. Rao, *Mechanical
Vibrations*, 5th ed., §6.4 and §2.6); the 13.8 Hz roller-shaft mode and the b01/J1 pole near
−3.3e4 1/s of DESIGN.md §3; the independent eigen-solver of the `opentorsion` package
(v0.3, Assembly.undamped_modal_analysis / modal_analysis).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rollerrig._validation import ParameterError
from rollerrig.rig.chain import (
    BODY_NAMES,
    assemble_chain,
    chain_matrices,
    contact_damping_matrix,
    damper_matrix,
    format_modal_table,
    modal_analysis,
    modal_table,
)
from rollerrig.rig.parameters import default_rig

RIG = default_rig()
J = [3.0, 0.95, 5.1, 11.6, 45.0, 6.6, 35.0]  # Kayaalp 4.5.1.5, J1..J7 [kg.m^2]


# ---- assembly and invariants --------------------------------------------------------------


def test_matrices_have_the_expected_pattern():
    M, K, C = chain_matrices(RIG)
    assert np.array_equal(M, np.diag(J))
    k01, k23, k34, k56, k70 = 5e5, 3.85e5, 3.70e5, 43.5e3, 5e5
    expected = np.zeros((7, 7))
    expected[0, 0] = k01
    expected[1:4, 1:4] = [[k23, -k23, 0], [-k23, k23 + k34, -k34], [0, -k34, k34]]
    expected[4:6, 4:6] = [[k56, -k56], [-k56, k56]]
    expected[6, 6] = k70
    assert np.array_equal(K, expected)
    # No coupling across the air gaps (1-2, 6-7) nor across the contact (4-5).
    for a, b in ((0, 1), (5, 6), (3, 4)):
        assert K[a, b] == K[b, a] == C[a, b] == C[b, a] == 0.0


def test_invariants_symmetry_definiteness_nullity():
    M, K, C = chain_matrices(RIG)
    assert np.array_equal(K, K.T)
    assert np.array_equal(C, C.T)
    assert np.all(np.linalg.eigvalsh(M) > 0)
    eig_k = np.linalg.eigvalsh(K)
    assert np.all(eig_k > -1e-9 * eig_k.max())
    eig_c = np.linalg.eigvalsh(C)
    assert np.all(eig_c > -1e-9 * eig_c.max())
    # Subchains not tied to ground, counted by hand from the topology: {2,3,4} (PMSM rotor,
    # wheel disc, tyre) and {5,6} (roller, AM rotor) -> nullity 2.
    assert 7 - np.linalg.matrix_rank(K) == 2
    result = modal_analysis(M, K)
    assert result.n_rigid == 2
    # The rigid modes are the (mass-normalised) indicator vectors of the two floating subchains.
    rigid_shapes = result.mode_shapes[:, result.rigid]
    supports = sorted(tuple(np.flatnonzero(np.abs(v) > 1e-12)) for v in rigid_shapes.T)
    assert supports == [(1, 2, 3), (4, 5)]
    np.testing.assert_allclose(K @ rigid_shapes, 0.0, atol=1e-9)


def test_mode_shapes_are_mass_normalised():
    M, K, C = chain_matrices(RIG)
    result = modal_analysis(M, K, C)
    phi = result.mode_shapes
    np.testing.assert_allclose(phi.T @ M @ phi, np.eye(7), atol=1e-12)
    omega2 = (2 * np.pi * result.natural_frequencies) ** 2
    np.testing.assert_allclose(phi.T @ K @ phi, np.diag(omega2), atol=1e-6 * omega2.max())


@settings(max_examples=40, deadline=None)
@given(
    inertias=st.lists(st.floats(0.1, 100.0), min_size=2, max_size=8),
    data=st.data(),
)
def test_random_chains_invariants(inertias, data):
    n = len(inertias)
    elements = []
    for _ in range(data.draw(st.integers(0, 2 * n))):
        i = data.draw(st.integers(0, n))
        j = data.draw(st.integers(0, n).filter(lambda v, i=i: v != i))
        elements.append((i, j, data.draw(st.floats(1.0, 1e6)), data.draw(st.floats(0.0, 1e3))))
    M, K, C = assemble_chain(inertias, elements)
    assert np.array_equal(K, K.T) and np.array_equal(C, C.T)
    # Rigid modes = connected components of the body graph that touch no ground element.
    parent = list(range(n + 1))

    def find(a):
        while parent[a] != a:
            a = parent[a]
        return a

    for i, j, _, _ in elements:
        parent[find(i)] = find(j)
    floating = {find(b) for b in range(1, n + 1)} - {find(0)}
    result = modal_analysis(M, K, C)
    assert result.n_rigid == len(floating)
    assert np.all(result.natural_frequencies >= 0.0)
    assert np.all(np.diff(result.natural_frequencies) >= 0.0)
    # Every pole of a passive chain lies in the closed left half-plane.
    assert np.all(result.poles.real <= 1e-6 * max(1.0, np.abs(result.poles).max()))


def test_assemble_chain_rejects_bad_input():
    with pytest.raises(ParameterError, match="inertias"):
        assemble_chain([1.0, -1.0], [])
    with pytest.raises(ParameterError, match="elements\\[0\\]"):
        assemble_chain([1.0], [(0, 2, 1.0, 0.0)])
    with pytest.raises(ParameterError, match="itself"):
        assemble_chain([1.0], [(1, 1, 1.0, 0.0)])
    with pytest.raises(ParameterError, match="stiffness"):
        assemble_chain([1.0], [(0, 1, -1.0, 0.0)])


def test_modal_analysis_rejects_bad_matrices():
    M, K, _ = chain_matrices(RIG)
    with pytest.raises(ParameterError, match="K"):
        modal_analysis(M, K + np.triu(np.ones((7, 7)), 1))
    with pytest.raises(ParameterError, match="positive definite"):
        modal_analysis(M - np.diag([3.0, 0, 0, 0, 0, 0, 0]), K)
    with pytest.raises(ParameterError, match="shape"):
        modal_analysis(M, K[:6, :6])


# ---- frequencies against closed forms and opentorsion ---------------------------------------


def test_roller_shaft_mode_two_inertia_closed_form():
    # f = (1/2π)·sqrt(k56 (J5 + J6)/(J5 J6)) (two inertias on a free shaft); DESIGN.md §3
    # "near 13.8 Hz".
    k56, j5, j6 = 43.5e3, 45.0, 6.6
    f_closed = math.sqrt(k56 * (j5 + j6) / (j5 * j6)) / (2 * math.pi)
    assert f_closed == pytest.approx(13.836, abs=1e-3)
    M, K, C = chain_matrices(RIG)
    result = modal_analysis(M, K, C)
    i = int(np.argmin(np.abs(result.natural_frequencies - f_closed)))
    assert result.natural_frequencies[i] == pytest.approx(f_closed, rel=1e-12)
    # Lightly damped: ζ = b56 / (2 sqrt(k56 J_eff)), J_eff = J5 J6/(J5 + J6).
    j_eff = j5 * j6 / (j5 + j6)
    zeta = 1.0 / (2 * math.sqrt(k56 * j_eff))
    assert result.damping_ratios[i] == pytest.approx(zeta, rel=1e-9)
    assert result.damped_frequencies[i] == pytest.approx(f_closed * math.sqrt(1 - zeta**2))


def test_grounded_mounts_single_inertia_closed_form():
    # Body 1 and body 7 hang on their mounts alone: f = (1/2π) sqrt(k/J).
    M, K, _ = chain_matrices(RIG)
    f = modal_analysis(M, K).natural_frequencies
    for k, j in ((5e5, 3.0), (5e5, 35.0)):
        target = math.sqrt(k / j) / (2 * math.pi)
        assert np.min(np.abs(f - target)) < 1e-9 * target


def _opentorsion_assembly():
    ot = pytest.importorskip("opentorsion")
    # Nodes 0..6 are bodies 1..7. opentorsion's Disk carries a stiffness and damping to
    # ground (Disk(node, I, c, k)), so the grounded mounts k01, k70 need no "huge ground
    # inertia"; its Shafts with given k (and I=0) are the massless springs k23, k34, k56.
    disks = [ot.Disk(0, J[0], c=1e5, k=5e5)]
    disks += [ot.Disk(node, J[node]) for node in range(1, 6)]
    disks += [ot.Disk(6, J[6], c=1e5, k=5e5)]
    shafts = [
        ot.Shaft(1, 2, k=3.85e5, c=1.0),
        ot.Shaft(2, 3, k=3.70e5, c=1e3),
        ot.Shaft(4, 5, k=43.5e3, c=1.0),
    ]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return ot.Assembly(shafts, disk_elements=disks)


def test_undamped_frequencies_match_opentorsion():
    assembly = _opentorsion_assembly()
    M, K, _ = chain_matrices(RIG)
    np.testing.assert_array_equal(assembly.M, M)
    lam, _ = assembly.undamped_modal_analysis()  # scipy.linalg.eig(K, M): ω²
    f_ot = np.sort(np.sqrt(np.abs(lam.real))) / (2 * np.pi)
    ours = modal_analysis(M, K).natural_frequencies
    nonzero = ours > 0
    assert nonzero.sum() == 5
    np.testing.assert_allclose(ours[nonzero], f_ot[nonzero], rtol=1e-9)
    # Reference numbers of this comparison [Hz]: 13.836, 19.023, 47.856, 64.975, 111.951.
    np.testing.assert_allclose(ours[nonzero], [13.836, 19.023, 47.856, 64.975, 111.951], atol=1e-3)


def test_damped_poles_match_opentorsion():
    assembly = _opentorsion_assembly()
    M, K, C = chain_matrices(RIG)
    np.testing.assert_array_equal(assembly.C, C)
    wn_ot, _, _ = assembly.modal_analysis()  # |λ| of its own state matrix, sorted
    ours = modal_analysis(M, K, C).poles
    big = np.sort(np.abs(ours))[4:]  # skip the four (numerically ~0) rigid-mode poles
    np.testing.assert_allclose(big, np.sort(wn_ot)[4:], rtol=1e-7)


def test_mount_damping_pole_near_minus_3_3e4():
    # DESIGN.md §3: b01 = 1e5 on J1 = 3 gives a pole near −3.3e4 1/s. Body 1 is decoupled
    # (air gap), so its poles are the roots of J1 s² + b01 s + k01 = 0.
    b01, j1, k01 = 1e5, 3.0, 5e5
    fast = (-b01 - math.sqrt(b01**2 - 4 * j1 * k01)) / (2 * j1)
    slow = (-b01 + math.sqrt(b01**2 - 4 * j1 * k01)) / (2 * j1)
    assert fast == pytest.approx(-3.33e4, rel=2e-3)
    M, K, C = chain_matrices(RIG)
    result = modal_analysis(M, K, C)
    assert np.min(result.poles.real) == pytest.approx(fast, rel=1e-9)
    mode = int(np.argmin(np.abs(result.natural_frequencies - math.sqrt(k01 / j1) / (2 * math.pi))))
    np.testing.assert_allclose(np.sort(result.mode_poles[mode].real), [fast, slow], rtol=1e-9)
    assert result.damping_ratios[mode] == pytest.approx(b01 / (2 * math.sqrt(k01 * j1)))
    assert result.damped_frequencies[mode] == 0.0  # overdamped


# ---- extra damping at an operating point ----------------------------------------------------


def test_contact_damping_couples_wheel_and_roller():
    r_w, r_r, d = 0.348, 0.452, 2.0e4
    Cc = contact_damping_matrix(d, r_w, r_r)
    assert np.array_equal(Cc, Cc.T)
    # Zero relative slip velocity r_w ω4 = r_r ω5 gives no torque.
    omega = np.zeros(7)
    omega[3], omega[4] = 1.0 / r_w, 1.0 / r_r
    np.testing.assert_allclose(Cc @ omega, 0.0, atol=1e-9)
    M, K, C = chain_matrices(RIG)
    coupled = modal_analysis(M, K, C, extra_damping=Cc)
    # The contact damps one of the two rigid modes (a real pole), the other stays at zero.
    rigid_poles = coupled.mode_poles[coupled.rigid]
    assert np.sum(np.abs(rigid_poles) > 1e-3) == 1
    assert np.all(coupled.poles.real <= 1e-9)


def test_damper_matrix_on_am_air_gap():
    # Linearised AM slip damping between rotor (6) and stator (7) ties {5,6} to ground: the
    # remaining rigid mode of that subchain gets a finite real pole -c/(J5 + J6) (slowly
    # varying limit, stiff shaft and stiff mount).
    c = 50.0
    Cm = damper_matrix(7, 6, 7, c)
    assert Cm[5, 5] == Cm[6, 6] == c and Cm[5, 6] == Cm[6, 5] == -c
    M, K, C = chain_matrices(RIG)
    result = modal_analysis(M, K, C, extra_damping=Cm)
    slow = result.poles[np.abs(result.poles) > 1e-3]
    slow = slow[np.argmin(np.abs(slow))]
    assert slow.real == pytest.approx(-c / (45.0 + 6.6), rel=0.02)


# ---- table ----------------------------------------------------------------------------------


def test_modal_table_rows():
    rows = modal_table(RIG)
    assert [r.mode for r in rows] == list(range(1, 8))
    assert [r.rigid for r in rows] == [True, True] + [False] * 5
    by_element = {r.dominant_element: r for r in rows if not r.rigid}
    assert set(by_element) == {
        "roller_shaft",
        "am_mount",
        "wheel_rubber",
        "pmsm_mount",
        "wheel_shaft",
    }
    shaft = by_element["roller_shaft"]
    assert shaft.frequency == pytest.approx(13.836, abs=1e-3)
    assert set(shaft.dominant_bodies) == {"roller", "am_rotor"}
    # Kinetic energy splits J5 φ5² : J6 φ6² = J6 : J5 in a two-inertia mode.
    assert shaft.kinetic_energy["am_rotor"] / shaft.kinetic_energy["roller"] == pytest.approx(
        45.0 / 6.6
    )
    assert sum(shaft.kinetic_energy.values()) == pytest.approx(1.0)
    assert set(shaft.kinetic_energy) == set(BODY_NAMES)
    text = format_modal_table(rows)
    assert "roller_shaft" in text and len(text.splitlines()) == 8


def test_stiffer_shaft_raises_the_mode():
    # Kayaalp 4.5.1.7 sweeps k56 upward from 43.5 kN.m/rad in 20 kN.m/rad steps.
    previous = 0.0
    for k56 in (43.5e3, 63.5e3, 83.5e3):
        rig = RIG.with_overrides({"stiffness.roller_shaft": k56})
        f = next(r.frequency for r in modal_table(rig) if r.dominant_element == "roller_shaft")
        assert f == pytest.approx(math.sqrt(k56 * (45 + 6.6) / (45 * 6.6)) / (2 * math.pi))
        assert f > previous
        previous = f


def test_a_huge_inertia_leaves_the_shaft_mode_of_the_other_body():
    """A roller of 1e20 kg.m^2 (a wall): the motor rotor rings on the roller shaft alone, ζ =
    b56 / (2 sqrt(k56 J6)) and f = sqrt(k56/J6)/2π (single-DOF closed form). The QZ algorithm
    on the pencil with M in it gave infinite poles and NaN damping for every elastic mode."""
    k56, b56, j6 = 43.5e3, 1.0, 6.6
    rig = RIG.with_overrides({"inertia.roller": 1e20})
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no RuntimeWarning either
        rows = modal_table(rig)
    (shaft,) = [r for r in rows if r.dominant_element == "roller_shaft"]
    assert shaft.frequency == pytest.approx(math.sqrt(k56 / j6) / (2 * math.pi), rel=1e-9)
    assert shaft.damping_ratio == pytest.approx(b56 / (2 * math.sqrt(k56 * j6)), rel=1e-6)
    assert all(np.isfinite(r.damping_ratio) for r in rows if not r.rigid)


def test_a_tiny_inertia_keeps_the_other_modes_and_says_what_it_cannot_resolve():
    """A PMSM stator of tiny inertia J1 on its mount: a pole at about −b01/J1 beside the
    chain's. At 1e-10 kg.m^2 its damping is the one-body closed form b01/(2 sqrt(k01 J1))
    within 2 % and the other modes keep theirs (each mode's poles judged zero against its own
    frequency and the eigenvalues' rounding, not against that pole: every damping was NaN).
    At 3e-12 and 1e-13 kg.m^2 the mount's slow pole is lost in the rounding (computed −4 and
    −128 1/s, exact −5): no damping is printed that is off by more than 10 %; n/a instead,
    with the reason."""
    k01, b01 = 5e5, 1e5
    reference = {r.dominant_element: r for r in modal_table(RIG)}
    for inertia in (1e-10, 3e-12, 1e-13):
        rig = RIG.with_overrides({"inertia.pmsm_stator": inertia})
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # no RuntimeWarning either
            rows = modal_table(rig)
        for r in rows:
            if r.rigid or not np.isfinite(r.damping_ratio):
                continue
            if r.dominant_element == "pmsm_mount":
                want = b01 / (2 * math.sqrt(k01 * inertia))
                assert inertia == 1e-10 and r.damping_ratio == pytest.approx(want, rel=0.02)
            else:
                want = reference[r.dominant_element].damping_ratio
                assert r.damping_ratio == pytest.approx(want, rel=0.1)
        text = format_modal_table(rows)
        assert " nan" not in text
        assert ("n/a" in text and "double precision" in text) == (inertia < 1e-10)


@settings(max_examples=60, deadline=None)
@given(n=st.integers(1, 12), seed=st.integers(0, 2**32 - 1), density=st.floats(0.0, 0.6))
def test_component_labels_match_scipy_csgraph(n, seed, density):
    # Reference: scipy.sparse.csgraph.connected_components (undirected), which the chain no
    # longer imports; the same partition (labels may be numbered differently).
    from scipy.sparse.csgraph import connected_components

    from rollerrig.rig.chain import _component_labels

    rng = np.random.default_rng(seed)
    upper = np.triu(rng.uniform(size=(n, n)) < density, 1)
    adjacency = upper | upper.T
    ours = _component_labels(adjacency)
    count, theirs = connected_components(adjacency, directed=False)
    assert len(np.unique(ours)) == count
    same_ours = ours[:, None] == ours[None, :]
    same_theirs = theirs[:, None] == theirs[None, :]
    assert np.array_equal(same_ours, same_theirs)


def test_contact_and_damper_matrices_refuse_counts_that_are_not_whole():
    import re

    from rollerrig.rig.chain import contact_damping_matrix, damper_matrix

    with pytest.raises(ParameterError, match=re.escape("n_bodies must be a whole number")):
        contact_damping_matrix(1.0, 0.3, 0.3, n_bodies=7.5)
    with pytest.raises(ParameterError, match=re.escape("n_bodies must be a whole number")):
        contact_damping_matrix(1.0, 0.3, 0.3, n_bodies=10**6)
    with pytest.raises(ParameterError, match=re.escape("wheel_body must be a whole number")):
        contact_damping_matrix(1.0, 0.3, 0.3, wheel_body=4.5)
    with pytest.raises(ParameterError, match=re.escape("roller_body must be a whole number")):
        contact_damping_matrix(1.0, 0.3, 0.3, roller_body="a")
    with pytest.raises(ParameterError, match=re.escape("n_bodies must be a whole number")):
        damper_matrix(2.5, 0, 1, 1.0)


def test_modal_table_and_analysis_refuse_a_nan_threshold():
    import re

    from rollerrig.rig.chain import modal_analysis, modal_table

    with pytest.raises(ParameterError, match=re.escape("threshold must be finite [-]")):
        modal_table(default_rig(), threshold=float("nan"))
    for bad in (2.0, -1.0):
        with pytest.raises(ParameterError, match=re.escape("threshold must lie in [0, 1] [-]")):
            modal_table(default_rig(), threshold=bad)
    with pytest.raises(ParameterError, match=re.escape("rigid_tolerance must be finite")):
        modal_analysis(np.eye(2), np.eye(2), rigid_tolerance=float("nan"))
