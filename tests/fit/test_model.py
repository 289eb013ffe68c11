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
