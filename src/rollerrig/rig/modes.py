"""The damped modes of the coupled twin for every roller drive, through one function.

:func:`twin_modes` linearises the twin about steady free rolling and returns its modes as
:class:`~rollerrig.rig.linear.CoupledModes`, whichever roller drive the twin has: the drives of
the 22-state model (the lag model of the induction motor, the servo) through
:func:`rollerrig.rig.linear.coupled_modes`, the dq induction machine under open-loop V/f through
its coupled twin (:class:`rollerrig.rig.dq_twin.DqTwin`, the machine's fluxes and the
controller's filters among the states). Both use the same model inputs
(:func:`rollerrig.rig.assemble.assemble`) and the same modal analysis
(:func:`rollerrig.rig.linear.modes_of`).
"""

from __future__ import annotations

from rollerrig.rig import model as m
from rollerrig.rig.drive_dynamics import DqTwin, default_dq_drive
from rollerrig.rig.linear import (
    DEFAULT_DAMPING_THRESHOLD,
    CoupledModes,
    check_damping_threshold,
    coupled_modes,
)

__all__ = ["twin_modes"]


def twin_modes(
    rig,
    speed: float,
    normal_load: float,
    *,
    drives: m.DriveConfig | None = None,
    friction: str = "dry",
    damping_threshold: float = DEFAULT_DAMPING_THRESHOLD,
    load_source: str = "given",
) -> CoupledModes:
    """Damped modes of the coupled, linearised twin, for any roller drive.

    Parameters
    ----------
    rig : RigParameters
        Rig parameters (with the dq drive: its ``[roller_drive_vf]`` settings).
    speed : float
        Roller surface speed [m/s], > 0.
    normal_load : float
        Normal load [N], > 0.
    drives : DriveConfig, optional
        Drive models; ``roller="induction_dq"`` takes the dq machine under the rig's V/f
        settings (``roller_lag`` does not apply to it).
    friction : str
        Friction condition (Polach's ``"dry"`` or ``"wet"``).
    damping_threshold : float
        ζ below which an oscillatory mode may ring [-], in (0, 1).
    load_source : str
        Where the load came from, stated in every output.

    Returns
    -------
    CoupledModes

    Examples
    --------
    >>> from rollerrig.rig.parameters import default_rig
    >>> lag = twin_modes(default_rig(), 30 / 3.6, 4.3e3)
    >>> dq_drive = m.DriveConfig(roller="induction_dq")
    >>> dq = twin_modes(default_rig(), 30 / 3.6, 4.3e3, drives=dq_drive)
    >>> [round(md.frequency, 1) for md in lag.ringing]
    [0.8, 13.8, 110.8]
    >>> [round(md.frequency, 1) for md in dq.ringing]
    [14.8, 15.4, 110.8]
    """
    drives = drives or m.DriveConfig()
    if drives.roller != "induction_dq":
        return coupled_modes(
            rig,
            speed,
            normal_load,
            drives=drives,
            friction=friction,
            damping_threshold=damping_threshold,
            load_source=load_source,
        )
    threshold = check_damping_threshold(damping_threshold)
    twin = DqTwin.at(
        rig, speed, normal_load, default_dq_drive(rig), wheel=drives.wheel, friction=friction
    )
    return CoupledModes(
        speed=float(speed),
        normal_load=float(normal_load),
        load_source=str(load_source),
        drives=drives,
        friction=friction,
        damping_threshold=threshold,
        modes=twin.modes(threshold),
    )
