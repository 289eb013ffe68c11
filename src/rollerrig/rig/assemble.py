"""Assemble the coupled model's numeric inputs from a rig, a drive choice and a protocol.

The solvers see only flat arrays (:mod:`rollerrig.rig.model`): a parameter vector, a table of
piecewise-linear inputs, the list of integration segments (the protocol's breakpoints, across
which friction may switch) and an initial state. This module builds them, and finds the steady
free-rolling state the experiment starts from.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from itertools import pairwise

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig._warnings import DomainWarning
from rollerrig.contact.creep import (
    POLACH_PARAMETER_SETS,
    PolachParameters,
)
from rollerrig.contact.creep import friction_kernel as _friction_kernel
from rollerrig.contact.creep import polach_force_kernel as _polach_force_kernel
from rollerrig.contact.hertz import hertz_contact
from rollerrig.contact.kalker import kalker_coefficients
from rollerrig.contact.kinematics import DEFAULT_REGULARISATION_SPEED
from rollerrig.contact.laws import EUROSPRINTER_MODIFIED_FASTSIM, FastsimParameters
from rollerrig.drives.induction import lag_time_constant_from_clp
from rollerrig.drives.pmsm import max_phase_voltage, pi_gains_for_bandwidth, pmsm_torque
from rollerrig.drives.pmsm_envelope import VOLTAGE_LIMIT_SHARE, pmsm_voltage_share
from rollerrig.drives.servo import servo_gains_for_bandwidth
from rollerrig.experiment.protocol import Protocol
from rollerrig.rig import model as m
from rollerrig.rig.parameters import RigParameters

__all__ = ["ModelInputs", "Segment", "assemble"]


@dataclass(frozen=True)
class Segment:
    """An integration interval with constant friction parameters."""

    start: float  # [s]
    end: float  # [s]
    friction_condition: str
    params: np.ndarray = field(repr=False)  # parameter vector valid on this segment


@dataclass(frozen=True)
class ModelInputs:
    """Everything a solver needs, as arrays, plus the objects they came from (for provenance)."""

    rig: RigParameters
    drives: m.DriveConfig
    protocol: Protocol
    friction_sets: Mapping[str, PolachParameters | FastsimParameters]
    tables: np.ndarray = field(repr=False)
    segments: tuple[Segment, ...] = field(repr=False)
    initial_state: np.ndarray = field(repr=False)
    contact_reference: dict = field(repr=False)

    @property
    def duration(self) -> float:
        """Experiment duration [s]."""
        return self.protocol.duration


_REFERENCE_CONTACTS: dict[tuple[float, ...], tuple[float, float, float]] = {}
"""(a, b, c11) of the Hertz contact by (load, the four radii, E, ν), as :func:`_base_parameters`
found them: a calibration or a study assembles hundreds of variants of one geometry, and the exact
ellipse (a solve through elliptic integrals) with Kalker's c11 cost 1.1 ms of a 4.5 ms
assembly. Contacts outside Hertz's half-space domain are not kept: each assembly warns again."""

_REFERENCE_CONTACTS_KEPT = 256


