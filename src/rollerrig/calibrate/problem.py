"""The calibration problem: free parameters, the friction law and the replayed experiment.

The experiment (:func:`replay_protocol_from_recording`): the recorded wheel-torque request
(channel ``torque_request``) replayed as a piecewise-linear protocol (collinear samples merged,
exactly), at a constant normal load and a constant roller speed set point, both fitted as
nuisance parameters (:data:`NUISANCE_KEYS`): the load is started from the mean of
``normal_load`` (or ``air_spring_pressure`` × ``sensors.air_spring_effective_area``) and
fitted with the load channel among the residuals, whose mean weighs as one measurement with the
sensors' classes' error (:func:`rollerrig.calibrate.measurement.load_sigma`), so that the torque and
speeds tell the load too; the set point is started from the mean roller encoder speed before
the first torque request (the open-loop roller drive runs below its set speed by a slip that
depends on the bearing losses, so the set point cannot be read from the recording to the
accuracy the encoder counts give).

Free parameters (:func:`free_parameter_catalogue`): every float of a rig file outside
``[meta]`` and ``[sensors]`` by its dotted key (anything
:meth:`~rollerrig.rig.parameters.RigParameters.with_overrides` accepts), and the parameters of
the creep law of the recording's friction condition (:func:`law_keys`). The law is a choice
(:data:`CALIBRATION_LAWS`, :class:`rollerrig.rig.model.DriveConfig` ``law``): Polach's
(the default) has ``polach.static_friction``, ``polach.limit_ratio``,
``polach.friction_decay``, ``polach.k_adhesion``, ``polach.k_slip``
(:class:`~rollerrig.contact.creep.PolachParameters`); the modified FASTSIM has
``fastsim.static_friction``, ``fastsim.limit_ratio``, ``fastsim.friction_decay``,
``fastsim.k0``, ``fastsim.alpha_inf``, ``fastsim.beta``
(:class:`~rollerrig.contact.laws.FastsimParameters`), and FASTSIM and FaStrip the first three
of them (they read no slope reduction). Each is fitted as ``z = ln(p − p_low)`` (``p_low`` its
lower bound, 0 for most), so that it stays in its physical range and a step in ``z`` is a
relative step.

The FASTSIM family runs from a table in ε = G a b C11 ξ/(μN) (:mod:`rollerrig.contact.table`)
that none of the law's parameters enters (μ0, A, B, k0, α_∞, β are entries of the twin's
parameter vector): a change of them builds no table. FaStrip's table depends on the contact's
a/b and ν, so a free rig key that changes them (radii, materials) builds one per variant
(about 0.5 s each, once per value: :func:`rollerrig.contact.table.creep_table` keeps 32).

The measured channels, their noise model and the torque's lines:
:mod:`rollerrig.calibrate.measurement`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from rollerrig.calibrate.errors import CalibrationError
from rollerrig.calibrate.settings import FD_STEP, FD_STEP_TABULATED
from rollerrig.contact.creep import POLACH_PARAMETER_SETS, PolachParameters
from rollerrig.contact.laws import (
    CREEP_LAWS,
    EUROSPRINTER_MODIFIED_FASTSIM,
    FRICTION_PARAMETER_SETS,
    FastsimParameters,
)
from rollerrig.rig.parameters import RigParameters
from rollerrig.rig.sections import SECTIONS, quantity_of, si_unit_of

if TYPE_CHECKING:
    from rollerrig.calibrate.measurement import Measurement

__all__ = [
    "CALIBRATION_LAWS",
    "DRIVE_KEY_PREFERENCE",
    "FASTSIM_KEYS",
    "LAG_DRIVE_KEYS",
    "LAW_KEY_PREFIXES",
    "NUISANCE_KEYS",
    "POLACH_KEYS",
    "ROLLER_DRIVES",
    "VF_SECTION",
    "CalibrationError",
    "FreeParameter",
    "check_law_keys",
    "drive_keys",
    "fd_steps",
    "free_parameter_catalogue",
    "free_parameters",
    "friction_parameters",
    "is_law_key",
    "law_keys",
    "replay_protocol_from_recording",
    "split_values",
    "with_polach",
]

POLACH_KEYS = (
    "polach.static_friction",
    "polach.limit_ratio",
    "polach.friction_decay",
    "polach.k_adhesion",
    "polach.k_slip",
)
"""Free keys of the friction law of the recording (:class:`PolachParameters` fields)."""

FASTSIM_KEYS = (
    "fastsim.static_friction",
    "fastsim.limit_ratio",
    "fastsim.friction_decay",
    "fastsim.k0",
    "fastsim.alpha_inf",
    "fastsim.beta",
)
"""Free keys of the modified FASTSIM (:class:`FastsimParameters` fields: μ0, A, B and the slope
reduction k0, α_∞, β); FASTSIM and FaStrip have the first three."""

CALIBRATION_LAWS = CREEP_LAWS
"""Creep laws a calibration may fit (:data:`rollerrig.contact.laws.CREEP_LAWS`)."""

LAW_KEY_PREFIXES = ("polach.", "fastsim.")
"""Prefixes of the creep law's keys: not rig keys (the law is not part of the rig file)."""

