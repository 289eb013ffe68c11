"""The study of the roller drive under V/f coupled with the rig (issue 13): modes and the lag.

:func:`drive_dynamics_study` compares, JSON-ready, the twin's modes at steady free rolling with
the dq V/f drive (:data:`VARIANTS`, :func:`drive_variants`) and with the Thevenin drive, the
first-order lag (τ, c_lp) that best reproduces the dq drive's torque response (to compare with
Kayaalp's c_lp = 2.75), and each drive's verdict about a frequency band and whether it holds
over its assumptions (:mod:`rollerrig.rig.drive_verdicts`).

Its parts, each in its module, their public names also importable from here:

* :mod:`rollerrig.rig.dq_drive` — the machine and its controller
  (:class:`~rollerrig.rig.dq_drive.DqDrive`, :func:`~rollerrig.rig.dq_drive.default_dq_drive`):
  :func:`~rollerrig.rig.dq_drive.drive_steady_state` at a held rotor speed or delivering a
  torque, :func:`~rollerrig.rig.dq_drive.simulate_drive_on_inertia` on one rigid inertia (the
  set-up motulator simulates), :func:`~rollerrig.rig.dq_drive.fit_lag_at_held_speed`.
* :mod:`rollerrig.rig.dq_twin` — :class:`~rollerrig.rig.dq_twin.DqTwin`, the coupled twin: its
  right-hand side, steady free rolling, linearisation and simulation.
* :mod:`rollerrig.rig.drive_mode_tables` — the modes at steady free rolling, with and without
  the dq drive: :func:`~rollerrig.rig.drive_mode_tables.dq_coupled_modes`,
  :func:`~rollerrig.rig.drive_mode_tables.eigen_table`,
  :func:`~rollerrig.rig.drive_mode_tables.thevenin_eigen_table`,
  :func:`~rollerrig.rig.drive_mode_tables.format_eigen_table`.
* :mod:`rollerrig.rig.lag_in_rig` — :func:`~rollerrig.rig.lag_in_rig.fit_lag_in_rig`, the lag
  the dq drive amounts to in the rig.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import fields
from numbers import Real

import numpy as np

from rollerrig.rig.dq_drive import (
    SEED_LAG,
    STATE_NAMES,
    DqDrive,
    DriveOperatingPoint,
    LagFit,
    default_dq_drive,
    drive_steady_state,
    fit_lag_at_held_speed,
    simulate_drive_on_inertia,
)
from rollerrig.rig.dq_twin import DqTwin
from rollerrig.rig.dq_twin import _protocol as _protocol  # tests/solve take the protocol from here
from rollerrig.rig.drive_mode_tables import (
    dq_coupled_modes,
    eigen_table,
    format_eigen_table,
    thevenin_eigen_table,
)
from rollerrig.rig.drive_verdicts import band_verdict, robustness
from rollerrig.rig.lag_in_rig import fit_lag_in_rig

__all__ = [
    "SEED_LAG",
    "STATE_NAMES",
    "VARIANTS",
    "DqDrive",
    "DqTwin",
    "DriveOperatingPoint",
    "LagFit",
    "default_dq_drive",
    "dq_coupled_modes",
    "drive_dynamics_study",
    "drive_steady_state",
    "drive_variants",
    "eigen_table",
    "equivalent_drives",
    "fit_lag_at_held_speed",
    "fit_lag_in_rig",
    "format_eigen_table",
    "simulate_drive_on_inertia",
    "thevenin_eigen_table",
]


VARIANTS: tuple[tuple[str, dict], ...] = (
    ("dq default", {}),
    ("dq pure V/f", {"boost": 0.0}),
    ("dq slip comp 1.0, 0.1 s", {"slip_compensation": 1.0, "slip_filter_time": 0.1}),
    ("dq slip comp 1.0, 0.05 s", {"slip_compensation": 1.0, "slip_filter_time": 0.05}),
    (
        "dq slip comp 1.0, 0.1 s, R_R est. 1.5",
        {"slip_compensation": 1.0, "slip_filter_time": 0.1, "rotor_resistance_estimate": 1.5},
    ),
    ("dq slip comp 1.5, 0.1 s", {"slip_compensation": 1.5, "slip_filter_time": 0.1}),
    ("dq slip comp 1.5, 0.05 s", {"slip_compensation": 1.5, "slip_filter_time": 0.05}),
)
"""The study's V/f variants: label and settings over the rig file's ``[roller_drive_vf]``."""


def drive_variants(rig) -> list[DqDrive]:
    """The V/f settings the study compares (:data:`VARIANTS`), each built by
    :func:`default_dq_drive` over the rig file's settings.

    ``dq default`` (the rig file's settings), ``pure V/f`` (no boost: the existing twin's
    law), full slip compensation with a 0.1 s and a 0.05 s slip filter, full compensation
    with a rotor-resistance estimate 50 % high (which acts exactly as 150 % compensation), and
    150 % compensation with 0.1 s and 0.05 s filters. Only the slip filter is set; the current
    filter keeps the rig file's value (the machine's default on the bundled rig).
    """
    return [default_dq_drive(rig, label=label, **settings) for label, settings in VARIANTS]


def _acting(drive: DqDrive) -> np.ndarray:
    """What a drive's behaviour depends on [SI]: the machine's values, and the controller's
    with its slip estimate's R̂_R folded into the gain k_sc."""
    c, m = drive.control, drive.machine

    def numbers(owner, skip=()):  # the parameters: not the assumptions' text, not a fit's record
        return [
            float(getattr(owner, f.name))
            for f in fields(owner)
            if f.compare and f.name not in skip and isinstance(getattr(owner, f.name), Real)
        ]

    values = numbers(m) + numbers(c, skip=("slip_gain", "rotor_resistance"))
    # ω_s = ω* + k_sc ω̂_r,f with ω̂_r,f proportional to R̂_R (vf_control_kernel): only the
    # product acts; the filtered estimate is a state scaled by R̂_R, its dynamics unchanged.
    values.append(c.slip_gain * c.rotor_resistance / m.rotor_resistance)
    return np.asarray(values)


