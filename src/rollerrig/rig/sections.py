"""The sections of a rig parameter set: one pydantic model per section, SI values inside.

Each field carries its physical quantity (a key of :data:`rollerrig.units.QUANTITIES`, in the
field's ``json_schema_extra``) and its physical range; its docstring, with the SI unit in
brackets, becomes the field's description. :mod:`rollerrig.rig.rigfile` reads and writes these
sections as TOML; :class:`rollerrig.rig.parameters.RigParameters` holds one of each.

Examples
--------
>>> InertiaParameters.model_fields["roller"].description
'J5, roller (rotating rail) [kg.m^2].'
>>> quantity_of(StiffnessParameters.model_fields["roller_shaft"])
'torsional_stiffness'
"""

from __future__ import annotations

import math
import warnings
from typing import Annotated, Any, Literal

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, model_validator

from rollerrig._validation import FieldProblem, interval
from rollerrig.drives.vf import VF_SETTING_RANGES
from rollerrig.units import QUANTITIES

__all__ = [
    "SECTIONS",
    "ArmParameters",
    "BearingParameters",
    "DampingParameters",
    "FrameParameters",
    "GeometryParameters",
    "InductionMotorParameters",
    "InertiaParameters",
    "MaterialParameters",
    "MetaParameters",
    "PmsmParameters",
    "RollerDriveVfParameters",
    "SensorParameters",
    "ServoRollerDriveParameters",
    "StiffnessParameters",
    "quantity_of",
    "si_unit_of",
]


def _si(quantity: str, **bounds: float) -> Any:
    """Field metadata: the quantity (its SI unit is the unit of the value) and the bounds."""
    return Field(json_schema_extra={"quantity": quantity}, **bounds)


def quantity_of(field) -> str:
    """The quantity of a section field (a key of :data:`rollerrig.units.QUANTITIES`)."""
    return field.json_schema_extra["quantity"]


def si_unit_of(field) -> str:
    """The SI unit of a section field's value."""
    return QUANTITIES[quantity_of(field)].si_unit


def _quadrature(value: int) -> int:
    if value not in (1, 2, 4):
        raise FieldProblem("", "not a quadrature factor", allowed=[1, 2, 4], got=value)
    return value


def _vf(name: str, unit: str | None = None) -> Any:
    """Field metadata of a ``[roller_drive_vf]`` key: its plausible range
    (:data:`~rollerrig.drives.vf.VF_SETTING_RANGES`) and, for a ratio, what it is a multiple of
    (``unit``, shown in its errors)."""
    low, high = VF_SETTING_RANGES[name]
    quantity = "dimensionless" if unit else "time"
    extra = {"quantity": quantity, **({"unit": unit} if unit else {})}
    return Field(json_schema_extra=extra, ge=low, le=high)


def _filter_time(value: float) -> float:
    low, high = VF_SETTING_RANGES["filter_time"]
    if 0.0 < value < low:
        raise FieldProblem(
            "",
            "must be 0 (the machine's default) or at least 1 ms",
            unit="s",
            allowed=f"0 or {interval(low, high, low_inclusive=True, high_inclusive=True)}",
            got=value,
        )
    return value


# Value types: float (or int) in the SI unit of a quantity, with its physical range.
_Inertia = Annotated[float, _si("inertia", gt=0)]
_Stiffness = Annotated[float, _si("torsional_stiffness", gt=0)]
_Damping = Annotated[float, _si("torsional_damping", ge=0)]
_Length = Annotated[float, _si("length", gt=0)]
_Pressure = Annotated[float, _si("pressure", gt=0)]
_Speed = Annotated[float, _si("angular_speed", gt=0)]
_Bandwidth = Annotated[float, _si("angular_frequency", gt=0)]
_Power = Annotated[float, _si("power", gt=0)]
_Torque = Annotated[float, _si("torque", gt=0)]
_Current = Annotated[float, _si("current", gt=0)]
_Voltage = Annotated[float, _si("voltage", gt=0)]
_Resistance = Annotated[float, _si("resistance", gt=0)]
_Inductance = Annotated[float, _si("inductance", gt=0)]
_Frequency = Annotated[float, _si("frequency", gt=0)]
_Time = Annotated[float, _si("time", gt=0)]
_PolePairs = Annotated[int, _si("count", ge=1)]
_Fraction = Annotated[float, _si("dimensionless", ge=0, lt=1)]


