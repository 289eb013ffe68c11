"""The one unit registry of the package: quantities, their accepted units, and unit aliases.

SI inside the package; other units only at the edges (rig files, channel maps, recordings,
protocol traces). Every edge converts through this module:

- :data:`QUANTITIES` — quantity -> (SI unit, {accepted unit: factor to SI}); the first accepted
  unit is the SI unit itself.
- :data:`ALIASES` — other spellings of an accepted unit (``"Nm"`` -> ``"N.m"``,
  ``"U/min"`` -> ``"rpm"``, ``"µm"`` -> ``"um"``, ...). :func:`normalize_unit` also reads
  ``·``/``⋅``/``*``/a space between symbols as the product dot, superscripts ``²``/``³`` as
  ``^2``/``^3``, and torque units in any letter case (``NM``, ``knm``).
- :func:`si_factor`, :func:`to_si` — conversion to a given SI unit; :func:`quantity_factor` —
  conversion for a named quantity. An unknown unit is a :class:`UnitError` that lists the
  accepted units.

pint was tried and misreads ``"Nm"`` (nanometre), ``"U/min"`` and ``"1/min"``; a table of our own
states exactly what a rig file, a channel map or a DAQ export may say.

Dimensionless quantities (ratios, CoA, creep, damping ratios) and counts have one unit, spelled
two ways by rule, never otherwise:

- as a unit *value* (a ``units``/``unit`` attribute or field: NetCDF ``units``, Parquet
  ``unit``, TDMS ``unit_string``, MDF4 and MAT units, the ``variables`` entry of a metadata
  object, a ``"unit"`` field of a JSON summary, this registry): :data:`DIMENSIONLESS`, ``"1"``,
  as CF-1.10 (section 3.1) and UDUNITS require;
- inside a *name or label* (a CSV column header, a JSON key ``"creep [-]"``, a console table's
  column or unit cell, an option's help, an error message, a figure's axis label):
  :data:`DIMENSIONLESS_LABEL`, ``[-]`` (``-`` in a unit column), through :func:`unit_label` and
  :func:`labelled`.

(These helpers and constants live in :mod:`rollerrig._display`, the lowest layer, so that the
output writers share them; they are exported here.) ``[1]`` is never written, and ``"-"`` never
as a unit value; both are read (``"-"`` is an alias of
``"1"``, so a CSV header ``creep [-]`` reads back as unit ``"1"``).

``value_SI = value * factor``. Where ``1/factor`` is a short decimal (mm, ms, mH, km/h, ...) the
conversion divides by it instead, so that decimal inputs convert correctly rounded (348 mm ->
0.348 m, not 0.34800000000000003); see :func:`apply_factor`.

Examples
--------
>>> normalize_unit("Nm"), normalize_unit("U/min"), normalize_unit("kN·m")
('N.m', 'rpm', 'kN.m')
>>> round(si_factor("rpm", "rad/s"), 9), si_factor("bar", "Pa")
(0.104719755, 100000.0)
>>> to_si([348.0], "mm", "m").tolist()
[0.348]
>>> QUANTITIES["torque"].si_unit, list(QUANTITIES["torque"].units)
('N.m', ['N.m', 'kN.m'])
>>> labelled("creep", "1"), labelled("torque", "N.m"), unit_label("-")
('creep [-]', 'torque [N.m]', '[-]')
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from types import MappingProxyType
from typing import NamedTuple

import numpy as np

from rollerrig._display import (
    DIMENSIONLESS,
    DIMENSIONLESS_LABEL,
    is_dimensionless,
    labelled,
    unit_label,
)
from rollerrig._validation import ParameterError, Problem, show_allowed

__all__ = [
    "ALIASES",
    "DIMENSIONLESS",
    "DIMENSIONLESS_LABEL",
    "QUANTITIES",
    "UNITS_BY_SI",
    "Quantity",
    "UnitError",
    "apply_factor",
    "is_dimensionless",
    "labelled",
    "normalize_unit",
    "quantity_factor",
    "si_factor",
    "to_si",
    "unit_label",
]


class UnitError(ParameterError):
    """A unit is unknown or does not fit the quantity; the message lists the accepted units.

    ``problem`` is the :class:`rollerrig._validation.Problem` (without a key), for a caller
    that reports it under the key of a file.
    """

    problem: Problem | None = None


class Quantity(NamedTuple):
    """A physical quantity: its SI unit and its accepted units with their factors to SI."""

    si_unit: str
    units: Mapping[str, float]


_TWO_PI = 2.0 * math.pi
_RPM = _TWO_PI / 60.0  # one revolution is 2π rad, one minute 60 s

_TABLE: dict[str, dict[str, float]] = {
    # quantity: {unit: factor to SI}; the first unit is the SI unit.
    "length": {"m": 1.0, "mm": 1e-3, "um": 1e-6},
    "area": {"m^2": 1.0, "cm^2": 1e-4, "mm^2": 1e-6},
    "torsional_stiffness": {"N.m/rad": 1.0, "kN.m/rad": 1e3},
    "torsional_damping": {"N.m.s/rad": 1.0},
    "inertia": {"kg.m^2": 1.0},
    "force": {"N": 1.0, "kN": 1e3},
    # Gauge readings (bar(g), psig) are the rig's air-spring pressures; absolute ones (bar(a))
    # are not accepted, since reading them as gauge would add one atmosphere.
    "pressure": {
        "Pa": 1.0,
        "kPa": 1e3,
        "mbar": 1e2,
        "bar": 1e5,
        "MPa": 1e6,
        "GPa": 1e9,
        "psi": 6894.757293168361,  # lbf/in^2 = 0.45359237 kg x 9.80665 m/s^2 / 0.0254^2 m^2
    },
    # A rotation speed; "Hz" here means revolutions per second (x 2π).
    "speed": {"m/s": 1.0, "km/h": 1.0 / 3.6},
    "angular_speed": {"rad/s": 1.0, "rpm": _RPM, "Hz": _TWO_PI},
    # A bandwidth: an angular frequency, which a file may also state in Hz (x 2π).
    "angular_frequency": {"rad/s": 1.0, "Hz": _TWO_PI},
    "frequency": {"Hz": 1.0, "kHz": 1e3},
    "rate": {"1/s": 1.0},
    "voltage": {"V": 1.0, "mV": 1e-3, "kV": 1e3},
    "current": {"A": 1.0, "mA": 1e-3},
    "resistance": {"ohm": 1.0, "mohm": 1e-3},
    "inductance": {"H": 1.0, "mH": 1e-3},
    "flux_linkage": {"Wb": 1.0},
    "power": {"W": 1.0, "kW": 1e3},
    "torque": {"N.m": 1.0, "kN.m": 1e3},
    "time": {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9, "min": 60.0, "h": 3600.0},
    "second_moment": {"m^4": 1.0, "cm^4": 1e-8, "mm^4": 1e-12},
    "section_modulus": {"m^3": 1.0, "cm^3": 1e-6, "mm^3": 1e-9},
    "density": {"kg/m^3": 1.0, "t/m^3": 1e3, "g/cm^3": 1e3},
    "mass": {"kg": 1.0, "t": 1e3},
    "linear_stiffness": {"N/m": 1.0, "N/mm": 1e3, "kN/mm": 1e6, "MN/m": 1e6},
    "linear_damping": {"N.s/m": 1.0},
    "dimensionless": {"1": 1.0},
    "count": {"1": 1.0},
}

QUANTITIES: Mapping[str, Quantity] = MappingProxyType(
    {q: Quantity(next(iter(u)), MappingProxyType(u)) for q, u in _TABLE.items()}
)
"""Quantity -> :class:`Quantity` (SI unit, {accepted unit: factor to SI}), read-only."""

ALIASES: Mapping[str, str] = MappingProxyType(
    {
        # torque (N·m written every way DAQ software and people write it)
        "Nm": "N.m",
        "N-m": "N.m",
        "kNm": "kN.m",
        "Nm/rad": "N.m/rad",
        "kNm/rad": "kN.m/rad",
        "Nms/rad": "N.m.s/rad",
        # rotation speed
        "rad/sec": "rad/s",
        "RPM": "rpm",
        "r/min": "rpm",
        "1/min": "rpm",
        "min^-1": "rpm",
        "min-1": "rpm",
        "min⁻¹": "rpm",
        "U/min": "rpm",
        "rev/min": "rpm",
        "rev/s": "Hz",
        "tr/min": "rpm",  # French: tours par minute
        "tr/s": "Hz",
        # micro: the micro sign (U+00B5) and the Greek mu (U+03BC)
        "µm": "um",
        "μm": "um",
        "µs": "us",
        "μs": "us",
        # time (the spellings DAQ exports use)
        "sec": "s",
        "secs": "s",
        "second": "s",
        "seconds": "s",
        "sec.": "s",
        "msec": "ms",
        "usec": "us",
        "µsec": "us",
        "nsec": "ns",
        "hr": "h",
        # gauge pressure
        "barg": "bar",
        "bar(g)": "bar",
        "psig": "psi",
        "psi(g)": "psi",
        # others
        "1/sec": "1/s",
        "s^-1": "1/s",
        "Newtons": "N",
        "Volt": "V",
        "Volts": "V",
        "volt": "V",
        "Ohm": "ohm",
        "Ω": "ohm",
        "mΩ": "mohm",
        "mOhm": "mohm",
        "kgm^2": "kg.m^2",
        "m⁴": "m^4",
        "cm⁴": "cm^4",
        "mm⁴": "mm^4",
        "m³": "m^3",
        "cm³": "cm^3",
        "mm³": "mm^3",
        "kg/m³": "kg/m^3",
        "counts": "1",
        "count": "1",
        "-": "1",
    }
)
"""Other spellings -> the accepted unit they mean (after the separators are read, see
:func:`normalize_unit`)."""

_CASELESS: dict[str, str] = {"n.m": "N.m", "nm": "N.m", "kn.m": "kN.m", "knm": "kN.m"}
"""Torque units accepted in any letter case (recorded torque-request traces write ``NM``,
``knm``, ...): no other accepted unit is spelled with these letters."""

_BY_SI: dict[str, dict[str, float]] = {}
for _q in _TABLE.values():
    _BY_SI.setdefault(next(iter(_q)), {}).update(_q)
UNITS_BY_SI: Mapping[str, Mapping[str, float]] = MappingProxyType(
    {si: MappingProxyType(units) for si, units in _BY_SI.items()}
)
"""SI unit -> {accepted unit: factor} over every quantity with that SI unit (``"rad/s"``: rad/s,
rpm, Hz = rev/s), read-only. Quantities sharing an SI unit agree on every factor (tested)."""

_KNOWN = frozenset(u for table in _TABLE.values() for u in table)
_SPACED = re.compile(r"\s*([/^])\s*")


def normalize_unit(unit: str) -> str:
    """The accepted spelling of ``unit`` (``"Nm"`` -> ``"N.m"``); an unknown unit, stripped.

    Reads ``·``, ``⋅``, ``*`` and a space between two symbols as the product dot, ``²``/``³`` as
    ``^2``/``^3``, then the :data:`ALIASES`, then the torque units in any letter case.

    Examples
    --------
    >>> normalize_unit(" Nm "), normalize_unit("1/min"), normalize_unit("µm")
    ('N.m', 'rpm', 'um')
    >>> normalize_unit("kg·m²"), normalize_unit("N m"), normalize_unit("KNM")
    ('kg.m^2', 'N.m', 'kN.m')
    >>> normalize_unit("furlong")
    'furlong'
    """
    raw = str(unit).strip()
    if raw in _KNOWN:
        return raw
    if raw in ALIASES:
        return ALIASES[raw]
    u = raw.translate({ord("·"): ".", ord("⋅"): ".", ord("*"): ".", ord("²"): "^2", ord("³"): "^3"})
    u = re.sub(r"\s+", ".", _SPACED.sub(r"\1", u))
    u = ALIASES.get(u, u)
    if u in _KNOWN:
        return u
    return _CASELESS.get(u.lower(), raw)


def _unit_error(unit, si_unit: str, table: Mapping[str, float], what: str, kind: str):
    aliases = [a for a, target in ALIASES.items() if target in table]
    allowed = show_allowed(list(table))
    if aliases:
        allowed += f" (also written {show_allowed(aliases)})"
    problem = Problem("", f"unit not accepted for {kind}", si_unit, allowed, unit)
    error = UnitError(f"{what}{problem.format()}")
    error.problem = problem
    return error


def si_factor(unit: str, si_unit: str, *, what: str = "") -> float:
    """Factor that converts values in ``unit`` into ``si_unit``.

    Parameters
    ----------
    unit : str
        Unit the values are in, e.g. ``"rpm"`` (any spelling :func:`normalize_unit` reads).
    si_unit : str
        Target SI unit, a key of :data:`UNITS_BY_SI`, e.g. ``"rad/s"``.
    what : str
        Where the unit came from, the start of the error message (e.g. ``"map.toml:
        channels.torque.unit: "``).

    Raises
    ------
    UnitError
        When ``unit`` is not an accepted unit of that quantity (the message lists them).

    Examples
    --------
    >>> round(si_factor("rpm", "rad/s"), 6), si_factor("bar", "Pa")
    (0.10472, 100000.0)
    """
    table = UNITS_BY_SI.get(si_unit)
    if table is None:
        raise UnitError(f"{what}no unit table for SI unit {si_unit!r}; known: {list(UNITS_BY_SI)}")
    u = normalize_unit(unit) if isinstance(unit, str) else None
    if u not in table:
        kind = " or ".join(q for q, spec in QUANTITIES.items() if spec.si_unit == si_unit)
        raise _unit_error(unit, si_unit, table, what, kind)
    return table[u]


def quantity_factor(unit: str, quantity: str, *, what: str = "") -> float:
    """Factor that converts values in ``unit`` into the SI unit of ``quantity``.

    Examples
    --------
    >>> quantity_factor("kN.m/rad", "torsional_stiffness")
    1000.0
    >>> quantity_factor("rpm", "angular_frequency")
    Traceback (most recent call last):
    ...
    rollerrig.units.UnitError: unit not accepted for angular_frequency [rad/s]; allowed 'rad/s', \
'Hz' (also written 'rad/sec', 'rev/s', 'tr/s'); got 'rpm'
    """
    table = QUANTITIES[quantity].units
    u = normalize_unit(unit) if isinstance(unit, str) else None
    if u not in table:
        raise _unit_error(unit, QUANTITIES[quantity].si_unit, table, what, quantity)
    return table[u]


def apply_factor(values, factor: float):
    """``values * factor``, dividing by ``1/factor`` where that is a short decimal (mm: 1000,
    km/h: 3.6, ...) so that decimal inputs convert correctly rounded. A scalar stays a float.

    Examples
    --------
    >>> apply_factor(348.0, 1e-3), 348.0 * 1e-3
    (0.348, 0.34800000000000003)
    >>> apply_factor(30.0, 1 / 3.6) == 30.0 / 3.6
    True
    """
    scalar = np.ndim(values) == 0 and not isinstance(values, np.ndarray)
    inverse = round(1.0 / factor, 6)
    # A value beyond the float range becomes inf, which the validators refuse by name; numpy's
    # overflow warning beside that error said nothing more (1e308 kN.m/rad).
    with np.errstate(over="ignore"):
        if factor < 1.0 and abs(1.0 / factor - inverse) <= 1e-12 * inverse:
            out = np.divide(values, inverse)
        else:
            out = np.multiply(values, factor)
    return float(out) if scalar else out


def to_si(values, unit: str, si_unit: str) -> np.ndarray:
    """``values`` in ``unit`` converted to ``si_unit`` (a float array).

    Examples
    --------
    >>> to_si([60.0], "rpm", "rad/s").round(6).tolist(), to_si([2.0], "kN", "N").tolist()
    ([6.283185], [2000.0])
    """
    return apply_factor(np.asarray(values, dtype=float), si_factor(unit, si_unit))
