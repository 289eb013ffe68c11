"""Validated rig parameter sets: TOML files with units and provenance, SI objects in memory.

A rig file is TOML. Every physical value is an inline table with its value, its unit and where
it comes from; a value the source does not give carries its reasoning as an ``assumption``::

    [inertia]
    roller = { value = 45.0, unit = "kg.m^2", source = "Kayaalp 4.5.1.5 (J5)" }

    [bearing]
    wheel_bearing_radius = { value = 60.0, unit = "mm", assumption = "120 mm axle bearing bore" }

Only the two ``[meta]`` entries (``name``, ``description``) are plain strings. The loader checks
the section and key names, the unit against the accepted units of that quantity (see
:data:`UNITS`), the type and the physical range, converts to SI and returns a frozen
:class:`RigParameters` whose sections hold plain SI floats. Every error names the offending
``section.key``.

The bundled default rig (:func:`default_rig`) is the tram wheel–roller rig of the University of
Pardubice as described in Kayaalp's dissertation ("Kayaalp", Table 1, Table 2, section 4.5.1.5);
see ``rollerrig/rig/data/default_rig.toml`` for the provenance of every value.

Examples
--------
>>> rig = default_rig()
>>> rig.inertia.roller
45.0
>>> rig.stiffness.roller_shaft
43500.0
>>> rig.provenance["stiffness.roller_shaft"]["unit"]
'kN.m/rad'
>>> stiffer = rig.with_overrides({"stiffness.roller_shaft": (63.5, "kN.m/rad")})
>>> stiffer.stiffness.roller_shaft
63500.0
"""

from __future__ import annotations

import json
import math
import os
import tempfile
import tomllib
from collections.abc import Mapping
from importlib import resources
from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from rollerrig._validation import ParameterError

__all__ = [
    "UNITS",
    "BearingParameters",
    "DampingParameters",
    "GeometryParameters",
    "InductionMotorParameters",
    "InertiaParameters",
    "MaterialParameters",
    "MetaParameters",
    "PmsmParameters",
    "RigFileError",
    "RigParameters",
    "SensorParameters",
    "ServoRollerDriveParameters",
    "StiffnessParameters",
    "default_rig",
    "load_rig",
    "save_rig",
]


class RigFileError(ParameterError):
    """A rig parameter file (or an override) is malformed or non-physical.

    The message names every offending ``section.key`` and what is wrong with it.

    Attributes
    ----------
    origin : str
        The file (or ``"overrides"``) the problems were found in.
    problems : list of str
        One line per problem, each starting with ``section.key``.
    """

    def __init__(self, origin: str, problems: list[str]):
        self.origin = origin
        self.problems = list(problems)
        lines = "\n  ".join(self.problems)
        super().__init__(f"{origin}: {len(self.problems)} problem(s):\n  {lines}")


# --------------------------------------------------------------------------------------------
# Units: quantity -> {unit string: factor to SI}. The first entry of each table is the SI unit.
# --------------------------------------------------------------------------------------------

_TWO_PI = 2.0 * math.pi

#: Accepted units per quantity and their factor to SI (``value_SI = value * factor``). The first
#: unit of each quantity is its SI unit, used when writing values that have no recorded unit.
UNITS: dict[str, dict[str, float]] = {
    "length": {"m": 1.0, "mm": 1e-3},
    "area": {"m^2": 1.0, "cm^2": 1e-4, "mm^2": 1e-6},
    "torsional_stiffness": {"N.m/rad": 1.0, "kN.m/rad": 1e3},
    "torsional_damping": {"N.m.s/rad": 1.0},
    "inertia": {"kg.m^2": 1.0},
    "force": {"N": 1.0, "kN": 1e3},
    "pressure": {"Pa": 1.0, "kPa": 1e3, "bar": 1e5, "MPa": 1e6, "GPa": 1e9},
    "angular_speed": {"rad/s": 1.0, "rpm": _TWO_PI / 60.0},
    # A bandwidth: an angular frequency, which a TOML file may also state in Hz (x 2π).
    "angular_frequency": {"rad/s": 1.0, "Hz": _TWO_PI},
    "frequency": {"Hz": 1.0, "kHz": 1e3},
    "rate": {"1/s": 1.0},
    "voltage": {"V": 1.0, "kV": 1e3},
    "current": {"A": 1.0},
    "resistance": {"ohm": 1.0, "mohm": 1e-3},
    "inductance": {"H": 1.0, "mH": 1e-3},
    "flux_linkage": {"Wb": 1.0},
    "power": {"W": 1.0, "kW": 1e3},
    "torque": {"N.m": 1.0, "kN.m": 1e3},
    "time": {"s": 1.0, "ms": 1e-3},
    "dimensionless": {"1": 1.0, "-": 1.0},
    "count": {"1": 1.0, "-": 1.0},
    "text": {"-": 1.0},
}