def _base_parameters(rig: RigParameters, drives: m.DriveConfig, reference_load: float):
    p = np.zeros(m.N_PARAMS)
    inertia = rig.inertia
    p[m.P_J : m.P_J + 7] = [
        inertia.pmsm_stator,
        inertia.pmsm_rotor,
        inertia.wheel_disc,
        inertia.wheel_tyre,
        inertia.roller,
        inertia.am_rotor,
        inertia.am_stator,
    ]
    k, b = rig.stiffness, rig.damping
    p[[m.P_K01, m.P_K23, m.P_K34, m.P_K56, m.P_K70]] = [
        k.pmsm_mount,
        k.wheel_shaft,
        k.wheel_rubber,
        k.roller_shaft,
        k.am_mount,
    ]
    p[[m.P_B01, m.P_B23, m.P_B34, m.P_B56, m.P_B70]] = [
        b.pmsm_mount,
        b.wheel_shaft,
        b.wheel_rubber,
        b.roller_shaft,
        b.am_mount,
    ]
    g = rig.geometry
    p[m.P_RW], p[m.P_RR] = g.wheel_radius_x, g.roller_radius_x

    # Contact at the reference load: Hertz (exact) and Kalker's C11 at the contact's a/b.
    mat = rig.material
    radii = (g.wheel_radius_x, g.wheel_radius_y, g.roller_radius_x, g.roller_radius_y)
    key = (float(reference_load), *map(float, radii), mat.youngs_modulus, mat.poisson)
    known = _REFERENCE_CONTACTS.get(key)
    if known is None:
        # Kept only when Hertz's half-space assumption holds: hertz_contact's own warning says
        # when it does not, and such an assembly must warn every time.
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            contact = hertz_contact(
                reference_load,
                *radii,
                youngs_modulus=mat.youngs_modulus,
                poisson=mat.poisson,
            )
        for w in said:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        a, bb = float(contact.semi_axis_x), float(contact.semi_axis_y)
        c11 = float(kalker_coefficients(a / bb, mat.poisson).c11)
        if not said:
            if len(_REFERENCE_CONTACTS) >= _REFERENCE_CONTACTS_KEPT:
                _REFERENCE_CONTACTS.clear()
            _REFERENCE_CONTACTS[key] = (a, bb, c11)
    else:
        a, bb, c11 = known
    shear_modulus = mat.youngs_modulus / (2.0 * (1.0 + mat.poisson))
    p[m.P_CREEP_STIFF_REF] = shear_modulus * a * bb * c11
    p[m.P_LOAD_REF] = reference_load
    p[m.P_VREG] = DEFAULT_REGULARISATION_SPEED
    contact_reference = {
        "reference_load_N": reference_load,
        "semi_axis_x_m": a,
        "semi_axis_y_m": bb,
        "c11": c11,
        "shear_modulus_Pa": shear_modulus,
        "creep_stiffness_N": p[m.P_CREEP_STIFF_REF],
    }

    br = rig.bearing
    p[m.P_BEAR_W] = br.friction_coefficient * br.wheel_bearing_radius
    p[m.P_BEAR_R] = br.friction_coefficient * br.roller_bearing_radius
    p[m.P_W_ROLLER] = br.roller_subsystem_weight
    p[m.P_OMEGA_REG] = br.regularisation_speed

    pm = rig.pmsm
    p[m.P_WHEEL_MODE] = m.WHEEL_MODES[drives.wheel]
    p[[m.P_PP, m.P_RS, m.P_LD, m.P_LQ, m.P_FLUX]] = [
        pm.pole_pairs,
        pm.stator_resistance,
        pm.inductance_d,
        pm.inductance_q,
        pm.flux_linkage,
    ]
    kp, ki = pi_gains_for_bandwidth(
        pm.inductance_q, pm.stator_resistance, pm.current_loop_bandwidth
    )
    p[m.P_KP], p[m.P_KI] = kp, ki
    p[m.P_VMAX] = max_phase_voltage(pm.dc_link_voltage)
    p[m.P_IMAX] = pm.max_current
    p[m.P_RIPPLE_AMP] = pm.torque_ripple_amplitude
    p[m.P_RIPPLE_FREQ] = pm.torque_ripple_frequency

    am = rig.induction_motor
    p[m.P_ROLLER_MODE] = m.ROLLER_MODES[drives.roller]
    circuit = am.circuit()
    p[[m.P_AM_PP, m.P_AM_V, m.P_AM_RTH, m.P_AM_XTH, m.P_AM_R2, m.P_AM_X2, m.P_AM_FRATED]] = [
        am.pole_pairs,
        circuit.voltage,
        circuit.resistance,
        circuit.reactance_th,
        circuit.rotor_resistance,
        circuit.rotor_reactance,
        am.rated_frequency,
    ]
    omega_sync = 2.0 * np.pi * am.rated_frequency / am.pole_pairs
    omega_rated = am.rated_power / am.rated_torque
    p[m.P_AM_SLOPE] = am.rated_torque / (omega_sync - omega_rated)

    servo = rig.servo_roller_drive
    if drives.roller == "servo":
        tau = servo.torque_time_constant if drives.roller_lag is None else drives.roller_lag
        inertia_servo = inertia.am_rotor + inertia.roller
        s_kp, s_ki = servo_gains_for_bandwidth(inertia_servo, servo.speed_bandwidth)
        p[m.P_SERVO_KP], p[m.P_SERVO_KI], p[m.P_SERVO_TLIM] = s_kp, s_ki, servo.torque_limit
    elif drives.roller_lag is None:
        tau = lag_time_constant_from_clp(am.response_lag_clp, am.response_lag_reference_step)
    else:
        tau = drives.roller_lag
    p[m.P_LAG_TAU] = tau
    frame = rig.frame
    p[m.P_FRAME_MODE] = m.FRAME_MODES[drives.frame]
    p[m.P_FRAME_K], p[m.P_FRAME_M] = frame.longitudinal_stiffness, frame.modal_mass
    p[m.P_FRAME_C] = (
        2.0 * frame.damping_ratio * np.sqrt(frame.longitudinal_stiffness * frame.modal_mass)
    )
    p[m.P_ARM_RATIO] = rig.arm.transfer_ratio
    p[m.P_ARM_WEIGHT] = rig.arm.dead_weight

    # Creep law: Polach's closed form, or the law's table in eps (rollerrig.contact.table).
    p[m.P_LAW] = m.LAW_CODES[drives.law]
    p[m.P_K0], p[m.P_ALPHA_INF], p[m.P_BETA] = 1.0, 1.0, 0.0
    contact_reference["creep_law"] = drives.law
    if drives.law != "polach":
        from rollerrig.contact.table import creep_table

        table = creep_table(drives.law, a / bb, mat.poisson, nodes=m.N_TAB)
        p[m.P_TAB_STEP], p[m.P_TAB_INV] = table.step, 1.0 / table.step
        p[m.P_TAB_F : m.P_TAB_F + m.N_TAB] = table.values
        p[m.P_TAB_DF : m.P_TAB_DF + m.N_TAB] = table.slopes
        contact_reference["creep_table"] = table.to_dict()
    return p, contact_reference


