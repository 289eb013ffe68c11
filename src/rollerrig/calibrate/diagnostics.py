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
    "DELAY_SHARE",
    "STRUCTURE_ALPHA",
    "STRUCTURE_BLOCK_ALPHA",
    "STRUCTURE_LAG1",
    "STRUCTURE_TAU",
    "WORSE_MARGIN",
    "channel_delay",
    "channel_structured",
    "conditional_note",
    "identified_combinations",
    "law_comparison_suggestion",
    "model_suggestion",
]

DELAY_SHARE = 0.4
"""Share of a structured torque residual's sum of squares that a delay of the channel, fitted
with the free keys, must remove before the calibration names the delay as its likely cause
[-]. On the calibration tests' recording (250 Hz, five noise seeds; 2026-12-03) the torque
3 ms late gave 0.80-0.83, 2 ms late 0.48-0.53, 1 ms late 0.16 (k56 then 1.9 standard errors
off); a creep law the twin does not share 0.17, a gain of 3 %, an offset of 5 N.m or another
shaft damping none named. A first-order low-pass of 2-4 ms group delay gave 0.12-0.14: its
delay depends on the frequency, and it is not named."""


def channel_delay(
    residual: np.ndarray, rate: np.ndarray, jacobian: np.ndarray | None = None
) -> tuple[float, float] | None:
    """The delay of a channel against the twin that best explains the residual, and how much
    of the residual's sum of squares it removes.

    A channel late by τ reads the twin's ``p(t − τ) ≈ p(t) − τ ṗ(t)``, so the delay adds
    ``−τ ṗ`` to its residual ``r = measured − p``. With ``jacobian`` (the fit's columns at the
    optimum) the delay is fitted with them, linearised: least squares of ``r`` on
    ``[J, −ṗ]``; the reduction is the sum of squares that the delay's column removes beyond
    ``J``. A filter's group delay in the torque's amplifier or DAQ module, against the
    encoders' counts, makes such a residual; the twin takes the channels as simultaneous.

    Parameters
    ----------
    residual : ndarray
        The residual after the fit (stacked and weighted as the fit weighs it) [-].
    rate : ndarray
        The twin's rate of change of the channel at the same samples, stacked and weighted
        the same way (zero in the other channels' rows) [1/s].
    jacobian : ndarray, optional
        The fit's Jacobian at the optimum, shape (len(residual), p) [-].

    Returns
    -------
    (float, float) or None
        ``(τ [s], reduction [-])``, τ > 0 where the channel is late; None where the twin's
        channel does not change.

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 1001)
    >>> twin = np.sin(2 * np.pi * 3 * t)
    >>> late = np.sin(2 * np.pi * 3 * (t - 0.002))
    >>> tau, removed = channel_delay(late - twin, np.gradient(twin, t))
    >>> round(tau * 1e3, 2), bool(removed / np.sum((late - twin) ** 2) > 0.99)
    (2.0, True)
    """
    r = np.asarray(residual, dtype=float)
    d = -np.asarray(rate, dtype=float)
    if not float(d @ d) > 0.0:
        return None
    before = r
    columns = d[:, None]
    if jacobian is not None and jacobian.size:
        before = r - jacobian @ np.linalg.lstsq(jacobian, r, rcond=None)[0]
        columns = np.column_stack([jacobian, d])
    coef = np.linalg.lstsq(columns, r, rcond=None)[0]
    after = r - columns @ coef
    return float(coef[-1]), float(before @ before - after @ after)


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

STRUCTURE_BLOCK_ALPHA = 0.001
"""Level of the block-mean test (:func:`rollerrig.calibrate.stats.block_mean_test`) below
which a channel's residuals show a local bias the model does not explain. Ljung-Box, lag-1
and the autocorrelation time miss it: an untold swinging arm (pivot 0.80 m behind, 0.30 m up,
300 N outside the spring's calibration) left the 6.5 s release test's torque lag-1 0.33 and
1.6 samples, no structure by those, while the fit stated bearing friction 7 and mu0 11
standard errors from the truth; its block-mean p was 1e-5, that of the twin's own recordings
0.15-0.97 (three fits, the torque and the load). The level is low because four channels are
tested; on filtered noise (lag-1 0.26-0.79, 6 000-75 000 samples) the test flagged at most
0.3 % of channels (2026-12-03)."""

