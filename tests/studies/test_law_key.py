"""A study varies the creep law of the contact force (``contact.law``, issue 19 point 2)."""

import numpy as np
import pytest

from rollerrig.studies import StudyFileError, run_study
from rollerrig.studies.design import point_setup
from rollerrig.studies.studyfile import key_quantity, si_unit, study_from_toml_string

LAWS = """
name = "laws"
experiment = "release-test"
[grid]
"contact.law" = ["polach", "fastsim", "modified-fastsim"]
[outputs]
metrics = ["release_overshoot", "coa_bias_rms"]
"""


def test_the_law_is_a_categorical_model_key():
    assert key_quantity("contact.law") == (
        None,
        sorted(["polach", "fastsim", "modified-fastsim", "fastrip"]),
    )
    assert si_unit("contact.law") == ""


def test_a_point_gets_its_law_in_the_drive_config():
    from rollerrig.experiment import load_protocol
    from rollerrig.rig.parameters import default_rig

    rig, protocol = default_rig(), load_protocol("release-test")
    _, _, drive = point_setup(rig, protocol, {"contact.law": "fastsim"})
    assert drive.law == "fastsim"
    assert point_setup(rig, protocol, {})[2].law == "polach"


def test_an_unknown_law_is_refused_naming_the_key_and_the_laws():
    with pytest.raises(StudyFileError, match=r"contact\.law.*fastsim"):
        study_from_toml_string("[grid]\n'contact.law' = ['fastsimm']\n")


def test_a_study_over_the_creep_law_runs_every_law():
    ds = run_study(study_from_toml_string(LAWS), executor="local").dataset
    assert list(ds.status.values) == ["ok"] * 3
    assert list(ds["contact.law"].values) == ["polach", "fastsim", "modified-fastsim"]
    # The law changes the run: the creep curve's shape shows in the CoA's bias.
    bias = ds.coa_bias_rms.values
    assert np.unique(bias).size == 3