def _friction_into(
    p: np.ndarray, params: PolachParameters | FastsimParameters, law: str, condition: str
) -> np.ndarray:
    """The parameter vector ``p`` with a friction condition's parameters for the creep law.

    Every law takes μ0, A, B (μ(w) of Polach's form); Polach's law needs k_A, k_S (a
    :class:`PolachParameters`); the modified FASTSIM takes k0, α_∞, β from a
    :class:`FastsimParameters`, or the Eurosprinter set's
    (:data:`rollerrig.contact.laws.EUROSPRINTER_MODIFIED_FASTSIM`) with a Polach set.
    """
    q = p.copy()
    if isinstance(params, PolachParameters):
        q[[m.P_MU0, m.P_A, m.P_B, m.P_KA, m.P_KS]] = params.as_tuple()
    elif law == "polach":
        raise ParameterError(
            f"creep law 'polach' needs Polach's k_A, k_S: the friction set of condition "
            f"{condition!r} ({params.name!r}) has none; give a PolachParameters, or choose "
            "the law 'fastsim' or 'modified-fastsim'"
        )
    else:
        q[[m.P_MU0, m.P_A, m.P_B]] = (
            params.static_friction,
            params.limit_ratio,
            params.friction_decay,
        )
        q[[m.P_KA, m.P_KS]] = 0.0
    if law == "modified-fastsim":
        source = params if isinstance(params, FastsimParameters) else EUROSPRINTER_MODIFIED_FASTSIM
        q[[m.P_K0, m.P_ALPHA_INF, m.P_BETA]] = source.k0, source.alpha_inf, source.beta
    return q


_SHORTEST_SEGMENT = 1e-12
"""Shortest protocol segment [s]: a breakpoint closer than this to the one before it (or to
the experiment's end) is merged into its neighbour's segment, not integrated over a step of
round-off."""


def _segment_cuts(protocol) -> np.ndarray:
    """The segments' boundaries [s]: 0, the protocol's breakpoints and its duration, a cut
    closer than :data:`_SHORTEST_SEGMENT` to the one kept before it (or to the end) left out,
    so that the segments always cover exactly ``[0, duration]`` (a span that was dropped
    instead had left the first output instant before the first segment, or the last after
    the last).

    Examples
    --------
    >>> from rollerrig.experiment import load_protocol
    >>> float(_segment_cuts(load_protocol("release-test"))[0])
    0.0
    """
    duration = float(protocol.duration)
    cuts = np.unique(np.clip(np.asarray(protocol.breakpoints(), dtype=float), 0.0, duration))
    kept = [0.0]
    for cut in cuts:
        if cut - kept[-1] > _SHORTEST_SEGMENT and duration - cut > _SHORTEST_SEGMENT:
            kept.append(float(cut))
    kept.append(duration)
    return np.array(kept)