_LAW_KIND = {"polach": "polach", "fastsim": "fastsim", "modified-fastsim": "fastsim",
             "fastrip": "fastsim"}  # fmt: skip

NUISANCE_KEYS = ("experiment.roller_speed", "experiment.normal_load")
"""Fitted beside the free keys: the roller drive's speed set point [m/s] and the constant
normal load of the replay [N] (not when the load channel is exactly constant). The load is
known only as well as the pressure's scatter allows, and the torque near the adhesion limit is
proportional to it: a fixed load would pass its error to the other parameters unseen."""

ROLLER_DRIVES = ("induction", "induction_dq")
"""Roller-drive models a calibration may fit (:class:`rollerrig.rig.model.DriveConfig`): the
Thevenin torque with a first-order lag (``induction``, the default) and the dq machine under
open-loop V/f (``induction_dq``)."""

VF_SECTION = "roller_drive_vf"
"""The rig-file table of the V/f settings: its keys are free keys of the dq drive only (the lag
model does not read them)."""

LAG_DRIVE_KEYS = ("induction_motor.response_lag_clp",)
"""The lag model's own drive key: c_lp of Kayaalp eq. 4.29, which sets the lag time constant
(τ from c_lp, :class:`rollerrig.rig.model.DriveConfig` ``roller_lag=None``)."""

DRIVE_KEY_PREFERENCE = (
    "slip_compensation",
    "slip_filter_time",
    "current_filter_time",
    "filter_time",
)
"""The V/f settings the comparison frees with the dq drive, those of them that the rig file's
``[roller_drive_vf]`` table has (:func:`drive_keys`): the settings that shape the torque after a
release (the slip compensation's gain and its two filters; the slip estimate uses the filtered
current). ``filter_time``, the former single key of both filters, only where the table has
neither ``slip_filter_time`` nor ``current_filter_time``. Not freed unless named: boost, ramp
and current limit (they act at start-up and in overload only) and ``rotor_resistance_estimate``
(the slip compensation scales the estimated slip by it and by the gain alike: the two are one
combination in the torque)."""

_VF_START_TIME = 0.3
"""Starting value [s] of a V/f filter time that the rig leaves at 0 (the machine's default, about
0.37 s on the bundled rig): the fit steps in ln(value), so it needs a start above 0."""

_VF_START_FRACTION = 0.5
"""Starting value of any other V/f setting that the rig leaves at its lower bound, as a fraction
of its plausible range (:data:`rollerrig.drives.vf.VF_SETTING_RANGES`): slip compensation 0.75."""

_EXCLUDED_SECTIONS = ("meta", "sensors")  # names and the DAQ: how the data are read, not fitted
_POLACH_RANGES = {  # (lower, upper) of each Polach parameter [-, -, s/m, -, -]
    "static_friction": (0.0, None),
    "limit_ratio": (0.0, 1.0),
    "friction_decay": (0.0, None),
    "k_adhesion": (0.0, 1.0),
    "k_slip": (0.0, 1.0),
}
_POLACH_UNITS = {"friction_decay": "s/m"}
_FASTSIM_RANGES = {  # (lower, upper) of each FastsimParameters field [-, -, s/m, -, -, -]
    "static_friction": (0.0, None),
    "limit_ratio": (0.0, 1.0),
    "friction_decay": (0.0, None),
    "k0": (0.0, 1.0),
    "alpha_inf": (0.0, 1.0),
    "beta": (0.0, None),
}


