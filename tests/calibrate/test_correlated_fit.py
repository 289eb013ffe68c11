"""A real calibration with two correlated keys: the roller shaft's stiffness k56 and the
induction motor's rotor inertia, fitted together on the short synthetic test of the bundled
rig (the twin's motor-side mode fixes about their ratio). The recording determines their
combination, which holds the truth; the console's and the figure's residual RMS are the same
number (issue 23, point 6)."""

import math

import numpy as np
import pytest

from rollerrig.calibrate import calibrate
from rollerrig.calibrate.settings import MAX_CORRELATION
from rollerrig.report.calibration import torque_residual
from rollerrig.rig.parameters import default_rig

FREE = "stiffness.roller_shaft,inertia.am_rotor"


@pytest.fixture(scope="module")
def calibration(recording_maker):
    rec, _ = recording_maker(truth={}, seed=6)  # the bundled rig: the truth is the start
    return calibrate(rec, FREE, max_iterations=8)


def test_the_correlated_pair_is_reported_as_one_combination(calibration):
    c = calibration
    # the groups come from the statistical covariance (a sensor's offset moving two keys
    # together is no combination the recording fixes)
    stat = c.covariance_statistical
    r = stat[0, 1] / math.sqrt(stat[0, 0] * stat[1, 1])
    assert abs(r) > MAX_CORRELATION
    (combo,) = c.combinations
    assert combo["keys"] == ["stiffness.roller_shaft", "inertia.am_rotor"]
    assert combo["max_abs_correlation"] == pytest.approx(abs(r))
    # the determined combination is fixed better than either key on its own
    rel = [c.parameters[k].relative_standard_error for k in combo["keys"]]
    assert combo["relative_standard_error"] < 0.5 * min(rel)
    assert combo["undetermined"]["relative_standard_error"] > max(rel) * 0.9
    # it holds the truth (the bundled rig made the recording) within 3 of its standard errors
    rig = default_rig()
    truth = math.prod(
        getattr(getattr(rig, k.partition(".")[0]), k.partition(".")[2]) ** e
        for k, e in combo["exponents"].items()
    )
    assert abs(combo["value"] - truth) < 3 * combo["standard_error"]
    # the same number from the covariance by the linear transform in ln(value)
    g = np.array(list(combo["exponents"].values()))
    v = np.array([c.parameters[k].value for k in combo["keys"]])
    var = g @ (c.covariance[:2, :2] / np.outer(v, v)) @ g
    assert combo["relative_standard_error"] == pytest.approx(math.sqrt(var), rel=1e-12)


def test_the_json_and_the_warning_name_the_combination(calibration):
    doc = calibration.to_json()
    (entry,) = doc["combinations"]
    assert entry["expression"] == calibration.combinations[0]["expression"]
    for key in entry["keys"]:
        assert doc["parameters"][key]["in_combination"] == entry["expression"]
        assert "marginal only" in doc["parameters"][key]["standard_error_meaning"]
    assert "in_combination" not in doc["nuisance"]["experiment.roller_speed"]
    said = [w for w in calibration.warnings if entry["expression"] in w]
    assert len(said) == 1 and "are correlated" in said[0]
    assert not [w for w in calibration.warnings if "are correlated (+" in w]  # not said twice


def test_the_figure_s_residual_is_the_console_s(calibration):
    ds = calibration.fit_dataset()
    ch = calibration.channels["torque"]
    for which, rms in (("start", ch.rms_before), ("fitted", ch.rms_after)):
        _, got, raw = torque_residual(ds, which)
        assert got == pytest.approx(rms, rel=1e-9)
        assert raw > got  # the lines left in: the larger number the figure used to show
    assert int(ds["torque_in_fit"].sum()) == ch.samples
    assert "residual_rms_convention" in calibration.to_json()