def assemble(
    rig: RigParameters,
    protocol: Protocol,
    drives: m.DriveConfig | None = None,
    friction_sets: Mapping[str, PolachParameters | FastsimParameters] | None = None,
) -> ModelInputs:
    """Build the solver inputs for one experiment on one rig.

    Parameters
    ----------
    rig : RigParameters
        Validated rig parameters (SI).
    protocol : Protocol
        Compiled experiment protocol.
    drives : DriveConfig, optional
        Drive models; default PMSM wheel drive, induction-motor roller drive with the rig's lag.
    friction_sets : mapping of str to PolachParameters or FastsimParameters, optional
        Friction parameters by friction-condition name; default Polach (2005) dry and wet. The
        creep law (``drives.law``) takes μ0, A, B of each; Polach's law needs a
        :class:`PolachParameters`, the modified FASTSIM takes k0, α_∞, β from a
        :class:`FastsimParameters` (else the Eurosprinter set's).

    Returns
    -------
    ModelInputs

    Raises
    ------
    ParameterError
        If a friction condition has no parameter set, or no steady free rolling exists to start
        from (see :func:`steady_free_rolling_state`; the message gives the range of normal load
        or friction in which one exists).

    Warns
    -----
    DomainWarning
        If the protocol requests more wheel torque than the rig's PMSM can deliver (the air-gap
        torque at its current limit), the Hertz contact at the initial load is outside its
        domain (:func:`rollerrig.contact.hertz.hertz_contact`), or a shaft is so stiff that its
        torque is round-off (:data:`SHAFT_TORQUE_RESOLUTION`).
    """
    # Another object had raised an AttributeError deep inside (rig.inertia, drives.wheel).
    for name, value, kind in (
        ("rig", rig, RigParameters),
        ("protocol", protocol, Protocol),
        ("drives", drives, (m.DriveConfig, type(None))),
    ):
        if not isinstance(value, kind):
            want = "a DriveConfig or None" if name == "drives" else f"a {kind.__name__}"
            raise ParameterError(f"{name} must be {want}, got {type(value).__name__}")
    drives = drives or m.DriveConfig()
    friction_sets = dict(friction_sets or POLACH_PARAMETER_SETS)
    missing = sorted(set(protocol.friction_condition) - set(friction_sets))
    if missing:
        raise ParameterError(
            f"protocol {protocol.name!r} uses friction condition(s) {missing} that have no Polach "
            f"parameter set; known: {sorted(friction_sets)}"
        )
    reference_load = float(protocol.normal_load[0])
    base, contact_reference = _base_parameters(rig, drives, reference_load)
    tables = m.stack_table_rows(
        [
            protocol.torque_time,
            protocol.torque_request,
            protocol.speed_time,
            protocol.roller_speed,
            protocol.load_time,
            protocol.normal_load,
        ]
    )

    segments = []
    # One parameter vector per friction condition, shared by its segments (an input table at
    # the DAQ's rate makes tens of thousands of segments, and few conditions).
    spans = list(pairwise(_segment_cuts(protocol)))
    middles = np.array([0.5 * (s + e) for s, e in spans])
    conditions = protocol.friction_at(middles) if spans else []
    vectors: dict[str, np.ndarray] = {}
    for (start, end), condition in zip(spans, conditions, strict=True):
        condition = str(condition)
        if condition not in vectors:
            vectors[condition] = _friction_into(
                base, friction_sets[condition], drives.law, condition
            )
        segments.append(Segment(float(start), float(end), condition, vectors[condition]))
    if drives.roller == "induction_dq":
        segments, tables, x0 = _with_dq_drive(rig, segments, tables)
    else:
        x0 = steady_free_rolling_state(
            segments[0].params, tables, friction_condition=segments[0].friction_condition
        )
    _warn_torque_beyond_drive(rig, drives, protocol)
    _warn_voltage_beyond_drive(rig, drives, protocol)
    _warn_unresolved_shaft_torque(rig, protocol)
    return ModelInputs(
        rig=rig,
        drives=drives,
        protocol=protocol,
        friction_sets=friction_sets,
        tables=tables,
        segments=tuple(segments),
        initial_state=x0,
        contact_reference=contact_reference,
    )


def _with_dq_drive(rig: RigParameters, segments: list[Segment], tables: np.ndarray):
    """Segments, tables and initial state of the model with the dq V/f roller drive.

    The parameter vectors get the machine's and the controller's parameters after the rig's
    (:func:`rollerrig.rig.model_dq.rig_dq_params`; the rig's nameplate machine,
    :func:`rollerrig.rig.dq_drive.default_dq_drive`), the speed set point passes the
    drive's frequency ramp (as :class:`rollerrig.rig.dq_twin.DqTwin`), and the initial
    state is the dq drive's steady free rolling (:func:`dq_steady_free_rolling_state`).
    """
    from rollerrig.rig import model_dq
    from rollerrig.rig.dq_drive import _ramped_tables, default_dq_drive

    drive = default_dq_drive(rig)
    rr = rig.geometry.roller_radius_x
    rate_v = drive.control.ramp_rate * 2.0 * np.pi * rr / drive.machine.pole_pairs
    tables = _ramped_tables(tables, rate_v)
    segments = [
        Segment(
            s.start,
            s.end,
            s.friction_condition,
            model_dq.rig_dq_params(s.params, drive.machine, drive.control),
        )
        for s in segments
    ]
    x0 = dq_steady_free_rolling_state(
        segments[0].params, tables, drive, friction_condition=segments[0].friction_condition
    )
    return segments, tables, x0


