"""Tests for rollerrig.contact.curves: the Polach creep-adhesion curve of a geometry."""

import numpy as np
import pytest

from rollerrig._validation import ParameterError
from rollerrig.contact.curves import polach_creep_curve

RIG = (10e3, 30 / 3.6, 0.348, 0.291, 0.452, 1.890)  # Q [N], v [m/s], radii [m]


@pytest.mark.parametrize("creep", [[], np.empty((0, 3))])
def test_no_creep_values_are_refused(creep):
    # An empty curve has no peak and nothing to plot: it was returned, and its peak failed
    # with numpy's "attempt to get argmax of an empty sequence".
    with pytest.raises(
        ParameterError,
        match=r"creep must hold at least one value \[-\] to make a creep curve, got an empty "
        r"array \(shape \(0,(?: 3)?\)\)",
    ):
        polach_creep_curve(creep, *RIG)


def test_peak_of_a_single_creep_and_of_a_2d_creep_array():
    one = polach_creep_curve(0.01, *RIG)
    assert one.peak == (0.01, pytest.approx(float(one.adhesion_coefficient)))
    grid = np.array([[0.0, 0.01], [0.035, 0.05]])
    two = polach_creep_curve(grid, *RIG)
    flat = polach_creep_curve(grid.ravel(), *RIG)
    assert two.peak == flat.peak == (0.035, pytest.approx(flat.adhesion_coefficient[2]))