WORSE_MARGIN = 0.01
"""A channel ends "worse than it started" when its residual RMS after the fit exceeds the one
before by more than this fraction and exceeds its sensor noise (a channel at its noise, such as
the normal load, moves by 1e-7 between fits)."""

CONDITIONAL_NOTE = (
    "conditional on the model: the residuals show structure the fitted model does not explain "
    "(Ljung-Box p < {alpha:g} with an autocorrelation time above {tau:g} samples, or lag-1 "
    "autocorrelation > {lag1:g}, or means of blocks of {block:d} samples off zero (chi-square "
    "p < {block_alpha:g}), in a channel; the encoders' "
    "quantisation (lag-1 -0.5) excepted); each standard error is what the data allow if the "
    "model were right, not the distance to the truth"
)


def conditional_note() -> str:
    """:data:`CONDITIONAL_NOTE` with the thresholds filled in."""
    from rollerrig.calibrate.stats import BLOCK_MEAN_SAMPLES

    return CONDITIONAL_NOTE.format(
        alpha=STRUCTURE_ALPHA,
        tau=STRUCTURE_TAU,
        lag1=STRUCTURE_LAG1,
        block=BLOCK_MEAN_SAMPLES,
        block_alpha=STRUCTURE_BLOCK_ALPHA,
    )


def channel_structured(w: dict, quantised: bool) -> bool:
    """Whether a channel's residuals show structure the model does not explain
    (:data:`STRUCTURE_ALPHA`, :data:`STRUCTURE_LAG1`, :data:`STRUCTURE_BLOCK_ALPHA` on
    ``w["block_mean_p"]`` where given; an encoder speed's quantisation, lag-1 autocorrelation
    -0.5, is no structure by the first two)."""
    if float(w.get("block_mean_p", 1.0)) < STRUCTURE_BLOCK_ALPHA:
        return True
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
        BIC of this law minus the winner's [-] (0 for the winner itself).
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