def dq_steady_free_rolling_state(
    p: np.ndarray, tables: np.ndarray, drive, t: float = 0.0, *, friction_condition: str = ""
) -> np.ndarray:
    """Steady free rolling with the dq V/f roller drive (the state of
    :mod:`rollerrig.rig.model_dq`), as
    :meth:`rollerrig.rig.dq_twin.DqTwin.steady_free_rolling`.

    The chain's state is :func:`steady_free_rolling_state` with the roller held at the dq
    drive's steady speed; that speed is where the drive delivers the bearing losses
    (:func:`rollerrig.rig.dq_drive.drive_steady_state`, three fixed-point passes).

    Raises
    ------
    ParameterError
        No steady state (see :func:`steady_free_rolling_state`), or a set speed of 0 at ``t``
        (the V/f drive has no steady state at zero frequency: start the protocol moving).
    """
    from rollerrig.rig import model_dq
    from rollerrig.rig.dq_drive import drive_steady_state

    p_ideal = p[: m.N_PARAMS].copy()
    p_ideal[m.P_ROLLER_MODE] = m.ROLLER_MODES["ideal_speed"]
    rr = p[m.P_RR]
    speed = float(np.interp(t, tables[m.TAB_SPEED_T], tables[m.TAB_SPEED]))
    if not speed > 0.0:
        raise ParameterError(
            f"the roller drive induction_dq needs a roller speed set point > 0 at t = {t:g} s "
            f"to start from steady free rolling (got {speed:g} m/s); start the protocol moving "
            "or choose another roller drive"
        )
    omega_cmd = drive.electrical_omega_command(speed, rr)
    roller_speed = speed / rr
    tab = tables.copy()
    x_rig = op = None
    for _ in range(3):  # the losses depend on the speed only through tanh(ω/ω_reg)
        tab[m.TAB_SPEED] = roller_speed * rr
        x_rig = steady_free_rolling_state(p_ideal, tab, t, friction_condition=friction_condition)
        op = drive_steady_state(drive, omega_cmd, torque=float(x_rig[m.X_T_ROLLER]))
        roller_speed = op.rotor_speed
    x = np.zeros(model_dq.N_DQ_STATES)
    x[: m.N_STATES] = x_rig
    x[m.X_T_ROLLER] = 0.0
    x[model_dq.X_PSI : model_dq.X_PSI + 7] = op.state
    return x


def _warn_torque_beyond_drive(rig: RigParameters, drives: m.DriveConfig, protocol: Protocol):
    """DomainWarning when the protocol requests more wheel torque than the PMSM can deliver.

    The limit is the air-gap torque at the inverter's current limit with i_d = 0 (the current
    reference is clipped there, :func:`rollerrig.drives.pmsm.pmsm_current_reference`).
    """
    pm = rig.pmsm
    peak = float(
        pmsm_torque(
            0.0, pm.max_current, pm.pole_pairs, pm.flux_linkage, pm.inductance_d, pm.inductance_q
        )
    )
    requests = np.abs(np.asarray(protocol.torque_request, dtype=float))
    k = int(np.argmax(requests))
    if not requests[k] > peak:
        return
    if drives.wheel == "pmsm":
        consequence = "the twin's PMSM saturates at that torque"
    else:
        consequence = "the ideal torque source delivers it, the rig's PMSM could not"
    warnings.warn(
        f"torque request {protocol.torque_request[k]:.4g} N.m (protocol {protocol.name!r}, "
        f"t = {protocol.torque_time[k]:.4g} s) exceeds what the wheel drive can deliver: the "
        f"PMSM reaches at most {peak:.4g} N.m at its current limit max_current = "
        f"{pm.max_current:g} A (rated torque {pm.rated_torque:g} N.m); {consequence}",
        DomainWarning,
        stacklevel=3,
    )


def _warn_voltage_beyond_drive(rig: RigParameters, drives: m.DriveConfig, protocol: Protocol):
    """DomainWarning when the protocol takes the wheel's PMSM to its voltage limit.

    The wheel turns at the roller's tread speed over its radius (free rolling); at the
    protocol's breakpoints and on a grid of 3001 instants, the steady voltage its i_d = 0
    control needs (:func:`rollerrig.drives.pmsm_envelope.pmsm_voltage_share`) is compared
    with the inverter's V_dc/√3, from
    :data:`~rollerrig.drives.pmsm_envelope.VOLTAGE_LIMIT_SHARE` of it on. There the twin's
    PMSM (no field weakening) cannot hold its current: the torque falls short of the request
    and collapses within tens of ms, faster than the correction's smoothing follows (the
    corrected CoA missed by up to 4 U there: :mod:`rollerrig.drives.pmsm_envelope`).
    """
    if drives.wheel != "pmsm":
        return
    # The breakpoints and a grid between them: a ramp crosses the limit between two of them.
    times = np.union1d(
        np.union1d(np.asarray(protocol.torque_time), np.asarray(protocol.speed_time)),
        np.linspace(0.0, float(protocol.duration), 3001),
    )
    torque = np.interp(times, protocol.torque_time, protocol.torque_request)
    speed = np.interp(times, protocol.speed_time, protocol.roller_speed)
    omega = speed / rig.geometry.wheel_radius_x
    share = pmsm_voltage_share(torque, omega, rig.pmsm)
    k = int(np.argmax(share))
    if not share[k] >= VOLTAGE_LIMIT_SHARE:
        return
    first = int(np.flatnonzero(share >= VOLTAGE_LIMIT_SHARE)[0])
    pm = rig.pmsm
    warnings.warn(
        f"the wheel's PMSM needs {100 * share[k]:.3g} % of the voltage its inverter has "
        f"(V_dc/√3 = {float(max_phase_voltage(pm.dc_link_voltage)):.4g} V) at t = "
        f"{times[k]:.4g} s of protocol {protocol.name!r} ({torque[k]:.4g} N.m at "
        f"{speed[k] * 3.6:.4g} km/h: the wheel at {omega[k]:.4g} rad/s free rolling, rated "
        f"{pm.rated_speed:.4g} rad/s), {100 * VOLTAGE_LIMIT_SHARE:g} % or more from "
        f"t = {times[first]:.4g} s: with i_d = 0 control and no field weakening its torque falls "
        "short of the request near that limit and collapses within tens of ms, faster than the "
        "corrected CoA's smoothing follows (its band is not tested there)",
        DomainWarning,
        stacklevel=3,
    )


