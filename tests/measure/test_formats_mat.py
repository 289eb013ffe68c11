"""MAT files: units from the ``units`` struct (new) and the ``rollerrig_units`` JSON text (older
rollerrig files), provenance split from the stored metadata."""

import json

import numpy as np
import pytest

from rollerrig.measure.formats.mat import read_mat

T = np.arange(5) / 250.0


def test_units_struct_of_a_foreign_v5_file(tmp_path):
    from scipy.io import savemat

    f = tmp_path / "lab.mat"
    savemat(f, {"t": T.reshape(-1, 1), "F": np.ones((5, 1)), "units": {"t": "s", "F": "kN"}})
    table = read_mat(f)
    assert sorted(table.names) == ["F", "t"]
    assert table.load("F").unit == "kN" and table.load("t").unit == "s"


def test_older_rollerrig_units_json_text_is_still_read(tmp_path):
    from scipy.io import savemat

    f = tmp_path / "old.mat"
    savemat(
        f,
        {
            "time": T.reshape(-1, 1),
            "torque": np.ones((5, 1)),
            "rollerrig_units": json.dumps({"time": "s", "torque": "N.m"}),
            "rollerrig_metadata": json.dumps({"seed": 3}),
        },
    )
    table = read_mat(f)
    assert table.load("torque").unit == "N.m"
    assert table.stored_metadata == {"seed": 3} and table.stored_provenance is None


@pytest.mark.parametrize("version", ["5", "7.3"])
def test_write_table_mat_gives_units_metadata_and_provenance(tmp_path, version):
    from rollerrig.output import write_table

    f = write_table(
        tmp_path / "run.mat",
        {"torque": (np.arange(5.0), "N.m", "shaft torque")},
        time=T,
        attrs={"seed": 3},
        mat_version=version,
    )
    table = read_mat(f)
    assert table.load("torque").unit == "N.m" and table.load("time").unit == "s"
    assert table.stored_metadata == {"seed": 3}
    assert table.stored_provenance["software"] == "rollerrig"
    assert table.stored_variables["torque"]["long_name"] == "shaft torque"
    assert "units.torque" not in table.names and "provenance" not in table.names
