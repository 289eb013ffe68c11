"""Creep laws by name, friction parameter sets with sources, and the optional CONTACT backend."""

import numpy as np
import pytest

from rollerrig._validation import ParameterError
from rollerrig.contact import POLACH_DRY, POLACH_WET, polach_creep_curve, polach_creep_force
from rollerrig.contact.cntc import ContactNotAvailable, contact_dir, exact_creep_force, load_contact
from rollerrig.contact.laws import (
    CREEP_LAWS,
    EUROSPRINTER_MODIFIED_FASTSIM,
    FRICTION_PARAMETER_SETS,
    FastsimParameters,
    check_law,
    creep_force,
    default_parameter_sets,
    law_creep_curve,
    parameter_set,
)

GEOM = (4300.0, 3.4e-3, 2.7e-3, 8.08e10, 0.3)  # N, a, b, G, nu


def test_every_set_has_a_source_and_the_polach_sets_are_the_packages():
    assert parameter_set("polach-dry") is POLACH_DRY
    assert parameter_set("polach-wet") is POLACH_WET
    for name, p in FRICTION_PARAMETER_SETS.items():
        assert p.source, name


def test_eurosprinter_modified_fastsim_set_is_contacts():
    # CONTACT tractcurv.inp, series 4: "0.540 0.020 0.620  K0_MF,ALFAMF,BETAMF" and
    # "0.1368 0.2232 990.  FKIN, FEXP1, SABSH1" = mu0 0.36, A 0.38, B ln2/0.990 ~ 0.7 s/m
    # (user guide: "mu_stat = 0.36, A = 0.38, B = 0.7").
    p = parameter_set("eurosprinter-modified-fastsim")
    assert (p.k0, p.alpha_inf, p.beta) == (0.54, 0.02, 0.62)
    assert (p.static_friction, p.limit_ratio, p.friction_decay) == (0.36, 0.38, 0.7)
    assert p.static_friction * p.limit_ratio == pytest.approx(0.1368)
    assert p.static_friction * (1 - p.limit_ratio) == pytest.approx(0.2232)
    assert np.log(2) / p.friction_decay == pytest.approx(0.990, abs=5e-4)


@pytest.mark.parametrize(
    ("call", "name", "hint"),
    [
        (parameter_set, "eurosprinter-modified", "eurosprinter-modified-fastsim"),
        (parameter_set, "polach_dry", "polach-dry"),
        (check_law, "fastsm", "fastsim"),
        (check_law, "modified_fastsim", "modified-fastsim"),
    ],
)
def test_unknown_names_get_a_did_you_mean(call, name, hint):
    with pytest.raises(ParameterError, match=f"did you mean '{hint}'"):
        call(name)


def test_polach_law_is_the_packages_polach():
    s = np.linspace(-0.02, 0.02, 9)
    w = s * 8.33
    r = creep_force("polach", s, w, *GEOM, POLACH_DRY)
    from rollerrig.contact.kalker import kalker_coefficients

    c11 = float(kalker_coefficients(3.4 / 2.7, 0.3).c11)
    expected = polach_creep_force(s, w, 4300.0, 3.4e-3, 2.7e-3, c11, 8.08e10, POLACH_DRY)
    np.testing.assert_allclose(r.fx, expected, rtol=1e-12)


@pytest.mark.parametrize("law", CREEP_LAWS)
def test_every_law_saturates_at_mu_of_the_slip_velocity(law):
    p = default_parameter_sets(law)
    params = next(iter(p.values()))
    s = np.array([0.5])
    w = np.array([0.0])  # friction at zero slip velocity: mu0
    r = creep_force(law, s, w, *GEOM, params)
    assert r.fx[0] / 4300.0 == pytest.approx(params.static_friction, rel=0.02)