SHAFT_TORQUE_RESOLUTION = 0.1
"""Coarsest resolution [N.m] of a shaft's torque, k (θi − θj), that :func:`assemble` accepts
without a :class:`DomainWarning`. The angles are absolute states (hundreds of rad after a
test), so a shaft's twist is known to their round-off only, and its torque to the stiffness
times that: 5e-9 N.m on the rig's roller shaft after 30 s at 30 km/h, 0.1 N.m at 1e12 N.m/rad,
and at 1e20 N.m/rad T56 read 7e5 N.m where the contact's torque was 800 (2026-11-30)."""


def _warn_unresolved_shaft_torque(rig: RigParameters, protocol: Protocol):
    """DomainWarning when a shaft between rotating bodies is so stiff that the angles' round-off
    makes its torque coarser than :data:`SHAFT_TORQUE_RESOLUTION`.

    The largest angle is bounded by the protocol's top roller speed over the smaller of the
    two radii, for the protocol's duration (the bodies turn at about the same tread speed).
    """
    radius = min(rig.geometry.wheel_radius_x, rig.geometry.roller_radius_x)
    top_speed = float(np.max(np.abs(np.asarray(protocol.roller_speed, dtype=float))))
    angle = max(top_speed / radius * float(protocol.duration), 1.0)
    step = float(np.spacing(angle))  # the angles' round-off there [rad]
    shafts = {
        "stiffness.wheel_shaft": rig.stiffness.wheel_shaft,
        "stiffness.wheel_rubber": rig.stiffness.wheel_rubber,
        "stiffness.roller_shaft": rig.stiffness.roller_shaft,
    }
    for key, k in shafts.items():
        resolution = float(k) * step
        if resolution > SHAFT_TORQUE_RESOLUTION:
            warnings.warn(
                f"{key} = {float(k):.4g} N.m/rad: the twin resolves that shaft's torque only to "
                f"{resolution:.3g} N.m (its angles reach about {angle:.3g} rad in protocol "
                f"{protocol.name!r}, known to {step:.3g} rad); torques from its twist (T56 for the "
                f"roller shaft) are round-off beyond that: a stiffness below "
                f"{SHAFT_TORQUE_RESOLUTION / step:.3g} N.m/rad keeps them within "
                f"{SHAFT_TORQUE_RESOLUTION:g} N.m",
                DomainWarning,
                stacklevel=3,
            )


