"""Mode tables of the twin at steady free rolling, with the dq V/f drive and the Thevenin drive.

Per drive, speed and load: the oscillatory modes below 20 Hz with what moves, whether one in
a frequency band is lightly damped, the band's class
(:func:`rollerrig.rig.drive_verdicts.band_class`) and any unstable eigenvalue; the same for the
twin's Thevenin drive with a response lag (:func:`rollerrig.rig.linear.coupled_modes`); and
the plain text of such a table.
"""

from __future__ import annotations

from collections.abc import Sequence

from rollerrig.rig import model as m
from rollerrig.rig.dq_drive import DqDrive
from rollerrig.rig.dq_twin import DqTwin
from rollerrig.rig.drive_verdicts import band_class, mode_class
from rollerrig.rig.linear import DEFAULT_DAMPING_THRESHOLD, CoupledMode, coupled_modes

__all__ = ["dq_coupled_modes", "eigen_table", "format_eigen_table", "thevenin_eigen_table"]


def dq_coupled_modes(
    rig, speed: float, normal_load: float, drive: DqDrive | None = None, **kwargs
) -> tuple[CoupledMode, ...]:
    """Modes of the twin with the dq V/f drive at steady free rolling (speed [m/s], load [N])."""
    return DqTwin.at(rig, speed, normal_load, drive, **kwargs).modes()


def _row(modes, speed, load, label, band, threshold=DEFAULT_DAMPING_THRESHOLD):
    """One row of a mode table: the oscillatory modes below 20 Hz and the verdict for ``band``."""
    osc = [md for md in modes if md.kind == "oscillatory" and md.frequency < 20.0]
    in_band = [md for md in osc if band[0] <= md.frequency <= band[1]]
    unstable = [md for md in modes if md.kind != "rigid" and md.eigenvalue.real > 0.0]
    row = {
        "speed [km/h]": speed * 3.6,
        "normal_load [kN]": load / 1e3,
        "drive": label,
        "modes below 20 Hz": [
            {
                "frequency [Hz]": md.frequency,
                "damping_ratio [-]": md.damping_ratio,
                "class": mode_class(md.damping_ratio, threshold),
                "what_moves": md.what_moves,
                "am_rotor_share [-]": md.bodies.get("am_rotor", 0.0),
            }
            for md in osc
        ],
        f"lightly damped in {band[0]:g}-{band[1]:g} Hz": any(
            0.0 <= md.damping_ratio < threshold for md in in_band
        ),
        "least damped in band": (
            None
            if not in_band
            else min(((md.frequency, md.damping_ratio) for md in in_band), key=lambda fz: fz[1])
        ),
        "unstable": [(float(md.eigenvalue.real), md.frequency) for md in unstable],
    }
    row[f"class in {band[0]:g}-{band[1]:g} Hz"] = band_class(row, band)
    return row


def eigen_table(
    rig,
    drives: Sequence[DqDrive],
    speeds: Sequence[float] = (5 / 3.6, 10 / 3.6, 20 / 3.6, 30 / 3.6),
    loads: Sequence[float] = (4.3e3, 10e3, 20e3),
    *,
    band: tuple[float, float] = (1.0, 1.7),
    wheel: str = "pmsm",
) -> list[dict]:
    """Modes of the twin with each dq drive at steady free rolling, one row per (drive, speed
    [m/s], load [N]): the oscillatory modes below 20 Hz with what moves, whether one in ``band``
    [Hz] is lightly damped (0 <= ζ below :data:`rollerrig.rig.linear.DEFAULT_DAMPING_THRESHOLD`;
    a growing mode, ζ < 0, is ``unstable``, never lightly damped), the class of the band
    (:func:`rollerrig.rig.drive_verdicts.band_class`) and any unstable eigenvalue."""
    rows = []
    for d in drives:
        for v in speeds:
            for n in loads:
                modes = DqTwin.at(rig, v, n, d, wheel=wheel).modes()
                rows.append(_row(modes, v, n, d.label, band))
    return rows


def thevenin_eigen_table(
    rig,
    lags: Sequence[float | None] = (None, 0.0),
    speeds: Sequence[float] = (5 / 3.6, 10 / 3.6, 20 / 3.6, 30 / 3.6),
    loads: Sequence[float] = (4.3e3, 10e3, 20e3),
    *,
    band: tuple[float, float] = (1.0, 1.7),
) -> list[dict]:
    """The same table for the existing Thevenin drive (:func:`rollerrig.rig.linear.coupled_modes`)
    with each response lag τ [s] (None: the rig's c_lp)."""
    rows = []
    for lag in lags:
        label = "Thevenin, lag " + ("c_lp (rig)" if lag is None else f"{lag:g} s")
        for v in speeds:
            for n in loads:
                cm = coupled_modes(rig, v, n, drives=m.DriveConfig(roller_lag=lag))
                rows.append(_row(cm.modes, v, n, label, band))
    return rows


def format_eigen_table(rows: Sequence[dict]) -> str:
    """Plain text of :func:`eigen_table` rows: ``f/ζ`` of each oscillatory mode below 20 Hz.

    Examples
    --------
    >>> from rollerrig.rig.parameters import default_rig
    >>> from rollerrig.rig.dq_drive import default_dq_drive
    >>> rig = default_rig()
    >>> text = format_eigen_table(eigen_table(rig, [default_dq_drive(rig)], [30 / 3.6], [4.3e3]))
    >>> text.splitlines()[0].split()[:3]
    ['drive', 'speed', '[km/h]']
    """
    lines = [f"{'drive':<38} {'speed [km/h]':>12} {'N [kN]':>7}  modes below 20 Hz: f [Hz]/zeta"]
    for r in rows:
        modes = " ".join(
            f"{md['frequency [Hz]']:.2f}/{md['damping_ratio [-]']:.3f}"
            for md in r["modes below 20 Hz"]
        )
        flag = " UNSTABLE" if r["unstable"] else ""
        flag += "".join(f" [{v}]" for k, v in r.items() if k.startswith("class in "))
        lines.append(
            f"{r['drive']:<38} {r['speed [km/h]']:>12.0f} {r['normal_load [kN]']:>7.1f}  "
            f"{modes}{flag}"
        )
    return "\n".join(lines)