class _Section(BaseModel):
    """Base of the SI parameter sections: frozen, no extra keys, strict types, finite floats."""

    model_config = ConfigDict(
        frozen=True,
        extra="forbid",
        strict=True,
        allow_inf_nan=False,
        use_attribute_docstrings=True,
    )


class MetaParameters(BaseModel):
    """Name and description of a parameter set (plain strings in the TOML file)."""

    model_config = ConfigDict(
        frozen=True, extra="forbid", strict=True, use_attribute_docstrings=True
    )

    name: str
    """Short name of the parameter set."""
    description: str
    """What rig this is and where its numbers come from."""


class InertiaParameters(_Section):
    """Moments of inertia J1..J7 of the seven bodies of the torsional chain [kg.m^2]."""

    pmsm_stator: _Inertia
    """J1, PMSM stator [kg.m^2]."""
    pmsm_rotor: _Inertia
    """J2, PMSM rotor [kg.m^2]."""
    wheel_disc: _Inertia
    """J3, wheel disc (hub) [kg.m^2]."""
    wheel_tyre: _Inertia
    """J4, wheel tyre, outside the rubber layer [kg.m^2]."""
    roller: _Inertia
    """J5, roller (rotating rail) [kg.m^2]."""
    am_rotor: _Inertia
    """J6, asynchronous (induction) motor rotor [kg.m^2]."""
    am_stator: _Inertia
    """J7, asynchronous motor stator [kg.m^2]."""


class StiffnessParameters(_Section):
    """Torsional stiffnesses of the five spring elements of the chain [N.m/rad]."""

    pmsm_mount: _Stiffness
    """k01, PMSM stator mount to ground [N.m/rad]."""
    wheel_shaft: _Stiffness
    """k23, wheel shaft [N.m/rad]."""
    wheel_rubber: _Stiffness
    """k34, rubber layer between wheel disc and tyre [N.m/rad]."""
    roller_shaft: _Stiffness
    """k56, roller shaft (CV shaft and torque sensor) [N.m/rad]."""
    am_mount: _Stiffness
    """k70, AM stator mount to ground [N.m/rad]."""


class DampingParameters(_Section):
    """Viscous torsional damping of the five spring elements of the chain [N.m.s/rad]."""

    pmsm_mount: _Damping
    """b01, PMSM stator mount [N.m.s/rad]."""
    wheel_shaft: _Damping
    """b23, wheel shaft [N.m.s/rad]."""
    wheel_rubber: _Damping
    """b34, rubber layer [N.m.s/rad]."""
    roller_shaft: _Damping
    """b56, roller shaft [N.m.s/rad]."""
    am_mount: _Damping
    """b70, AM stator mount [N.m.s/rad]."""


class GeometryParameters(_Section):
    """Principal radii of the wheel and the roller at the contact point [m]."""

    wheel_radius_x: _Length
    """Wheel rolling radius r_wx, longitudinal [m]."""
    wheel_radius_y: _Length
    """Wheel transverse profile radius r_wy [m]."""
    roller_radius_x: _Length
    """Roller rolling radius r_rx, longitudinal [m]."""
    roller_radius_y: _Length
    """Roller transverse profile radius r_ry [m]."""


class MaterialParameters(_Section):
    """Elastic constants of wheel and roller (both steel) [Pa], [-]."""

    youngs_modulus: _Pressure
    """Young's modulus E of both bodies [Pa]."""
    poisson: Annotated[float, _si("dimensionless", gt=0, lt=0.5)]
    """Poisson's ratio ν of both bodies [-], in (0, 0.5)."""


class BearingParameters(_Section):
    """Bearing losses R03 (wheel) and R05 (roller), Kayaalp eqs. 4.13-4.14, made torques.

    The seed's ``R03 = N f_g`` and ``R05 = (W_r + N) f_g`` are friction *forces* [N]; the loss
    torques are these forces times the bearing (journal) radius, and are smoothed with
    ``tanh(ω / regularisation_speed)`` so that they are finite and continuous through standstill.
    """

    friction_coefficient: Annotated[float, _si("dimensionless", ge=0, lt=1)]
    """Bearing friction coefficient f_g [-], in [0, 1)."""
    roller_subsystem_weight: Annotated[float, _si("force", ge=0)]
    """Weight W_r of the roller subsystem carried by the roller bearings [N]."""
    wheel_bearing_radius: _Length
    """Friction radius of the wheel bearings (half the bore) [m]."""
    roller_bearing_radius: _Length
    """Friction radius of the roller bearings (half the bore) [m]."""
    regularisation_speed: _Speed
    """Speed below which Coulomb bearing friction is smoothed (tanh) [rad/s]."""


