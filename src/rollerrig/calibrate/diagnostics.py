"""What a calibration's residuals say about it: structure the fitted model does not explain
(:func:`channel_structured`: every standard error is then conditional on the model), what to
try then (:func:`model_suggestion`: the two suspects, the roller drive model and the creep law,
each with the comparison that tests it; :func:`law_comparison_suggestion` once a creep-law
comparison has named the law that lost) and a fit that is no valid calibration (no
convergence, or worse than its start).

The thresholds are recorded in ``calibration.json``
(:meth:`rollerrig.calibrate.calibration.Calibration.to_json`).
"""

from __future__ import annotations

import numpy as np

from rollerrig.calibrate.problem import ROLLER_DRIVES

__all__ = [
    "CONDITIONAL_NOTE",
    "STRUCTURE_ALPHA",
    "STRUCTURE_LAG1",
    "STRUCTURE_TAU",
    "WORSE_MARGIN",
    "channel_structured",
    "law_comparison_suggestion",
    "model_suggestion",
]

_QUANTISATION_LAG1 = -0.5  # lag-1 autocorrelation of a gated speed's quantisation error
_LAG1_MARGIN = 0.1  # above -0.5 + this: structure beyond the quantisation


STRUCTURE_LAG1 = 0.5
"""Lag-1 autocorrelation of a channel's residuals above which they show structure the model
does not explain, whatever Ljung-Box says (white residuals of the >= 1000 samples of a test
give |r1| < 0.1; the twin that made a synthetic recording leaves r1 = 0.00 in the torque once
its lines are fitted, a wrong drive model 0.88 to 0.99)."""

STRUCTURE_ALPHA = 0.01
"""Level of the Ljung-Box test of whiteness (:func:`rollerrig.calibrate.stats.whiteness`)."""

STRUCTURE_TAU = 2.0
"""Integrated autocorrelation time [samples] a channel's residuals must also exceed for a
Ljung-Box rejection to count as structure: with thousands of samples Ljung-Box rejects the
DAQ's anti-alias filter over white sensor noise (the demo's torque: lag-1 0.26, 1.1 samples),
which the Newey-West standard errors already account for; a wrong drive model leaves far more
(lag-1 0.88-0.99)."""

WORSE_MARGIN = 0.01
"""A channel ends "worse than it started" when its residual RMS after the fit exceeds the one
before by more than this fraction and exceeds its sensor noise (a channel at its noise, such as
the normal load, moves by 1e-7 between fits)."""

CONDITIONAL_NOTE = (
    "conditional on the model: the residuals show structure the fitted model does not explain "
    "(Ljung-Box p < {alpha:g} with an autocorrelation time above {tau:g} samples, or lag-1 "
    "autocorrelation > {lag1:g}, in a channel; the encoders' "
    "quantisation (lag-1 -0.5) excepted); each standard error is what the data allow if the "
    "model were right, not the distance to the truth"
)


def channel_structured(w: dict, quantised: bool) -> bool:
    """Whether a channel's residuals show structure the model does not explain
    (:data:`STRUCTURE_ALPHA`, :data:`STRUCTURE_LAG1`; an encoder speed's quantisation, lag-1
    autocorrelation -0.5, is no structure)."""
    r1 = float(w["lag1_autocorrelation"])
    if quantised and r1 <= _QUANTISATION_LAG1 + _LAG1_MARGIN:
        return False
    tau = float(w.get("integrated_autocorrelation_time [samples]", np.inf))
    return bool((w["ljung_box_p"] < STRUCTURE_ALPHA and tau > STRUCTURE_TAU) or r1 > STRUCTURE_LAG1)


_LAW_RIVAL = {"polach": "modified-fastsim"}  # the law to compare with; any other: polach


def model_suggestion(roller: str, law: str) -> str:
    """What to try when a calibration's residuals show structure: the two suspects.

    The structure comes from something the fitted twin does not model; on the rig the two
    model choices a calibration makes are the roller drive model and the creep law, and each
    has a comparison that tests it on the same recording (``--compare-drives``,
    ``--compare-laws``). Neither is blamed before its comparison has run.

    Parameters
    ----------
    roller : str
        The roller drive model fitted (``"induction"`` or ``"induction_dq"``).
    law : str
        The creep law fitted (:data:`rollerrig.contact.laws.CREEP_LAWS`).

    Returns
    -------
    str
        One clause naming both suspects and the command that tests each.

    Examples
    --------
    >>> model_suggestion("induction", "modified-fastsim")[:78]
    'the structure may come from the roller drive model (induction) or the creep la'
    """
    other_drive = next((d for d in ROLLER_DRIVES if d != roller), ROLLER_DRIVES[0])
    rival = _LAW_RIVAL.get(law, "polach")
    return (
        f"the structure may come from the roller drive model ({roller}) or the creep law "
        f"({law}): test the drive with rollerrig calibrate RECORDING --free ... "
        f"--compare-drives (or --roller-drive {other_drive}), the law with rollerrig calibrate "
        f"RECORDING --free ... --compare-laws (default: polach against modified-fastsim; or "
        f"--law {rival})"
    )


def law_comparison_suggestion(
    law: str, winner: str, delta_bic: float, roller: str, *, lost: bool
) -> str:
    """The advice of a calibration after a creep-law comparison on its recording.

    Parameters
    ----------
    law : str
        The creep law of this calibration.
    winner : str
        The law the comparison chose.
    delta_bic : float
        BIC of this law minus the winner's [1] (0 for the winner itself).
    roller : str
        The roller drive model fitted: the suspect left when this law won.
    lost : bool
        Whether this law lost the comparison.

    Examples
    --------
    >>> law_comparison_suggestion("fastsim", "polach", 120.0, "induction", lost=True)[:60]
    "the creep law 'fastsim' lost the creep-law comparison on thi"
    """
    if lost:
        return (
            f"the creep law {law!r} lost the creep-law comparison on this recording to "
            f"{winner!r} (BIC larger by {delta_bic:.4g}): calibrate with --law {winner}"
        )
    return (
        f"the creep law {law!r} won the creep-law comparison on this recording; the structure "
        f"left points at the roller drive model ({roller}) or at something neither comparison "
        f"fits: compare the drives with rollerrig calibrate RECORDING --free ... "
        f"--compare-drives --law {law}"
    )


def _invalid_reasons(channels: dict, converged: bool, iterations: int):
    """Why a fit is not a valid calibration (empty: valid): no convergence, a larger cost
    (with the sensor-noise weights) or a larger residual in a channel than at the start.
    ``channels``: name -> :class:`~rollerrig.calibrate.calibration.ChannelFit`."""
    out = []
    if not converged:
        out.append(f"the fit did not converge within {iterations} iterations")

    def cost(which: str) -> float:
        return sum(
            ch.samples * (getattr(ch, which) / ch.sigma_sensor) ** 2 for ch in channels.values()
        )

    before, after = cost("rms_before"), cost("rms_after")
    if after > before:
        out.append(
            f"it ended with a larger cost than it started with ({after:.6g} against {before:.6g}, "
            "sum of squared residuals over the sensor noise)"
        )
    worse = [
        f"{c} ({ch.rms_after:.4g} against {ch.rms_before:.4g} {ch.unit})"
        for c, ch in channels.items()
        if ch.rms_after > (1.0 + WORSE_MARGIN) * ch.rms_before and ch.rms_after > ch.sigma_sensor
    ]
    if worse:
        out.append("it ended with larger residuals than it started with in " + ", ".join(worse))
    return out