def _q(quantity: str, description: str, **kwargs: Any):
    """A field of a parameter section: ``quantity`` keys :data:`UNITS`; the description has
    the SI unit in brackets."""
    return Field(description=description, json_schema_extra={"quantity": quantity}, **kwargs)


class _Section(BaseModel):
    """Base of the SI parameter sections: frozen, no extra keys, strict types, finite floats."""

    model_config = ConfigDict(frozen=True, extra="forbid", strict=True, allow_inf_nan=False)


# --------------------------------------------------------------------------------------------
# Sections
# --------------------------------------------------------------------------------------------


class MetaParameters(BaseModel):
    """Name and description of a parameter set (plain strings in the TOML file)."""

    model_config = ConfigDict(frozen=True, extra="forbid", strict=True)

    name: str = Field(description="Short name of the parameter set.")
    description: str = Field(description="What rig this is and where its numbers come from.")


class InertiaParameters(_Section):
    """Moments of inertia J1..J7 of the seven bodies of the torsional chain [kg.m^2]."""

    pmsm_stator: float = _q("inertia", "J1, PMSM stator [kg.m^2].", gt=0)
    pmsm_rotor: float = _q("inertia", "J2, PMSM rotor [kg.m^2].", gt=0)
    wheel_disc: float = _q("inertia", "J3, wheel disc (hub) [kg.m^2].", gt=0)
    wheel_tyre: float = _q("inertia", "J4, wheel tyre, outside the rubber layer [kg.m^2].", gt=0)
    roller: float = _q("inertia", "J5, roller (rotating rail) [kg.m^2].", gt=0)
    am_rotor: float = _q("inertia", "J6, asynchronous (induction) motor rotor [kg.m^2].", gt=0)
    am_stator: float = _q("inertia", "J7, asynchronous motor stator [kg.m^2].", gt=0)


class StiffnessParameters(_Section):
    """Torsional stiffnesses of the five spring elements of the chain [N.m/rad]."""

    pmsm_mount: float = _q(
        "torsional_stiffness", "k01, PMSM stator mount to ground [N.m/rad].", gt=0
    )
    wheel_shaft: float = _q("torsional_stiffness", "k23, wheel shaft [N.m/rad].", gt=0)
    wheel_rubber: float = _q(
        "torsional_stiffness", "k34, rubber layer between wheel disc and tyre [N.m/rad].", gt=0
    )
    roller_shaft: float = _q(
        "torsional_stiffness", "k56, roller shaft (CV shaft and torque sensor) [N.m/rad].", gt=0
    )
    am_mount: float = _q("torsional_stiffness", "k70, AM stator mount to ground [N.m/rad].", gt=0)


class DampingParameters(_Section):
    """Viscous torsional damping of the five spring elements of the chain [N.m.s/rad]."""

    pmsm_mount: float = _q("torsional_damping", "b01, PMSM stator mount [N.m.s/rad].", ge=0)
    wheel_shaft: float = _q("torsional_damping", "b23, wheel shaft [N.m.s/rad].", ge=0)
    wheel_rubber: float = _q("torsional_damping", "b34, rubber layer [N.m.s/rad].", ge=0)
    roller_shaft: float = _q("torsional_damping", "b56, roller shaft [N.m.s/rad].", ge=0)
    am_mount: float = _q("torsional_damping", "b70, AM stator mount [N.m.s/rad].", ge=0)