def equivalent_drives(drives: Sequence[DqDrive]) -> dict[str, dict]:
    """Drives that act exactly alike, by construction: the same machine and controller but for
    the slip gain k_sc and the rotor resistance R̂_R of the slip estimate, whose product alone
    enters the controller (:func:`rollerrig.drives.vf.vf_control_kernel`; e.g. k_sc = 1 with
    R̂_R = 1.5 R_R is k_sc = 1.5 with R̂_R = R_R). Their modes are the same (to the rounding of
    the numerical linearisation, ~1e-8).

    Parameters
    ----------
    drives : sequence of DqDrive
        The drives (labels unique).

    Returns
    -------
    dict
        For each drive that acts as another: label -> ``{"same_as": [the others' labels],
        "first": the label of the first of them in ``drives``, "slip_gain_effective":
        k_sc R̂_R / R_R [-], "why": a sentence}``.

    Examples
    --------
    >>> from rollerrig.rig.parameters import default_rig
    >>> same = equivalent_drives(drive_variants(default_rig()))
    >>> same["dq slip comp 1.5, 0.1 s"]["same_as"]
    ['dq slip comp 1.0, 0.1 s, R_R est. 1.5']
    """
    groups: list[tuple[np.ndarray, list[DqDrive]]] = []
    for d in drives:
        values = _acting(d)
        # rtol 1e-12: 1.0 x (1.5 R_R) and 1.5 x (1.0 R_R) may differ in the last bit
        group = next((g for v, g in groups if np.allclose(values, v, rtol=1e-12, atol=0.0)), None)
        if group is None:
            groups.append((values, [d]))
        else:
            group.append(d)
    out: dict[str, dict] = {}
    for values, group in groups:
        if len(group) < 2:
            continue
        gain = float(values[-1])
        for d in group:
            others = [o.label for o in group if o is not d]
            names = ", ".join(others)
            if all(o.control.slip_gain == d.control.slip_gain for o in group):
                why = f"has the same settings as {names}"
            else:
                why = (
                    f"acts exactly as {names}: only the product k_sc x R̂_R/R_R (= {gain:.4g} "
                    "in each) enters the slip compensation, so the modes are the same"
                )
            out[d.label] = {
                "same_as": others,
                "first": group[0].label,
                "slip_gain_effective": gain,
                "why": why,
            }
    return out


