"""The estimators on a recording with a rig's parameters, and the choice of the smoother to trust
(:func:`choose_smoother`): the chain where its shaft is calibrated and its innovations are
consistent, else the roller alone.
"""

from __future__ import annotations

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.estimation.kalman import ContactEstimate, estimate_contact_torque
from rollerrig.estimation.smoother import DEFAULT_DRIVE_NOISE, RollerChain, smooth_contact_torque

__all__ = [
    "CHAIN_CONSISTENCY",
    "chain_reason",
    "choose_smoother",
    "estimate_from_recording",
    "smooth_from_recording",
]


def uniform_rate(recording, purpose: str = "the contact-torque estimator") -> float:
    """The recording's sampling rate [Hz] (:attr:`Recording.sample_rate`, the rate the rest of
    the analysis uses), refused unless its samples are equally spaced
    (:func:`~rollerrig.recordings.timebase.require_uniform_time`, naming the file and
    ``purpose``): the estimators differentiate at one rate, and a 0.5 s gap taken for one step
    had made a CoA of 910 out of a largest 0.35, with no warning."""
    from rollerrig.recordings.timebase import require_uniform_time

    source = recording.metadata.get("source") or "the recording"
    require_uniform_time(recording.time, str(source), purpose)
    return float(recording.sample_rate)


def estimate_from_recording(recording, rig=None, **options) -> ContactEstimate:
    """:func:`estimate_contact_torque` on a recording with a rig's parameters.

    Parameters
    ----------
    recording : Recording
        Needs ``torque``, ``roller_encoder_counts`` and ``normal_load`` or
        ``air_spring_pressure`` (then N = p·A_eff of the rig).
    rig : RigParameters, optional
        Inertia, bearing, geometry and encoder of the rig; default the bundled rig.
    **options
        ``torque_noise``, ``process_noise``, ``model`` of :func:`estimate_contact_torque`.

    Returns
    -------
    ContactEstimate
    """
    from rollerrig.rig.parameters import default_rig

    rig = default_rig() if rig is None else rig
    load = _recording_load(recording, rig)
    recording.require("torque", "roller_encoder_counts")
    b = rig.bearing
    estimate = estimate_contact_torque(
        recording["torque"],
        recording["roller_encoder_counts"],
        load,
        uniform_rate(recording),
        counts_per_rev=rig.sensors.encoder_counts_per_revolution,
        roller_inertia=rig.inertia.roller,
        bearing_friction=b.friction_coefficient,
        bearing_radius=b.roller_bearing_radius,
        roller_weight=b.roller_subsystem_weight,
        roller_radius=rig.geometry.roller_radius_x,
        regularisation_speed=b.regularisation_speed,
        **options,
    )
    return _on_contact_load(estimate, load, rig)


CHAIN_CONSISTENCY = 1.25
"""With ``chain="auto"`` the chain smoother is used only when the variance of its angle
innovations, each over its predicted standard deviation, is at most this multiple of the
roller-alone smoother's [-]: the encoder angle is the measurement both models predict, and a
chain that does not fit the recording predicts it worse (the dq drive under the lag model's
default drive noise: 200 to 900 times; with the drive noise by maximum likelihood the chain
fits the twin's own, the dq drive's and the arm's recordings at 0.9–1.0 times). The test does
not see a wrong shaft mode (k56 ±10 % changes the ratio by under 5 % while it doubles the
chain's error): that needs the calibration (``shaft_calibrated``)."""