class PmsmParameters(_Section):
    """Wheel drive: direct-drive permanent-magnet synchronous motor (Kayaalp Table 1).

    The dq model uses the amplitude-invariant transform: ``T = 1.5 p φ i_q`` (Kayaalp eq. 4.25
    with ``i_d = 0``).
    """

    rated_power: _Power
    """Rated mechanical power [W]."""
    rated_speed: _Speed
    """Rated speed [rad/s]."""
    rated_torque: _Torque
    """Rated (nominal) torque [N.m]."""
    rated_current: _Current
    """Rated current [A]."""
    flux_linkage: Annotated[float, _si("flux_linkage", gt=0)]
    """Permanent-magnet flux linkage φ [Wb]."""
    pole_pairs: _PolePairs
    """Number of pole pairs p [-]."""
    stator_resistance: _Resistance
    """Stator phase resistance R_s [ohm]."""
    inductance_d: _Inductance
    """d-axis inductance L_d [H]."""
    inductance_q: _Inductance
    """q-axis inductance L_q [H]."""
    dc_link_voltage: _Voltage
    """Inverter DC-link voltage [V]."""
    current_loop_bandwidth: _Bandwidth
    """Closed-loop bandwidth of the dq current controllers [rad/s]."""
    max_current: _Current
    """Current limit of the inverter (dq amplitude) [A]."""
    torque_ripple_amplitude: Annotated[float, _si("torque", ge=0)] = 0.0
    """Amplitude of the inverter torque ripple [N.m] (0: none)."""
    torque_ripple_frequency: Annotated[float, _si("frequency", ge=0)] = 0.0
    """Frequency of the inverter torque ripple [Hz]."""

    @model_validator(mode="after")
    def _consistent(self):
        if self.torque_ripple_amplitude > 0 and self.torque_ripple_frequency <= 0:
            raise FieldProblem(
                "torque_ripple_frequency",
                "must be > 0 when torque_ripple_amplitude > 0",
                unit="Hz",
                allowed=interval(0, math.inf),
                got=self.torque_ripple_frequency,
            )
        if self.max_current < self.rated_current:
            raise FieldProblem(
                "max_current",
                "must be >= rated_current",
                unit="A",
                allowed=interval(self.rated_current, math.inf, low_inclusive=True),
                got=self.max_current,
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

    rated_power: _Power
    """Rated mechanical power [W]."""
    rated_frequency: _Frequency
    """Rated supply frequency [Hz]."""
    rated_torque: _Torque
    """Rated torque [N.m]."""
    rated_current: _Current
    """Rated line current [A]."""
    rated_line_voltage: _Voltage
    """Rated line-to-line voltage (RMS) [V]."""
    connection: Annotated[Literal["delta", "star"], _si("dimensionless")]
    """Winding connection: 'delta' or 'star' (unit "-")."""
    pole_pairs: _PolePairs
    """Number of pole pairs p [-]."""
    breakdown_torque_ratio: Annotated[float, _si("dimensionless", gt=1)]
    """Breakdown (pull-out) torque over rated torque [-], > 1."""
    stator_resistance: _Resistance
    """Stator resistance per phase of the winding *as connected* [ohm]: per delta phase for a
    delta machine (the Thevenin circuit, :meth:`circuit`, takes it with the delta phase voltage,
    the line voltage), per star phase for a star machine. The equivalent star has
    :attr:`equivalent_star_stator_resistance` (R_Δ/3 for delta), the value the dq machine
    (:func:`rollerrig.drives.induction_dq.inverse_gamma_from_rig`) uses."""
    response_lag_clp: Annotated[float, _si("rate", gt=0)]
    """Response-lag parameter c_lp of Kayaalp eq. 4.29 [1/s] (weight c_lp·Δt)."""
    response_lag_reference_step: _Time
    """Step Δt at which c_lp was fitted (Kayaalp 4.5.1.8) [s]."""

    @model_validator(mode="after")
    def _consistent(self):
        weight = self.response_lag_clp * self.response_lag_reference_step
        if weight > 1.0:
            raise FieldProblem(
                "response_lag_clp",
                f"c_lp·Δt = {weight:g} must be <= 1 (the filter weight of Kayaalp eq. 4.29, "
                "Δt = response_lag_reference_step)",
                unit="1/s",
                allowed=interval(0, 1.0 / self.response_lag_reference_step, high_inclusive=True),
                got=self.response_lag_clp,
            )
        if self.rated_slip <= 0.0:
            raise FieldProblem(
                "",
                f"rated speed rated_power/rated_torque ({self.rated_speed:g} rad/s) must be below "
                f"the synchronous speed 2π·rated_frequency/pole_pairs "
                f"({self.synchronous_speed:g} rad/s)",
            )
        return self

    @property
    def synchronous_speed(self) -> float:
        """Mechanical synchronous speed at the rated frequency, ``2π f / p`` [rad/s]."""
        return 2.0 * math.pi * self.rated_frequency / self.pole_pairs

    @property
    def rated_speed(self) -> float:
        """Rated mechanical speed from the nameplate, ``P / T`` [rad/s]."""
        return self.rated_power / self.rated_torque

    @property
    def rated_slip(self) -> float:
        """Rated slip ``1 - ω_N / ω_sync`` [-] (≈ 1.76 % for the default rig)."""
        return 1.0 - self.rated_speed / self.synchronous_speed

    @property
    def breakdown_torque(self) -> float:
        """Breakdown torque ``ratio × T_N`` [N.m]."""
        return self.breakdown_torque_ratio * self.rated_torque

    @property
    def phase_voltage(self) -> float:
        """Phase voltage of the equivalent star, ``V_line / √3`` (RMS) [V]."""
        return self.rated_line_voltage / math.sqrt(3.0)

    @property
    def equivalent_star_stator_resistance(self) -> float:
        """Stator resistance of the equivalent star [ohm]: R_Δ/3 for a delta winding (a delta
        of impedances Z is a star of Z/3), the value itself for a star winding."""
        return self.stator_resistance / (3.0 if self.connection == "delta" else 1.0)

    @property
    def stator_resistance_per_unit(self) -> float:
        """R_s over the base impedance of a phase of the winding as connected [-]: delta
        U_line / (I_line/√3), star (U_line/√3) / I_line (the same per unit either way)."""
        return self.equivalent_star_stator_resistance * self.rated_current / self.phase_voltage

    def circuit(self):
        """The Thevenin circuit derived from this nameplate
        (:func:`rollerrig.drives.induction.thevenin_from_nameplate`)."""
        from rollerrig.drives.induction import thevenin_from_nameplate

        return thevenin_from_nameplate(
            self.rated_power,
            self.rated_frequency,
            self.rated_torque,
            self.rated_line_voltage,
            self.connection,
            self.pole_pairs,
            breakdown_torque_ratio=self.breakdown_torque_ratio,
            stator_resistance=self.stator_resistance,
        )


class ServoRollerDriveParameters(_Section):
    """Speed-controlled servo/PMSM roller drive: the seed's proposed fix (Kayaalp 5, 4.5.1.8)."""

    speed_bandwidth: _Bandwidth
    """Closed-loop speed bandwidth [rad/s]."""
    torque_limit: _Torque
    """Torque limit of the servo drive [N.m]."""
    torque_time_constant: _Time
    """Time constant of the inner torque (current) loop [s]."""


class SensorParameters(_Section):
    """Data acquisition and sensors (Kayaalp 4.1.3), and the accuracy of the measurement chain.

    The accuracy keys feed the uncertainty of the corrected CoA
    (:mod:`rollerrig.estimation.uncertainty`); each has a default (the bundled rig's value).
    """

    daq_rate: _Frequency
    """Sampling rate of the DAQ [Hz]."""
    encoder_pulses_per_revolution: _PolePairs
    """Encoder lines (pulses per revolution per channel) [-]."""
    encoder_quadrature_factor: Annotated[int, _si("count"), AfterValidator(_quadrature)]
    """Edges counted per line: 1, 2 or 4 (quadrature) [-]."""
    air_spring_effective_area: Annotated[float, _si("area", gt=0)]
    """Effective area of the air spring: normal force = pressure × area [m^2]."""
    torque_sensor_range: _Torque
    """Full-scale range of the torque sensor [N.m]."""
    # The accuracy of the measurement chain (rollerrig.estimation.uncertainty). Defaults equal the
    # bundled rig's values, so rig files written before these keys existed still load.
    torque_sensor_accuracy: _Fraction = 0.001
    """Accuracy class of the torque sensor: bound of its error as a fraction of
    torque_sensor_range [-] (rectangular, the same error over a test)."""
    pressure_sensor_range: _Pressure = 1.0e6
    """Full-scale range of the air-spring pressure sensor [Pa]."""
    pressure_sensor_accuracy: _Fraction = 0.0035
    """Accuracy class of the pressure sensor: bound of its error as a fraction of
    pressure_sensor_range [-] (rectangular, the same error over a test)."""
    air_spring_area_uncertainty: _Fraction = 0.02
    """Relative standard uncertainty of air_spring_effective_area [-] (normal)."""
    roller_radius_tolerance: Annotated[float, _si("length", ge=0)] = 2.5e-4
    """Half-width of the tolerance of the roller rolling radius r_rx [m] (rectangular)."""
    wheel_radius_tolerance: Annotated[float, _si("length", ge=0)] = 2.5e-4
    """Half-width of the tolerance of the wheel rolling radius r_wx [m] (rectangular)."""
    roller_inertia_uncertainty: _Fraction = 0.05
    """Relative standard uncertainty of the roller inertia J5 [-] (normal)."""
    bearing_loss_uncertainty: Annotated[float, _si("dimensionless", ge=0)] = 0.5
    """Relative standard uncertainty of the roller bearing loss R05 [-] (normal)."""

    @property
    def encoder_counts_per_revolution(self) -> int:
        """Counts per revolution after quadrature decoding [-]."""
        return self.encoder_pulses_per_revolution * self.encoder_quadrature_factor


class ArmParameters(_Section):
    """The swinging arm that carries the wheel: how the normal load at the contact differs from
    the air-spring force the rig measures (Kayaalp 4.1.1).

    The wheel hangs on an arm pivoted on the rear columns; the air spring pushes the arm down
    with the force S the DAQ computes from its pressure. Moments about the pivot give

        N = S + W_d + σ (h / l) F_x

    with h the pivot's height above the contact, l the horizontal distance from the pivot to
    the wheel centre, σ = +1 when the pivot lies on the side toward which positive traction
    pushes the wheel at the contact (``pivot_side = "rear"``: traction presses the wheel on the
    roller), −1 on the other side, and W_d the weight of arm, wheel and PMSM that the air
    spring's load calibration does not include. The dissertation gives none of these values
    (its figures are lost): each default is a stated assumption with its own uncertainty, which
    the uncertainty of the corrected CoA carries as type-B terms. ``pivot_height = 0`` means no
    transfer. Rig files without an ``[arm]`` table get these defaults.

    The air spring is taken to push the arm above the wheel (the Pardubice rig's top beam). A
    spring seated on another lever l_s about the pivot gives N = (l_s/l) S + W_d + σ (h/l) F_x:
    state it by scaling the air-spring channel by l_s/l in the channel map (its ``scale``),
    and the ratio's relative uncertainty within ``sensors.air_spring_area_uncertainty``
    (combined in quadrature with the area's own: N depends on l_s/l and the spring's effective
    area only through their product, so the band carries the one as the other); unstated, the
    corrected CoA's band covered 30 % of a recording with l_s/l = 0.7 and 97.7 % with the scale
    given (docs/guide/tour.rst, "What holds, and on which recordings").
    """

    pivot_height: Annotated[float, _si("length", ge=-5.0, le=5.0)] = 0.348
    """Height h of the arm's pivot above the contact point [m]."""
    pivot_height_tolerance: Annotated[float, _si("length", ge=0, le=5.0)] = 0.15
    """Half-width of the rectangular distribution of h [m] (standard uncertainty
    tolerance/√3)."""
    arm_length: Annotated[float, _si("length", gt=0.05, le=10.0)] = 0.70
    """Horizontal distance l from the pivot to the wheel centre [m]."""
    arm_length_tolerance: Annotated[float, _si("length", ge=0, le=5.0)] = 0.15
    """Half-width of the rectangular distribution of l [m]."""
    pivot_side: Annotated[Literal["rear", "front"], _si("dimensionless")] = "rear"
    """``"rear"``: the pivot lies on the side toward which positive traction pushes the wheel
    at the contact, so traction adds σ (h/l) F_x to the load (the Pardubice rig's rear columns);
    ``"front"``: the other side, traction takes it away."""
    dead_weight: Annotated[float, _si("force", ge=-1.0e5, le=1.0e5)] = 0.0
    """Weight share W_d of arm, wheel and PMSM on the contact that the air-spring force S does
    not include [N]."""
    dead_weight_uncertainty: Annotated[float, _si("force", ge=0, le=1.0e5)] = 200.0
    """Standard uncertainty of W_d [N] (normal)."""

    @model_validator(mode="after")
    def _consistent(self):
        if self.arm_length_tolerance >= self.arm_length:
            raise FieldProblem(
                "arm_length_tolerance",
                "must be below arm_length (the arm's length must stay positive)",
                unit="m",
                allowed=interval(0, self.arm_length, high_inclusive=False),
                got=self.arm_length_tolerance,
            )
        if abs(self.transfer_ratio) >= 1.0:
            raise FieldProblem(
                "pivot_height",
                f"h/l = {self.transfer_ratio:g}: the load transfer σ h/l must stay within ±1 "
                "(a pivot higher above the contact than the arm is long would lift the wheel "
                "off at a CoA of 1)",
                unit="m",
                allowed=interval(-self.arm_length, self.arm_length, high_inclusive=False),
                got=self.pivot_height,
            )
        return self

    @property
    def sign(self) -> float:
        """σ: +1 for ``pivot_side = "rear"``, −1 for ``"front"`` [-]."""
        return 1.0 if self.pivot_side == "rear" else -1.0

    @property
    def transfer_ratio(self) -> float:
        """σ h / l [-]: the share of the contact force F_x that adds to the normal load."""
        return self.sign * self.pivot_height / self.arm_length

    @property
    def transfer_ratio_uncertainty(self) -> float:
        """Standard uncertainty of σ h/l [-] from the rectangular tolerances of h and l (first
        order, JCGM 100 eq. 10)."""
        u_h = self.pivot_height_tolerance / math.sqrt(3.0)
        u_l = self.arm_length_tolerance / math.sqrt(3.0)
        return math.hypot(u_h / self.arm_length, self.pivot_height * u_l / self.arm_length**2)

    def contact_load(self, air_spring_force, contact_force):
        """Normal load at the contact N = S + W_d + σ (h/l) F_x [N].

        Parameters
        ----------
        air_spring_force : array_like
            S [N], what the rig measures.
        contact_force : array_like
            F_x [N], traction positive.

        Examples
        --------
        >>> arm = ArmParameters()
        >>> round(arm.transfer_ratio, 4), round(float(arm.contact_load(4300.0, 1000.0)), 1)
        (0.4971, 4797.1)
        """
        return air_spring_force + self.dead_weight + self.transfer_ratio * contact_force


class RollerDriveVfParameters(_Section):
    """The roller inverter's open-loop V/f control, used by the dq roller drive
    (``DriveConfig(roller="induction_dq")``, :func:`rollerrig.drives.vf.vf_control_for`).

    Kayaalp (4.5.1.4.2) says only "open-loop volts per Hertz": every default is a stated
    assumption of a general-purpose inverter as shipped. Rig files without a
    ``[roller_drive_vf]`` table get these defaults. Each key has a plausible range
    (:data:`rollerrig.drives.vf.VF_SETTING_RANGES`, where each is justified), checked when the
    file is read: e.g. a current limit of 1e-9 is one error naming the key, its unit (times the
    rated current) and the range.
    """

    boost: Annotated[float, _vf("boost", "U_0/(R_s.I_N)")] = 0.5
    """Continuous voltage boost U_0 / (R_s I_N) [-] (Siemens P1310 form), in [0, 2.5]; 0:
    none."""
    ir_compensation: Annotated[float, _si("dimensionless", ge=0, le=1)] = 0.0
    """Automatic IR compensation: 1 on, 0 off [-]."""
    slip_compensation: Annotated[float, _vf("slip_compensation", "x rated slip")] = 0.0
    """Slip-compensation gain [-] (1: the rated slip is compensated), in [0, 1.5]; 0: none."""
    current_limit: Annotated[float, _vf("current_limit", "x induction_motor.rated_current")] = 1.5
    """Current limit as a multiple of the rated current [-], in [1, 4]."""
    ramp_time: Annotated[float, _vf("ramp_time")] = 10.0
    """Frequency-command ramp from 0 to the rated frequency [s], in [0.01, 650]."""
    current_filter_time: Annotated[
        float,
        _si("time", ge=0, le=VF_SETTING_RANGES["current_filter_time"][1]),
        AfterValidator(_filter_time),
    ] = 0.0
    """Time constant of the current filter (IR and slip compensation, current limit) [s], in
    [0.001, 10]; 0: the machine's default 1/(0.1 (R_R/L_σ + R_R/L_M)) (Hinkkanen et al. 2022;
    0.36 s on the bundled rig)."""
    slip_filter_time: Annotated[
        float,
        _si("time", ge=0, le=VF_SETTING_RANGES["slip_filter_time"][1]),
        AfterValidator(_filter_time),
    ] = 0.0
    """Time constant of the slip-estimate filter of the slip compensation [s], in [0.001, 10];
    0: the machine's default (as ``current_filter_time``)."""
    rotor_resistance_estimate: Annotated[
        float, _vf("rotor_resistance_estimate", "x the machine's rotor resistance")
    ] = 1.0
    """The inverter's rotor resistance R̂_R over the machine's [-], in [0.5, 2]: its slip
    estimate scales with it, so an estimate 50 % high acts like 1.5 × the slip compensation."""
    filter_time: Annotated[
        float,
        _si("time", ge=0, le=VF_SETTING_RANGES["filter_time"][1]),
        AfterValidator(_filter_time),
    ] = 0.0
    """Deprecated: the former single key of both filters [s]; read as ``current_filter_time``
    and ``slip_filter_time`` (with a :class:`FutureWarning`); 0: not given."""

    @model_validator(mode="after")
    def _one_filter_key(self):
        if self.filter_time > 0.0:
            if self.current_filter_time > 0.0 or self.slip_filter_time > 0.0:
                raise FieldProblem(
                    "filter_time",
                    "is the deprecated key of both filters: give current_filter_time and "
                    "slip_filter_time instead, not with it",
                    unit="s",
                    got=self.filter_time,
                )
            warnings.warn(
                "roller_drive_vf.filter_time is deprecated: it is read as both "
                f"current_filter_time and slip_filter_time ({self.filter_time:g} s); write "
                "those two keys instead",
                FutureWarning,
                stacklevel=2,
            )
        return self

    def options(self) -> dict:
        """Keyword arguments of :func:`rollerrig.drives.vf.vf_control_for`."""
        old = self.filter_time or None  # the deprecated key of both filters
        return {
            "boost": self.boost,
            "ir_compensation": self.ir_compensation > 0.0,
            "slip_compensation": self.slip_compensation,
            "current_limit": self.current_limit,
            "ramp_time": self.ramp_time,
            "current_filter_time": self.current_filter_time or old,
            "slip_filter_time": self.slip_filter_time or old,
            "rotor_resistance_estimate": self.rotor_resistance_estimate,
        }


class FrameParameters(_Section):
    """The rig frame seen from the wheel-roller contact: one longitudinal degree of freedom.

    Used by the twin when ``DriveConfig(frame="flexible")``: the roller's contact point moves
    with the frame relative to the wheel's by x_f, with m_f ẍ_f = F_x − k_f x_f − c_f ẋ_f and
    c_f = 2 ζ_f sqrt(k_f m_f) (Kayaalp 4.3.1's hypothesis of a longitudinally flexible frame).
    The defaults are ``rollerrig frame``'s result on the bundled default frame
    (``rollerrig.frame.contact_dof``): every value here is only as good as that frame's
    assumed geometry. Rig files without a ``[frame]`` table get them.
    """

    longitudinal_stiffness: Annotated[float, _si("linear_stiffness", gt=0)] = 1.006e8
    """Static stiffness between the wheel's and the roller's contact points k_f [N/m]."""
    modal_mass: Annotated[float, _si("mass", gt=0)] = 1101.0
    """Mass of the one-degree-of-freedom frame m_f = k_f / ω_f² [kg], so that it keeps both the
    static compliance and the frequency of the first longitudinal mode."""
    damping_ratio: Annotated[float, _si("dimensionless", ge=0, lt=1)] = 0.01
    """Damping ratio ζ_f of that mode [-]."""

    @property
    def frequency(self) -> float:
        """Undamped natural frequency of the frame degree of freedom [Hz]."""
        import math

        return math.sqrt(self.longitudinal_stiffness / self.modal_mass) / (2.0 * math.pi)


SECTIONS: dict[str, type[BaseModel]] = {
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
    "frame": FrameParameters,
    "roller_drive_vf": RollerDriveVfParameters,
    "arm": ArmParameters,
}
"""Section name -> model, in file order."""
