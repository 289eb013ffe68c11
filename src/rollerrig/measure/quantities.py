"""Physical quantities from raw DAQ channels, computed "as the rig does today".

- Normal force from the air-spring pressure, N = p·A_eff.
- Angular speed from cumulative encoder counts: counts over a gate of k sample intervals,
  ω = 2π Δc / (CPR · k Δt). One count in the gate is a speed step of 2π/(CPR·k·Δt): with
  10000 counts per revolution at 250 Hz, 0.157 rad/s for k = 1 (0.85 % of the roller's
  18.4 rad/s at 30 km/h, i.e. a creep resolution of about 0.85 %), ten times finer for k = 10
  at a tenth of the bandwidth (the gate is a moving average of k samples).
- Creep and slip velocity (Kayaalp eqs. 4.21-4.22), s = (ω_w r_w − ω_r r_r)/(ω_r r_r), by
  :func:`rollerrig.contact.kinematics.creep_and_slip_velocity`.
- Tangential force F = T/r_r and CoA = T/(r_r N) from the roller-shaft torque T56: the rig's
  present estimate, which ignores the roller's inertia and bearing losses (the gap the twin
  exposes, see :mod:`rollerrig.solve.results`).
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from typing import Any

import numpy as np

from rollerrig._validation import require_broadcastable, require_finite, require_positive
from rollerrig.contact.kinematics import DEFAULT_REGULARISATION_SPEED
from rollerrig.contact.kinematics import creep_and_slip_velocity as _creep_and_slip
from rollerrig.contact.kinematics import creep_kernel as _creep_kernel
from rollerrig.recordings.recording import CANONICAL_CHANNELS, Recording, RecordingError

__all__ = [
    "ANALYSIS_CHANNELS",
    "DERIVED_CHANNELS",
    "coefficient_of_adhesion",
    "creep_and_slip_velocity",
    "derive_quantities",
    "encoder_speed",
    "encoder_speed_resolution",
    "normal_force_from_pressure",
    "tangential_force",
]

DERIVED_CHANNELS: dict[str, tuple[str, str]] = {
    "creep": ("1", "creep from the encoder speeds (Kayaalp eq. 4.21)"),
    "slip_velocity": ("m/s", "slip velocity from the encoder speeds (Kayaalp eq. 4.22)"),
    "tangential_force": ("N", "tangential force the rig derives, T / r_r"),
    "coa": ("1", "coefficient of adhesion the rig reports, T / (r_r N)"),
}
"""Channels :func:`derive_quantities` adds beside the canonical ones: name -> (unit, meaning)."""

ANALYSIS_CHANNELS: dict[str, tuple[str, str]] = {
    "torque_smoothed": ("N.m", "roller-shaft torque T56, Savitzky-Golay smoothed"),
    "creep_smoothed": ("1", "creep from the smoothed wheel and roller speeds"),
    "slip_velocity_smoothed": ("m/s", "slip velocity from the smoothed wheel and roller speeds"),
    "coa_smoothed": ("1", "CoA the rig reports from the smoothed torque, T56 / (r_r N)"),
    "coa_corrected": (
        "1",
        "CoA corrected for the roller's inertia and bearing loss, "
        "(T56 + J5 alpha5 + R05) / (r_r N)",
    ),
    "roller_acceleration": (
        "rad/s^2",
        "roller angular acceleration alpha5 (Savitzky-Golay derivative of the roller speed)",
    ),
}
"""Channels :func:`rollerrig.analysis.adhesion.analyze_test` adds: name -> (SI unit, meaning)."""

creep_and_slip_velocity = _creep_and_slip


def normal_force_from_pressure(pressure, effective_area):
    """Normal force of the air spring.

    .. math:: N = p \\, A_{eff}

    Parameters
    ----------
    pressure : array_like
        Air-spring gauge pressure p [Pa].
    effective_area : float
        Effective area of the air spring A_eff [m^2], > 0.

    Returns
    -------
    numpy.ndarray
        N [N].

    Examples
    --------
    >>> float(normal_force_from_pressure(86e3, 0.05))
    4300.0
    """
    p = require_finite("pressure", pressure, "Pa")
    area = require_positive("effective_area", effective_area, "m^2")
    return p * area


def encoder_speed_resolution(counts_per_revolution, interval):
    """Speed step of one encoder count in a gate of duration ``interval``.

    .. math:: \\Delta\\omega = \\frac{2\\pi}{\\mathrm{CPR}\\,\\Delta t}

    Parameters
    ----------
    counts_per_revolution : float
        Counts per revolution after quadrature decoding [-].
    interval : array_like
        Gate duration k·Δt [s].

    Returns
    -------
    numpy.ndarray
        Δω [rad/s].

    Examples
    --------
    >>> round(float(encoder_speed_resolution(10000, 1 / 250)), 4)
    0.1571
    """
    cpr = require_positive("counts_per_revolution", counts_per_revolution, "1")
    dt = require_positive("interval", interval, "s")
    return 2.0 * np.pi / (cpr * dt)


def encoder_speed(counts, time, counts_per_revolution, gate: int = 1, centred: bool = False):
    """Angular speed from cumulative encoder counts, over a gate of ``gate`` sample intervals.

    .. math:: \\omega_i = \\frac{2\\pi}{\\mathrm{CPR}}\\,
              \\frac{c_i - c_{i-k}}{t_i - t_{i-k}}

    The resolution is 2π/(CPR·k·Δt) (:func:`encoder_speed_resolution`); a longer gate k trades
    bandwidth (a k-sample moving average) for resolution. With ``centred=False`` the value is
    the DAQ's causal estimate at the end of the gate (delayed by k·Δt/2); the first k samples
    use the gate available so far and sample 0 repeats sample 1 (as
    :func:`rollerrig.solve.results.build_dataset` does for k = 1). With ``centred=True`` each
    gate's mean speed is placed at its mid-time and interpolated to the sample times (no delay;
    the ends hold the nearest value).

    Parameters
    ----------
    counts : array_like, shape (n,)
        Cumulative encoder counts [-].
    time : array_like, shape (n,)
        Sample times [s], strictly increasing.
    counts_per_revolution : float
        Counts per revolution [-], > 0.
    gate : int
        Gate length k in samples [-], >= 1.
    centred : bool
        Place each estimate at the middle of its gate.

    Returns
    -------
    numpy.ndarray, shape (n,)
        ω [rad/s].

    Examples
    --------
    A shaft at 1 rev/s with 1000 counts per revolution, sampled at 100 Hz:

    >>> t = np.arange(6) / 100.0
    >>> c = np.floor(t * 1000)
    >>> np.round(encoder_speed(c, t, 1000) / (2 * np.pi), 6).tolist()
    [1.0, 1.0, 1.0, 1.0, 1.0, 1.0]
    """
    c = require_finite("counts", counts, "1")
    t = require_finite("time", time, "s")
    cpr = require_positive("counts_per_revolution", counts_per_revolution, "1", single=True)
    k = int(gate)
    if k < 1 or k != gate:
        raise RecordingError(f"gate must be an integer >= 1 [samples], got {gate!r}")
    if c.shape != t.shape or t.ndim != 1 or t.size < 2:
        raise RecordingError(f"counts {c.shape} and time {t.shape} must be 1-D, same length >= 2")
    if np.any(np.diff(t) <= 0.0):  # a step back had given a negative speed, a repeat inf
        k = int(np.flatnonzero(np.diff(t) <= 0.0)[0]) + 1
        raise RecordingError(
            f"time must be strictly increasing [s]: time[{k}] = {t[k]:.9g} after "
            f"time[{k - 1}] = {t[k - 1]:.9g}"
        )
    scale = 2.0 * np.pi / cpr
    n = t.size
    if centred:
        if k >= n:
            raise RecordingError(f"gate {k} must be shorter than the recording ({n} samples)")
        mean_speed = scale * (c[k:] - c[:-k]) / (t[k:] - t[:-k])
        mid = 0.5 * (t[k:] + t[:-k])
        return np.interp(t, mid, mean_speed)
    start = np.maximum(np.arange(n) - k, 0)
    speed = np.empty(n)
    speed[1:] = scale * (c[1:] - c[start[1:]]) / (t[1:] - t[start[1:]])
    speed[0] = speed[1]
    return speed


def tangential_force(torque, roller_radius):
    """Tangential force the rig derives from the roller-shaft torque.

    .. math:: F = T_{56} / r_r

    Parameters
    ----------
    torque : array_like
        Roller-shaft torque T56 [N.m].
    roller_radius : float
        Roller rolling radius r_r [m].

    Returns
    -------
    numpy.ndarray
        F [N].

    Examples
    --------
    >>> float(tangential_force(452.0, 0.452))
    1000.0
    """
    tq = require_finite("torque", torque, "N.m")
    rr = require_positive("roller_radius", roller_radius, "m")
    return tq / rr


def coefficient_of_adhesion(torque, roller_radius, normal_force):
    """Coefficient of adhesion as the rig reports it.

    .. math:: \\mathrm{CoA} = \\frac{T_{56}}{r_r N}

    Parameters
    ----------
    torque : array_like
        Roller-shaft torque T56 [N.m].
    roller_radius : float
        Roller rolling radius r_r [m].
    normal_force : array_like
        Normal force N [N], > 0.

    Returns
    -------
    numpy.ndarray
        CoA [-].

    Examples
    --------
    >>> round(float(coefficient_of_adhesion(904.0, 0.452, 4000.0)), 6)
    0.5
    """
    tq = require_finite("torque", torque, "N.m")
    rr = require_positive("roller_radius", roller_radius, "m")
    n = require_positive("normal_force", normal_force, "N")
    tq, rr, n = require_broadcastable(torque=tq, roller_radius=rr, normal_force=n)
    return tq / (rr * n)


def _rig_values(recording: Recording, rig_or_params) -> dict[str, float]:
    """Roller/wheel radii, counts per revolution and air-spring area from a rig description."""
    if rig_or_params is None:
        rig: Any = recording.metadata.get("rig")
        if rig is None and "twin_provenance" in recording.metadata:
            twin = json.loads(recording.metadata["twin_provenance"])
            rig = twin.get("rig_parameters") or twin["rig"]  # "rig": files before 0.1.0
        if rig is None:
            raise RecordingError(
                "derive_quantities needs the rig parameters: pass rig_or_params "
                "(RigParameters or a {section: {key: value}} mapping)"
            )
    else:
        rig = rig_or_params
    if hasattr(rig, "to_dict") and not isinstance(rig, Mapping):
        rig = rig.to_dict()
    try:
        geometry, sensors = rig["geometry"], rig["sensors"]
        # A mapping is not a validated rig: a negative or NaN radius had made every sample's
        # creep -2.03 or NaN. Each value named as its key.
        values = {
            key: require_positive(f"{section}.{name}", section_map[name], unit, single=True)
            for key, section, section_map, name, unit in (
                ("wheel_radius", "geometry", geometry, "wheel_radius_x", "m"),
                ("roller_radius", "geometry", geometry, "roller_radius_x", "m"),
                ("ppr", "sensors", sensors, "encoder_pulses_per_revolution", "1"),
                ("quadrature", "sensors", sensors, "encoder_quadrature_factor", "1"),
                ("area", "sensors", sensors, "air_spring_effective_area", "m^2"),
            )
        }
        return {
            "wheel_radius": values["wheel_radius"],
            "roller_radius": values["roller_radius"],
            "cpr": values["ppr"] * values["quadrature"],
            "area": values["area"],
        }
    except (KeyError, TypeError) as exc:
        raise RecordingError(
            f"rig parameters lack {exc}: need geometry.wheel_radius_x, geometry.roller_radius_x, "
            "sensors.encoder_pulses_per_revolution, sensors.encoder_quadrature_factor, "
            "sensors.air_spring_effective_area"
        ) from None


def derive_quantities(
    recording: Recording,
    rig_or_params=None,
    *,
    gate: int = 1,
    centred: bool = False,
) -> Recording:
    """Add the physical quantities the rig derives from its raw channels.

    Adds, where their inputs are present and they are not already there: ``normal_load`` [N]
    from ``air_spring_pressure``; ``wheel_speed`` and ``roller_speed`` [rad/s] from the encoder
    counts (:func:`encoder_speed` with ``gate`` and ``centred``); ``creep`` [-] and
    ``slip_velocity`` [m/s] from the speeds; ``tangential_force`` [N] and ``coa`` [-] from
    ``torque`` (and ``normal_load``).

    Parameters
    ----------
    recording : Recording
        Raw channels by canonical name.
    rig_or_params : RigParameters or mapping, optional
        The rig (radii, encoder resolution, air-spring area); a ``{section: {key: value}}``
        mapping in SI (as ``RigParameters.to_dict()`` gives) also works. Default: the ``rig``
        entry of the recording's metadata (synthetic recordings carry it).
    gate : int
        Encoder gate in samples [-].
    centred : bool
        Centre the encoder speed on its gate (see :func:`encoder_speed`).

    Returns
    -------
    Recording
        A copy with the derived channels added; its ``metadata["derived"]`` holds the gate, the
        rig values and definitions used, the names of the channels computed here
        (``"channels"``) and what each was computed from (``"from"``, which error messages
        quote).

    Examples
    --------
    >>> t = np.arange(4) / 250.0
    >>> rec = Recording(t, {"torque": np.full(4, 904.0), "air_spring_pressure": np.full(4, 8e4)},
    ...                 {"torque": "N.m", "air_spring_pressure": "Pa"})
    >>> rig = {"geometry": {"wheel_radius_x": 0.348, "roller_radius_x": 0.452},
    ...        "sensors": {"encoder_pulses_per_revolution": 2500, "encoder_quadrature_factor": 4,
    ...                    "air_spring_effective_area": 0.05}}
    >>> out = derive_quantities(rec, rig)
    >>> float(out["normal_load"][0]), round(float(out["coa"][0]), 6)
    (4000.0, 0.5)
    """
    rig = _rig_values(recording, rig_or_params)
    channels = dict(recording.channels)
    units = dict(recording.units)

    added: dict[str, str] = {}  # name -> what it was computed from (for messages)

    def add(name: str, values: np.ndarray, source: str) -> None:
        channels[name] = values
        units[name] = (CANONICAL_CHANNELS.get(name) or DERIVED_CHANNELS[name])[0]
        added[name] = source

    if "normal_load" not in channels and "air_spring_pressure" in channels:
        add(
            "normal_load",
            normal_force_from_pressure(channels["air_spring_pressure"], rig["area"]),
            "the air-spring pressure times its effective area",
        )
    for which in ("wheel", "roller"):
        counts = f"{which}_encoder_counts"
        if f"{which}_speed" not in channels and counts in channels:
            add(
                f"{which}_speed",
                encoder_speed(channels[counts], recording.time, rig["cpr"], gate, centred),
                f"the {which} encoder's counts",
            )
    if "wheel_speed" in channels and "roller_speed" in channels:
        creep, slip = _creep_kernel(
            channels["wheel_speed"],
            channels["roller_speed"],
            rig["wheel_radius"],
            rig["roller_radius"],
            DEFAULT_REGULARISATION_SPEED,
        )
        add("creep", creep, "the wheel and roller speeds")
        add("slip_velocity", slip, "the wheel and roller speeds")
    if "torque" in channels:
        force = tangential_force(channels["torque"], rig["roller_radius"])
        add("tangential_force", force, "the torque over r_r")
        if "normal_load" in channels:
            load = channels["normal_load"]
            with np.errstate(divide="ignore", invalid="ignore"):
                coa = np.where(load > 0, channels["torque"] / (rig["roller_radius"] * load), np.nan)
            add(
                "coa",
                coa,
                "the torque over r_r times the normal load; NaN where the normal load is <= 0 N",
            )
    metadata = dict(recording.metadata)
    metadata["derived"] = {
        "gate_samples": int(gate),
        "centred": bool(centred),
        "rig_values": rig,
        "definitions": "N = p A_eff; s = (w_w r_w - w_r r_r)/(w_r r_r); F = T/r_r; CoA = T/(r_r N)",
        "channels": list(added),  # computed here, not read: messages name them as such
        "from": added,
    }
    return Recording(recording.time, channels, units, metadata)
