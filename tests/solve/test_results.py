"""Labelled results: the NaN policy of derived channels, provenance, and save_dataset's formats.

One tiny simulation (2 s, reference solver: no numba compilation) serves the whole module.
"""

import json

import numpy as np
import pytest

from rollerrig.experiment import protocol_from_toml_string
from rollerrig.output import rig_sha256
from rollerrig.rig.parameters import default_rig
from rollerrig.solve.results import NAN_MEANINGS, SAVE_FORMATS, save_dataset
from rollerrig.solve.simulation import Simulation

TINY = """
[experiment]
name = "tiny-standstill"
normal_load_kN = 4.3
friction = "dry"
roller_speed_kmh = 0
[[step]]
action = "hold"
duration_s = 0.4
[[step]]
action = "set_roller_speed"
to_kmh = 5
duration_s = 1.0
[[step]]
action = "ramp_torque"
to_Nm = 300
duration_s = 0.6
"""


@pytest.fixture(scope="module")
def ds():
    protocol = protocol_from_toml_string(TINY)
    return Simulation(experiment=protocol, solver="reference", output_rate=250.0).run()


def test_measured_creep_is_nan_exactly_at_encoder_standstill_and_says_why(ds):
    creep = ds.measured_creep.values
    standstill = ds.measured_roller_speed.values == 0.0
    assert standstill[:100].all()  # the roller stands for the first 0.4 s
    np.testing.assert_array_equal(np.isnan(creep), standstill)
    assert "standstill" in ds.measured_creep.attrs["nan_meaning"]
    assert ds.attrs["measured_creep_nan_samples"] == int(standstill.sum())


def test_other_channels_are_finite_and_the_coa_states_when_it_would_not_be(ds):
    for name in NAN_MEANINGS:
        assert ds[name].attrs["nan_meaning"]
    assert ds.attrs["coa_nan_samples"] == 0 and ds.attrs["measured_coa_nan_samples"] == 0
    for name, var in ds.data_vars.items():
        if name != "measured_creep" and np.issubdtype(var.dtype, np.number):
            assert np.all(np.isfinite(var.values)), name
    # the CoA the rig reports is T56 / (r_r S), S the air spring's force; the truth's is F_x / N
    # with N = S + σ (h/l) F_x at the contact (the default rig's arm, h/l = 0.348/0.70)
    np.testing.assert_allclose(ds.measured_coa, ds.t56 / (0.452 * ds.air_spring_force), rtol=1e-12)
    np.testing.assert_allclose(
        ds.normal_load, ds.air_spring_force + 0.348 / 0.70 * ds.contact_force, rtol=1e-11
    )
    np.testing.assert_allclose(ds.coa, ds.contact_force / ds.normal_load, rtol=1e-12)


def test_provenance_has_the_package_record_and_the_rig_hash(ds):
    prov = json.loads(ds.attrs["provenance"])
    rig = default_rig()
    assert prov["software"] == "rollerrig" and prov["version"]
    assert prov["commit"] is not None or prov["commit_note"]
    assert isinstance(prov["command"], list)
    # "rig" is {name, sha256} as in every output of the package; the set itself beside it.
    assert prov["rig"] == {"name": rig.meta.name, "sha256": rig_sha256(rig)}
    assert prov["rig_parameters"]["geometry"]["roller_radius_x"] == rig.geometry.roller_radius_x
    assert prov["protocol"]["name"] == "tiny-standstill"
    assert "NaN" not in ds.attrs["provenance"]