def steady_free_rolling_state(
    p: np.ndarray, tables: np.ndarray, t: float = 0.0, *, friction_condition: str = ""
) -> np.ndarray:
    """Steady free rolling at the set speed with no wheel torque: the state a test starts from.

    The roller drive supplies the bearing losses of both bodies through the contact, which
    drags the wheel with a small negative creep; every shaft carries its static twist. An
    open-loop roller drive runs on the stable branch of its characteristic (between its
    breakdown torque and synchronous speed) at the slip where it delivers the losses; the
    wheel runs on the rising (adhesion) branch of the creep-force curve.

    Parameters
    ----------
    p : ndarray
        Parameter vector (see :mod:`rollerrig.rig.model`).
    tables : ndarray
        Input tables; the set speed and load are read at time ``t``.
    t : float
        Time at which the state is taken [s].
    friction_condition : str, optional
        Name of the Polach parameter set in ``p``, for error messages.

    Returns
    -------
    ndarray, shape (N_STATES,)

    Raises
    ------
    ParameterError
        If no steady state exists: the roller drive cannot deliver the bearing losses (normal
        load too large for its breakdown torque or torque limit), or the contact cannot carry
        the wheel's bearing loss (friction too low). The message gives the range in which a
        steady state exists.
    """
    speed = float(np.interp(t, tables[m.TAB_SPEED_T], tables[m.TAB_SPEED]))
    air_spring = float(np.interp(t, tables[m.TAB_LOAD_T], tables[m.TAB_LOAD]))
    load = max(air_spring + p[m.P_ARM_WEIGHT], 0.0)
    rw, rr = p[m.P_RW], p[m.P_RR]
    omega_ref = speed / rr
    at = f"at {speed * 3.6:.4g} km/h and normal load {load:.4g} N"

    omega_roller = omega_ref
    # Fixed point: the bearing loss depends weakly on speed (tanh) and on the normal load,
    # which the arm changes by κ F_x (F_x here is the small drag of the bearing losses).
    for _ in range(5):
        bearing_w, bearing_r = m._bearing_torques(load, omega_roller * rr / rw, omega_roller, p)
        force = -bearing_w / rw  # the roller drags the wheel against its bearing friction
        t56 = force * rr - bearing_r
        t_roller = -t56
        omega_roller = _roller_speed(p, omega_ref, t_roller, load, at)
        load = max(air_spring + p[m.P_ARM_WEIGHT] + p[m.P_ARM_RATIO] * force, 0.0)

    v_roller = omega_roller * rr
    polach = (p[m.P_MU0], p[m.P_A], p[m.P_B], p[m.P_KA], p[m.P_KS])
    creep_stiffness = m._creep_stiffness_at(load, p)

    def braking_force(d):  # −F_x at the slip velocity w = −d (wheel slower than the roller)
        creep = -d / np.hypot(v_roller, p[m.P_VREG])  # as in contact.kinematics
        if p[m.P_LAW] == 0.0:
            return -_polach_force_kernel(creep, -d, load, creep_stiffness, *polach)
        mu = _friction_kernel(-d, p[m.P_MU0], p[m.P_A], p[m.P_B])
        force = [m._force_and_slope(c, load, f, p)[0] for c, f in np.broadcast(creep, mu)]
        return -np.reshape(force, np.shape(creep))

    slip = 0.0
    if force != 0.0:
        d, peak = _rising_branch_root(braking_force, -force, max(v_roller, 1.0), 1e-15)
        if d is None:
            name = f"friction set {friction_condition!r}" if friction_condition else "the contact"
            raise ParameterError(
                f"no steady free rolling {at}: the contact must carry the wheel's bearing loss, "
                f"F_x = {-force:.4g} N (F_x/N = {-force / load:.3g}), but {name} "
                f"(static_friction mu0 = {p[m.P_MU0]:g}) transmits at most {peak:.4g} N; a "
                f"steady state exists for static_friction above about "
                f"{p[m.P_MU0] * -force / peak:.3g} (or a smaller bearing friction)"
            )
        slip = -d
    omega_wheel = (v_roller + slip) / rw

    x = np.zeros(m.N_STATES)
    t34 = -bearing_w
    t70 = t56  # stator 7: −T_a − T70 = 0 with T_a = −T56
    x[m.X_THETA + 0] = 0.0  # T01 = T_p = 0
    x[m.X_THETA + 3] = 0.0
    x[m.X_THETA + 2] = t34 / p[m.P_K34]
    x[m.X_THETA + 1] = x[m.X_THETA + 2]  # T23 = T_p = 0
    x[m.X_THETA + 4] = 0.0
    x[m.X_THETA + 5] = -t56 / p[m.P_K56]
    x[m.X_THETA + 6] = t70 / p[m.P_K70]
    x[m.X_OMEGA + 1 : m.X_OMEGA + 4] = omega_wheel
    x[m.X_OMEGA + 4 : m.X_OMEGA + 6] = omega_roller
    x[m.X_T_ROLLER] = t_roller
    if p[m.P_ROLLER_MODE] == 3.0 and p[m.P_SERVO_KI] > 0:
        x[m.X_INT_SPEED] = t_roller / p[m.P_SERVO_KI]
    if p[m.P_FRAME_MODE] != 0.0:
        x[m.X_FRAME_X] = force / p[m.P_FRAME_K]  # k_f x_f = F_x: the steady contact force
    return x


#: Search grid of :func:`_rising_branch_root`, as fractions of the span: 0, then geometric from
#: 1e-9 to 1, so that a steep branch (a tiny slip) and a wide one are both resolved.
_GRID = np.concatenate([[0.0], np.geomspace(1e-9, 1.0, 400)])


