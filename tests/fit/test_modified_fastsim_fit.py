"""Fit of the modified FASTSIM (issue 19 point 2): recovery of its own set, misfit on FaStrip."""

import warnings

import numpy as np
import pytest

from rollerrig._validation import ParameterError
from rollerrig.contact.fastsim import fastsim_grid
from rollerrig.contact.laws import EUROSPRINTER_MODIFIED_FASTSIM as P
from rollerrig.contact.laws import creep_force
from rollerrig.fit.modified_fastsim import (
    ModifiedFastsimFitWarning,
    fit_modified_fastsim,
    modified_fastsim_coa,
)

GRID = fastsim_grid(16, 16)
A, B, G, NU, N = 6e-3, 5e-3, 8.08e10, 0.3, 1e5


def _points(noise=0.0, n=30):
    xi = np.tile(np.linspace(5e-4, 0.06, n), 2)
    w = xi * np.repeat([5.0, 20.0], n)
    y = modified_fastsim_coa(xi, w, N, A, B, G, NU, P, grid=GRID)
    return xi, w, y + np.random.default_rng(3).normal(0, noise, y.size)


def test_recovers_its_own_parameters_within_their_standard_errors():
    xi, w, y = _points(noise=0.003)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        f = fit_modified_fastsim(xi, y, N, A, B, G, NU, slip_velocity=w, grid=GRID, profile=False)
    d = f.truth_distance(P)
    assert f.rmse == pytest.approx(0.003, rel=0.3)
    for name in ("k0", "static_friction"):
        assert d[name]["sigma"] is not None and d[name]["sigma"] < 4, (name, d[name])
    assert f.parameters.k0 == pytest.approx(0.54, abs=0.03)
    s = f.summary()
    assert s["law"] == "modified-fastsim" and len(s["correlation"]["matrix"]) == 6


def test_load_scaling_is_exact():
    """A point at load 2N equals the reference-load point at creepage xi 2^(-1/3)."""
    a = modified_fastsim_coa([0.01], [0.1], 2 * N, A, B, G, NU, P, reference_load=N, grid=GRID)
    b = modified_fastsim_coa([0.01 * 2 ** (-1 / 3)], [0.1], N, A, B, G, NU, P, grid=GRID)
    from rollerrig.contact.hertz import hertz_contact

    assert a[0] == pytest.approx(b[0], rel=1e-12)
    # and against a direct evaluation on the Hertz ellipse of the larger load
    c1 = hertz_contact(N, 0.5, 0.3, np.inf, 0.3)
    c2 = hertz_contact(2 * N, 0.5, 0.3, np.inf, 0.3)
    x1 = modified_fastsim_coa([0.01], [0.1], 2 * N, float(c1.semi_axis_x), float(c1.semi_axis_y),
                              G, NU, P, reference_load=N, grid=GRID)  # fmt: skip
    r2 = creep_force("modified-fastsim", 0.01, 0.1, 2 * N, float(c2.semi_axis_x),
                     float(c2.semi_axis_y), G, NU, P, grid=GRID)  # fmt: skip
    assert x1[0] == pytest.approx(r2.fx[0] / (2 * N), rel=1e-9)


def test_fit_to_a_fastrip_curve_reports_its_misfit():
    """FaStrip, a law the fit does not share: the misfit is reported, not hidden."""
    xi = np.tile(np.linspace(5e-4, 0.06, 30), 2)
    w = xi * np.repeat([5.0, 20.0], 30)
    r = creep_force("fastrip", xi, w, N, A, B, G, NU, P, grid=GRID)
    y = r.fx / N
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        f = fit_modified_fastsim(xi, y, N, A, B, G, NU, slip_velocity=w, grid=GRID, profile=False)
    # FaStrip has Kalker's slope (no reduction): the fit finds k0 near 1, and a small misfit.
    assert f.parameters.k0 > 0.85
    assert f.rmse < 0.02
    assert f.residual_structure is not None and f.residual_structure.structured
    assert any(issubclass(c.category, ModifiedFastsimFitWarning) for c in caught)


def test_inputs_are_checked():
    with pytest.raises(ParameterError, match="at least 7"):
        fit_modified_fastsim([0.01] * 3, [0.1] * 3, N, A, B, G, NU, rolling_speed=5.0)
    with pytest.raises(ParameterError, match="slip_velocity"):
        fit_modified_fastsim(np.linspace(0.001, 0.01, 8), np.linspace(0.1, 0.3, 8), N, A, B, G,
                             NU)  # fmt: skip


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"normal_load": np.full(5, 1e5)},
         "creep (shape (12,)) and normal_load (shape (5,)) must have the same shape"),
        ({"rolling_speed": np.full(5, 8.0)},
         "creep (shape (12,)) and rolling_speed (shape (5,)) must have the same shape"),
        ({"reference_load": "x"}, "reference_load must be a number"),
        ({"max_points": np.nan}, "max_points must be a whole number >= 7 [-], got nan"),
        ({"max_points": 7.5}, "max_points must be a whole number >= 7 [-], got 7.5"),
        ({"creep": np.zeros(12)}, "creep must be nonzero [-] at 7 points at least"),
        ({"grid": "coarse"}, "grid must be a FastsimGrid"),
    ],
)  # fmt: skip
def test_fit_inputs_that_had_given_bare_errors_are_named(options, message):
    # Each had raised numpy's broadcast error, a bare ValueError, a ZeroDivisionError (all
    # creep zero) or an AttributeError, naming no parameter; 7.5 had been taken as 7.
    import re

    xi = np.linspace(5e-4, 0.06, 12)
    args = {"creep": xi, "normal_load": 1e5, "rolling_speed": 8.0, "grid": fastsim_grid(8, 8)}
    args.update(options)
    creep, load = args.pop("creep"), args.pop("normal_load")
    with pytest.raises(ParameterError, match=re.escape(message)):
        fit_modified_fastsim(
            creep, 0.3 * np.tanh(50 * xi), load, 6e-3, 5e-3, 8.08e10, 0.3, profile=False, **args
        )