@dataclass(frozen=True)
class FreeParameter:
    """One fitted parameter.

    Attributes
    ----------
    key : str
        Dotted key (``stiffness.roller_shaft``, ``polach.k_slip``, ``fastsim.k0``,
        ``experiment.roller_speed``).
    kind : str
        ``"rig"``, ``"polach"``, ``"fastsim"`` (a creep law's parameter) or ``"experiment"``.
    initial : float
        Starting value [SI unit].
    unit : str
        SI unit of the value.
    lower : float
        Lower bound [unit]: the fit works on z = ln(value − lower).
    upper : float or None
        Upper bound [unit] (inclusive), if any.
    """

    key: str
    kind: str
    initial: float
    unit: str
    lower: float = 0.0
    upper: float | None = None

    @property
    def z_initial(self) -> float:
        """ln(initial − lower) [-]."""
        return math.log(self.initial - self.lower)

    @property
    def z_upper(self) -> float:
        """ln(upper − lower), or +inf [-]."""
        return math.inf if self.upper is None else math.log(self.upper - self.lower)

    def value(self, z: float) -> float:
        """The parameter [unit] at z [-]."""
        return self.lower + math.exp(z)


def _rig_float_fields() -> dict[str, Any]:
    """``section.key`` -> pydantic field of every float of a rig file that may be fitted."""
    out = {}
    for section, model in SECTIONS.items():
        if section in _EXCLUDED_SECTIONS:
            continue
        for key, field in model.model_fields.items():
            if field.annotation is float:
                out[f"{section}.{key}"] = field
    return out


def _check_roller(roller: str) -> str:
    if roller not in ROLLER_DRIVES:
        from rollerrig._validation import did_you_mean

        raise CalibrationError(
            f"roller drive {roller!r} cannot be calibrated"
            f"{did_you_mean(str(roller), ROLLER_DRIVES)}; choose one of {list(ROLLER_DRIVES)}"
        )
    return roller


def _check_law(law: str) -> str:
    if law not in CALIBRATION_LAWS:
        from rollerrig._validation import did_you_mean

        raise CalibrationError(
            f"creep law {law!r} cannot be calibrated{did_you_mean(str(law), CALIBRATION_LAWS)}; "
            f"choose one of {list(CALIBRATION_LAWS)}"
        )
    return law


def law_keys(law: str = "polach") -> tuple[str, ...]:
    """The free keys of the creep law ``law``: its parameter set's fields.

    Examples
    --------
    >>> law_keys("modified-fastsim")[3:]
    ('fastsim.k0', 'fastsim.alpha_inf', 'fastsim.beta')
    >>> law_keys("fastrip")
    ('fastsim.static_friction', 'fastsim.limit_ratio', 'fastsim.friction_decay')
    """
    law = _check_law(law)
    if law == "polach":
        return POLACH_KEYS
    return FASTSIM_KEYS if law == "modified-fastsim" else FASTSIM_KEYS[:3]


def is_law_key(key: str) -> bool:
    """Whether ``key`` names a creep law's parameter (of any law), not a rig key.

    Examples
    --------
    >>> is_law_key("fastsim.k0"), is_law_key("polach.k_slip"), is_law_key("inertia.roller")
    (True, True, False)
    """
    return key in POLACH_KEYS or key in FASTSIM_KEYS


def free_parameter_catalogue(roller: str = "induction", law: str = "polach") -> tuple[str, ...]:
    """Every key :func:`rollerrig.calibrate.calibrate` accepts in ``free`` with the roller drive
    ``roller`` (the ``roller_drive_vf.*`` keys with ``"induction_dq"`` only) and the creep law
    ``law`` (its keys, :func:`law_keys`).

    Examples
    --------
    >>> keys = free_parameter_catalogue()
    >>> "stiffness.roller_shaft" in keys, "polach.k_slip" in keys, "sensors.daq_rate" in keys
    (True, True, False)
    >>> "roller_drive_vf.slip_compensation" in keys
    False
    >>> "roller_drive_vf.slip_compensation" in free_parameter_catalogue("induction_dq")
    True
    >>> "fastsim.k0" in free_parameter_catalogue(law="modified-fastsim"), "fastsim.k0" in keys
    (True, False)
    """
    dq = _check_roller(roller) == "induction_dq"
    rig = [k for k in _rig_float_fields() if dq or not k.startswith(f"{VF_SECTION}.")]
    return (*rig, *law_keys(law))