def _rising_branch_root(fun, needed, span, xtol):
    """Root of ``fun(d) = needed`` on the rising branch of ``fun`` from ``d = 0``.

    ``fun`` (vectorised, ``fun(0) = 0``) rises with ``d`` up to its first maximum: the stable
    branch of a drive characteristic or the adhesion branch of a creep-force curve. Returns
    ``(d, peak)`` with ``peak`` the first maximum on the grid over ``[0, span]``, and ``d =
    None`` when ``needed`` exceeds it (no root on the branch).
    """
    d = _GRID * span
    values = np.asarray(fun(d), dtype=float)
    falling = np.flatnonzero(np.diff(values) < 0.0)
    branch = values[: falling[0] + 1] if falling.size else values
    peak = float(branch.max())
    if not needed <= peak:
        return None, peak
    k = int(np.argmax(branch >= needed))
    if k == 0 or branch[k] == needed:
        return float(d[k]), peak
    return _bracketed_root(fun, needed, float(d[k - 1]), float(d[k]), xtol), peak


_REFINE = np.linspace(0.0, 1.0, 65)[1:-1]  # interior points of a bracket, 64 sub-brackets


def _bracketed_root(fun, needed, lo, hi, xtol):
    """Root of ``fun(d) = needed`` in ``[lo, hi]`` [same unit as ``d``] to ``xtol`` (absolute,
    plus 4 ulp of the root), for a vectorised ``fun`` that rises through ``needed`` there
    (``fun(lo) < needed <= fun(hi)``).

    The bracket is cut into 64 at each pass (one vectorised call) and the first sub-bracket
    whose right end reaches ``needed`` is kept: a 5 % bracket reaches 1e-15 in about eight
    passes. Bisection's guarantee with Brent's economy of calls (``scipy.optimize.brentq``,
    the reference in tests/rig/test_assemble.py), without importing ``scipy.optimize``
    (0.1-0.2 s of every command that builds a rig, for six roots).
    """
    tiny = 4.0 * np.finfo(float).eps
    while hi - lo > xtol + tiny * max(abs(lo), abs(hi)):
        x = lo + (hi - lo) * _REFINE
        reached = np.asarray(fun(x), dtype=float) >= needed
        k = int(np.argmax(reached)) if reached.any() else x.size
        new_lo = float(x[k - 1]) if k > 0 else lo
        new_hi = float(x[k]) if k < x.size else hi
        if new_lo == lo and new_hi == hi:  # no representable point left between them
            break
        lo, hi = new_lo, new_hi
    return 0.5 * (lo + hi)


def _roller_speed(p, omega_ref, needed, load, at):
    """Roller speed [rad/s] at which the roller drive delivers the torque ``needed`` [N.m]."""
    mode = p[m.P_ROLLER_MODE]
    if mode == 3.0 and needed > p[m.P_SERVO_TLIM]:
        _raise_drive_limit(p, omega_ref, needed, p[m.P_SERVO_TLIM], "servo torque_limit", at)
    if mode not in (1.0, 2.0) or omega_ref <= 0.0:
        return omega_ref  # speed-controlled (or at rest): on the set point
    # Open loop: the rotor runs below the set speed by the slip at which the motor delivers
    # the needed torque, on the stable branch of its characteristic.
    d, peak = _rising_branch_root(
        lambda d: m._open_loop_roller_torque(omega_ref - d, omega_ref, p), needed, omega_ref, 1e-13
    )
    if d is None:
        _raise_drive_limit(p, omega_ref, needed, peak, "its largest torque at this set speed", at)
    return omega_ref - d


def _raise_drive_limit(p, omega_ref, needed, limit, what, at):
    """ParameterError: the roller drive cannot deliver the bearing losses; the load range."""
    # Losses at the set speed: P_BEAR_R (W_r + N) th_r + P_BEAR_W N th_w r_r/r_w = c0 + c1 N.
    rw, rr, reg = p[m.P_RW], p[m.P_RR], p[m.P_OMEGA_REG]
    th_r = np.tanh(omega_ref / reg)
    th_w = np.tanh(omega_ref * rr / rw / reg)
    c0 = p[m.P_BEAR_R] * p[m.P_W_ROLLER] * th_r
    c1 = p[m.P_BEAR_R] * th_r + p[m.P_BEAR_W] * th_w * rr / rw
    drive = next(k for k, v in m.ROLLER_MODES.items() if v == p[m.P_ROLLER_MODE])
    if c1 > 0.0 and limit > c0:
        hint = f"a steady state exists for normal loads below about {(limit - c0) / c1:.3g} N"
    else:
        hint = "no normal load gives one: the roller's own bearing loss exceeds it"
    raise ParameterError(
        f"no steady free rolling {at}: the roller drive ({drive}) must supply the bearing "
        f"losses, {needed:.4g} N.m, but delivers at most {limit:.4g} N.m ({what}); {hint}"
    )
