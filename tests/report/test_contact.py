"""Contact report figures: creep curves on the roller and on a tangent rail (with Kalker's
linear theory), and the contact size against the roller radius, as matplotlib objects."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from rollerrig.contact import POLACH_DRY, POLACH_WET
from rollerrig.contact.roller import contact_versus_roller_radius
from rollerrig.report.contact import contact_size_figure, creep_curve_figure

GEOMETRY = (0.348, 0.291, 0.452, 1.890)  # wheel r_x, r_y; roller r_x, r_y [m]


def test_creep_curve_figure_draws_roller_tangent_and_linear_theory():
    sets = {"dry": POLACH_DRY, "wet": POLACH_WET}
    fig, curves = creep_curve_figure(sets, 10e3, 30 / 3.6, *GEOMETRY)
    ax = fig.axes[0]
    assert ax.get_xlabel() == "creep s [%]" and ax.get_ylabel() == "adhesion coefficient F/N [-]"
    assert ax.get_title() == "Polach creep curves, N = 10 kN, v = 30 km/h"
    entries = [t.get_text() for t in ax.get_legend().get_texts()]
    assert entries == [
        "dry, roller r = 452 mm",
        "dry, tangent rail",
        "dry, Kalker linear theory",
        "wet, roller r = 452 mm",
        "wet, tangent rail",
    ]
    assert set(curves) == {(c, w) for c in sets for w in ("roller", "tangent")}
    solid = next(ln for ln in ax.get_lines() if ln.get_label() == "dry, roller r = 452 mm")
    np.testing.assert_allclose(solid.get_ydata(), curves[("dry", "roller")].adhesion_coefficient)
    # Each roller curve's peak is marked at the curve's maximum.
    peaks = [ln for ln in ax.get_lines() if ln.get_marker() == "o"]
    assert len(peaks) == 2
    assert peaks[0].get_ydata()[0] == curves[("dry", "roller")].peak[1]
    plt.close(fig)


def test_contact_size_figure_has_units_and_marks_the_rig_roller():
    comparison = contact_versus_roller_radius(np.geomspace(0.1, 5.0, 30))
    fig = contact_size_figure(comparison, rig_roller_radius=0.452)
    ax1, ax2 = fig.axes
    assert (ax1.get_ylabel(), ax2.get_ylabel()) == ("semi-axis [mm]", "contact area [mm²]")
    assert ax1.get_xlabel() == ax2.get_xlabel() == "roller longitudinal radius [mm]"
    assert ax1.get_xscale() == ax2.get_xscale() == "log"
    for ax in (ax1, ax2):
        assert "rig roller" in [t.get_text() for t in ax.get_legend().get_texts()]
        rig = next(ln for ln in ax.get_lines() if ln.get_label() == "rig roller")
        assert rig.get_xdata()[0] == 452.0  # [mm]
    a = next(ln for ln in ax1.get_lines() if ln.get_label() == "a (rolling)")
    np.testing.assert_allclose(a.get_ydata(), comparison.semi_axis_x * 1e3)
    plt.close(fig)


def test_report_figures_refuse_inputs_of_the_wrong_kind():
    """None had been a bare AttributeError, a str of rows a bare TypeError (string indices)."""
    import pytest

    from rollerrig._validation import ParameterError
    from rollerrig.report.traction import law_curve_figure, traction_figure

    before = plt.get_fignums()
    with pytest.raises(ParameterError, match="comparison must be a RollerRailComparison"):
        contact_size_figure(None)
    with pytest.raises(ParameterError, match="curve must be a CreepCurve"):
        traction_figure(None, "fastsim", 0.28)
    with pytest.raises(ParameterError, match="rows must be a dict"):
        law_curve_figure("rows", "fastsim", 0.46)
    assert plt.get_fignums() == before  # refused before a figure was made