def _law_key_mismatch(keys: Sequence[str], law: str) -> str:
    """The message for law keys that ``law`` does not have ('' when there are none)."""
    own = law_keys(law)
    wrong = [k for k in keys if is_law_key(k) and k not in own]
    if not wrong:
        return ""
    hints = []
    for key in wrong:  # the counterpart of a parameter both laws have (mu0, A, B)
        name = key.partition(".")[2]
        twin = [k for k in own if k.partition(".")[2] == name]
        hints.append(f"{key!r}" + (f" (did you mean {twin[0]!r}?)" if twin else ""))
    fits = [lw for lw in CALIBRATION_LAWS if all(k in law_keys(lw) for k in wrong)]
    other = (
        f"; {'it is a key' if len(wrong) == 1 else 'they are keys'} of the law "
        f"{max(fits, key=lambda lw: len(law_keys(lw)))!r} (choose it with --law or law=...)"
        if fits
        else ""
    )
    return (
        f"free parameter(s) {', '.join(hints)}: not "
        f"{'a parameter' if len(wrong) == 1 else 'parameters'} of the creep law {law!r}, whose "
        f"keys are {', '.join(own)}{other}"
    )


def check_law_keys(keys: Iterable[str], law: str = "polach") -> None:
    """Refuse creep-law keys that the law ``law`` does not have, naming its own keys.

    Raises
    ------
    CalibrationError
        One message for every such key: the law's keys, the counterpart of each key where
        the two laws share the parameter (μ0, A, B), and the law the keys belong to.

    Examples
    --------
    >>> check_law_keys(["fastsim.k0", "inertia.roller"], "modified-fastsim")
    >>> try:
    ...     check_law_keys(["polach.limit_ratio"], "modified-fastsim")
    ... except CalibrationError as exc:
    ...     print(exc)  # doctest: +NORMALIZE_WHITESPACE
    free parameter(s) 'polach.limit_ratio' (did you mean 'fastsim.limit_ratio'?): not a
    parameter of the creep law 'modified-fastsim', whose keys are fastsim.static_friction,
    fastsim.limit_ratio, fastsim.friction_decay, fastsim.k0, fastsim.alpha_inf, fastsim.beta;
    it is a key of the law 'polach' (choose it with --law or law=...)
    """
    message = _law_key_mismatch(list(keys), _check_law(law))
    if message:
        raise CalibrationError(message)


def drive_keys(roller: str) -> tuple[str, ...]:
    """The drive model's own free keys: c_lp for the lag model, the V/f settings of
    :data:`DRIVE_KEY_PREFERENCE` that the rig file has for the dq drive.

    Examples
    --------
    >>> drive_keys("induction")
    ('induction_motor.response_lag_clp',)
    >>> "roller_drive_vf.slip_compensation" in drive_keys("induction_dq")
    True
    """
    if _check_roller(roller) == "induction":
        return LAG_DRIVE_KEYS
    fields = _rig_float_fields()
    keys = [k for k in DRIVE_KEY_PREFERENCE if f"{VF_SECTION}.{k}" in fields]
    if "filter_time" in keys and {"slip_filter_time", "current_filter_time"} & set(keys):
        keys.remove("filter_time")
    return tuple(f"{VF_SECTION}.{k}" for k in keys)


def _vf_start(name: str, field, lower: float) -> float | None:
    """Starting value of a V/f setting the rig leaves at its lower bound (None: no rule)."""
    from rollerrig.drives.vf import VF_SETTING_RANGES

    if "time" in name and (quantity_of(field) == "time"):
        return _VF_START_TIME
    if name in VF_SETTING_RANGES:
        low, high = VF_SETTING_RANGES[name]
        return max(low, lower) + _VF_START_FRACTION * (high - max(low, lower))
    return None


