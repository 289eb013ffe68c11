"""The model a Polach fit fits: Polach's CoA (Polach 2005, eqs. as in Kayaalp 4.19-4.20,
written out here independently of the twin's kernel) and the creep stiffness of the rig's
contact (against the contact package's creep curve)."""

import numpy as np
import pytest

from rollerrig.contact.creep import POLACH_DRY
from rollerrig.contact.curves import polach_creep_curve
from rollerrig.fit.model import PARAMETER_NAMES, creep_stiffness_for_rig, polach_coa

LOAD = 4300.0  # [N], the seed's load


def test_creep_stiffness_matches_the_creep_curve():
    # Independent path: polach_creep_curve's Kalker slope at the default rig geometry.
    c = polach_creep_curve([0.0], LOAD, 8.0, 0.348, 0.291, 0.452, 1.890)
    assert float(creep_stiffness_for_rig(LOAD)) == pytest.approx(c.creep_stiffness, rel=1e-12)


def test_creep_stiffness_per_load_keeps_the_shape():
    loads = np.array([[4300.0, 8600.0], [4300.0, 2000.0]])
    k = creep_stiffness_for_rig(loads)
    assert k.shape == loads.shape and k[0, 0] == k[1, 0]
    # Hertz: a b grows as Q^(2/3), c11 depends on a/b only (constant for one geometry).
    assert k[0, 1] / k[0, 0] == pytest.approx(2.0 ** (2.0 / 3.0), rel=1e-9)


def test_polach_coa_is_polachs_closed_form():
    s = np.linspace(1e-4, 0.1, 50)
    w = s * 30 / 3.6
    k = 1.13e6
    mu0, a, b, ka, ks = (getattr(POLACH_DRY, n) for n in PARAMETER_NAMES)
    mu = mu0 * ((1 - a) * np.exp(-b * w) + a)
    eps = np.pi / 4 * k * s / (LOAD * mu)
    expected = 2 * mu / np.pi * (ka * eps / (1 + (ka * eps) ** 2) + np.arctan(ks * eps))
    np.testing.assert_allclose(polach_coa(s, w, LOAD, k, POLACH_DRY), expected, rtol=1e-12)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((0.01, 0.0833, 0.0, 1.13e6), "normal_load must be > 0"),  # was NaN
        ((0.01, 0.0833, 4300.0, -1.13e6), "creep_stiffness must be > 0"),  # was CoA -0.42
        ((np.nan, 0.0833, 4300.0, 1.13e6), "creep must be finite"),  # was NaN
        ((0.01, np.inf, 4300.0, 1.13e6), "slip_velocity must be finite"),
    ],
)
def test_polach_coa_refuses_what_has_no_coa(args, message):
    from rollerrig._validation import ParameterError

    with pytest.raises(ParameterError, match=message):
        polach_coa(*args, POLACH_DRY)


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_whiteness_helpers_refuse_a_series_with_a_gap(bad):
    """A NaN made every lag's correlation 0 and the time 1: a series that looked white."""
    from rollerrig._validation import ParameterError
    from rollerrig.fit.whiteness import autocorrelation, integrated_autocorrelation_time

    x = np.r_[np.sin(np.arange(99.0)), bad]
    with pytest.raises(ParameterError, match="x must be finite"):
        autocorrelation(x, 3)
    with pytest.raises(ParameterError, match="x must be finite"):
        integrated_autocorrelation_time(x)
    with pytest.raises(ParameterError, match=r"max_lag must be a whole number in \[0, 99\]"):
        autocorrelation([*x[:-1].tolist(), 0.0], 100)
    with pytest.raises(ParameterError, match="at least 2 samples"):
        autocorrelation([], 0)