class GeometryParameters(_Section):
    """Principal radii of the wheel and the roller at the contact point [m]."""

    wheel_radius_x: float = _q("length", "Wheel rolling radius r_wx, longitudinal [m].", gt=0)
    wheel_radius_y: float = _q("length", "Wheel transverse profile radius r_wy [m].", gt=0)
    roller_radius_x: float = _q("length", "Roller rolling radius r_rx, longitudinal [m].", gt=0)
    roller_radius_y: float = _q("length", "Roller transverse profile radius r_ry [m].", gt=0)


class MaterialParameters(_Section):
    """Elastic constants of wheel and roller (both steel) [Pa], [1]."""

    youngs_modulus: float = _q("pressure", "Young's modulus E of both bodies [Pa].", gt=0)
    poisson: float = _q(
        "dimensionless", "Poisson's ratio ν of both bodies [1], in (0, 0.5).", gt=0, lt=0.5
    )


class BearingParameters(_Section):
    """Bearing losses R03 (wheel) and R05 (roller), Kayaalp eqs. 4.13-4.14, made torques.

    The seed's ``R03 = N f_g`` and ``R05 = (W_r + N) f_g`` are friction *forces* [N]; the loss
    torques are these forces times the bearing (journal) radius, and are smoothed with
    ``tanh(ω / regularisation_speed)`` so that they are finite and continuous through standstill.
    """

    friction_coefficient: float = _q(
        "dimensionless", "Bearing friction coefficient f_g [1], in [0, 1).", ge=0, lt=1
    )
    roller_subsystem_weight: float = _q(
        "force", "Weight W_r of the roller subsystem carried by the roller bearings [N].", ge=0
    )
    wheel_bearing_radius: float = _q(
        "length", "Friction radius of the wheel bearings (half the bore) [m].", gt=0
    )
    roller_bearing_radius: float = _q(
        "length", "Friction radius of the roller bearings (half the bore) [m].", gt=0
    )
    regularisation_speed: float = _q(
        "angular_speed",
        "Speed below which Coulomb bearing friction is smoothed (tanh) [rad/s].",
        gt=0,
    )


class PmsmParameters(_Section):
    """Wheel drive: direct-drive permanent-magnet synchronous motor (Kayaalp Table 1).

    The dq model uses the amplitude-invariant transform: ``T = 1.5 p φ i_q`` (Kayaalp eq. 4.25
    with ``i_d = 0``).
    """

    rated_power: float = _q("power", "Rated mechanical power [W].", gt=0)
    rated_speed: float = _q("angular_speed", "Rated speed [rad/s].", gt=0)
    rated_torque: float = _q("torque", "Rated (nominal) torque [N.m].", gt=0)
    rated_current: float = _q("current", "Rated current [A].", gt=0)
    flux_linkage: float = _q("flux_linkage", "Permanent-magnet flux linkage φ [Wb].", gt=0)
    pole_pairs: int = _q("count", "Number of pole pairs p [1].", ge=1)
    stator_resistance: float = _q("resistance", "Stator phase resistance R_s [ohm].", gt=0)
    inductance_d: float = _q("inductance", "d-axis inductance L_d [H].", gt=0)
    inductance_q: float = _q("inductance", "q-axis inductance L_q [H].", gt=0)
    dc_link_voltage: float = _q("voltage", "Inverter DC-link voltage [V].", gt=0)
    current_loop_bandwidth: float = _q(
        "angular_frequency", "Closed-loop bandwidth of the dq current controllers [rad/s].", gt=0
    )
    max_current: float = _q("current", "Current limit of the inverter (dq amplitude) [A].", gt=0)
    torque_ripple_amplitude: float = _q(
        "torque", "Amplitude of the inverter torque ripple [N.m] (0: none).", ge=0, default=0.0
    )
    torque_ripple_frequency: float = _q(
        "frequency", "Frequency of the inverter torque ripple [Hz].", ge=0, default=0.0
    )

    @model_validator(mode="after")
    def _consistent(self):
        if self.torque_ripple_amplitude > 0 and self.torque_ripple_frequency <= 0:
            raise ValueError(
                "pmsm.torque_ripple_frequency must be > 0 [Hz] when "
                "pmsm.torque_ripple_amplitude > 0"
            )
        if self.max_current < self.rated_current:
            raise ValueError(
                f"pmsm.max_current ({self.max_current:g} A) must be >= pmsm.rated_current "
                f"({self.rated_current:g} A)"
            )
        return self

    @property
    def torque_constant(self) -> float:
        """``1.5 p φ`` [N.m/A]: q-axis current to torque (amplitude-invariant dq)."""
        return 1.5 * self.pole_pairs * self.flux_linkage

    @property
    def rated_torque_current(self) -> float:
        """q-axis current that produces the rated torque, ``T_N / (1.5 p φ)`` [A]."""
        return self.rated_torque / self.torque_constant