def _bounds(field) -> tuple[float, float | None]:
    """(lower, upper) of a rig field from its pydantic constraints."""
    lower, upper = 0.0, None
    for item in field.metadata:
        for name in ("gt", "ge"):
            if getattr(item, name, None) is not None:
                lower = float(getattr(item, name))
        for name in ("lt", "le"):
            if getattr(item, name, None) is not None:
                upper = float(getattr(item, name))
    return lower, upper


def free_parameters(
    free: str | Iterable[str],
    rig: RigParameters,
    friction: PolachParameters | FastsimParameters,
    roller: str = "induction",
    law: str = "polach",
) -> tuple[FreeParameter, ...]:
    """The free parameters named by ``free``, started from ``rig`` and ``friction``.

    Parameters
    ----------
    free : str or iterable of str
        Dotted keys, or one string of keys separated by commas.
    rig : RigParameters
        Starting values of the rig keys.
    friction : PolachParameters or FastsimParameters
        Starting values of the creep law's keys (``polach.*``, or ``fastsim.*`` for the
        FASTSIM family: :func:`friction_parameters`).
    roller : {"induction", "induction_dq"}
        The roller drive of the twin: the ``roller_drive_vf.*`` keys are free keys of the dq
        drive only. A V/f setting the rig leaves at its lower bound (no slip compensation, a
        filter time of 0 = the machine's default) starts from 0.3 s (times) or the middle of
        its plausible range (others), since the fit steps in relative terms.
    law : str
        The creep law of the twin (:data:`CALIBRATION_LAWS`): its keys (:func:`law_keys`) are
        the friction keys that may be free.

    Returns
    -------
    tuple of FreeParameter
        In the order given, duplicates removed.

    Raises
    ------
    CalibrationError
        No key, an unknown key (the message lists the valid ones), a key of another creep
        law (the message names the law's own keys, :func:`check_law_keys`), or a starting
        value at its lower bound (a zero damping: no relative step exists; give a starting
        value in a rig file).

    Examples
    --------
    >>> from rollerrig.rig.parameters import default_rig
    >>> from rollerrig.contact.creep import POLACH_DRY
    >>> [p.key for p in free_parameters("stiffness.roller_shaft,polach.k_slip", default_rig(),
    ...                                 POLACH_DRY)]
    ['stiffness.roller_shaft', 'polach.k_slip']
    >>> law = friction_parameters("dry", "modified-fastsim")
    >>> [(p.key, p.initial) for p in free_parameters("fastsim.k0", default_rig(), law,
    ...                                              law="modified-fastsim")]
    [('fastsim.k0', 0.54)]
    """
    keys = free.split(",") if isinstance(free, str) else list(free)
    keys = list(dict.fromkeys(str(k).strip() for k in keys if str(k).strip()))
    if not keys:
        raise CalibrationError(
            "no free parameter given; name one or more dotted keys, e.g. "
            "stiffness.roller_shaft,bearing.friction_coefficient"
        )
    fields = _rig_float_fields()
    _check_roller(roller)
    check_law_keys(keys, law)
    own = law_keys(law)
    vf = [k for k in keys if k.startswith(f"{VF_SECTION}.") and k in fields]
    if vf and roller != "induction_dq":
        raise CalibrationError(
            f"free parameter(s) {vf}: the V/f settings act on the dq roller drive only; the "
            f"roller drive {roller!r} does not read them (its lag is "
            f"{LAG_DRIVE_KEYS[0]}); calibrate with the roller drive induction_dq "
            "(--roller-drive induction_dq), or leave them out"
        )
    unknown = [k for k in keys if k not in fields and k not in own]
    if unknown:
        raise CalibrationError(
            f"unknown free parameter(s) {unknown}; valid keys are the floats of a rig file "
            f"outside [meta] and [sensors] and the friction law of the recording: "
            f"{', '.join(free_parameter_catalogue(roller, law))}"
        )
    kind_of_law = _LAW_KIND[law]
    wanted = PolachParameters if kind_of_law == "polach" else FastsimParameters
    if any(k in own for k in keys) and not isinstance(friction, wanted):
        raise CalibrationError(
            f"the creep law {law!r} takes its starting values from a {wanted.__name__}, got "
            f"{type(friction).__name__} (friction_parameters(friction, law) gives one)"
        )
    out = []
    for key in keys:
        if key in own:
            name = key.partition(".")[2]
            ranges = _POLACH_RANGES if kind_of_law == "polach" else _FASTSIM_RANGES
            lower, upper = ranges[name]
            value = float(getattr(friction, name))
            unit = _POLACH_UNITS.get(name, "1")
            kind = kind_of_law
        else:
            section, _, name = key.partition(".")
            field = fields[key]
            lower, upper = _bounds(field)
            value = float(getattr(getattr(rig, section), name))
            unit = si_unit_of(field)
            kind = "rig"
            if section == VF_SECTION and not value > lower:
                start = _vf_start(name, field, lower)
                value = value if start is None else start
        if not value > lower:
            raise CalibrationError(
                f"free parameter {key}: starting value {value:g} {unit} is at its lower bound "
                f"{lower:g}; the fit steps in relative terms, so give a starting value above it "
                f"(a rig file with --rig, or friction=...; B = 0 cannot be fitted)"
            )
        out.append(FreeParameter(key, kind, value, unit, lower, upper))
    return tuple(out)


