"""calibrate's console: a pair of correlated keys is printed as the combination the recording
determines, not each key at its own (marginal, misleadingly small) standard error."""

import numpy as np

from rollerrig.calibrate.calibration import Calibration, FittedParameter
from rollerrig.calibrate.diagnostics import identified_combinations
from rollerrig.cli._console import console
from rollerrig.cli.calibrate import print_calibration
from rollerrig.contact.creep import POLACH_DRY
from rollerrig.rig.parameters import default_rig


def _calibration():
    keys = ("stiffness.roller_shaft", "inertia.am_rotor", "inertia.roller")
    values = np.array([43466.8, 6.59474, 45.015])
    units = ["N.m/rad", "kg.m^2", "kg.m^2"]
    rel = np.array([1.89e-4, 1.96e-4, 1.07e-4])
    corr = np.array([[1.0, 0.9997, -0.3], [0.9997, 1.0, -0.3], [-0.3, -0.3, 1.0]])
    cov = corr * np.outer(rel * values, rel * values)
    params = {
        k: FittedParameter(k, u, v, float(v), float(s * v), float(s * v), True)
        for k, u, v, s in zip(keys, units, values, rel, strict=True)
    }
    return Calibration(
        parameters=params,
        nuisance={},
        keys=keys,
        covariance=cov,
        correlation=corr,
        channels={},
        rig=default_rig(),
        friction=POLACH_DRY,
        warnings=[],
        notes=[],
        experiment={},
        fit={"iterations": 3, "simulations": 9, "wall_time [s]": 1.0, "converged": True},
        recording={},
        series={},
        combinations=tuple(identified_combinations(keys, values, units, cov, 0.98)),
    )


def test_the_console_prints_the_combination_not_the_members_errors():
    cal = _calibration()
    width = console.width
    console.width = 240  # one line per row: the expression is not wrapped
    try:
        with console.capture() as captured:
            print_calibration(cal)
    finally:
        console.width = width
    text = captured.get()
    (combo,) = cal.combinations
    assert combo["keys"] == ["stiffness.roller_shaft", "inertia.am_rotor"]
    assert "combination 1" in text
    assert combo["expression"] in text  # e.g. stiffness.roller_shaft · inertia.am_rotor^-0.964
    assert combo["undetermined"]["expression"] in text
    # the members' marginal errors (8.22 N.m/rad, 0.00129 kg.m^2) are not printed as theirs;
    # the key correlated with neither keeps its own
    assert "8.22" not in text and "0.00129" not in text
    assert "0.00482" in text  # inertia.roller: 1.07e-4 x 45.015
    assert f"{100 * combo['relative_standard_error']:.3g} %" in text