def smooth_from_recording(
    recording,
    rig=None,
    *,
    chain: str | None = "auto",
    lines: bool = True,
    shaft_calibrated: bool = False,
    **options,
) -> ContactEstimate:
    """:func:`smooth_contact_torque` on a recording with a rig's parameters.

    Parameters
    ----------
    recording : Recording
        Needs ``torque``, ``roller_encoder_counts`` and ``normal_load`` or
        ``air_spring_pressure`` (then N = p·A_eff of the rig); ``wheel_encoder_counts`` for
        the wheel's lines.
    rig : RigParameters, optional
        Default the bundled rig. The chain model needs its roller shaft and motor rotor
        accurate (module docstring): a calibrated rig.
    chain : {"auto", "induction", "unknown", None}
        The drive of :meth:`RollerChain.from_rig`, or None for the roller alone. ``"auto"``
        (default): the chain with the lag model of the drive linearised
        (``"induction"``) and its drive noise by maximum likelihood, used when its angle
        innovations are consistent (:data:`CHAIN_CONSISTENCY`) and ``shaft_calibrated``,
        else the roller alone; the estimate's ``choice`` says which and why.
    lines : bool
        With a chain, remove the lines at orders 1, 2, p, 2p, 3p of the roller (p: the roller
        motor's pole pairs) and 1, 2, p_PMSM of the wheel (when the wheel encoder is recorded).
    shaft_calibrated : bool
        Whether the rig's k56 and J6 come from a calibration whose residuals show no
        structure, to a few per cent (``chain="auto"`` only): the chain needs the shaft's
        mode √(k56 (1/J5 + 1/J6))/2π that well (k56 ±10 % doubles its error, module
        docstring), and its innovations cannot tell.
    **options
        ``torque_noise``, ``process_noise``, ``model``, ``drive_noise`` of
        :func:`smooth_contact_torque`.

    Returns
    -------
    ContactEstimate
    """
    from rollerrig.rig.parameters import default_rig

    rig = default_rig() if rig is None else rig
    if chain == "auto":
        return _chain_or_roller(recording, rig, lines, shaft_calibrated, options)
    load = _recording_load(recording, rig)
    recording.require("torque", "roller_encoder_counts")
    b = rig.bearing
    extra: dict = {}
    if chain is not None:
        extra["chain"] = RollerChain.from_rig(rig, drive=chain)
        if lines:
            p = rig.induction_motor.pole_pairs
            extra["roller_orders"] = (1, 2, p, 2 * p, 3 * p)
            if "wheel_encoder_counts" in recording:
                extra["wheel_counts"] = recording["wheel_encoder_counts"]
                extra["wheel_orders"] = (1, 2, rig.pmsm.pole_pairs)
    estimate = smooth_contact_torque(
        recording["torque"],
        recording["roller_encoder_counts"],
        load,
        uniform_rate(recording),
        counts_per_rev=rig.sensors.encoder_counts_per_revolution,
        roller_inertia=rig.inertia.roller,
        bearing_friction=b.friction_coefficient,
        bearing_radius=b.roller_bearing_radius,
        roller_weight=b.roller_subsystem_weight,
        roller_radius=rig.geometry.roller_radius_x,
        regularisation_speed=b.regularisation_speed,
        **extra,
        **options,
    )
    return _on_contact_load(estimate, load, rig)


def _chain_or_roller(
    recording, rig, lines: bool, shaft_calibrated: bool, options: dict
) -> ContactEstimate:
    """``chain="auto"`` of :func:`smooth_from_recording` (:func:`choose_smoother`)."""
    roller_options = {k: v for k, v in options.items() if k != "drive_noise"}
    alone = smooth_from_recording(recording, rig, chain=None, **roller_options)
    chained: ContactEstimate | str | None = None
    if shaft_calibrated:
        try:
            chained = smooth_from_recording(
                recording, rig, chain="induction", lines=lines, **{"drive_noise": "ml", **options}
            )
        except ParameterError as exc:  # a rig the chain cannot take
            chained = str(exc)
    return choose_smoother(alone, chained, shaft_calibrated)


