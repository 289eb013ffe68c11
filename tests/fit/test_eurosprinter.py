"""The creep laws fitted to a real creep curve: the Eurosprinter 127 001 (issues 19 and 22).

The points are the measurements of Engel, Beck & Alders (1998) digitised from the two figures
of CONTACT's user guide by ``tools/digitise_eurosprinter.py`` (``data/eurosprinter_engel1998.csv``,
its header says how and how well). The contact is CONTACT's ``euro_tractcurv.inp``: wheel
radius 625 mm on a tangent rail, 106.7 kN, Hertz a/b = 0.5 (a rail crown radius chosen to give
it), G = 82 GPa, ν = 0.28, V = 10 m/s.

The bounds are pinned from what was measured on these points (2025, default FASTSIM grid):
Polach fit rmse 0.02392, modified FASTSIM fit 0.02393, the published modified FASTSIM set
(Spiryagin, Polach & Cole 2013, as CONTACT runs it) 0.02527, Kalker with Coulomb friction
μ = 0.33 0.0602, Polach's dry set 0.135; a margin of about 2 % of the rmse on each.
"""

import filecmp
import warnings
from itertools import pairwise
from pathlib import Path

import numpy as np
import pytest
from scipy import optimize

from rollerrig.analysis.measured_curve import read_curve_csv
from rollerrig.contact.creep import POLACH_DRY
from rollerrig.contact.hertz import combined_elastic_constants, hertz_contact
from rollerrig.contact.kalker import kalker_coefficients
from rollerrig.contact.laws import EUROSPRINTER_COULOMB, EUROSPRINTER_MODIFIED_FASTSIM
from rollerrig.fit import PolachFitWarning, fit_polach, polach_coa
from rollerrig.fit.modified_fastsim import (
    ModifiedFastsimFitWarning,
    fit_modified_fastsim,
    modified_fastsim_coa,
)

DATA = Path(__file__).parent / "data" / "eurosprinter_engel1998.csv"
EXAMPLE_COPY = Path(__file__).parents[2] / "examples" / "eurosprinter_engel1998.csv"
WHEEL_RADIUS = 0.625  # [m]
NU = 0.28  # [-]
YOUNGS = 2.0 * 82e9 * (1.0 + NU)  # [Pa], from CONTACT's G = 82 GPa
FIT_RMSE = 0.0245  # both fits measured 0.0239
PUBLISHED_MODIFIED_FASTSIM_RMSE = 0.0258  # measured 0.02527


@pytest.fixture(scope="module")
def curve():
    return read_curve_csv(DATA, creepage="mean")


@pytest.fixture(scope="module")
def contact(curve):
    """(a, b, G, ν, N): the Hertz ellipse of the wheel on a rail whose crown gives a/b = 0.5."""
    load = float(curve.normal_load[0])

    def axes(crown):
        h = hertz_contact(load, WHEEL_RADIUS, np.inf, np.inf, crown, YOUNGS, NU)
        return float(h.semi_axis_x), float(h.semi_axis_y)

    crown = optimize.brentq(lambda r: axes(r)[0] / axes(r)[1] - 0.5, 0.7, 10.0, xtol=1e-10)
    a, b = axes(crown)
    g = float(combined_elastic_constants(YOUNGS, NU, YOUNGS, NU).shear_modulus)
    return a, b, g, NU, load


def _rmse(model, y):
    return float(np.sqrt(np.mean((np.asarray(model) - y) ** 2)))


def test_the_file_reads_as_kalker_creepage_and_the_example_has_the_same_points(curve):
    lines = [ln for ln in DATA.read_text(encoding="utf-8").splitlines() if not ln.startswith("#")]
    assert lines[0].startswith("creep [%],coa [-],slip_velocity [m/s]")
    xi = np.array([float(ln.split(",")[0]) for ln in lines[1:]]) / 100.0
    np.testing.assert_allclose(curve.creepage, xi, rtol=0, atol=1e-12)
    np.testing.assert_allclose(curve.slip_velocity, xi * 10.0, rtol=1e-4)
    assert np.all(curve.creep > curve.creepage)  # the rig's creep, referred to the slower body
    assert curve.normal_load[0] == pytest.approx(106.7e3)
    assert curve.rolling_speed[0] == pytest.approx(10.0)
    assert filecmp.cmp(DATA, EXAMPLE_COPY, shallow=False)