def test_netcdf_is_cf_with_units_and_the_same_provenance(ds, tmp_path):
    import xarray as xr

    path = save_dataset(ds, tmp_path / "run.nc")
    with xr.open_dataset(path, engine="h5netcdf") as back:
        assert back.attrs["Conventions"] == "CF-1.10"
        assert back.attrs["title"] == ds.attrs["title"]
        assert back.attrs["history"] and back.attrs["experiment"] == "tiny-standstill"
        assert json.loads(back.attrs["provenance"]) == json.loads(ds.attrs["provenance"])
        assert back.attrs["measured_creep_nan_samples"] == ds.attrs["measured_creep_nan_samples"]
        for name, var in ds.data_vars.items():
            assert back[name].attrs["long_name"] == var.attrs["long_name"]
            if name != "friction_condition":
                assert back[name].attrs["units"] == var.attrs["units"], name
        assert back.measured_creep.attrs["nan_meaning"] == ds.measured_creep.attrs["nan_meaning"]
        np.testing.assert_array_equal(back.measured_creep.values, ds.measured_creep.values)
        assert back.friction_condition.values[0] == "dry"
        assert back.time.attrs["units"] == "s"


def test_mat_is_column_vectors_with_a_units_struct(ds, tmp_path):
    from scipy.io import loadmat

    mat = loadmat(save_dataset(ds, tmp_path / "run.mat"))
    n = ds.time.size
    assert mat["time"].shape == (n, 1) and mat["t56"].shape == (n, 1)
    np.testing.assert_array_equal(mat["t56"][:, 0], ds.t56.values)
    units = mat["units"][0, 0]
    assert str(units["t56"][0]) == "N.m" and str(units["measured_creep"][0]) == "1"
    assert str(units["time"][0]) == "s"
    numeric = [v for v in ds.data_vars if v != "friction_condition"]
    assert set(numeric) <= set(units.dtype.names)
    assert json.loads(str(mat["provenance"][0])) == json.loads(ds.attrs["provenance"])


def test_csv_and_parquet_carry_units_and_provenance(ds, tmp_path):
    import pandas as pd
    import pyarrow.parquet as pq

    csv = save_dataset(ds, tmp_path / "run.csv")
    frame = pd.read_csv(csv)
    assert frame.columns[0] == "time [s]" and "t56 [N.m]" in frame.columns
    assert "measured_creep [-]" in frame.columns and "friction_condition" in frame.columns
    meta = json.loads(csv.with_suffix(".metadata.json").read_text())
    assert meta["provenance"] == json.loads(ds.attrs["provenance"])
    assert "standstill" in meta["variables"]["measured_creep"]["nan_meaning"]

    table = pq.read_table(save_dataset(ds, tmp_path / "run.parquet"))
    assert table.schema.field("t56").metadata[b"unit"] == b"N.m"
    blob = json.loads(table.schema.metadata[b"rollerrig"])
    assert blob["metadata"]["provenance"]["rig"]["sha256"] == rig_sha256(default_rig())


def test_save_dataset_refuses_to_overwrite_and_unknown_formats(ds, tmp_path):
    assert SAVE_FORMATS == (".nc", ".csv", ".parquet", ".mat")
    path = save_dataset(ds, tmp_path / "run.parquet")
    with pytest.raises(FileExistsError, match="overwrite=True"):
        save_dataset(ds, path)
    save_dataset(ds, path, overwrite=True)
    with pytest.raises(ValueError, match="format"):
        save_dataset(ds, tmp_path / "run.xlsx")


def test_build_results_refuses_states_that_do_not_match_the_times():
    import re

    from rollerrig._validation import ParameterError
    from rollerrig.solve.results import build_results

    sim = Simulation(output_rate=50.0)
    t = sim.times
    x = np.zeros((t.size, sim.inputs.initial_state.size))
    with pytest.raises(ParameterError, match=re.escape("x must have shape (len(t), n_states)")):
        build_results(sim.inputs, t[:-3], x, {})
    with pytest.raises(ParameterError, match=re.escape("x must have shape (len(t), n_states)")):
        build_results(sim.inputs, t, x[:, 0], {})
    with pytest.raises(ParameterError, match=re.escape("solver must be a mapping")):
        build_results(sim.inputs, t, x, None)
    with pytest.raises(ParameterError, match=re.escape("ds must be an xarray Dataset")):
        save_dataset(None, "never-written.nc")