def _merge_collinear(time: np.ndarray, values: np.ndarray, tolerance: float):
    """Breakpoints of the piecewise-linear trace ``values(time)`` with collinear samples dropped.

    Exact within ``tolerance`` [unit of values]: the merged trace is checked at every sample,
    and the samples are kept as they are where it would deviate by more.
    """
    d2 = np.abs(np.diff(values, 2))
    keep = np.ones(values.size, dtype=bool)
    keep[1:-1] = d2 > tolerance
    t, v = time[keep], values[keep]
    if np.max(np.abs(np.interp(time, t, v) - values)) > tolerance:
        return time, values
    return t, v


def replay_protocol_from_recording(
    measurement: Measurement, roller_speed: float, friction: str, name: str, load: float
):
    """The recorded torque request as a protocol at constant load, speed and friction.

    Parameters
    ----------
    measurement : Measurement
        The request [N.m], the mean normal load [N] and the time base [s].
    roller_speed : float
        Roller peripheral-speed set point [m/s].
    friction : str
        Name of the friction condition (the Polach set).
    name : str
        Protocol name.
    load : float
        Constant normal load [N].

    Returns
    -------
    Protocol
        One ``replay`` event; collinear samples of the request merged (exact to 1e-9 of its
        peak), so that the solver integrates long smooth segments.
    """
    from rollerrig.experiment.protocol import Protocol, ProtocolEvent

    t = measurement.time
    request = measurement.torque_request
    tolerance = 1e-9 * max(float(np.max(np.abs(request))), 1.0)
    bt, bv = _merge_collinear(t, request, tolerance)
    duration = float(t[-1])
    return Protocol(
        name=name,
        description="recorded wheel-torque request replayed at constant load and speed",
        source=f"torque request of {measurement.source}",
        duration=duration,
        torque_time=bt,
        torque_request=bv,
        speed_time=np.array([0.0, duration]),
        roller_speed=np.array([roller_speed, roller_speed]),
        load_time=np.array([0.0, duration]),
        normal_load=np.array([load, load]),
        friction_time=np.array([0.0]),
        friction_condition=(friction,),
        events=(ProtocolEvent(0.0, duration, "replay", measurement.source),),
        origin=measurement.source,
    )