def drive_dynamics_study(
    rig,
    speeds: Sequence[float] = (5 / 3.6, 10 / 3.6, 20 / 3.6, 30 / 3.6),
    loads: Sequence[float] = (4.3e3, 10e3, 20e3),
    drives: Sequence[DqDrive] | None = None,
    *,
    rig_fit_points: Sequence[tuple[float, float]] = ((10 / 3.6, 4.3e3), (30 / 3.6, 4.3e3)),
    check_loads: Sequence[float] | None = None,
    band: tuple[float, float] = (1.0, 1.7),
    progress: Callable[[str], None] | None = None,
) -> dict:
    """The issue-13 study, JSON-ready: mode tables with and without the dq drive, the lag fits,
    the verdict of each drive about ``band`` [Hz] and whether it holds over its assumptions.

    ``check_loads`` [N]: the loads of the robustness checks (default ``loads``: the whole
    grid of speeds × loads); an empty sequence skips the checks. Drives not built by
    :func:`default_dq_drive` are not checked. Cost (one core): the checks linearise the twin
    at about 950 operating points, about 15 s; the rest of the study about 11 s.
    ``progress``: called as ``progress(step)`` as each step starts (a command's progress).

    Returns
    -------
    dict
        ``thevenin`` and ``dq`` (rows of :func:`thevenin_eigen_table` / :func:`eigen_table`;
        a drive that acts exactly as an earlier one, :func:`equivalent_drives`, gets that
        one's rows, relabelled), ``verdicts`` (per drive:
        :func:`~rollerrig.rig.drive_verdicts.band_verdict` and
        :func:`~rollerrig.rig.drive_verdicts.robustness`; ``same_as``, the drives it acts
        exactly as, and ``slip_gain_effective [-]``, with the text saying so),
        ``robustness_grid`` (speeds and loads of the checks),
        ``lag_held_speed`` (per speed: τ [s] and c_lp [1/s] of :func:`fit_lag_at_held_speed`
        for the first drive), ``lag_in_rig`` (per point of ``rig_fit_points``:
        :func:`fit_lag_in_rig`), ``seed_lag [s]`` (τ of c_lp = 2.75) and the machine's
        parameters and assumptions.
    """
    say = progress if progress is not None else (lambda step: None)
    drives = list(drives or drive_variants(rig))
    first = drives[0]
    rr = rig.geometry.roller_radius_x
    held = []
    say(f"the dq machine's lag at held speed ({len(speeds)} speeds)")
    for v in speeds:
        fit = fit_lag_at_held_speed(first, v, rr)
        held.append(
            {
                "speed [km/h]": v * 3.6,
                "tau [s]": fit.time_constant,
                "c_lp [1/s]": fit.clp,
                "rms_error [N.m]": fit.rms_error,
                "peak_response [N.m]": fit.peak_response,
            }
        )
    in_rig = []
    say(f"the lag fitted in the rig ({len(rig_fit_points)} points)")
    for v, n in rig_fit_points:
        fit = fit_lag_in_rig(rig, v, n, drive=first)
        in_rig.append(
            {
                "speed [km/h]": v * 3.6,
                "normal_load [kN]": n / 1e3,
                "tau [s]": fit.time_constant,
                "c_lp [1/s]": fit.clp,
                "rms_error [N.m]": fit.rms_error,
                "peak_response [N.m]": fit.peak_response,
            }
        )
    say(f"modes of the twin with {len(drives)} dq drives at {len(speeds) * len(loads)} points")
    same = equivalent_drives(drives)
    by_drive = {
        d.label: eigen_table(rig, [d], speeds, loads, band=band)
        for d in drives
        if d.label not in same or same[d.label]["first"] == d.label
    }
    for d in drives:  # identical by construction: the rows of the first drive it acts as
        if d.label not in by_drive:
            lead = same[d.label]["first"]
            by_drive[d.label] = [{**r, "drive": d.label} for r in by_drive[lead]]
    dq_rows = [r for d in drives for r in by_drive[d.label]]
    if check_loads is None:
        check_loads = tuple(loads)
    cache: dict = {}

    def rows_for(r, settings):
        # the same drive on the same rig recurs across variants and assumptions: once each
        key = (r.model_dump_json(exclude={"provenance"}), tuple(sorted(settings.items())))
        if key not in cache:
            drive = default_dq_drive(r, **settings)
            cache[key] = eigen_table(r, [drive], speeds, check_loads, band=band)
        return cache[key]

    verdicts = []
    for i, d in enumerate(drives):
        if check_loads and d.settings is not None:
            say(f"verdicts over the assumptions: {d.label} ({i + 1} of {len(drives)})")
        nominal = band_verdict([r for r in dq_rows if r["drive"] == d.label], band)
        entry = {"drive": d.label, "settings": d.settings, **nominal}
        if d.label in same:  # its rows and figure markers are another drive's: say so
            entry["same_as"] = same[d.label]["same_as"]
            entry["text"] += f"; it {same[d.label]['why']}"
            entry["slip_gain_effective [-]"] = same[d.label]["slip_gain_effective"]
        if check_loads and d.settings is not None:
            entry["robustness"] = robustness(rig, d.settings, rows_for, nominal, band=band)
        verdicts.append(entry)
    mach = first.machine
    say("modes with the Thevenin drive")
    return {
        "machine": {
            "stator_resistance_equivalent_star [ohm]": mach.stator_resistance,
            "stator_resistance_as_connected [ohm]": rig.induction_motor.stator_resistance,
            "connection": rig.induction_motor.connection,
            "stator_resistance_per_unit [-]": rig.induction_motor.stator_resistance_per_unit,
            "rotor_resistance [ohm]": mach.rotor_resistance,
            "leakage_inductance [H]": mach.leakage_inductance,
            "magnetising_inductance [H]": mach.magnetising_inductance,
            "transient_rotor_time_constant [s]": mach.transient_rotor_time_constant,
            "rotor_time_constant [s]": mach.rotor_time_constant,
            "assumptions": list(mach.assumptions),
        },
        "controls": {d.label: list(d.control.assumptions) for d in drives},
        "thevenin": thevenin_eigen_table(rig, speeds=speeds, loads=loads),
        "dq": dq_rows,
        "band [Hz]": list(band),
        "verdicts": verdicts,
        "robustness_grid": {
            "speeds [km/h]": [v * 3.6 for v in speeds],
            "normal_loads [kN]": [n / 1e3 for n in check_loads],
            "one at a time": "each assumption over its range, the others at the drive's values",
        },
        "lag_held_speed": held,
        "lag_in_rig": in_rig,
        "seed_lag [s]": SEED_LAG,
    }
