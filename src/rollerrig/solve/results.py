"""Labelled results: truth channels beside what the rig would measure, with provenance.

The dataset holds, on one time axis sampled at the DAQ rate:

- truth: the contact force and true CoA, creep and slip velocity at the contact, every torque
  and speed of the chain, the angular accelerations of tyre, roller and AM rotor (the equations
  of motion at each sample), the drive currents and voltages;
- measured (``measured_*``): the roller-shaft torque T56 (the torque sensor), the speeds the
  encoders report (quantised: counts per sample interval), the normal force, and the creep, slip
  velocity, force and CoA the rig software derives from them, CoA = T56 / (r_r S);
- ``coa_error``: measured minus true CoA, the gap this project exists to expose.

NaN policy (:mod:`rollerrig.output`): a derived channel holds NaN only where it is undefined,
and says so in its ``nan_meaning`` attribute; the dataset attribute ``<name>_nan_samples``
counts them. ``measured_creep`` is undefined at standstill (roller encoder speed 0: no counts in
the sample interval), the CoA channels where the normal load is 0.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rollerrig._validation import ParameterError, require_finite
from rollerrig.output import OutputError, write_dataset
from rollerrig.output.jsonfile import json_text
from rollerrig.output.labelled import LabelledData
from rollerrig.output.provenance import provenance as _provenance
from rollerrig.output.provenance import rig_sha256
from rollerrig.rig import model as m

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "SAVE_FORMATS",
    "build_dataset",
    "build_results",
    "evaluate_terms",
    "first_segment_terms",
    "save_dataset",
]

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
    "air_spring_force": ("air_spring_force", "N", "air-spring force S (the load the rig sets)"),
    "normal_load": ("normal_load", "N", "normal load N at the contact, S + W_d + σ (h/l) F_x"),
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

_ACCELERATIONS = {
    "wheel_acceleration": (m.X_OMEGA + 3, "rad/s^2", "wheel tyre angular acceleration α4"),
    "roller_acceleration": (m.X_OMEGA + 4, "rad/s^2", "roller angular acceleration α5"),
    "am_rotor_acceleration": (m.X_OMEGA + 5, "rad/s^2", "AM rotor angular acceleration α6"),
}
"""Accelerations of the truth [rad/s²]: the right-hand side at the output instants
(:func:`rollerrig.solve._compiled.rig_rates_series`), so that the roller's equation of motion
F_x r_r = T56 + J5 α5 + R05 holds at every sample, at any output rate (issue 20, point 4)."""

_FRAME_STATES = {
    "frame_displacement": (
        m.X_FRAME_X,
        "m",
        "longitudinal displacement of the roller's contact point relative to the wheel's",
    ),
    "frame_velocity": (m.X_FRAME_V, "m/s", "its velocity"),
}

_FRAME_DQ = "in the V/f controller's frame rotating at the output frequency"
_DQ_STATES = {
    "am_psi_s_d": (m.N_STATES + 0, "Wb", f"AM stator flux linkage, d axis {_FRAME_DQ}"),
    "am_psi_s_q": (m.N_STATES + 1, "Wb", f"AM stator flux linkage, q axis {_FRAME_DQ}"),
    "am_psi_r_d": (m.N_STATES + 2, "Wb", f"AM rotor flux linkage (inverse-Γ), d axis {_FRAME_DQ}"),
    "am_psi_r_q": (m.N_STATES + 3, "Wb", f"AM rotor flux linkage (inverse-Γ), q axis {_FRAME_DQ}"),
}
"""Variables of the roller drive ``"induction_dq"`` (:mod:`rollerrig.rig.model_dq`)."""

SAVE_FORMATS = (".nc", ".csv", ".parquet", ".mat")

_NO_LOAD = "undefined where the normal load is 0 (CoA = F / N)"
NAN_MEANINGS = {
    "coa": _NO_LOAD,
    "measured_creep": (
        "creep undefined at standstill: roller encoder speed 0 (no counts in the sample "
        "interval), s = slip / v_roller"
    ),
    "measured_coa": _NO_LOAD,
    "coa_error": _NO_LOAD,
}
"""Derived channels that may hold NaN, and where (their ``nan_meaning`` attribute)."""


def _encoder_speed(angle, t, counts_per_rev):
    """Speed an incremental encoder reports: counts per sample interval, as the DAQ computes it."""
    counts = np.floor(angle * counts_per_rev / (2.0 * np.pi))
    speed = np.empty_like(angle)
    speed[1:] = np.diff(counts) / np.diff(t) * 2.0 * np.pi / counts_per_rev
    speed[0] = speed[1] if angle.size > 1 else np.nan
    return speed


def _segment_of(inputs, t: np.ndarray) -> np.ndarray:
    """Index of the protocol segment of each sample time."""
    seg_of = np.searchsorted([s.end for s in inputs.segments], t, side="left")
    return np.minimum(seg_of, len(inputs.segments) - 1)


def first_segment_terms(inputs, t, x) -> np.ndarray:
    """The model's derived quantities at every sample with the first protocol segment's
    parameters, as an array (n, len(TERM_NAMES)) in the order of
    :data:`rollerrig.rig.model.TERM_NAMES`: exact for the terms that do not depend on a
    segment's friction or set points (T56, the shaft torques), and cheap (one compiled pass,
    no accelerations); :func:`evaluate_terms` for everything.

    Parameters
    ----------
    inputs : ModelInputs
        What was simulated (the rig's own states: not the dq drive's).
    t : ndarray, shape (n,)
        Sample times [s].
    x : ndarray, shape (n, N_STATES)
        States at those times.
    """
    from rollerrig.solve._compiled import rig_terms_series

    terms = np.empty((np.size(t), len(m.TERM_NAMES)))
    rig_terms_series(t, np.ascontiguousarray(x), inputs.segments[0].params, inputs.tables, terms)
    return terms


def evaluate_terms(inputs, t, x) -> dict[str, np.ndarray]:
    """The model's derived quantities (:data:`rollerrig.rig.model.TERM_NAMES`) at every sample.

    Parameters
    ----------
    inputs : ModelInputs
        What was simulated.
    t : ndarray, shape (n,)
        Sample times [s].
    x : ndarray, shape (n, N_STATES)
        States at those times.

    Returns
    -------
    dict of str to ndarray
        Term name -> values (SI units, see :data:`_TRUTH`), e.g. ``"t56"`` [N.m],
        ``"contact_force"`` [N], ``"normal_load"`` [N]; and the accelerations of
        :data:`_ACCELERATIONS` [rad/s²] from the right-hand side at the same instants.
    """
    from rollerrig.solve._compiled import rig_rates_series, rig_terms_series

    dq = inputs.drives.roller == "induction_dq"
    if dq:  # the rig's part, with the machine's air-gap torque in the roller-drive slot
        x = _rig_part_of_dq(inputs, x)
    terms = np.empty((t.size, len(m.TERM_NAMES)))
    rates = np.empty((t.size, m.N_STATES))
    # Terms depend on friction through the segment's parameters: evaluate per segment.
    seg_of = _segment_of(inputs, t)
    for i, seg in enumerate(inputs.segments):
        sel = np.flatnonzero(seg_of == i)
        if sel.size:
            out = np.empty((sel.size, len(m.TERM_NAMES)))
            xs = np.ascontiguousarray(x[sel, : m.N_STATES])
            p = np.ascontiguousarray(seg.params[: m.N_PARAMS])
            rig_terms_series(t[sel], xs, p, inputs.tables, out)
            terms[sel] = out
            out = np.empty((sel.size, m.N_STATES))
            rig_rates_series(t[sel], xs, p, inputs.tables, out)
            rates[sel] = out
    result = {name: terms[:, j] for j, name in enumerate(m.TERM_NAMES)}
    for name, (idx, _, _) in _ACCELERATIONS.items():
        result[name] = rates[:, idx]
    if dq:  # no lag: the torque is the machine's own
        result["roller_drive_torque_target"] = result["roller_drive_torque"].copy()
    return result


def _rig_part_of_dq(inputs, x: np.ndarray) -> np.ndarray:
    """The rig's 22 states of a dq-drive solution, the roller torque slot set to the machine's
    air-gap torque (:func:`rollerrig.rig.model_dq.air_gap_torque`)."""
    from rollerrig.rig import model_dq

    p = inputs.segments[0].params  # the machine's parameters are the same in every segment
    xr = np.array(x[:, : m.N_STATES], dtype=float)
    xr[:, m.X_T_ROLLER] = model_dq.air_gap_torque(x.T, p)
    return np.ascontiguousarray(xr)


def _solution(inputs, t, x) -> tuple[np.ndarray, np.ndarray]:
    """``t`` and ``x`` as float arrays of shapes (n,) and (n, n_states) (numpy's broadcast
    and index errors had named neither)."""
    t = require_finite("t", t, "s")
    x = np.asarray(x, dtype=float)
    n_states = inputs.initial_state.size
    if t.ndim != 1 or x.shape != (t.size, n_states):
        raise ParameterError(
            f"x must have shape (len(t), n_states) = ({t.size if t.ndim == 1 else '?'}, "
            f"{n_states}) for t of shape {t.shape}, got x of shape {x.shape}"
        )
    return t, x


def build_dataset(inputs, t, x, solver: dict) -> xr.Dataset:
    """Assemble the labelled dataset from a solution: :func:`build_results` (same parameters)
    as an :class:`xarray.Dataset`."""
    return build_results(inputs, t, x, solver).to_xarray()


def build_results(inputs, t, x, solver: dict) -> LabelledData:
    """Assemble the labelled results from a solution, without xarray.

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
    LabelledData
        The content of :func:`build_dataset`'s Dataset (variables, coordinate ``time``,
        attributes), which :func:`save_dataset`, :func:`rollerrig.report.twin.
        experiment_figure` and :func:`rollerrig.studies.metrics.release_overshoots` take as
        they take the Dataset.
    """
    from rollerrig import __version__

    t, x = _solution(inputs, t, x)
    if not isinstance(solver, Mapping):
        raise ParameterError(
            f"solver must be a mapping (its name, settings and statistics), got a "
            f"{type(solver).__name__}"
        )
    term = evaluate_terms(inputs, t, x)
    seg_of = _segment_of(inputs, t)

    data = {}
    for name, (src, units, long_name) in _TRUTH.items():
        data[name] = ("time", term[src], {"units": units, "long_name": long_name})
    for name, (idx, units, long_name) in _STATES.items():
        data[name] = ("time", x[:, idx], {"units": units, "long_name": long_name})
    for name, (_, units, long_name) in _ACCELERATIONS.items():
        data[name] = ("time", term[name], {"units": units, "long_name": long_name})
    if inputs.drives.frame != "rigid":  # the frame's degree of freedom, when it has one
        for name, (idx, units, long_name) in _FRAME_STATES.items():
            data[name] = ("time", x[:, idx], {"units": units, "long_name": long_name})
    if inputs.drives.roller == "induction_dq":  # the machine's fluxes
        for name, (idx, units, long_name) in _DQ_STATES.items():
            data[name] = ("time", x[:, idx], {"units": units, "long_name": long_name})

    def per(load: np.ndarray):
        loaded = load > 0.0

        def divide(values: np.ndarray) -> np.ndarray:
            with np.errstate(divide="ignore", invalid="ignore"):
                return np.where(loaded, values / np.where(loaded, load, 1.0), np.nan)

        return divide

    # The truth divides by the load at the contact, the rig by the air-spring force it measures.
    per_load, per_spring = per(term["normal_load"]), per(term["air_spring_force"])

    data["coa"] = (
        "time",
        per_load(term["contact_force"]),
        {"units": "1", "long_name": "true adhesion coefficient F_x / N"},
    )

    rig = inputs.rig
    rw, rr = rig.geometry.wheel_radius_x, rig.geometry.roller_radius_x
    cpr = rig.sensors.encoder_counts_per_revolution
    wheel_enc = _encoder_speed(x[:, m.X_THETA + 2], t, cpr)  # encoder on the wheel shaft (disc)
    roller_enc = _encoder_speed(x[:, m.X_THETA + 4], t, cpr)  # encoder on the roller shaft
    v_roller = roller_enc * rr
    slip = wheel_enc * rw - v_roller
    moving = np.abs(v_roller) > 0
    creep_meas = np.where(moving, slip / np.where(moving, v_roller, 1.0), np.nan)
    t56 = term["t56"]
    measured = {
        "measured_t56": (t56, "N.m", "roller-shaft torque sensor T56"),
        "measured_wheel_speed": (wheel_enc, "rad/s", "wheel encoder speed (quantised)"),
        "measured_roller_speed": (roller_enc, "rad/s", "roller encoder speed (quantised)"),
        "measured_normal_load": (
            term["air_spring_force"],
            "N",
            "normal force from the air-spring pressure",
        ),
        "measured_slip_velocity": (slip, "m/s", "slip velocity from the encoders"),
        "measured_creep": (creep_meas, "1", "creep from the encoders (Kayaalp eq. 4.21)"),
        "measured_force": (t56 / rr, "N", "tangential force the rig derives, T56 / r_r"),
        "measured_coa": (per_spring(t56 / rr), "1", "CoA the rig reports, T56 / (r_r S)"),
    }
    for name, (values, units, long_name) in measured.items():
        data[name] = ("time", values, {"units": units, "long_name": long_name})
    data["coa_error"] = (
        "time",
        data["measured_coa"][1] - data["coa"][1],
        {"units": "1", "long_name": "measured minus true CoA"},
    )

    nan_counts = {}
    for name, meaning in NAN_MEANINGS.items():
        data[name][2]["nan_meaning"] = meaning
        nan_counts[f"{name}_nan_samples"] = int(np.count_nonzero(np.isnan(data[name][1])))

    friction = np.array([inputs.segments[i].friction_condition for i in seg_of])
    data["friction_condition"] = ("time", friction, {"long_name": "friction condition"})

    # The package's record (version, commit, command, inputs of the run), then the simulation:
    # "rig" is {name, sha256} as in every output; "rig_parameters" the whole set [SI] (the
    # synthetic recording and the figures read it).
    provenance = {
        **_provenance(),
        "rig": {"name": rig.meta.name, "sha256": rig_sha256(rig)},
        "rig_parameters": rig.to_dict(),
        "protocol": inputs.protocol.to_dict(),
        "drives": {
            "wheel": inputs.drives.wheel,
            "roller": inputs.drives.roller,
            "roller_lag_s": (
                None  # the dq drive has no lag: its dynamics are the machine's
                if inputs.drives.roller == "induction_dq"
                else float(inputs.segments[0].params[m.P_LAG_TAU])
            ),
            "frame": inputs.drives.frame,
            "law": inputs.drives.law,
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
        **nan_counts,
        "provenance": json_text(provenance),
    }
    time = {"time": ("time", t, {"units": "s", "long_name": "time"})}
    return LabelledData(data, coords=time, attrs=attrs)


def save_dataset(
    ds: xr.Dataset | LabelledData, path: str | os.PathLike, *, overwrite: bool = False
) -> Path:
    """Write a results dataset (or :func:`build_results`' labelled results); the format
    follows the suffix (.nc, .csv, .parquet, .mat).

    A thin adapter over :func:`rollerrig.output.write_dataset` (one convention per format: units
    on every column; NetCDF with CF-1.10 attributes; CSV with ``name [unit]`` headers and a
    ``<stem>.metadata.json`` sidecar; ``.mat`` as column vectors with a ``units`` struct and the
    ``provenance`` text). The dataset's attributes are the file's metadata, its ``provenance``
    attribute (JSON) the provenance record. Writing is atomic and never replaces an existing
    file unless ``overwrite`` is set.

    Raises
    ------
    OutputError
        An unknown suffix (a :class:`ValueError`), or the file cannot be written.
    FileExistsError
        The file exists and ``overwrite`` is False.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in SAVE_FORMATS:
        raise OutputError(
            f"{path}: unknown results format {suffix!r}; choose one of {SAVE_FORMATS}"
        )
    return write_dataset(path, ds, overwrite=overwrite)