def choose_smoother(
    alone: ContactEstimate,
    chained,
    shaft_calibrated: bool,
    not_calibrated: str = "they are not calibrated",
) -> ContactEstimate:
    """The smoother to trust: the chain where k56 and J6 are calibrated and its angle
    innovations are consistent (:data:`CHAIN_CONSISTENCY`), else the roller alone; the
    returned estimate's ``choice`` says which and why.

    Parameters
    ----------
    alone : ContactEstimate
        The roller-alone smoother's estimate.
    chained : ContactEstimate, str or None
        The chain smoother's estimate (drive noise by maximum likelihood), or why it could
        not be made, or None (not made).
    shaft_calibrated : bool
        As :func:`smooth_from_recording`.
    not_calibrated : str
        Why k56 and J6 are not known well enough, for the reason (when not
        ``shaft_calibrated``).

    Returns
    -------
    ContactEstimate
        ``alone`` or ``chained`` with ``choice`` set.
    """
    import dataclasses

    if not shaft_calibrated:
        why = (
            "roller alone: the chain needs k56 and J6 to a few per cent (k56 ±10 % doubles its "
            f"error) and {not_calibrated} (rollerrig calibrate --free "
            "stiffness.roller_shaft,inertia.am_rotor)"
        )
        return dataclasses.replace(alone, choice=why)
    if not isinstance(chained, ContactEstimate):
        why = f"roller alone: the chain could not be made ({chained or 'not asked for'})"
        return dataclasses.replace(alone, choice=why)
    if "angle" not in (chained.innovations or {}) or "angle" not in (alone.innovations or {}):
        why = "roller alone: the recording is too short to test the chain's innovations"
        return dataclasses.replace(alone, choice=why)
    v_chain = chained.innovations["angle"]["variance"]
    v_alone = alone.innovations["angle"]["variance"]
    ratio = v_chain / v_alone
    numbers = (
        f"variance of the angle innovations over their prediction: chain {v_chain:.3g}, "
        f"roller alone {v_alone:.3g}"
    )
    if ratio > CHAIN_CONSISTENCY:
        why = (
            f"roller alone: the chain predicts the encoder angle {ratio:.3g} times worse than "
            f"the roller alone (limit {CHAIN_CONSISTENCY:g}: its shaft, rotor or drive do not "
            f"fit this recording); {numbers}"
        )
        return dataclasses.replace(alone, choice=why)
    return dataclasses.replace(chained, choice=chain_reason(chained, numbers))


def chain_reason(chained: ContactEstimate, numbers: str = "") -> str:
    """Why the chain's estimate can be used, with what its drive noise says of the drive
    model (a noise far above :data:`DEFAULT_DRIVE_NOISE`: the recording's drive is not the lag
    model and the chain leans on the torque sensor)."""
    tail = f"; {numbers}" if numbers else ""
    if chained.drive_noise is None:
        return f"chain{tail}"
    ratio = chained.drive_noise / DEFAULT_DRIVE_NOISE
    drive = (
        "the lag model of the drive holds"
        if ratio <= 100.0
        else f"{ratio:.3g} times the default: the recording's drive is not the lag model, "
        "the chain leans on the torque sensor"
    )
    return (
        f"chain (roller shaft and rotor, the drive's lag model linearised, its noise "
        f"{chained.drive_noise:.3g} N^2.m^2/s by maximum likelihood: {drive}){tail}"
    )


def _on_contact_load(estimate: ContactEstimate, air_spring_force, rig) -> ContactEstimate:
    """The estimate with its CoA on the contact's load N = S + W_d + κ F_x (the swinging arm,
    :class:`rollerrig.rig.sections.ArmParameters`) instead of the air-spring force S.

    The filters take the bearing loss at S: the arm's share κ F_x changes R05 by f_g r_b κ F_x
    (about 0.1 N.m at the dry peak on the default rig), well inside their noise.
    """
    import dataclasses

    force = estimate.contact_torque / rig.geometry.roller_radius_x
    load = rig.arm.contact_load(np.asarray(air_spring_force, dtype=float), force)
    return dataclasses.replace(estimate, coa=force / load)


def _recording_load(recording, rig):
    """The normal load of a recording: its ``normal_load``, else p·A_eff of the rig [N]."""
    from rollerrig.measure.quantities import normal_force_from_pressure

    if "normal_load" in recording:
        return recording["normal_load"]
    recording.require("air_spring_pressure")
    return normal_force_from_pressure(
        recording["air_spring_pressure"], rig.sensors.air_spring_effective_area
    )