class InductionMotorParameters(_Section):
    """Roller drive: squirrel-cage asynchronous motor under open-loop V/f (Kayaalp Table 2)."""

    rated_power: float = _q("power", "Rated mechanical power [W].", gt=0)
    rated_frequency: float = _q("frequency", "Rated supply frequency [Hz].", gt=0)
    rated_torque: float = _q("torque", "Rated torque [N.m].", gt=0)
    rated_current: float = _q("current", "Rated line current [A].", gt=0)
    rated_line_voltage: float = _q("voltage", "Rated line-to-line voltage (RMS) [V].", gt=0)
    connection: Literal["delta", "star"] = _q("text", "Winding connection: 'delta' or 'star'.")
    pole_pairs: int = _q("count", "Number of pole pairs p [1].", ge=1)
    breakdown_torque_ratio: float = _q(
        "dimensionless", "Breakdown (pull-out) torque over rated torque [1], > 1.", gt=1
    )
    stator_resistance: float = _q(
        "resistance", "Stator resistance per phase of the equivalent star [ohm].", gt=0
    )
    response_lag_clp: float = _q(
        "rate", "Response-lag parameter c_lp of Kayaalp eq. 4.29 [1/s] (weight c_lp·Δt).", gt=0
    )
    response_lag_reference_step: float = _q(
        "time", "Step Δt at which c_lp was fitted (Kayaalp 4.5.1.8) [s].", gt=0
    )

    @model_validator(mode="after")
    def _consistent(self):
        weight = self.response_lag_clp * self.response_lag_reference_step
        if weight > 1.0:
            raise ValueError(
                "induction_motor.response_lag_clp × induction_motor.response_lag_reference_step "
                f"= {weight:g} must be <= 1 (the filter weight of Kayaalp eq. 4.29)"
            )
        if self.rated_slip <= 0.0:
            raise ValueError(
                "induction_motor: rated speed rated_power/rated_torque "
                f"({self.rated_speed:g} rad/s) must be below the synchronous speed "
                f"2π·rated_frequency/pole_pairs ({self.synchronous_speed:g} rad/s)"
            )
        return self

    @property
    def synchronous_speed(self) -> float:
        """Mechanical synchronous speed at the rated frequency, ``2π f / p`` [rad/s]."""
        return _TWO_PI * self.rated_frequency / self.pole_pairs

    @property
    def rated_speed(self) -> float:
        """Rated mechanical speed from the nameplate, ``P / T`` [rad/s]."""
        return self.rated_power / self.rated_torque

    @property
    def rated_slip(self) -> float:
        """Rated slip ``1 - ω_N / ω_sync`` [1] (≈ 1.76 % for the default rig)."""
        return 1.0 - self.rated_speed / self.synchronous_speed

    @property
    def breakdown_torque(self) -> float:
        """Breakdown torque ``ratio × T_N`` [N.m]."""
        return self.breakdown_torque_ratio * self.rated_torque

    @property
    def phase_voltage(self) -> float:
        """Phase voltage of the equivalent star, ``V_line / √3`` (RMS) [V]."""
        return self.rated_line_voltage / math.sqrt(3.0)


