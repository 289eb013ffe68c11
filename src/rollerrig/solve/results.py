"""Labelled results: truth channels beside what the rig would measure, with provenance.

The dataset holds, on one time axis sampled at the DAQ rate:

- truth: the contact force and true CoA, creep and slip velocity at the contact, every torque
  and speed of the chain, the drive currents and voltages;
- measured (``measured_*``): the roller-shaft torque T56 (the torque sensor), the speeds the
  encoders report (quantised: counts per sample interval), the normal force, and the creep, slip
  velocity, force and CoA the rig software derives from them, CoA = T56 / (r_r N);
- ``coa_error``: measured minus true CoA, the gap this project exists to expose.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import xarray as xr

from rollerrig.report._io import atomic_write
from rollerrig.rig import model as m

__all__ = ["SAVE_FORMATS", "build_dataset", "save_dataset"]

# name: (source, units, long name); source is a TERM name or ("state", index)
_TRUTH = {
    "torque_request": ("torque_request", "N.m", "wheel torque request"),
    "pmsm_torque": ("pmsm_torque", "N.m", "PMSM air-gap torque T_p (T12)"),
    "roller_drive_torque": ("roller_drive_torque", "N.m", "roller-drive air-gap torque T_a (T67)"),
    "roller_drive_torque_target": (
        "roller_drive_torque_target",
        "N.m",
        "roller-drive torque before the response lag",
    ),
    "roller_speed_setpoint": ("roller_speed_setpoint", "m/s", "roller peripheral speed set point"),
    "normal_load": ("normal_load", "N", "normal load N"),
    "contact_force": ("contact_force", "N", "longitudinal contact force F_x (true)"),
    "creep": ("creep", "1", "creep at the contact (true, from tyre and roller speeds)"),
    "slip_velocity": ("slip_velocity", "m/s", "slip velocity at the contact (true)"),
    "friction_coefficient": ("friction", "1", "slip-velocity-dependent friction coefficient"),
    "t01": ("t01", "N.m", "PMSM mount torque T01"),
    "t23": ("t23", "N.m", "wheel shaft torque T23"),
    "t34": ("t34", "N.m", "disc-tyre rubber torque T34"),
    "t56": ("t56", "N.m", "roller shaft torque T56"),
    "t70": ("t70", "N.m", "AM mount torque T70"),
    "bearing_torque_wheel": ("bearing_torque_wheel", "N.m", "wheel bearing loss torque R03"),
    "bearing_torque_roller": ("bearing_torque_roller", "N.m", "roller bearing loss torque R05"),
    "v_d": ("v_d", "V", "PMSM d-axis voltage"),
    "v_q": ("v_q", "V", "PMSM q-axis voltage"),
}
_STATES = {
    "pmsm_stator_speed": (m.X_OMEGA + 0, "rad/s", "PMSM stator speed (mount)"),
    "pmsm_rotor_speed": (m.X_OMEGA + 1, "rad/s", "PMSM rotor speed"),
    "wheel_disc_speed": (m.X_OMEGA + 2, "rad/s", "wheel disc speed"),
    "wheel_speed": (m.X_OMEGA + 3, "rad/s", "wheel tyre speed (at the contact)"),
    "roller_speed": (m.X_OMEGA + 4, "rad/s", "roller speed"),
    "am_rotor_speed": (m.X_OMEGA + 5, "rad/s", "AM rotor speed"),
    "am_stator_speed": (m.X_OMEGA + 6, "rad/s", "AM stator speed (mount)"),
    "i_d": (m.X_ID, "A", "PMSM d-axis current"),
    "i_q": (m.X_IQ, "A", "PMSM q-axis current"),
}

SAVE_FORMATS = (".nc", ".csv", ".parquet", ".mat")


def _encoder_speed(angle, t, counts_per_rev):
    """Speed an incremental encoder reports: counts per sample interval, as the DAQ computes it."""
    counts = np.floor(angle * counts_per_rev / (2.0 * np.pi))
    speed = np.empty_like(angle)
    speed[1:] = np.diff(counts) / np.diff(t) * 2.0 * np.pi / counts_per_rev
    speed[0] = speed[1] if angle.size > 1 else np.nan
    return speed


def build_dataset(inputs, t, x, solver: dict) -> xr.Dataset:
    """Assemble the labelled dataset from a solution.

    Parameters
    ----------
    inputs : ModelInputs
        What was simulated.
    t : ndarray, shape (n,)
        Sample times [s].
    x : ndarray, shape (n, N_STATES)
        States at those times.
    solver : dict
        Solver name, settings and statistics (kept in the provenance).

    Returns
    -------
    xarray.Dataset
    """
    from rollerrig import __version__
    from rollerrig.solve._compiled import rig_terms_series

    terms = np.empty((t.size, len(m.TERM_NAMES)))
    # Terms depend on friction through the segment's parameters: evaluate per segment.
    seg_of = np.searchsorted([s.end for s in inputs.segments], t, side="left")
    seg_of = np.minimum(seg_of, len(inputs.segments) - 1)
    for i, seg in enumerate(inputs.segments):
        sel = np.flatnonzero(seg_of == i)
        if sel.size:
            out = np.empty((sel.size, len(m.TERM_NAMES)))
            rig_terms_series(t[sel], np.ascontiguousarray(x[sel]), seg.params, inputs.tables, out)
            terms[sel] = out
    term = {name: terms[:, j] for j, name in enumerate(m.TERM_NAMES)}

    data = {}
    for name, (src, units, long_name) in _TRUTH.items():
        data[name] = ("time", term[src], {"units": units, "long_name": long_name})
    for name, (idx, units, long_name) in _STATES.items():
        data[name] = ("time", x[:, idx], {"units": units, "long_name": long_name})
    load = term["normal_load"]
    data["coa"] = (
        "time",
        term["contact_force"] / load,
        {"units": "1", "long_name": "true adhesion coefficient F_x / N"},
    )

    rig = inputs.rig
    rw, rr = rig.geometry.wheel_radius_x, rig.geometry.roller_radius_x
    cpr = rig.sensors.encoder_counts_per_revolution
    wheel_enc = _encoder_speed(x[:, m.X_THETA + 2], t, cpr)  # encoder on the wheel shaft (disc)
    roller_enc = _encoder_speed(x[:, m.X_THETA + 4], t, cpr)  # encoder on the roller shaft
    v_roller = roller_enc * rr
    slip = wheel_enc * rw - v_roller
    with np.errstate(divide="ignore", invalid="ignore"):
        creep_meas = np.where(np.abs(v_roller) > 0, slip / v_roller, np.nan)
    t56 = term["t56"]
    measured = {
        "measured_t56": (t56, "N.m", "roller-shaft torque sensor T56"),
        "measured_wheel_speed": (wheel_enc, "rad/s", "wheel encoder speed (quantised)"),
        "measured_roller_speed": (roller_enc, "rad/s", "roller encoder speed (quantised)"),
        "measured_normal_load": (load, "N", "normal force from the air-spring pressure"),
        "measured_slip_velocity": (slip, "m/s", "slip velocity from the encoders"),
        "measured_creep": (creep_meas, "1", "creep from the encoders (Kayaalp eq. 4.21)"),
        "measured_force": (t56 / rr, "N", "tangential force the rig derives, T56 / r_r"),
        "measured_coa": (t56 / (rr * load), "1", "CoA the rig reports, T56 / (r_r N)"),
    }
    for name, (values, units, long_name) in measured.items():
        data[name] = ("time", values, {"units": units, "long_name": long_name})
    data["coa_error"] = (
        "time",
        data["measured_coa"][1] - data["coa"][1],
        {"units": "1", "long_name": "measured minus true CoA"},
    )

    friction = np.array([inputs.segments[i].friction_condition for i in seg_of])
    data["friction_condition"] = ("time", friction, {"long_name": "friction condition"})

    provenance = {
        "software": "rollerrig",
        "version": __version__,
        "rig": rig.to_dict(),
        "rig_name": rig.meta.name,
        "protocol": inputs.protocol.to_dict(),
        "drives": {
            "wheel": inputs.drives.wheel,
            "roller": inputs.drives.roller,
            "roller_lag_s": float(inputs.segments[0].params[m.P_LAG_TAU]),
        },
        "friction_sets": {k: v.to_dict() for k, v in inputs.friction_sets.items()},
        "contact_reference": inputs.contact_reference,
        "solver": solver,
    }
    attrs = {
        "title": f"rollerrig simulation: {inputs.protocol.name} on {rig.meta.name}",
        "software": "rollerrig",
        "version": __version__,
        "experiment": inputs.protocol.name,
        "rig": rig.meta.name,
        "wheel_drive": inputs.drives.wheel,
        "roller_drive": inputs.drives.roller,
        "solver": solver.get("name", ""),
        "provenance": json.dumps(provenance, default=_jsonable),
    }
    ds = xr.Dataset(data, coords={"time": ("time", t, {"units": "s", "long_name": "time"})})
    ds.attrs.update(attrs)
    return ds


def _jsonable(obj):
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    return str(obj)


def save_dataset(ds: xr.Dataset, path: str | os.PathLike, *, overwrite: bool = False) -> Path:
    """Write a results dataset; the format follows the suffix (.nc, .csv, .parquet, .mat).

    NetCDF keeps every attribute; CSV puts units in the column headers and the provenance in a
    JSON file beside it; Parquet keeps it in the file's key-value metadata; .mat in a
    ``provenance`` string. Writing is atomic and never replaces an existing file unless
    ``overwrite`` is set.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in SAVE_FORMATS:
        raise ValueError(f"unknown results format {suffix!r}; choose one of {SAVE_FORMATS}")
    if path.exists() and not overwrite:
        raise FileExistsError(f"{path} exists; pass overwrite=True to replace it")
    if suffix == ".nc":
        return atomic_write(path, lambda p: ds.to_netcdf(p, engine="h5netcdf"))
    frame = ds.drop_vars("friction_condition").to_dataframe()
    frame.columns = [f"{c} [{ds[c].attrs.get('units', '')}]" for c in frame.columns]
    frame.index.name = "time [s]"
    frame["friction_condition"] = ds["friction_condition"].values
    if suffix == ".csv":
        atomic_write(
            path.with_suffix(".provenance.json"), lambda p: p.write_text(ds.attrs["provenance"])
        )
        return atomic_write(path, lambda p: frame.to_csv(p))
    if suffix == ".parquet":
        import pyarrow as pa
        import pyarrow.parquet as pq

        table = pa.Table.from_pandas(frame.reset_index())
        meta = dict(table.schema.metadata or {})
        meta[b"rollerrig_provenance"] = ds.attrs["provenance"].encode()
        table = table.replace_schema_metadata(meta)
        return atomic_write(path, lambda p: pq.write_table(table, p))
    from scipy.io import savemat

    mat = {k.replace(" ", ""): ds[k].values for k in ds.data_vars if k != "friction_condition"}
    mat["time"] = ds["time"].values
    mat["provenance"] = ds.attrs["provenance"]
    return atomic_write(path, lambda p: savemat(p, mat, do_compression=True))