def friction_parameters(
    friction: str | PolachParameters | FastsimParameters | None, law: str = "polach"
) -> PolachParameters | FastsimParameters:
    """The starting friction law of the creep law ``law``: a set by name or as given.

    Polach's law: a Polach set by name (``"dry"``, ``"wet"``) or :class:`PolachParameters`.
    The FASTSIM family: :class:`FastsimParameters` as given, a named set of
    :data:`rollerrig.contact.laws.FRICTION_PARAMETER_SETS`
    (``"eurosprinter-modified-fastsim"``), or a friction condition (``"dry"``, ``"wet"`` or
    :class:`PolachParameters`) as the twin runs it with that law
    (:func:`rollerrig.rig.assemble.assemble`): μ0, A, B of the Polach set and, for the
    modified FASTSIM, k0, α_∞, β of the Eurosprinter set
    (:data:`~rollerrig.contact.laws.EUROSPRINTER_MODIFIED_FASTSIM`, the law's default set);
    k_A and k_S are not used.

    Parameters
    ----------
    friction : str, PolachParameters, FastsimParameters or None
        The set; None: ``"dry"``.
    law : str
        The creep law (:data:`CALIBRATION_LAWS`).

    Returns
    -------
    PolachParameters or FastsimParameters
        :class:`PolachParameters` for Polach's law, :class:`FastsimParameters` otherwise.

    Raises
    ------
    CalibrationError
        An unknown name (the message lists the known ones), or a :class:`FastsimParameters`
        for Polach's law (it has no k_A, k_S).

    Examples
    --------
    >>> friction_parameters("dry").k_slip
    0.4
    >>> f = friction_parameters("dry", "modified-fastsim")
    >>> f.static_friction, f.k0, f.name
    (0.55, 0.54, 'dry')
    """
    law = _check_law(law)
    if friction is None:
        friction = "dry"
    if law == "polach":
        if isinstance(friction, PolachParameters):
            return friction
        if isinstance(friction, FastsimParameters):
            raise CalibrationError(
                f"the creep law 'polach' needs Polach's k_A, k_S: the set {friction.name!r} "
                "has none; give PolachParameters or a Polach set's name, or calibrate with "
                "the law 'modified-fastsim' (--law modified-fastsim)"
            )
        if str(friction) not in POLACH_PARAMETER_SETS:
            raise CalibrationError(
                f"unknown friction set {friction!r}; known: {sorted(POLACH_PARAMETER_SETS)} "
                "(or pass PolachParameters)"
            )
        return POLACH_PARAMETER_SETS[str(friction)]
    if isinstance(friction, FastsimParameters):
        return friction
    if isinstance(friction, str):
        known = {**POLACH_PARAMETER_SETS, **FRICTION_PARAMETER_SETS}
        if friction not in known:
            raise CalibrationError(
                f"unknown friction set {friction!r}; known: {sorted(known)} (or pass "
                "FastsimParameters or PolachParameters)"
            )
        friction = known[friction]
        if isinstance(friction, FastsimParameters):
            return friction
    return _fastsim_from_polach(friction, law)


def _fastsim_from_polach(polach: PolachParameters, law: str) -> FastsimParameters:
    """The FASTSIM-family set the twin makes of a Polach set under ``law``."""
    slope = EUROSPRINTER_MODIFIED_FASTSIM if law == "modified-fastsim" else None
    return FastsimParameters(
        static_friction=polach.static_friction,
        limit_ratio=polach.limit_ratio,
        friction_decay=polach.friction_decay,
        k0=1.0 if slope is None else slope.k0,
        alpha_inf=1.0 if slope is None else slope.alpha_inf,
        beta=0.0 if slope is None else slope.beta,
        name=polach.name,
        source=f"mu0, A, B of the Polach set {polach.name!r} ({polach.source})"
        + ("" if slope is None else f"; k0, alpha_inf, beta of {slope.name!r}"),
    )


def split_values(
    params: Sequence[FreeParameter], values: Sequence[float]
) -> tuple[dict[str, float], dict[str, float], dict[str, float]]:
    """Values [SI] by kind: (rig overrides, creep-law fields, experiment settings)."""
    rig: dict[str, float] = {}
    law: dict[str, float] = {}
    experiment: dict[str, float] = {}
    targets = {"rig": rig, "polach": law, "fastsim": law, "experiment": experiment}
    for p, v in zip(params, values, strict=True):
        targets[p.kind][p.key if p.kind == "rig" else p.key.partition(".")[2]] = float(v)
    return rig, law, experiment


def with_polach(
    friction: PolachParameters | FastsimParameters, values: Mapping[str, float]
) -> PolachParameters | FastsimParameters:
    """``friction`` with some fields replaced (validated by its class: Polach's or the FASTSIM
    family's)."""
    return dataclasses.replace(friction, **values) if values else friction


def fd_steps(params) -> np.ndarray:
    """The finite-difference step in z of each free parameter [-].

    :data:`~rollerrig.calibrate.settings.FD_STEP`, and
    :data:`~rollerrig.calibrate.settings.FD_STEP_TABULATED` for a tabulated creep law's
    (``fastsim.*``) keys.
    """
    return np.array([FD_STEP_TABULATED if p.kind == "fastsim" else FD_STEP for p in params])