class ServoRollerDriveParameters(_Section):
    """Speed-controlled servo/PMSM roller drive: the seed's proposed fix (Kayaalp 5, 4.5.1.8)."""

    speed_bandwidth: float = _q("angular_frequency", "Closed-loop speed bandwidth [rad/s].", gt=0)
    torque_limit: float = _q("torque", "Torque limit of the servo drive [N.m].", gt=0)
    torque_time_constant: float = _q(
        "time", "Time constant of the inner torque (current) loop [s].", gt=0
    )


class SensorParameters(_Section):
    """Data acquisition and sensors (Kayaalp 4.1.3)."""

    daq_rate: float = _q("frequency", "Sampling rate of the DAQ [Hz].", gt=0)
    encoder_pulses_per_revolution: int = _q(
        "count", "Encoder lines (pulses per revolution per channel) [1].", ge=1
    )
    encoder_quadrature_factor: int = _q(
        "count", "Edges counted per line: 1, 2 or 4 (quadrature) [1].", ge=1, le=4
    )
    air_spring_effective_area: float = _q(
        "area", "Effective area of the air spring: normal force = pressure × area [m^2].", gt=0
    )
    torque_sensor_range: float = _q("torque", "Full-scale range of the torque sensor [N.m].", gt=0)

    @model_validator(mode="after")
    def _consistent(self):
        if self.encoder_quadrature_factor not in (1, 2, 4):
            raise ValueError(
                "sensors.encoder_quadrature_factor must be 1, 2 or 4, "
                f"got {self.encoder_quadrature_factor}"
            )
        return self

    @property
    def encoder_counts_per_revolution(self) -> int:
        """Counts per revolution after quadrature decoding [1]."""
        return self.encoder_pulses_per_revolution * self.encoder_quadrature_factor


#: Section name -> model, in file order.
_SECTIONS: dict[str, type[BaseModel]] = {
    "meta": MetaParameters,
    "inertia": InertiaParameters,
    "stiffness": StiffnessParameters,
    "damping": DampingParameters,
    "geometry": GeometryParameters,
    "material": MaterialParameters,
    "bearing": BearingParameters,
    "pmsm": PmsmParameters,
    "induction_motor": InductionMotorParameters,
    "servo_roller_drive": ServoRollerDriveParameters,
    "sensors": SensorParameters,
}


