"""The points of a study and what each one simulates."""

import numpy as np
import pytest

from rollerrig._validation import ParameterError
from rollerrig.experiment import load_protocol
from rollerrig.rig.parameters import default_rig
from rollerrig.studies.design import design_points, point_setup, protocol_groups
from rollerrig.studies.studyfile import study_from_toml_string


def test_a_grid_is_in_c_order_over_its_axes():
    spec = study_from_toml_string(
        "[grid]\nload = [4300.0, 10000.0, 20000.0]\n'drive.roller' = ['induction', 'servo']\n"
    )
    table = design_points(spec)
    assert table.attrs["grid_shape"] == [3, 2]
    loads = np.reshape(table.columns["load"], (3, 2))
    drives = np.reshape(table.columns["drive.roller"], (3, 2))
    assert (loads[:, 0] == [4300.0, 10000.0, 20000.0]).all() and (loads[:, 1] == loads[:, 0]).all()
    assert drives[0].tolist() == ["induction", "servo"]
    assert table.point(1) == {"load": 4300.0, "drive.roller": "servo"}


def test_a_sobol_design_is_salibs_saltelli_sample_through_the_inverse_cdfs():
    from SALib.sample import sobol

    spec = study_from_toml_string(
        """
        [sample]
        method = "sobol"
        n = 16
        seed = 3
        [sample.parameters]
        load = { distribution = "uniform", low = 4.3, high = 20, unit = "kN" }
        "stiffness.roller_shaft" = { distribution = "loguniform", low = 40e3, high = 160e3 }
        """
    )
    table = design_points(spec)
    cube = sobol.sample({"num_vars": 2, "names": ["a", "b"], "bounds": [[0, 1]] * 2}, 16,
                        calc_second_order=False, seed=3)  # fmt: skip
    assert len(table) == 16 * 4 == cube.shape[0]
    np.testing.assert_allclose(table.columns["load"], 4300 + cube[:, 0] * 15700)
    np.testing.assert_allclose(
        table.columns["stiffness.roller_shaft"], 40e3 * 4.0 ** cube[:, 1], rtol=1e-12
    )
    assert table.attrs["sample"]["parameters"]["load"] == {
        "distribution": "uniform", "low": 4300.0, "high": 20000.0,
    }  # fmt: skip


def test_lhs_design_has_one_point_per_stratum():
    spec = study_from_toml_string(
        "[sample]\nmethod = 'lhs'\nn = 10\n[sample.parameters]\n"
        "load = { distribution = 'uniform', low = 0, high = 10 }\n"
    )
    values = design_points(spec).columns["load"]
    assert sorted(np.floor(values).astype(int).tolist()) == list(range(10))


def test_points_that_share_an_experiment_are_grouped():
    spec = study_from_toml_string(
        "[grid]\n'stiffness.roller_shaft' = [4e4, 8e4]\nfriction = ['dry', 'wet']\n"
    )
    table = design_points(spec)
    groups = protocol_groups(table, np.arange(4))
    assert [g.tolist() for g in groups] == [[0, 2], [1, 3]]


def test_a_point_scales_the_experiment_and_sets_rig_and_drives():
    rig, base = default_rig(), load_protocol("release-test")
    r, p, d = point_setup(
        rig, base,
        {"load": 20e3, "speed": 5.0, "friction": "wet", "stiffness.roller_shaft": 9e4,
         "drive.roller": "servo", "drive.roller_lag": 0.1},
    )  # fmt: skip
    assert p.normal_load.max() == 20e3 and p.roller_speed.max() == 5.0
    assert set(p.friction_condition) == {"wet"} and p.duration == base.duration
    assert r.stiffness.roller_shaft == 9e4 and rig.stiffness.roller_shaft == 43.5e3
    assert (d.roller, d.roller_lag, d.wheel) == ("servo", 0.1, "pmsm")
    with pytest.raises(ParameterError, match=r"inertia\.roller"):
        point_setup(rig, base, {"inertia.roller": -1.0})


def test_the_frame_model_and_its_keys_are_study_keys():
    spec = study_from_toml_string(
        "[grid]\nframe = ['rigid', 'flexible']\n"
        "'frame.longitudinal_stiffness' = { values = [10, 100], unit = 'MN/m' }\n"
    )
    table = design_points(spec)
    r, _, d = point_setup(default_rig(), load_protocol("release-test"), table.point(3))
    assert d.frame == "flexible" and r.frame.longitudinal_stiffness == 1e8
    with pytest.raises(Exception, match="not a known frame"):
        study_from_toml_string("[grid]\nframe = ['wobbly']\n")


def test_the_dq_drive_runs_in_its_own_batches():
    # The dq roller drive is a second compiled model (29 states): a batch never mixes it in.
    spec = study_from_toml_string(
        "[grid]\n'drive.roller' = ['induction', 'induction_dq', 'servo']\nload = [4300.0]\n"
    )
    groups = protocol_groups(design_points(spec), np.arange(3))
    assert sorted(g.tolist() for g in groups) == [[0, 2], [1]]