@pytest.mark.parametrize("law", CREEP_LAWS)
def test_curves_of_every_law_start_on_kalkers_slope(law):
    s = np.array([1e-6])
    c = law_creep_curve(
        law,
        s,
        10e3,
        30 / 3.6,
        0.348,
        0.291,
        0.452,
        1.890,
        POLACH_DRY if law != "modified-fastsim" else EUROSPRINTER_MODIFIED_FASTSIM,
    )
    # Polach (2005) eq. 12 at small eps: F = (2 Q mu / pi)(kA + kS) eps -> (kA + kS)/2 Kalker's
    # slope (dry: 0.7); the modified FASTSIM starts at k0 Kalker's (Spiryagin et al. 2013).
    k = {"polach": 0.7, "fastsim": 1.0, "fastrip": 1.0, "modified-fastsim": 0.54}[law]
    assert c.adhesion_coefficient[0] * 10e3 == pytest.approx(k * c.creep_stiffness * 1e-6, rel=1e-2)


def test_law_curve_polach_equals_polach_creep_curve():
    s = np.linspace(0, 0.05, 51)
    a = law_creep_curve("polach", s, 10e3, 30 / 3.6, 0.348, 0.291, 0.452, 1.890)
    b = polach_creep_curve(s, 10e3, 30 / 3.6, 0.348, 0.291, 0.452, 1.890)
    np.testing.assert_allclose(a.adhesion_coefficient, b.adhesion_coefficient, rtol=1e-12)


def test_mismatched_sets_and_polach_spin_are_refused():
    with pytest.raises(ParameterError, match="needs Polach"):
        creep_force("polach", 0.01, 0.1, *GEOM, EUROSPRINTER_MODIFIED_FASTSIM)
    with pytest.raises(ParameterError, match="needs k0"):
        creep_force("modified-fastsim", 0.01, 0.1, *GEOM, POLACH_DRY)
    with pytest.raises(ParameterError, match="longitudinal only"):
        creep_force("polach", 0.01, 0.1, *GEOM, POLACH_DRY, lat_creep=0.01)
    with pytest.raises(ParameterError, match="k0"):
        FastsimParameters(0.3, 0.4, 0.6, k0=0.0)


def test_contact_backend_absent_gives_one_message(monkeypatch, tmp_path):
    monkeypatch.delenv("CONTACT_DIR", raising=False)
    monkeypatch.delenv("CONTACTDIR", raising=False)
    assert contact_dir() is None
    with pytest.raises(ContactNotAvailable, match=r"CONTACT_DIR is not set.*eve70a/CONTACT"):
        load_contact()
    monkeypatch.setenv("CONTACT_DIR", str(tmp_path))
    with pytest.raises(ContactNotAvailable, match="holds no python_intfc"):
        exact_creep_force(
            1e-3,
            semi_axis_x=6e-3,
            semi_axis_y=12e-3,
            normal_load=1e5,
            shear_modulus=82e9,
            poisson=0.28,
            friction=0.3,
        )
    (tmp_path / "python_intfc").mkdir()
    (tmp_path / "python_intfc" / "__init__.py").write_text("")
    with pytest.raises(ContactNotAvailable, match="no compiled library"):
        load_contact()


@pytest.mark.parametrize("law", CREEP_LAWS)
def test_mismatched_array_lengths_name_the_parameters(law):
    params = EUROSPRINTER_MODIFIED_FASTSIM if law == "modified-fastsim" else POLACH_DRY
    with pytest.raises(
        ParameterError,
        match=r"long_creep \(shape \(3,\)\) and slip_velocity \(shape \(2,\)\) must have the "
        r"same shape, or one of them be a single number",
    ):
        creep_force(law, [0.01, 0.02, 0.03], [0.1, 0.2], *GEOM, params)


def test_law_creep_curve_of_no_creep_is_refused():
    with pytest.raises(ParameterError, match=r"creep must hold at least one value \[-\]"):
        law_creep_curve("fastsim", [], 10e3, 30 / 3.6, 0.348, 0.291, 0.452, 1.890)


@pytest.mark.parametrize("name", [None, ["polach-dry"], 3])
def test_a_parameter_set_name_that_is_not_text_is_refused_with_the_names(name):
    """None had been a bare TypeError ("not iterable"), a list an unhashable-type one."""
    from rollerrig._validation import ParameterError
    from rollerrig.contact.laws import check_law, parameter_set

    with pytest.raises(ParameterError, match=r"a str.*known: polach-dry"):
        parameter_set(name)
    with pytest.raises(ParameterError, match=r"creep law.*known:"):
        check_law(name)