class RigParameters(BaseModel):
    """A complete, validated rig parameter set in SI units.

    Load one with :func:`load_rig` or :func:`default_rig`; derive variants with
    :meth:`with_overrides`; write one with :func:`save_rig`.

    Attributes
    ----------
    provenance : dict
        ``"section.key" -> {"value": value as written, "unit": unit as written,
        "source" | "assumption": text}`` for every physical value.
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    meta: MetaParameters
    inertia: InertiaParameters
    stiffness: StiffnessParameters
    damping: DampingParameters
    geometry: GeometryParameters
    material: MaterialParameters
    bearing: BearingParameters
    pmsm: PmsmParameters
    induction_motor: InductionMotorParameters
    servo_roller_drive: ServoRollerDriveParameters
    sensors: SensorParameters
    provenance: dict[str, dict[str, Any]] = Field(
        default_factory=dict,
        description="'section.key' -> {'value', 'unit', 'source' | 'assumption'} as written.",
    )

    def to_dict(self, *, include_provenance: bool = False) -> dict[str, dict[str, Any]]:
        """Plain nested dict of SI values ``{section: {key: value}}`` (for provenance records).

        Examples
        --------
        >>> default_rig().to_dict()["geometry"]["wheel_radius_x"]
        0.348
        """
        exclude = None if include_provenance else {"provenance"}
        return self.model_dump(exclude=exclude)

    def with_overrides(self, overrides: Mapping[str, Any]) -> RigParameters:
        """New validated parameter set with some values replaced.

        Parameters
        ----------
        overrides : mapping
            ``"section.key" -> value``. A number is taken in SI; a ``(value, unit)`` pair is
            converted with :data:`UNITS` (e.g. ``(63.5, "kN.m/rad")``). The provenance of each
            replaced value becomes an ``assumption`` that records the override and the old value.

        Returns
        -------
        RigParameters

        Raises
        ------
        RigFileError
            Unknown path, unknown unit, wrong type or a non-physical value; the message names
            the ``section.key``.

        Examples
        --------
        >>> rig = default_rig().with_overrides({"stiffness.roller_shaft": 63.5e3})
        >>> rig.stiffness.roller_shaft
        63500.0
        """
        data = self.model_dump(exclude={"provenance"})
        provenance = {k: dict(v) for k, v in self.provenance.items()}
        problems: list[str] = []
        for path, given in overrides.items():
            section, _, key = str(path).partition(".")
            if section not in _SECTIONS:
                problems.append(
                    f"{path}: unknown section '{section}' (known: {', '.join(_SECTIONS)})"
                )
                continue
            fields = _SECTIONS[section].model_fields
            if key not in fields:
                problems.append(
                    f"{path}: unknown key '{key}' in [{section}] (known: {', '.join(fields)})"
                )
                continue
            if isinstance(given, tuple):
                if len(given) != 2:
                    problems.append(f"{path}: give a number (SI) or a (value, unit) pair")
                    continue
                raw, unit = given
            else:
                raw, unit = given, None
            if section == "meta":
                if not isinstance(raw, str):
                    problems.append(f"{path}: must be a string, got {raw!r}")
                    continue
                data[section][key] = raw
                continue
            quantity = fields[key].json_schema_extra["quantity"]
            if unit is None:
                unit = next(iter(UNITS[quantity]))
            try:
                converted = _convert(path, quantity, fields[key].annotation, raw, unit)
            except _Problem as exc:
                problems.append(str(exc))
                continue
            old = provenance.get(f"{section}.{key}", {})
            old_text = old.get("source") or old.get("assumption") or "no provenance"
            old_value = f"{old['value']} {old['unit']}" if "value" in old else "unset"
            provenance[f"{section}.{key}"] = {
                "value": raw,
                "unit": unit,
                "assumption": f"override (was {old_value}: {old_text})",
            }
            data[section][key] = converted
        if problems:
            raise RigFileError("overrides", problems)
        return _build(data, provenance, "overrides")


# --------------------------------------------------------------------------------------------
# Reading
# --------------------------------------------------------------------------------------------

_ENTRY_KEYS = {"value", "unit", "source", "assumption"}


class _Problem(Exception):
    """One problem with one value; its message starts with ``section.key``."""


def _convert(name: str, quantity: str, annotation, raw, unit):
    """SI value of ``raw`` [unit] for a field of type ``annotation``; raises :class:`_Problem`."""
    units = UNITS[quantity]
    if not isinstance(unit, str) or unit not in units:
        accepted = ", ".join(units)
        raise _Problem(f"{name}: unknown unit {unit!r} for {quantity} (accepted: {accepted})")
    if quantity == "text":
        if not isinstance(raw, str):
            raise _Problem(f"{name}: value must be a string, got {raw!r}")
        return raw
    if annotation is int:
        if isinstance(raw, bool) or not isinstance(raw, int):
            raise _Problem(f"{name}: value must be an integer, got {raw!r}")
        return raw
    if isinstance(raw, bool) or not isinstance(raw, int | float):
        raise _Problem(f"{name}: value must be a number, got {raw!r}")
    if not math.isfinite(raw):
        raise _Problem(f"{name}: value must be finite, got {raw!r}")
    return _to_si(float(raw), units[unit])


def _to_si(value: float, factor: float) -> float:
    """``value * factor``, dividing by ``1/factor`` when that is an integer (mm, ms, mH, ...)
    so that decimal inputs convert correctly rounded (348 mm -> 0.348 m, not 0.34800000000000003).
    """
    inverse = 1.0 / factor
    if factor < 1.0 and abs(inverse - round(inverse)) <= 1e-9 * inverse:
        return value / round(inverse)
    return value * factor


def _from_toml(data: Mapping[str, Any], origin: str) -> RigParameters:
    problems: list[str] = []
    si: dict[str, dict[str, Any]] = {}
    provenance: dict[str, dict[str, Any]] = {}
    bad: set[str] = set()  # sections with a problem at file level: not range-checked
    for section in data:
        if section not in _SECTIONS:
            problems.append(f"[{section}]: unknown section (known: {', '.join(_SECTIONS)})")
    for section, model in _SECTIONS.items():
        if section not in data:
            problems.append(f"[{section}]: missing section")
            continue
        table = data[section]
        if not isinstance(table, Mapping):
            problems.append(f"[{section}]: must be a table")
            continue
        fields = model.model_fields
        si[section] = {}
        for key in table:
            if key not in fields:
                problems.append(
                    f"{section}.{key}: unknown key (known in [{section}]: {', '.join(fields)})"
                )
        before = len(problems)
        for key, field in fields.items():
            name = f"{section}.{key}"
            if key not in table:
                if field.is_required():
                    problems.append(f"{name}: missing key")
                continue
            entry = table[key]
            if section == "meta":
                if not isinstance(entry, str):
                    problems.append(f"{name}: must be a string, got {entry!r}")
                else:
                    si[section][key] = entry
                continue
            if not isinstance(entry, Mapping):
                problems.append(
                    f"{name}: must be an inline table "
                    "{ value = ..., unit = ..., source|assumption = ... }"
                )
                continue
            extra = set(entry) - _ENTRY_KEYS
            if extra:
                problems.append(f"{name}: unknown entry field(s) {sorted(extra)}")
            missing = [k for k in ("value", "unit") if k not in entry]
            if missing:
                problems.append(f"{name}: missing {' and '.join(missing)}")
                continue
            has = [k for k in ("source", "assumption") if k in entry]
            if len(has) != 1:
                problems.append(
                    f"{name}: needs exactly one of 'source' or 'assumption', got {has or 'none'}"
                )
                continue
            text = entry[has[0]]
            if not isinstance(text, str) or not text.strip():
                problems.append(f"{name}: '{has[0]}' must be a non-empty string")
                continue
            quantity = field.json_schema_extra["quantity"]
            try:
                converted = _convert(
                    name, quantity, field.annotation, entry["value"], entry["unit"]
                )
            except _Problem as exc:
                problems.append(str(exc))
                continue
            si[section][key] = converted
            provenance[name] = {"value": entry["value"], "unit": entry["unit"], has[0]: text}
        if len(problems) > before:
            bad.add(section)
    if problems:
        # Also report the range problems of the sections that were otherwise well formed.
        _, more = _validate_sections({k: v for k, v in si.items() if k not in bad})
        raise RigFileError(origin, problems + more)
    return _build(si, provenance, origin)


def _build(si: dict[str, dict[str, Any]], provenance, origin: str) -> RigParameters:
    """Validate the SI sections; pydantic errors become :class:`RigFileError` lines."""
    sections, problems = _validate_sections(si)
    if problems:
        raise RigFileError(origin, problems)
    return RigParameters(**sections, provenance=provenance)


def _validate_sections(si: dict[str, dict[str, Any]]) -> tuple[dict[str, BaseModel], list[str]]:
    """Validate each section present in ``si``; return the models and the problem lines."""
    problems: list[str] = []
    sections = {}
    for section, model in _SECTIONS.items():
        if section not in si:
            continue
        try:
            sections[section] = model.model_validate(si[section])
        except ValidationError as exc:
            for err in exc.errors():
                if err["loc"]:
                    key = ".".join(str(p) for p in err["loc"])
                    value = si[section].get(err["loc"][0], err.get("input"))
                    unit = _si_unit(model, err["loc"][0])
                    problems.append(f"{section}.{key} = {value!r}{unit}: {err['msg']}")
                else:  # a cross-field check: its message names the keys
                    problems.append(str(err["msg"]).removeprefix("Value error, "))
    return sections, problems


def _si_unit(model: type[BaseModel], key) -> str:
    field = model.model_fields.get(key)
    if field is None or not field.json_schema_extra:
        return ""
    unit = next(iter(UNITS[field.json_schema_extra["quantity"]]))
    return f" [{unit}]" if unit not in ("-", "1") else ""


def load_rig(path: str | os.PathLike) -> RigParameters:
    """Read and validate a rig parameter file.

    Parameters
    ----------
    path : str or path-like
        TOML file in the format of ``rollerrig/rig/data/default_rig.toml``.

    Returns
    -------
    RigParameters
        SI values and their provenance.

    Raises
    ------
    RigFileError
        Missing file, invalid TOML, unknown or missing section/key, unknown unit, a value of the
        wrong type, not finite or non-physical. The message names every ``section.key``.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "rig.toml"
    >>> save_rig(default_rig(), path)
    >>> load_rig(path) == default_rig()
    True
    """
    path = Path(path)
    if not path.is_file():
        raise RigFileError(str(path), ["rig file not found"])
    try:
        with path.open("rb") as fh:
            data = tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise RigFileError(str(path), [f"not valid TOML: {exc}"]) from exc
    return _from_toml(data, str(path))


def default_rig() -> RigParameters:
    """The bundled default rig: the Pardubice tram wheel–roller rig (Kayaalp, 4.1 and 4.5.1.5).

    Examples
    --------
    >>> rig = default_rig()
    >>> rig.pmsm.pole_pairs, round(rig.induction_motor.rated_slip, 4)
    (22, 0.0176)
    """
    text = resources.files("rollerrig.rig").joinpath("data/default_rig.toml").read_text("utf-8")
    return _from_toml(tomllib.loads(text), "rollerrig/rig/data/default_rig.toml")


# --------------------------------------------------------------------------------------------
# Writing
# --------------------------------------------------------------------------------------------


def _toml_str(text: str) -> str:
    # A JSON string literal is a valid TOML basic string (same escapes, \uXXXX included).
    return json.dumps(text, ensure_ascii=False)


def _toml_number(value) -> str:
    if isinstance(value, bool):  # pragma: no cover - rejected by validation
        raise TypeError("bool is not a number")
    if isinstance(value, int):
        return str(value)
    text = repr(float(value))
    return text  # repr gives '45.0', '1e-05', 'inf', 'nan': all valid TOML floats


def save_rig(rig: RigParameters, path: str | os.PathLike, *, overwrite: bool = False) -> None:
    """Write a rig parameter set as TOML in the format :func:`load_rig` reads.

    Each value is written in the unit it was given in (its provenance) when that reproduces the
    SI value exactly, otherwise in SI. The file is written atomically (temporary file in the
    same folder, then :func:`os.replace`).

    Parameters
    ----------
    rig : RigParameters
        The parameter set.
    path : str or path-like
        Destination file.
    overwrite : bool, optional
        Replace an existing file. Default False.

    Raises
    ------
    FileExistsError
        ``path`` exists and ``overwrite`` is False.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "rig.toml"
    >>> save_rig(default_rig(), path)
    >>> path.read_text().splitlines()[0].startswith("# rollerrig rig parameter set")
    True
    """
    path = Path(path)
    if path.exists() and not overwrite:
        raise FileExistsError(f"{path} exists; pass overwrite=True to replace it")
    lines = [
        "# rollerrig rig parameter set (written by rollerrig.rig.save_rig).",
        "# Each value: { value, unit, source | assumption }. SI inside the package.",
        "",
    ]
    for section, model in _SECTIONS.items():
        lines.append(f"[{section}]")
        values = getattr(rig, section)
        for key, field in model.model_fields.items():
            value = getattr(values, key)
            if section == "meta":
                lines.append(f"{key} = {_toml_str(value)}")
                continue
            quantity = field.json_schema_extra["quantity"]
            record = rig.provenance.get(f"{section}.{key}", {})
            written, unit = value, next(iter(UNITS[quantity]))
            if "value" in record and record.get("unit") in UNITS[quantity]:
                as_written = record["value"]
                try:
                    again = _convert("", quantity, field.annotation, as_written, record["unit"])
                except _Problem:
                    again = None
                if again == value and type(again) is type(value):
                    written, unit = as_written, record["unit"]
            kind = "source" if "source" in record else "assumption"
            text = record.get(kind, "no provenance recorded (set in Python)")
            shown = _toml_str(written) if isinstance(written, str) else _toml_number(written)
            lines.append(
                f"{key} = {{ value = {shown}, unit = {_toml_str(unit)}, "
                f"{kind} = {_toml_str(text)} }}"
            )
        lines.append("")
    payload = "\n".join(lines)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as fh:
            fh.write(payload)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
