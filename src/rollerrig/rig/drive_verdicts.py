"""Verdicts of the drive-dynamics study and whether they survive their assumptions.

A mode table (:func:`rollerrig.rig.drive_mode_tables.eigen_table`) gives, per drive, speed and
load, the twin's oscillatory modes below 20 Hz. This module

* classes each mode by its damping ratio ζ (:func:`mode_class`): ``unstable`` (ζ < 0, a
  growing oscillation: never "lightly damped"), ``lightly damped`` (0 <= ζ < 0.3, can ring as
  a line, :data:`rollerrig.rig.linear.DEFAULT_DAMPING_THRESHOLD`), ``damped``;
* turns one drive's rows into a verdict about the band of the dissertation's 1.33 Hz line
  (:func:`band_verdict`): ``unstable`` (some eigenvalue with a positive real part at some
  point), ``every speed`` (a lightly damped mode in the band at every speed), ``some speeds``
  or ``none``;
* checks each verdict over the ranges of the assumptions it rests on (:func:`robustness`),
  one assumption at a time, the others at the drive's values: the stator resistance
  (1.5-2 % per unit, docs/guide/datasheet.rst), the roller inertia J5 (±10 %), and the V/f
  settings the inverter's parameter list would decide (slip compensation 0-1.5, slip filter
  0.05-0.4 s, current filter 0.05-0.2 s, the rotor-resistance estimate 0.8-1.5: cold to hot
  ±20 % and 50 % high). The modes are computed on the study's speeds at the lightest and
  heaviest load (the modes move by < 1 % between 4.3 and 20 kN).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from rollerrig._validation import ParameterError, require_finite
from rollerrig.rig.linear import DEFAULT_DAMPING_THRESHOLD, check_damping_threshold

__all__ = [
    "ASSUMPTIONS",
    "MODE_CLASSES",
    "Assumption",
    "band_class",
    "band_verdict",
    "mode_class",
    "robustness",
]

MODE_CLASSES = ("unstable", "lightly damped", "damped")
"""Classes of an oscillatory mode by its damping ratio (:func:`mode_class`)."""


def mode_class(damping_ratio: float, threshold: float = DEFAULT_DAMPING_THRESHOLD) -> str:
    """Class of a mode by its damping ratio ζ [-]: ``unstable`` (ζ < 0), ``lightly damped``
    (0 <= ζ < ``threshold``), ``damped``.

    Examples
    --------
    >>> mode_class(-0.016), mode_class(0.0), mode_class(0.17), mode_class(0.3)
    ('unstable', 'lightly damped', 'lightly damped', 'damped')
    """
    # A NaN damping ratio had been classed "damped", and any threshold taken as it came.
    damping_ratio = require_finite("damping_ratio", damping_ratio, "-", single=True)
    threshold = check_damping_threshold(threshold)
    if damping_ratio < 0.0:
        return "unstable"
    return "lightly damped" if damping_ratio < threshold else "damped"


def band_class(row: Mapping, band: tuple[float, float]) -> str:
    """Class of one table row in ``band`` [Hz]: ``unstable`` when any eigenvalue of the point
    has a positive real part (wherever it lies), else the least damped class of the modes in
    the band (``lightly damped``, ``damped``), ``none`` without a mode there."""
    if row["unstable"]:
        return "unstable"
    classes = {
        mode_class(md["damping_ratio [-]"])
        for md in row["modes below 20 Hz"]
        if band[0] <= md["frequency [Hz]"] <= band[1]
    }
    for c in MODE_CLASSES[1:]:
        if c in classes:
            return c
    return "none"


def _least_damped_in_band(rows, band):
    """(f, ζ) of the least damped mode in the band at each row that has one."""
    out = []
    for r in rows:
        in_band = [
            (md["frequency [Hz]"], md["damping_ratio [-]"])
            for md in r["modes below 20 Hz"]
            if band[0] <= md["frequency [Hz]"] <= band[1]
        ]
        if in_band:
            out.append(min(in_band, key=lambda fz: fz[1]))
    return out


def _growing(rows):
    """(f, ζ) of the fastest-growing mode at each unstable row: of its modes below 20 Hz with
    ζ < 0, else of its unstable eigenvalues ``(real part [1/s], frequency [Hz])`` (one above
    20 Hz, or a real one: ζ = -1)."""
    out = []
    for r in rows:
        listed = [
            (md["frequency [Hz]"], md["damping_ratio [-]"])
            for md in r["modes below 20 Hz"]
            if md["damping_ratio [-]"] < 0.0
        ]
        if not listed:
            listed = [
                (f, -sigma / float(np.hypot(sigma, 2.0 * np.pi * f))) for sigma, f in r["unstable"]
            ]
        if listed:
            out.append(min(listed, key=lambda fz: fz[1]))
    return out


def band_verdict(rows: Sequence[Mapping], band: tuple[float, float] = (1.0, 1.7)) -> dict:
    """The verdict of one drive's rows (all its speeds and loads) about ``band`` [Hz].

    The frequencies and damping ratios it quotes are those of the rows it names, so that they
    bear it out: the growing modes of the unstable rows (ζ < 0), the lightly damped modes in
    the band of the lightly damped rows (0 <= ζ below the threshold), or, with neither, the
    least damped mode in the band of every row (all damped).

    Returns
    -------
    dict
        ``kind`` (``unstable``, ``every speed``, ``some speeds``, ``none``), ``speeds [km/h]``
        (where it is unstable, or lightly damped in the band), ``frequency [Hz]`` and
        ``damping_ratio [-]`` (the ranges ``[min, max]`` of the modes quoted: per row named, its
        fastest-growing mode, or its least damped mode in the band; None without), and ``text``.

    Examples
    --------
    >>> row = {"speed [km/h]": 10.0, "unstable": [(0.15, 1.55)],
    ...        "modes below 20 Hz": [{"frequency [Hz]": 1.55, "damping_ratio [-]": -0.016}]}
    >>> band_verdict([row])["kind"]
    'unstable'
    """
    lo, hi = band = _check_band(band)
    if not rows:
        raise ParameterError(
            "rows must hold at least one row of a mode table (eigen_table): no rows, no verdict"
        )
    speeds = sorted({r["speed [km/h]"] for r in rows})
    classes = [(r, band_class(r, band)) for r in rows]
    unstable = sorted({r["speed [km/h]"] for r, c in classes if c == "unstable"})
    light = sorted({r["speed [km/h]"] for r, c in classes if c == "lightly damped"})
    # Quoting every row's least damped mode had put ζ 0.339 (10-30 km/h, damped) into "lightly
    # damped at 5 km/h only", above the class's own 0.3.
    if unstable:
        fz = _growing([r for r, c in classes if c == "unstable"])
    elif light:
        fz = _least_damped_in_band([r for r, c in classes if c == "lightly damped"], band)
    else:
        fz = _least_damped_in_band(rows, band)
    f_range = [min(f for f, _ in fz), max(f for f, _ in fz)] if fz else None
    z_range = [min(z for _, z in fz), max(z for _, z in fz)] if fz else None
    span = (
        f" ({f_range[0]:.2f}-{f_range[1]:.2f} Hz, ζ {_zeta(z_range[0])} to {_zeta(z_range[1])})"
        if fz
        else ""
    )
    if unstable:
        kind, at = "unstable", unstable
        text = f"unstable at {_kmh(at)}{span}"
    elif light and set(light) == set(speeds):
        kind, at = "every speed", light
        text = f"lightly damped mode in {lo:g}-{hi:g} Hz at every speed{span}"
    elif light:
        kind, at = "some speeds", light
        text = f"lightly damped mode in {lo:g}-{hi:g} Hz at {_kmh(at)} only{span}"
    else:
        kind, at = "none", []
        text = f"no lightly damped mode in {lo:g}-{hi:g} Hz{span}"
    return {
        "kind": kind,
        "speeds [km/h]": at,
        "frequency [Hz]": f_range,
        "damping_ratio [-]": z_range,
        "text": text,
    }


def _check_band(band) -> tuple[float, float]:
    """``band`` [Hz] as ``(low, high)`` with 0 <= low < high, or a ParameterError (a reversed or
    NaN band had given the verdict "none": no mode lies in it)."""
    arr = require_finite("band", band, "Hz")
    if arr.shape != (2,):
        raise ParameterError(f"band must be (low, high) [Hz], got {band!r}")
    lo, hi = float(arr[0]), float(arr[1])
    if not 0.0 <= lo < hi:
        raise ParameterError(f"band must be (low, high) with 0 <= low < high [Hz], got {band!r}")
    return lo, hi


def _zeta(z: float, threshold: float = DEFAULT_DAMPING_THRESHOLD) -> str:
    """ζ to 3 decimals, or more where 3 would put it in another class (0.29996 as "0.300",
    above the 0.3 that "lightly damped" stops at: "0.29996").

    Examples
    --------
    >>> _zeta(0.2034), _zeta(0.29996), _zeta(-0.0002)
    ('0.203', '0.29996', '-0.0002')
    """
    for digits in range(3, 9):
        shown = f"{z:.{digits}f}"
        if mode_class(float(shown), threshold) == mode_class(z, threshold):
            break
    return shown


def _kmh(speeds) -> str:
    return ", ".join(f"{v:g}" for v in speeds) + " km/h"


# --------------------------------------------------------------------------------------------
# The assumptions and their ranges
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Assumption:
    """One assumption a verdict rests on, and the values it is checked at.

    Attributes
    ----------
    key : str
        ``section.key`` of the rig file (``roller_drive_vf.*`` keys are V/f settings).
    label : str
        Short name for the verdict's text.
    values : callable
        ``values(rig, nominal)`` -> the values to check [SI of the key], the nominal one left
        out by :func:`robustness`.
    range_text : str
        The assumed range and why.
    needs : str or None
        ``"slip_compensation"``: checked only where the drive compensates slip (else the
        setting is unused); ``"current_filter"``: only where the current filter is used.
    """

    key: str
    label: str
    values: Callable
    range_text: str
    needs: str | None = None


def _rs_per_unit(rig, per_unit: float) -> float:
    """R_s per phase of the winding as connected [ohm] at ``per_unit`` of its base."""
    am = rig.induction_motor
    return per_unit * am.stator_resistance / am.stator_resistance_per_unit


ASSUMPTIONS: tuple[Assumption, ...] = (
    Assumption(
        "induction_motor.stator_resistance",
        "R_s",
        lambda rig, nominal: tuple(round(_rs_per_unit(rig, pu), 4) for pu in (0.015, 0.02)),
        "1.5-2 % per unit (the datasheet guide's nameplate step; 0.074-0.099 ohm per delta "
        "phase on the bundled rig)",
    ),
    Assumption(
        "inertia.roller",
        "J5",
        lambda rig, nominal: (0.9 * nominal, 1.1 * nominal),
        "±10 % (Kayaalp 4.5.1.5 gives J5 = 45 kg.m^2 without its source)",
    ),
    Assumption(
        "roller_drive_vf.slip_compensation",
        "slip compensation",
        lambda rig, nominal: (0.0, 0.5, 1.0, 1.5),
        "0-1.5 (off to 150 %, the inverter's range)",
    ),
    Assumption(
        "roller_drive_vf.slip_filter_time",
        "slip filter",
        lambda rig, nominal: (0.05, 0.1, 0.2, 0.4),
        "0.05-0.4 s (the inverter's slip-compensation filter; its default near 0.36 s)",
        needs="slip_compensation",
    ),
    Assumption(
        "roller_drive_vf.current_filter_time",
        "current filter",
        lambda rig, nominal: (0.05, 0.2),
        "0.05-0.2 s (the filter of the current the slip estimate uses)",
        needs="current_filter",
    ),
    Assumption(
        "roller_drive_vf.rotor_resistance_estimate",
        "rotor-resistance estimate",
        lambda rig, nominal: (0.8, 1.2, 1.5),
        "0.8-1.5 x R_R (cold to hot ±20 %, and 50 % high)",
        needs="slip_compensation",
    ),
)
"""The assumptions every verdict is checked over, with their assumed ranges."""


def _nominal(rig, key: str, settings: Mapping):
    section, name = key.split(".")
    if section == "roller_drive_vf" and name in settings:
        return settings[name]
    value = getattr(getattr(rig, section), name)
    if name.endswith("filter_time") and not value:
        return None  # the machine's default
    return value


def robustness(
    rig,
    settings: Mapping,
    rows_for: Callable,
    nominal_verdict: Mapping,
    *,
    band: tuple[float, float] = (1.0, 1.7),
    assumptions: Sequence[Assumption] = ASSUMPTIONS,
) -> dict:
    """Check one drive's verdict over the ranges of its assumptions, one at a time.

    Parameters
    ----------
    rig : RigParameters
        The rig.
    settings : mapping
        The drive's V/f settings (keyword arguments of
        :func:`rollerrig.rig.dq_drive.default_dq_drive`, over the rig file's).
    rows_for : callable
        ``rows_for(rig, settings)`` -> the mode table rows of that drive on that rig (the study
        passes its grid).
    nominal_verdict : mapping
        :func:`band_verdict` of the drive as it is.
    band : (float, float)
        [Hz].
    assumptions : sequence of Assumption
        What to vary.

    Returns
    -------
    dict
        ``holds`` (bool), ``text`` ("holds over the assumed ranges" or "depends on X: ..."),
        ``assumptions``: per assumption its ``key``, ``range``, the ``values`` checked with
        their verdicts, and ``flips`` (the values whose verdict differs from the nominal one);
        an assumption the drive does not use is listed with ``unused``.
    """
    checked = []
    parts = []
    slip = float(settings.get("slip_compensation", rig.roller_drive_vf.slip_compensation))
    ir = bool(settings.get("ir_compensation", rig.roller_drive_vf.ir_compensation > 0.0))
    for a in assumptions:
        entry = {"key": a.key, "label": a.label, "range": a.range_text}
        unused = (a.needs == "slip_compensation" and slip == 0.0) or (
            a.needs == "current_filter" and slip == 0.0 and not ir
        )
        if unused:
            entry["unused"] = "the drive has no slip compensation: the setting acts on nothing"
            checked.append(entry)
            continue
        nominal = _nominal(rig, a.key, settings)
        section, name = a.key.split(".")
        values = [
            v
            for v in a.values(rig, nominal)
            if nominal is None or not np.isclose(v, nominal, rtol=1e-9)
        ]
        results = []
        for v in values:
            if section == "roller_drive_vf":
                vr = band_verdict(rows_for(rig, {**settings, name: v}), band)
            else:
                vr = band_verdict(rows_for(rig.with_overrides({a.key: v}), settings), band)
            results.append({"value": v, **vr})
        flips = [
            r
            for r in results
            if (r["kind"], r["speeds [km/h]"])
            != (nominal_verdict["kind"], nominal_verdict["speeds [km/h]"])
        ]
        entry.update(
            {
                "nominal": nominal,
                "values": results,
                "flips": [r["value"] for r in flips],
                "holds": not flips,
            }
        )
        checked.append(entry)
        if flips:
            parts.append(
                f"{a.label} ({a.range_text}): "
                + "; ".join(f"{r['text']} at {_show(r['value'])}" for r in flips)
            )
    holds = not parts
    return {
        "holds": holds,
        "text": "holds over the assumed ranges" if holds else "depends on " + " | ".join(parts),
        "assumptions": checked,
    }


def _show(value) -> str:
    return f"{value:.4g}"
