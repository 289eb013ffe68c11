"""The operating point of a recording: mean roller and wheel speeds and normal load, with sources.

The spectrum workflow (:mod:`rollerrig.signal.workflow`) predicts the rotation and motor lines from
the mean speeds and linearises the twin at the mean load. :func:`operating_point` takes each from
the recording and states where it came from: the speeds from the speed channels, else from the
first and last encoder counts; the load from the ``normal_load`` channel, else the air-spring
pressure times the rig's effective area, else the seed's test load 4.3 kN.

A roller at rest (mean speed at most :data:`AT_REST` rad/s) is an operating point too: its
``roller_speed`` is None and its source says so; the workflow then leaves the rotation orders and
motor lines unattributed (they would all lie at 0 Hz) instead of refusing the spectrum.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from rollerrig._validation import require_positive
from rollerrig.signal.recording_access import RecordingAccess

__all__ = ["AT_REST", "SPEED_ARGUMENT", "OperatingPoint", "operating_point"]

SPEED_ARGUMENT = "or pass roller_speed= (its mean angular speed [rad/s])"
"""How the error for a recording without a roller speed ends: the API's way to give it. The
command line, which takes no speed (each recording's own speed places its rotation orders),
replaces it with its own words."""

AT_REST = 1e-3
"""Mean angular speed [rad/s] at or below which a roller or wheel counts as at rest."""


@dataclass(frozen=True)
class OperatingPoint:
    """Mean speeds and load of a recording, with where each came from.

    Attributes
    ----------
    roller_speed : float or None
        Mean roller angular speed [rad/s] (> 0); None: the roller is at rest (its mean speed
        is in ``speed_source``), so no speed-proportional line can be attributed.
    wheel_speed : float or None
        Mean wheel angular speed [rad/s] (None: unknown; wheel and PMSM sources skipped).
    normal_load : float
        Normal load used for the twin's modes [N].
    speed_source, wheel_source, load_source : str
        Where each value came from.
    roller_radius : float
        Roller rolling radius [m] (for the surface speed).
    roller_speed_range : tuple of float or None
        Least and largest 1 s mean of the roller speed channel [rad/s] (None: no such
        channel, or a speed given).
    """

    roller_speed: float | None
    wheel_speed: float | None
    normal_load: float
    speed_source: str
    wheel_source: str
    load_source: str
    roller_radius: float
    roller_speed_range: tuple[float, float] | None = None

    @property
    def at_rest(self) -> bool:
        """True when the roller is at rest (no roller speed to attribute lines with)."""
        return self.roller_speed is None

    @property
    def surface_speed(self) -> float:
        """Roller surface speed ``ω_r r_r`` [m/s] (0 at rest)."""
        return 0.0 if self.roller_speed is None else self.roller_speed * self.roller_radius

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready (units in the keys)."""
        return {
            "roller_speed [rad/s]": self.roller_speed,
            "roller_speed [km/h]": None if self.at_rest else self.surface_speed * 3.6,
            "roller_speed_source": self.speed_source,
            "wheel_speed [rad/s]": self.wheel_speed,
            "wheel_speed_source": self.wheel_source,
            "normal_load [N]": self.normal_load,
            "normal_load_source": self.load_source,
        }


def _mean_speed(access: RecordingAccess, stats, which: str, rig, given: float | None):
    """Mean |angular speed| [rad/s] of the roller or wheel and its source (None: unknown)."""
    name, counts = f"{which}_speed", f"{which}_encoder_counts"
    if given is not None:
        return require_positive(f"{which}_speed", abs(given), "rad/s", single=True), "given"
    if name in stats:
        if not np.isfinite(stats[name][0]):
            raise access.fail(f"channel {name!r} has non-finite values; fill or cut them first")
        return abs(stats[name][0]), f"mean of the {name} channel"
    if counts in stats and rig is not None:
        cpr = rig.sensors.encoder_pulses_per_revolution * rig.sensors.encoder_quadrature_factor
        first, last = stats[counts].first, stats[counts].last
        duration = access.duration
        if duration > 0:
            return (
                abs(last - first) / duration * 2.0 * np.pi / cpr,
                f"mean from the first and last {counts} ({cpr:g} counts per revolution)",
            )
    return None, f"no {name} or {counts} channel"


def operating_point(
    recording, rig, roller_speed: float | None = None, wheel_speed: float | None = None
) -> OperatingPoint:
    """Mean speeds and normal load of a recording, each with its source (module docstring).

    Parameters
    ----------
    recording : Recording or chunked source
        The recording.
    rig : RigParameters
        Radii, encoder resolution, air-spring area.
    roller_speed, wheel_speed : float, optional
        Given mean angular speeds [rad/s] instead of the recording's.

    Returns
    -------
    OperatingPoint

    Raises
    ------
    RecordingError
        No roller speed (channel, encoder counts or given). A roller at rest is no error: the
        point's ``roller_speed`` is None and ``speed_source`` gives the mean speed measured.
    """
    from rollerrig.rig.linear import DEFAULT_NORMAL_LOAD

    access = recording if isinstance(recording, RecordingAccess) else RecordingAccess(recording)
    wanted = []
    for which, given in (("roller", roller_speed), ("wheel", wheel_speed)):
        if given is None:
            speed = f"{which}_speed"
            wanted.append(speed if speed in access else f"{which}_encoder_counts")
    wanted.append("normal_load" if "normal_load" in access else "air_spring_pressure")
    stats = access.stats(wanted)
    w_r, r_source = _mean_speed(access, stats, "roller", rig, roller_speed)
    if w_r is None:
        raise access.fail(
            "the spectrum's sources need the roller speed: map a roller_speed or "
            f"roller_encoder_counts channel, {SPEED_ARGUMENT}"
        )
    if not w_r > AT_REST:
        w_r, r_source = None, f"roller at rest (mean speed {w_r:.3g} rad/s, {r_source})"
    w_w, w_source = _mean_speed(access, stats, "wheel", rig, wheel_speed)
    if w_w is not None and not w_w > AT_REST:
        w_w, w_source = None, f"wheel at rest ({w_source})"
    if "normal_load" in stats:
        load, l_source = stats["normal_load"][0], "mean of the normal_load channel"
    elif "air_spring_pressure" in stats:
        area = rig.sensors.air_spring_effective_area
        load = stats["air_spring_pressure"][0] * area
        l_source = f"mean air_spring_pressure × effective area {area:g} m² (rig)"
    else:
        load, l_source = DEFAULT_NORMAL_LOAD, "no load channel: the seed's test load 4.3 kN"
    if not (np.isfinite(load) and load > 0.0):
        raise access.fail(
            f"the mean normal load is {load:.4g} N ({l_source}); check the channel's unit, "
            "scale and offset in the channel map"
        )
    speed = stats.get("roller_speed") if roller_speed is None else None
    return OperatingPoint(
        None if w_r is None else float(w_r),
        None if w_w is None else float(w_w),
        float(load),
        r_source,
        w_source,
        l_source,
        float(rig.geometry.roller_radius_x),
        None if speed is None or speed.block_low is None else (speed.block_low, speed.block_high),
    )