def test_the_points_have_the_shape_the_figure_shows(curve):
    xi, y = curve.creepage * 100.0, curve.coa  # [%], [-]
    assert 150 <= xi.size <= 190
    assert xi.min() < 0.5 and xi.max() > 20.0
    edges = np.arange(0.5, 5.01, 0.5)
    medians = np.array([np.median(y[(xi >= lo) & (xi < hi)]) for lo, hi in pairwise(edges)])
    peak = int(np.argmax(medians))
    assert 0.30 <= medians[peak] <= 0.32
    assert 1.0 <= edges[peak] < 3.0  # the peak near 1-3 % creepage
    upper = np.percentile(y[(xi >= 1.0) & (xi < 3.0)], 90)
    assert 0.30 <= upper <= 0.33  # the envelope of the points at the peak, 0.31-0.32
    assert np.median(y[xi < 0.7]) < medians[peak] - 0.03  # the rising branch
    tail = np.median(y[xi > 15.0])
    assert 0.18 <= tail <= 0.23  # falling to about 0.2 at 20 %
    assert tail < medians[peak] - 0.07
    assert y.max() < 0.35


def test_contact_is_contacts_ellipse(contact):
    a, b, g, _, _ = contact
    # CONTACT's euro_tractcurv.ref_out: "BASIC SEMIAXES AA,BB 6.304 12.61" [mm].
    assert a == pytest.approx(6.304e-3, rel=1e-3)
    assert b == pytest.approx(12.61e-3, rel=1e-3)
    assert g == pytest.approx(82e9)


def test_polach_fit_reaches_the_scatter_and_says_what_it_cannot_determine(curve, contact):
    a, b, g, nu, load = contact
    k = g * a * b * float(kalker_coefficients(a / b, nu).c11)
    with pytest.warns(PolachFitWarning, match="poorly determined"):
        fit = fit_polach(curve.creepage, curve.coa, load, k, slip_velocity=curve.slip_velocity)
    assert 0.022 < fit.rmse < FIT_RMSE
    assert not fit.identifiable
    assert not fit.coverage.a_and_b_identifiable
    assert fit.residual_structure is not None and not fit.residual_structure.structured
    # mu0 is what the points determine: the level of the plateau.
    assert 0.30 < fit.parameters.static_friction < 0.42
    assert fit.stderr["static_friction"] < 0.05
    # Polach's dry set (general-purpose, mu0 = 0.55) is not this curve.
    assert _rmse(polach_coa(curve.creepage, curve.slip_velocity, load, k, POLACH_DRY),
                 curve.coa) > 0.1  # fmt: skip


def test_modified_fastsim_fit_reaches_the_scatter(curve, contact):
    a, b, g, nu, load = contact
    with pytest.warns(ModifiedFastsimFitWarning, match="poorly determined"):
        fit = fit_modified_fastsim(
            curve.creepage, curve.coa, load, a, b, g, nu, slip_velocity=curve.slip_velocity,
            initial=EUROSPRINTER_MODIFIED_FASTSIM, profile=False,
        )  # fmt: skip
    assert 0.022 < fit.rmse < FIT_RMSE
    assert not fit.identifiable
    assert 0.4 < fit.parameters.k0 <= 1.0
    assert np.isfinite(fit.stderr["k0"]) and fit.stderr["k0"] < 0.4


def test_published_modified_fastsim_set_fits_the_points(curve, contact):
    """Spiryagin, Polach & Cole (2013), VSD 51, as run in CONTACT's tractcurv.inp series 4."""
    a, b, g, nu, load = contact
    args = (curve.creepage, curve.slip_velocity, load, a, b, g, nu)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        published = _rmse(modified_fastsim_coa(*args, EUROSPRINTER_MODIFIED_FASTSIM), curve.coa)
        coulomb = _rmse(modified_fastsim_coa(*args, EUROSPRINTER_COULOMB), curve.coa)
    assert published < PUBLISHED_MODIFIED_FASTSIM_RMSE
    assert published > 0.022  # not better than the scatter of the points
    assert coulomb > 2.0 * published  # Kalker with Coulomb friction misses the falling branch