def identified_combinations(
    keys, values, units, covariance: np.ndarray, threshold: float
) -> list[dict]:
    """The combinations a recording determines where fitted keys are strongly correlated.

    Keys whose correlation exceeds ``threshold`` in magnitude are grouped (connected through
    such pairs). In relative (logarithmic) coordinates x_i = ln v_i the covariance is
    L = C / (v v^T). Its eigenvector u_min of the smallest eigenvalue is the direction the data
    fix best; scaled so that its largest component is +1, its components are the exponents g of
    the power product P = prod v_i^g_i, whose relative standard error follows by the linear
    transform of L (delta method):

        u_rel(P) = sqrt(g^T L g),    u(P) = P u_rel(P).

    The eigenvector of the largest eigenvalue is the direction the data hardly fix (for a
    pair correlated +1: both keys times the same factor, i.e. the product when the ratio is
    what is fixed); its combination is reported the same way, as what the recording cannot
    tell apart. A member's own (marginal) standard error is the projection of that long, thin
    ellipse and says little on its own.

    Parameters
    ----------
    keys : sequence of str
        The identified keys, the order of ``covariance``.
    values : sequence of float
        Their fitted values [SI unit of each].
    units : sequence of str
        Their SI units.
    covariance : ndarray
        Their covariance [products of their SI units].
    threshold : float
        |correlation| above which a pair is grouped [-] (the calibration's
        :data:`rollerrig.calibrate.settings.MAX_CORRELATION`).

    Returns
    -------
    list of dict
        One per group of keys with all values > 0 (logarithms need them): ``keys``,
        ``exponents``, ``expression``, ``value``, ``standard_error`` and
        ``relative_standard_error`` of the determined combination [its unit], ``unit``,
        ``max_abs_correlation``, and ``undetermined`` (``exponents``, ``expression``,
        ``relative_standard_error``) for the direction the data hardly fix.

    References
    ----------
    JCGM 100:2008 (GUM), 5.2 (law of propagation of uncertainty for correlated inputs).

    Examples
    --------
    Two keys with equal relative standard errors s = 1 % correlated r = 0.999: the ratio is
    fixed to s sqrt(2 (1 - r)) = 0.0447 %, the product only to s sqrt(2 (1 + r)) = 2.00 %.

    >>> s, r = 0.01, 0.999
    >>> c = np.array([[s * s * 4.0, r * s * s * 2.0], [r * s * s * 2.0, s * s]])  # v = 2, 1
    >>> (g,) = identified_combinations(["a", "b"], [2.0, 1.0], ["m", "s"], c, 0.98)
    >>> g["expression"], round(g["value"], 12), round(100 * g["relative_standard_error"], 4)
    ('a · b^-1', 2.0, 0.0447)
    >>> loose = g["undetermined"]
    >>> loose["expression"], round(100 * loose["relative_standard_error"], 3)
    ('a · b', 1.999)
    """
    keys = list(keys)
    v = np.asarray(values, dtype=float)
    cov = np.asarray(covariance, dtype=float)
    se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(se, se)
    strong = np.abs(np.where(np.isfinite(corr), corr, 0.0)) > threshold
    np.fill_diagonal(strong, False)
    out: list[dict] = []
    seen: set[int] = set()
    for start in range(len(keys)):
        if start in seen or not strong[start].any():
            continue
        group, todo = [], [start]
        while todo:  # connected through strongly correlated pairs
            i = todo.pop()
            if i in seen:
                continue
            seen.add(i)
            group.append(i)
            todo.extend(int(j) for j in np.flatnonzero(strong[i]) if j not in seen)
        group.sort()
        if not np.all(v[group] > 0):
            continue
        rel = cov[np.ix_(group, group)] / np.outer(v[group], v[group])
        vectors = np.linalg.eigh(rel)[1]  # eigenvalues ascending
        names = [keys[i] for i in group]
        fixed = _power_product(names, v[group], [units[i] for i in group], vectors[:, 0], rel)
        loose = _power_product(names, v[group], [units[i] for i in group], vectors[:, -1], rel)
        sub = np.abs(corr[np.ix_(group, group)] - np.eye(len(group)))
        out.append(
            {
                "keys": names,
                **fixed,
                "max_abs_correlation": float(np.max(sub)),
                "undetermined": {
                    k: loose[k] for k in ("exponents", "expression", "relative_standard_error")
                },
                "how": "eigenvector of the smallest eigenvalue of the covariance of ln(value): "
                "the exponents of the power product the recording fixes best; its standard "
                "error by the linear transform g^T L g (L: the covariance of ln(value)); "
                "undetermined: the eigenvector of the largest eigenvalue",
            }
        )
    return out


def _power_product(names, values, units, direction, rel) -> dict:
    """The power product prod v_i^g_i along ``direction`` scaled so its largest |component| is
    +1 (exponents rounded to 3 significant digits, then the error of exactly that product)."""
    g = direction / direction[np.argmax(np.abs(direction))]
    g = np.array([float(f"{x:.3g}") for x in g])
    g[np.abs(g) < 1e-3] = 0.0
    value = float(np.prod(values**g))
    u_rel = float(np.sqrt(max(float(g @ rel @ g), 0.0)))

    def power(text: str, e: float) -> str:
        return text if e == 1.0 else f"{text}^{e:g}"

    def unit_power(u: str, e: float) -> str:
        return power(f"({u})" if e != 1.0 and any(c in u for c in "./^ ") else u, e)

    used = [(n, u, e) for n, u, e in zip(names, units, g, strict=True) if e != 0.0]
    unit = " ".join(unit_power(u, e) for _, u, e in used if u not in ("", "1")) or "1"
    return {
        "exponents": {n: float(e) for n, e in zip(names, g, strict=True)},
        "expression": " · ".join(power(n, e) for n, _, e in used),
        "value": value,
        "standard_error": value * u_rel,
        "relative_standard_error": u_rel,
        "unit": unit,
    }
