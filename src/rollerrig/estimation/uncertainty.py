"""Uncertainty of the corrected CoA: JCGM 100 (GUM) propagation and JCGM 101 Monte Carlo.

Measurement model (per sample; :mod:`rollerrig.measure.correction`)

.. math::
    \\mu_{corr} = \\frac{F_x}{N_c} + e_{res}, \\qquad
    F_x = \\frac{T_{56} + \\delta T + e_T + J_5 (\\alpha_5 + e_\\alpha) + k_b b (W_r + S + W_d)}
               {r_r - κ k_b b}, \\qquad N_c = S + W_d + κ F_x,

    S = (p + \\delta p + e_p) A, \\qquad b = f_g r_b \\tanh(\\omega_5/\\omega_{reg}),
    \\qquad κ = σ h / l

with T56, α5, ω5 the Savitzky-Golay estimates of the correction, p the air-spring pressure
(S/A when the recording gives the load), the swinging arm's load transfer κ and dead weight
W_d (:class:`rollerrig.rig.sections.ArmParameters`: the rig measures S, the contact carries
N_c), and these inputs (:data:`INPUT_NAMES`):

============================  ==========  ============  =========================================
input                         kind        distribution  standard uncertainty
============================  ==========  ============  =========================================
``torque_class`` δT           systematic  rectangular   class × range / √3 (rig ``sensors``)
``torque_noise`` e_T          random      normal        σ_T ‖h_i‖: type A σ_T through the smoother
``pressure_class`` δp         systematic  rectangular   class × range / √3
``pressure_noise`` e_p        random      normal        type A σ_p (the load is not smoothed)
``air_spring_area`` A         systematic  normal        relative × A (or calibrated)
``roller_radius`` r_r         systematic  rectangular   tolerance / √3 (or calibrated, normal)
``roller_inertia`` J5         systematic  normal        relative × J5 (or calibrated)
``bearing_loss`` k_b          systematic  normal        relative (1 when f_g, r_b or W_r are
                                                        calibrated: then those, normal)
``encoder_quantisation`` e_α  random      normal        √(1/12) count through the encoder speed
                                                        and the derivative weights, ‖a_i‖
``arm_pivot_height`` h        systematic  rectangular   tolerance / √3 (rig ``arm``)
``arm_length`` l              systematic  rectangular   tolerance / √3 (rig ``arm``)
``arm_dead_weight`` W_d       systematic  normal        stated (rig ``arm``)
``residual_steady``           residual    normal        type A: in-band disturbances in quiet
                                                        phases
``residual_release``          residual    normal        stated (twin): after each release
============================  ==========  ============  =========================================

**Systematic** inputs (calibration-type: sensor class, area, radius, J5, bearing) take one value
for the whole test: every sample and every point shares their error, so they do not average
down in a phase mean (their sensitivities are averaged instead). **Random** inputs are noise
through the correction's linear filters: their per-sample variance is σ² times the squared
norm of the filter row (exact at the ends too), and the variance of a phase mean uses the
phase's mean filter weights (the derivative weights of α5 telescope: a phase mean of α5 carries
little quantisation). The encoder counts are floor(θ·CPR/2π): with hundreds of counts per
sample their rounding errors are independent and uniform on [0, 1) count (variance 1/12;
recordings decimated before the analysis: 1/12 × new rate / old rate, the anti-alias filter
keeps that share of the white quantisation noise). **Residual** terms cover what the correction
does not resolve: the torque's periodic disturbances within the correction's pass band
(``residual_steady``, from the scatter of the corrected CoA in quiet phases, less the random
part) and the contact's own transient at a release, which a 0.2 s filter cannot follow
(``residual_release``, :class:`CorrectionResidual`, stated from the twin). Residual terms are
treated as correlated over one correction window.

Law of propagation (JCGM 100 §5.1-5.2): u²(μ) = Σ c_i² u²(x_i), with covariances between
calibrated parameters (§5.2.2); U = k u, k = 2. Monte Carlo (JCGM 101 §7): draws of every
input from its PDF through the full model; adaptive (§7.9) in runs of M = 10⁴ until twice the
standard deviation of the run means of y, u and the interval ends is below the numerical
tolerance δ of u (two significant digits, §7.9.2). Validation (JCGM 101 §8): the LPU interval
y ± U against the MC 95 % probabilistically symmetric interval, d_low and d_high ≤ δ. A
rectangular input that dominates makes the output flat-topped: then y ± 2u is wider than the
95 % interval (conservative) and the §8 check fails on the shape, not on the linearity, which
the agreement of u itself shows.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.estimation.coa_uncertainty import COVERAGE_FACTOR, CoaUncertainty
from rollerrig.estimation.filterweights import (
    BandedFilter,
    after_encoder_speed,
    savitzky_golay_matrix,
)
from rollerrig.estimation.montecarlo import (
    K95,
    MonteCarloResult,
    jcgm101_validation,
    monte_carlo,
    numerical_tolerance,
)
from rollerrig.measure.correction import correction_terms
from rollerrig.measure.quantities import encoder_speed

__all__ = [
    "COVERAGE_FACTOR",
    "INPUT_NAMES",
    "K95",
    "MODEL_KEYS",
    "CoaUncertainty",
    "CorrectionResidual",
    "InputQuantity",
    "MonteCarloResult",
    "calibration_covariance",
    "corrected_coa_uncertainty",
    "jcgm101_validation",
    "monte_carlo",
    "noise_level",
    "numerical_tolerance",
    "release_residual_from_truth",
]


INPUT_NAMES = (
    "torque_class",
    "torque_noise",
    "pressure_class",
    "pressure_noise",
    "air_spring_area",
    "roller_radius",
    "roller_inertia",
    "bearing_loss",
    "bearing_friction",
    "bearing_radius",
    "roller_weight",
    "encoder_quantisation",
    "arm_pivot_height",
    "arm_length",
    "arm_dead_weight",
    "residual_steady",
    "residual_release",
)
"""Inputs of the model, in budget order (the bearing's three appear only when calibrated)."""

MODEL_KEYS = {
    "sensors.air_spring_effective_area": "air_spring_area",
    "geometry.roller_radius_x": "roller_radius",
    "inertia.roller": "roller_inertia",
    "bearing.friction_coefficient": "bearing_friction",
    "bearing.roller_bearing_radius": "bearing_radius",
    "bearing.roller_subsystem_weight": "roller_weight",
}
"""Calibrated rig keys that are inputs of the corrected CoA -> input name."""


@dataclass(frozen=True)
class CorrectionResidual:
    """The stated residual of the dynamics correction after a release (type B, from the twin).

    A release drops the contact CoA within tens of ms and sets the wheel-roller system
    ringing; a 0.2 s correction filter follows neither. With H the span of the corrected CoA
    over the release (± one correction window), H_r the drop from the cycle's level (the largest
    corrected CoA in the 4 s before the release's end) to the value after it, s the largest
    measured creep in the 0.5 s before the release and Δ the time from the release's end, the
    standard uncertainty is ``fast·H`` from a quarter window before the release to half a window
    after it, and ``(ring + ring_slip·min(1, s/slip_scale))·H_r·exp(-Δ/ring_decay)`` after it
    (in quadrature). A wheel released from macro-slip rings harder and longer than one
    released on the adhesion branch, and its CoA has already fallen from the level during the
    slip, which H no longer shows: so the ring scales with H_r and grows with s.

    Derived with :func:`release_residual_from_truth` on the bundled rig's twin (with its
    swinging arm), seed-30kmh-dry at 250 Hz, synthetic seed 3, and the same test with the
    level raised so that the wheel slips deeper before each release (912 / 930 / 950 / 980
    N.m: creep at the release 0.048 / 0.14 / 0.30 / 0.61): ring amplitudes of 0.046 / 0.079 /
    0.096 / 0.23 of H_r, decaying with 2.5-3.1 s, the fast part 0.24 of H at most. Stated: fast
    0.25, ring 0.045, ring_slip 0.055 over slip_scale 0.15 (0.063 at the seed's 5 % creep, 0.10
    from 15 % on), decay 3.0 s: at or above each of those up to 30 % creep at the release. A
    wheel released from a runaway deeper than that (61 %: slip velocity 5 m/s) rings more than
    twice as hard as stated: the band does not cover it. Another rig (shaft, lag, damping, arm)
    rings otherwise: derive it again on its twin.

    Attributes
    ----------
    fast : float
        [-] of H.
    ring : float
        [-] of H_r.
    ring_decay : float
        [s].
    ring_slip : float
        [-] of H_r added at a creep of ``slip_scale`` or more before the release.
    slip_scale : float
        [-] creep.
    """

    fast: float = 0.25
    ring: float = 0.045
    ring_decay: float = 3.0
    ring_slip: float = 0.055
    slip_scale: float = 0.15

    def standard_uncertainty(
        self, time, coa, releases, window_s: float, creep=None
    ) -> tuple[np.ndarray, np.ndarray]:
        """u [-] of the fast part and of the ring at ``time`` [s] for ``releases`` [(start, end) s].

        ``creep`` [-]: the measured creep at ``time`` (None: taken as on the adhesion branch).
        The fast part is normal; the ring is a decaying oscillation of unknown phase, whose
        value at an instant has the arcsine PDF of standard deviation given in the class
        docstring (JCGM 101 §6.4.6); several releases add in quadrature.
        """
        t = np.asarray(time, dtype=float)
        fast_var, ring_var = np.zeros_like(t), np.zeros_like(t)
        for start, end in releases:
            span = (t >= start - window_s) & (t <= end + window_s)
            if not np.any(span):
                continue
            height = float(np.ptp(coa[span]))
            fast = (t >= start - 0.25 * window_s) & (t <= end + 0.5 * window_s)
            fast_var += np.where(fast, (self.fast * height) ** 2, 0.0)
            after = t >= end
            coefficient = self.ring + self.ring_slip * min(
                1.0, _slip_before(t, creep, start) / self.slip_scale
            )
            ring_height = max(height, _ring_height(t, coa, start, end, window_s))
            ring = (
                coefficient * ring_height * np.exp(-np.where(after, t - end, 0.0) / self.ring_decay)
            )
            ring_var += np.where(after, ring**2, 0.0)
        return np.sqrt(fast_var), np.sqrt(ring_var)

    def as_dict(self) -> dict:
        return {
            "fast [-] of H": self.fast,
            "ring [-] of H_r": self.ring,
            "ring_slip [-] of H_r": self.ring_slip,
            "slip_scale [-]": self.slip_scale,
            "ring_decay [s]": self.ring_decay,
            "basis": "stated, type B: RMS error of the corrected CoA against the twin's contact "
            "CoA after releases (bundled rig with its arm, seed-30kmh-dry and deeper-slipping "
            "variants, 250 Hz, synthetic seed 3), relative to the release's drop from the "
            "cycle's level H_r (release_residual_from_truth)",
        }


def _slip_before(t: np.ndarray, creep, start: float) -> float:
    """The largest |creep| [-] in the 0.5 s before ``start`` (0 without a creep channel)."""
    if creep is None:
        return 0.0
    c = np.asarray(creep, dtype=float)
    before = (t >= start - 0.5) & (t < start) & np.isfinite(c)
    return float(np.max(np.abs(c[before]))) if np.any(before) else 0.0


def _ring_height(t: np.ndarray, coa, start: float, end: float, window_s: float) -> float:
    """H_r [-]: the largest CoA in the 4 s before ``end`` less the median one to two windows
    after it."""
    level = (t >= start - 4.0) & (t <= end)
    after = (t > end + window_s) & (t < end + 2.0 * window_s)
    if not (np.any(level) and np.any(after)):
        return 0.0
    return max(0.0, float(np.max(coa[level]) - np.median(coa[after])))


@dataclass(frozen=True)
class InputQuantity:
    """One input of the model: its estimate, standard uncertainty, PDF and basis."""

    name: str
    symbol: str
    kind: str  # "systematic" | "random" | "residual"
    distribution: str  # "rectangular" | "normal"
    estimate: float | None  # None: per sample (the recording's)
    standard_uncertainty: float | None  # of the input [unit]; None: per sample
    unit: str
    basis: str
    key: str | None = None  # the rig key, for parameters

    def as_dict(self) -> dict:
        out = {
            "name": self.name,
            "symbol": self.symbol,
            "kind": self.kind,
            "distribution": self.distribution,
            "estimate": self.estimate,
            "standard_uncertainty": self.standard_uncertainty,
            "unit": self.unit,
            "basis": self.basis,
            "rig_key": self.key,
        }
        if self.estimate is None:
            out["estimate_null_because"] = "an estimate per sample (the recording's)"
        if self.standard_uncertainty is None:
            out["standard_uncertainty_null_because"] = "per sample: see the budget"
        if self.distribution == "rectangular" and self.standard_uncertainty is not None:
            out["half_width"] = self.standard_uncertainty * math.sqrt(3.0)
        return out


def noise_level(x) -> float:
    """Type A white-noise level [unit of x]: MAD of the second differences / (0.6745·√6).

    The second difference of white noise of standard deviation σ has standard deviation √6 σ;
    the median absolute value of a normal variable is 0.6745 of its standard deviation. A smooth
    signal adds little to the second differences; lines near the Nyquist frequency do
    (conservative).

    Examples
    --------
    >>> x = np.random.default_rng(1).normal(0.0, 2.0, 100_000) + np.linspace(0, 50, 100_000)
    >>> round(noise_level(x), 1)
    2.0
    """
    x = np.asarray(x, dtype=float)
    if x.size < 5:
        return 0.0
    return float(np.median(np.abs(np.diff(x, 2))) / (0.6745 * math.sqrt(6.0)))


# --------------------------------------------------------------------------------------------
# Calibration: values and covariance of the model's rig keys
# --------------------------------------------------------------------------------------------


def calibration_covariance(calibration: Mapping) -> tuple[dict, dict, np.ndarray, list[str], list]:
    """Values, standard errors and covariance of the calibrated keys the corrected CoA uses.

    Parameters
    ----------
    calibration : mapping
        As ``calibration.json`` (``rollerrig calibrate``) holds it: ``{"parameters": {key:
        {"value": v, "standard_error": s}}, "correlation": {"keys": [...], "matrix": [[...]]}}``
        (SI). Also accepted: ``"correlation": [[...]]`` with the row order in a top-level
        ``"keys"``. Without a correlation the keys are taken uncorrelated; a ``value`` of null
        (not identified) leaves the rig's value and stated accuracy; a ``standard_error`` of
        null keeps the value without a calibrated uncertainty (the stated one stays); a null
        correlation entry counts as 0 (noted).

    Returns
    -------
    values : dict
        Every calibrated key with a finite value -> value (to override the rig with).
    used : dict
        Input name -> key, for the keys of :data:`MODEL_KEYS` with a finite standard error.
    covariance : ndarray
        Covariance of the ``used`` inputs, in their order.
    names : list of str
        The ``used`` input names in that order.
    notes : list of str
        What was not used and why.

    Raises
    ------
    ParameterError
        A malformed dictionary, naming the entry.
    """
    if not isinstance(calibration, Mapping) or not isinstance(
        calibration.get("parameters"), Mapping
    ):
        raise ParameterError(
            "calibration: must be a mapping with 'parameters' {key: {value, standard_error}} "
            "(the content of calibration.json)"
        )
    params = calibration["parameters"]
    values, errors, notes = {}, {}, []
    for key, entry in params.items():
        where = f"calibration: parameters.{key}"
        if not isinstance(entry, Mapping) or "value" not in entry:
            raise ParameterError(f"{where}: must be a mapping with 'value' and 'standard_error'")
        value, se = entry["value"], entry.get("standard_error")
        if value is None:
            why = entry.get("why_null") or entry.get("reason") or "not identified"
            notes.append(f"{key}: no calibrated value ({why}): the rig's value is used")
            continue
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not math.isfinite(value)
        ):
            raise ParameterError(f"{where}.value: must be a finite number; got {value!r}")
        values[str(key)] = float(value)
        if se is None:
            notes.append(f"{key}: no standard error (not identified by the calibration)")
            continue
        if (
            isinstance(se, bool)
            or not isinstance(se, int | float)
            or not (se >= 0)
            or not (math.isfinite(se))
        ):
            raise ParameterError(
                f"{where}.standard_error: must be a finite number >= 0 or null; got {se!r}"
            )
        errors[str(key)] = float(se)
    corr = calibration.get("correlation")
    keys = calibration.get("keys", list(params))
    if isinstance(corr, Mapping):  # calibration.json: {"keys": [...], "matrix": [[...]]}
        keys, corr = corr.get("keys", keys), corr.get("matrix")
    keys = [str(k) for k in keys]
    if corr is not None:
        try:
            corr = np.array(
                [[math.nan if v is None else v for v in row] for row in corr], dtype=float
            )
        except (TypeError, ValueError):
            raise ParameterError(
                "calibration: correlation: must be a square matrix of numbers (null where the "
                "calibration could not give one)"
            ) from None
        if corr.shape != (len(keys), len(keys)):
            raise ParameterError(
                f"calibration: correlation: must be {len(keys)} x {len(keys)} (one row per entry "
                f"of 'keys'); got shape {corr.shape}"
            )
    used = {MODEL_KEYS[k]: k for k in MODEL_KEYS if k in errors}
    names = list(used)
    cov = np.diag([errors[used[n]] ** 2 for n in names])
    for a, na in enumerate(names):
        for b, nb in enumerate(names[:a]):
            if corr is None or used[na] not in keys or used[nb] not in keys:
                continue
            rho = corr[keys.index(used[na]), keys.index(used[nb])]
            if not math.isfinite(rho) or abs(rho) > 1.0 + 1e-9:
                notes.append(f"correlation of {used[na]} and {used[nb]} is {rho!r}: taken as 0")
                continue
            cov[a, b] = cov[b, a] = rho * math.sqrt(cov[a, a] * cov[b, b])
    if corr is None and len(names) > 1:
        notes.append("the calibration gives no correlation: its keys taken as uncorrelated")
    discrepancy = calibration.get("model_discrepancy")
    discrepancy = discrepancy.get("keys") if isinstance(discrepancy, Mapping) else None
    for i, n in enumerate(names):  # type-B term of the drive models' spread (calibrate compare)
        item = (discrepancy or {}).get(used[n])
        u_md = item.get("standard_uncertainty") if isinstance(item, Mapping) else None
        if isinstance(u_md, int | float) and math.isfinite(u_md) and u_md > 0.0:
            cov[i, i] += float(u_md) ** 2
            notes.append(
                f"{used[n]}: model discrepancy u = {u_md:.3g} (spread between adequate drive "
                "models, rectangular) added to its variance"
            )
    for key in values:
        if key not in MODEL_KEYS and not key.startswith("polach."):
            notes.append(f"{key}: calibrated, not an input of the corrected CoA (used in the rig)")
    return values, used, cov, names, notes


# --------------------------------------------------------------------------------------------
# The model
# --------------------------------------------------------------------------------------------


def corrected_coa_uncertainty(
    recording,
    rig,
    *,
    window: int,
    order: int = 4,
    releases=(),
    quiet=(),
    calibration: Mapping | None = None,
    residual: CorrectionResidual | None = None,
) -> CoaUncertainty:
    """The corrected CoA of a recording with its JCGM 100 uncertainty per sample.

    Parameters
    ----------
    recording : Recording
        With ``torque`` [N.m], ``roller_speed`` [rad/s], ``normal_load`` [N] (and, where the
        rig recorded them, ``air_spring_pressure`` [Pa] and ``roller_encoder_counts`` [1]), on
        a uniform time axis (:func:`rollerrig.measure.quantities.derive_quantities`).
    rig : RigParameters
        Geometry, inertia, bearing and the ``sensors`` accuracies. With ``calibration``, pass
        the calibrated rig (the values the correction uses); the calibration adds the
        covariance.
    window, order : int
        The correction's Savitzky-Golay window [samples] and order.
    releases : sequence of (float, float)
        Start and end [s] of each release (for ``residual_release``).
    quiet : sequence of (float, float)
        Quiet phases [s] (free rolling, rest) for ``residual_steady``.
    calibration : mapping, optional
        ``calibration.json`` content (:func:`calibration_covariance`).
    residual : CorrectionResidual, optional
        The stated release residual; default :class:`CorrectionResidual` ().

    Returns
    -------
    CoaUncertainty
    """
    residual = residual or CorrectionResidual()
    t = np.asarray(recording.time, dtype=float)
    n = t.size
    fs = float(recording.sample_rate)
    s, b, g = rig.sensors, rig.bearing, rig.geometry
    notes: list[str] = []
    terms = correction_terms(
        recording["torque"],
        recording["roller_speed"],
        recording["normal_load"],
        fs,
        roller_radius=g.roller_radius_x,
        roller_inertia=rig.inertia.roller,
        bearing_friction=b.friction_coefficient,
        bearing_radius=b.roller_bearing_radius,
        roller_weight=b.roller_subsystem_weight,
        regularisation_speed=b.regularisation_speed,
        window=window,
        order=order,
        load_transfer=rig.arm.transfer_ratio,
        dead_weight=rig.arm.dead_weight,
    )
    area, radius, j5 = s.air_spring_effective_area, g.roller_radius_x, rig.inertia.roller
    f_g, r_b, w_r = b.friction_coefficient, b.roller_bearing_radius, b.roller_subsystem_weight
    load = terms.normal_load
    if "air_spring_pressure" in recording:
        pressure = np.asarray(recording["air_spring_pressure"], dtype=float)
        p_basis = "air_spring_pressure"
    else:
        pressure = load / area
        p_basis = "normal_load / air_spring_effective_area"
        notes.append(
            "no air_spring_pressure channel: the load is taken as measured by the air spring "
            "(p = N/A), with the pressure sensor's accuracy"
        )
    th = np.tanh(terms.roller_speed / b.regularisation_speed)

    # Random inputs: white noise through the correction's filters.
    sigma_t = noise_level(np.asarray(recording["torque"], dtype=float))
    sigma_p = noise_level(pressure)
    half = window // 2
    smooth = BandedFilter(lambda m: savitzky_golay_matrix(m, window, order), n, half)
    counts_based = "roller_encoder_counts" in recording and _speed_from_counts(recording, rig)
    if counts_based:
        cpr = s.encoder_counts_per_revolution
        decimated = recording.metadata.get("decimated") or {}
        ratio = min(1.0, fs / float(decimated.get("from_rate_Hz", fs)))
        sigma_c = math.sqrt(ratio / 12.0)
        accel = BandedFilter(
            lambda m: after_encoder_speed(
                savitzky_golay_matrix(m, window, order, 1, 1.0 / fs), fs, cpr
            ),
            n,
            half + 1,
        )
        q_unit, q_basis = (
            "count",
            (
                f"encoder counts rounded down: uniform on [0, 1) count, variance {ratio:.3g}/12 "
                f"({cpr} counts/rev), through the encoder speed and the α5 derivative weights"
            ),
        )
        if ratio < 1.0:
            q_basis += "; decimated before the analysis (white share of the new rate)"
    else:
        sigma_c = noise_level(np.asarray(recording["roller_speed"], dtype=float))
        accel = BandedFilter(
            lambda m: savitzky_golay_matrix(m, window, order, 1, 1.0 / fs), n, half
        )
        q_unit, q_basis = (
            "rad/s",
            (
                "roller speed given by the recording (no encoder counts): type A white noise of "
                "the speed through the α5 derivative weights"
            ),
        )
    u_et = sigma_t * np.sqrt(smooth.row_norm2())
    u_ea = sigma_c * np.sqrt(accel.row_norm2())

    # Systematic inputs: the rig's accuracies, replaced by a calibration where it gives them.
    u_sys = {
        "torque_class": s.torque_sensor_accuracy * s.torque_sensor_range / math.sqrt(3.0),
        "pressure_class": s.pressure_sensor_accuracy * s.pressure_sensor_range / math.sqrt(3.0),
        "air_spring_area": s.air_spring_area_uncertainty * area,
        "roller_radius": s.roller_radius_tolerance / math.sqrt(3.0),
        "roller_inertia": s.roller_inertia_uncertainty * j5,
        "bearing_loss": s.bearing_loss_uncertainty,
        "arm_pivot_height": rig.arm.pivot_height_tolerance / math.sqrt(3.0),
        "arm_length": rig.arm.arm_length_tolerance / math.sqrt(3.0),
        "arm_dead_weight": rig.arm.dead_weight_uncertainty,
    }
    dist = {
        "torque_class": "rectangular",
        "pressure_class": "rectangular",
        "air_spring_area": "normal",
        "roller_radius": "rectangular" if s.roller_radius_tolerance > 0 else "normal",
        "roller_inertia": "normal",
        "bearing_loss": "normal",
        "arm_pivot_height": "rectangular",
        "arm_length": "rectangular",
        "arm_dead_weight": "normal",
    }
    basis = {
        "torque_class": f"accuracy class {s.torque_sensor_accuracy:g} of "
        f"{s.torque_sensor_range:g} N.m (sensors.torque_sensor_accuracy)",
        "pressure_class": f"accuracy class {s.pressure_sensor_accuracy:g} of "
        f"{s.pressure_sensor_range:g} Pa (sensors.pressure_sensor_accuracy)",
        "air_spring_area": f"{s.air_spring_area_uncertainty:g} relative "
        "(sensors.air_spring_area_uncertainty)",
        "roller_radius": f"tolerance ±{s.roller_radius_tolerance:g} m "
        "(sensors.roller_radius_tolerance)",
        "roller_inertia": f"{s.roller_inertia_uncertainty:g} relative "
        "(sensors.roller_inertia_uncertainty)",
        "bearing_loss": f"{s.bearing_loss_uncertainty:g} relative of R05 "
        "(sensors.bearing_loss_uncertainty)",
        "arm_pivot_height": f"tolerance ±{rig.arm.pivot_height_tolerance:g} m of the swinging "
        "arm's pivot height (arm.pivot_height_tolerance)",
        "arm_length": f"tolerance ±{rig.arm.arm_length_tolerance:g} m of the arm's length "
        "(arm.arm_length_tolerance)",
        "arm_dead_weight": f"{rig.arm.dead_weight_uncertainty:g} N standard "
        "(arm.dead_weight_uncertainty)",
    }
    calibrated: list[str] = []
    covariance = np.zeros((0, 0))
    if calibration is not None:
        values, used, covariance, calibrated, cal_notes = calibration_covariance(calibration)
        notes.extend(f"calibration: {x}" for x in cal_notes)
        conditional: set[str] = set()
        current = {
            "air_spring_area": area,
            "roller_radius": radius,
            "roller_inertia": j5,
            "bearing_friction": f_g,
            "bearing_radius": r_b,
            "roller_weight": w_r,
        }
        for name in calibrated:
            key = used[name]
            if not math.isclose(values[key], current[name], rel_tol=1e-9, abs_tol=0.0):
                notes.append(
                    f"calibration: {key} = {values[key]:.6g} differs from the rig's "
                    f"{current[name]:.6g}: pass the calibrated rig (analyze_test does)"
                )
            u_cal = math.sqrt(covariance[calibrated.index(name), calibrated.index(name)])
            entry = calibration["parameters"].get(key) or {}
            if entry.get("conditional_on_model") and u_cal < u_sys.get(name, 0.0):
                # residuals with structure: the standard error holds only if the model were
                # right; the larger of it and the rig's stated type-B uncertainty is kept
                conditional.add(name)
                basis[name] += f" (kept: the calibration of {key} is conditional on the model)"
                notes.append(
                    f"calibration: {key}'s standard error {u_cal:.3g} is conditional on the "
                    f"model (structured residuals): the rig's stated {u_sys[name]:.3g} is kept"
                )
                continue
            u_sys[name] = u_cal
            dist[name] = "normal"
            basis[name] = f"calibrated ({key}), standard error with the calibration's covariance"
        for name in conditional:  # its stated u, no longer correlated with the calibration's
            i = calibrated.index(name)
            covariance[i, :] = covariance[:, i] = 0.0
            covariance[i, i] = u_sys[name] ** 2
        bearing_keys = {"bearing_friction", "bearing_radius", "roller_weight"}
        if any(
            (calibration["parameters"].get(used[n]) or {}).get("conditional_on_model")
            for n in bearing_keys & set(calibrated)
        ):
            bearing_keys = set()  # conditional on the model: the stated bearing loss stays
            notes.append(
                "calibration: the bearing parameters' standard errors are conditional on the "
                "model: the bearing loss's stated uncertainty is kept beside them"
            )
        if bearing_keys & set(calibrated):
            del u_sys["bearing_loss"]
            notes.append(
                "calibration: the bearing loss's stated uncertainty is replaced by "
                "the calibrated bearing parameters"
            )
    # Sensitivity coefficients (∂μ/∂x at the estimates) of μ = F/N_c with
    # F = (T + J5 α + b (W_r + S + W_d)) / D, D = r_r − κ b, N_c = S + W_d + κ F (module
    # docstring): ∂μ/∂F|_S = (S + W_d)/N_c² =: G, ∂μ/∂S|_F = ∂μ/∂W_d|_F = −F/N_c²,
    # ∂μ/∂κ|_F = −F²/N_c²; ∂F/∂S = b/D, ∂F/∂κ = F b/D.
    arm = rig.arm
    kappa, w_d = arm.transfer_ratio, arm.dead_weight
    mu = terms.coa
    force, n_c = terms.contact_force, terms.contact_load
    b_th = f_g * r_b * th
    d = radius - kappa * b_th
    gain = (load + w_d) / n_c**2 / d  # ∂μ/∂(numerator of F)
    d_load = gain * b_th - force / n_c**2  # dμ/dS (and dμ/dW_d)
    d_kappa = gain * force * b_th - (force / n_c) ** 2
    bearing = b_th * (w_r + n_c)
    sens = {
        "torque_class": gain,
        "torque_noise": gain,
        "pressure_class": d_load * area,
        "pressure_noise": d_load * area,
        "air_spring_area": d_load * pressure,
        "roller_radius": -gain * force,
        "roller_inertia": gain * terms.acceleration,
        "bearing_loss": gain * bearing,
        "bearing_friction": gain * r_b * (w_r + n_c) * th,
        "bearing_radius": gain * f_g * (w_r + n_c) * th,
        "roller_weight": gain * b_th,
        "encoder_quantisation": gain * j5,
        "arm_pivot_height": d_kappa * arm.sign / arm.arm_length,
        "arm_length": -d_kappa * kappa / arm.arm_length,
        "arm_dead_weight": d_load,
        "residual_steady": np.ones(n),
        "residual_release": np.ones(n),
    }
    contributions = {}
    for name, u in u_sys.items():
        contributions[name] = np.abs(sens[name]) * u
    contributions["torque_noise"] = np.abs(sens["torque_noise"]) * u_et
    contributions["pressure_noise"] = np.abs(sens["pressure_noise"]) * sigma_p
    contributions["encoder_quantisation"] = np.abs(sens["encoder_quantisation"]) * u_ea
    random_u2 = sum(
        contributions[k] ** 2 for k in ("torque_noise", "pressure_noise", "encoder_quantisation")
    )
    # Residual: stated release transient, type A steady part from the quiet phases.
    w_s = window / fs
    creep = recording["creep"] if "creep" in recording else None
    u_fast, u_ring = residual.standard_uncertainty(t, mu, list(releases), w_s, creep)
    contributions["residual_release"] = np.hypot(u_fast, u_ring)
    steady, steady_note = _steady_residual(
        t, mu, random_u2, contributions["residual_release"], list(quiet), window
    )
    notes.append(steady_note)
    contributions["residual_steady"] = np.full(n, steady)
    correlation = np.zeros(n)
    if calibrated:
        c = np.stack([sens[k] for k in calibrated])
        full = np.einsum("in,ij,jn->n", c, covariance, c)
        correlation = full - np.sum(c**2 * np.diag(covariance)[:, None], axis=0)
    u2 = sum(v**2 for v in contributions.values()) + correlation
    order_names = [k for k in INPUT_NAMES if k in contributions]
    contributions = {k: contributions[k] for k in order_names}
    inputs = _input_table(
        order_names, u_sys, dist, basis, rig, sigma_t, sigma_p, sigma_c, q_unit, q_basis,
        p_basis, steady, residual,
    )  # fmt: skip
    model = {
        "pressure": pressure,
        "th": th,
        "u_torque_noise": u_et,
        "u_accel_noise": u_ea,
        "sigma_torque": sigma_t,
        "sigma_pressure": sigma_p,
        "sigma_counts": sigma_c,
        "u_sys": u_sys,
        "dist": dist,
        "params": {
            "area": area,
            "radius": radius,
            "j5": j5,
            "f_g": f_g,
            "r_b": r_b,
            "w_r": w_r,
            "h": arm.pivot_height,
            "l": arm.arm_length,
            "sign": arm.sign,
            "w_d": w_d,
        },
        "calibrated": calibrated,
        "covariance": covariance,
        "sensitivity": sens,
        "window": window,
        "u_release_fast": u_fast,
        "u_release_ring": u_ring,
    }
    return CoaUncertainty(
        time=t,
        value=mu,
        u=np.sqrt(np.maximum(u2, 0.0)),
        contributions=contributions,
        correlation=correlation,
        inputs=inputs,
        terms=terms,
        notes=notes,
        _model=model,
        _filters={"smooth": smooth, "acceleration": accel},
    )


def _speed_from_counts(recording, rig) -> bool:
    """Whether ``roller_speed`` is the encoder speed of ``roller_encoder_counts`` (gate 1)."""
    cpr = rig.sensors.encoder_counts_per_revolution
    speed = encoder_speed(recording["roller_encoder_counts"], recording.time, cpr)
    given = np.asarray(recording["roller_speed"], dtype=float)
    return bool(np.allclose(speed, given, rtol=1e-9, atol=1e-9 * max(1.0, np.max(np.abs(given)))))


def _steady_residual(t, mu, random_u2, release_u, quiet, window) -> tuple[float, str]:
    """Type A in-band residual [-]: scatter of μ_corr in quiet samples less the random part."""
    ok = np.zeros(t.size, dtype=bool)
    for start, end in quiet:
        ok |= (t >= start) & (t < end)
    ok[:window] = ok[t.size - window :] = False  # the ends of the recording
    ok &= release_u**2 < 0.01 * random_u2 + 1e-30  # the ringing has died out
    if ok.sum() < 2 * window:
        return 0.0, (
            "residual_steady: fewer than two correction windows of quiet samples (free rolling "
            "or rest with the release transient decayed): the in-band disturbances are not "
            "evaluated (term 0)"
        )
    resid = []
    for start, end in quiet:
        idx = np.flatnonzero(ok & (t >= start) & (t < end))
        if idx.size >= window:
            fit = np.polyval(np.polyfit(t[idx], mu[idx], 1), t[idx])
            resid.append(mu[idx] - fit)
    r = np.concatenate(resid) if resid else np.zeros(1)
    excess = float(np.mean(r**2) - np.mean(random_u2[ok]))
    value = math.sqrt(max(excess, 0.0))
    return value, (
        f"residual_steady: {value:.2g} (type A: scatter of the corrected CoA about a line in "
        f"{int(ok.sum())} quiet samples, {math.sqrt(float(np.mean(r**2))):.2g} RMS, less the "
        "random part in quadrature)"
    )


def _input_table(names, u_sys, dist, basis, rig, sigma_t, sigma_p, sigma_c, q_unit, q_basis,
                 p_basis, steady, residual) -> list[InputQuantity]:  # fmt: skip
    s, g, b = rig.sensors, rig.geometry, rig.bearing
    table = {
        "torque_class": ("δT", 0.0, "N.m", "torque_sensor_accuracy"),
        "pressure_class": ("δp", 0.0, "Pa", "pressure_sensor_accuracy"),
        "air_spring_area": ("A", s.air_spring_effective_area, "m^2", "air_spring_effective_area"),
        "roller_radius": ("r_r", g.roller_radius_x, "m", "geometry.roller_radius_x"),
        "roller_inertia": ("J5", rig.inertia.roller, "kg.m^2", "inertia.roller"),
        "bearing_loss": ("k_b", 1.0, "1", "bearing_loss_uncertainty"),
        "bearing_friction": ("f_g", b.friction_coefficient, "1", "bearing.friction_coefficient"),
        "bearing_radius": ("r_b", b.roller_bearing_radius, "m", "bearing.roller_bearing_radius"),
        "roller_weight": ("W_r", b.roller_subsystem_weight, "N", "bearing.roller_subsystem_weight"),
        "arm_pivot_height": ("h", rig.arm.pivot_height, "m", "arm.pivot_height"),
        "arm_length": ("l", rig.arm.arm_length, "m", "arm.arm_length"),
        "arm_dead_weight": ("W_d", rig.arm.dead_weight, "N", "arm.dead_weight"),
    }
    out = []
    for name in names:
        if name in table:
            symbol, estimate, unit, key = table[name]
            if not key.count("."):
                key = f"sensors.{key}"
            out.append(InputQuantity(name, symbol, "systematic", dist[name], estimate,
                                     u_sys[name], unit, basis[name], key))  # fmt: skip
        elif name == "torque_noise":
            out.append(InputQuantity(
                name, "e_T", "random", "normal", None, sigma_t, "N.m",
                "type A: white noise of the raw torque (MAD of second differences), through "
                "the correction's smoothing weights (‖h_i‖); lines above the pass band inflate "
                "it (conservative)"))  # fmt: skip
        elif name == "pressure_noise":
            out.append(InputQuantity(
                name, "e_p", "random", "normal", None, sigma_p, "Pa",
                f"type A: white noise of the {p_basis} (MAD of second differences); the load "
                "enters the correction unsmoothed"))  # fmt: skip
        elif name == "encoder_quantisation":
            out.append(InputQuantity(name, "e_α", "random", "normal", None, sigma_c, q_unit,
                                     q_basis))  # fmt: skip
        elif name == "residual_steady":
            out.append(InputQuantity(
                name, "e_res,s", "residual", "normal", 0.0, steady, "1",
                "type A: in-band disturbances (motor lines, rotation orders) and what else "
                "scatters the corrected CoA in quiet phases beyond the random inputs"))  # fmt: skip
        elif name == "residual_release":
            out.append(InputQuantity(
                name, "e_res,r", "residual", "normal (fast), arcsine (ring)", 0.0, None, "1",
                f"stated (type B, twin): fast {residual.fast:g}·H, ring {residual.ring:g}·H "
                f"decaying with {residual.ring_decay:g} s after each release of height H "
                "(CorrectionResidual)"))  # fmt: skip
    return out


def release_residual_from_truth(time, error, releases, coa, random_u, window_s: float) -> dict:
    """The :class:`CorrectionResidual` parameters from a synthetic test's error against truth.

    Parameters
    ----------
    time : ndarray
        [s].
    error : ndarray
        μ_corr − true contact CoA [-].
    releases : sequence of (float, float)
        Release start and end [s].
    coa : ndarray
        μ_corr [-] (for the heights H).
    random_u : ndarray
        The random part of u per sample [-], removed in quadrature.
    window_s : float
        Correction window [s].

    Returns
    -------
    dict
        ``fast`` [-] of H, ``ring`` [-] of H_r and ``ring_decay`` [s]: the largest relative RMS
        error over sub-spans of 0.15 window within the fast span, and a log-linear fit of the
        relative RMS error in 0.5 s bins after it (the ring's decay); H and H_r as in
        :class:`CorrectionResidual`.
    """
    t = np.asarray(time, dtype=float)
    fast, ring_t, ring_v = [], [], []
    for start, end in releases:
        span = (t >= start - window_s) & (t <= end + window_s)
        height = float(np.ptp(coa[span]))
        if height <= 0:
            continue
        excess = np.maximum(error**2 - random_u**2, 0.0) / height**2
        edges = np.arange(start - 0.25 * window_s, end + 0.5 * window_s, 0.15 * window_s)
        for a in edges:  # the largest RMS over sub-spans of 0.15 window (30 ms at 0.2 s)
            f = (t >= a) & (t < a + 0.15 * window_s)
            if np.any(f):
                fast.append(float(np.sqrt(np.mean(excess[f]))))
        ring_height = max(height, _ring_height(t, coa, start, end, window_s))
        excess_r = excess * (height / ring_height) ** 2
        for a in np.arange(end + 0.5 * window_s, end + 5.0, 0.5):
            m = (t >= a) & (t < a + 0.5)
            if np.any(m):
                ring_t.append(a + 0.25 - end)
                ring_v.append(float(np.sqrt(np.mean(excess_r[m]))))
    ok = np.asarray(ring_v) > 0
    slope, intercept = np.polyfit(np.asarray(ring_t)[ok], np.log(np.asarray(ring_v)[ok]), 1)
    return {
        "fast": float(np.max(fast)),
        "ring": float(np.exp(intercept)),
        "ring_decay": float(-1.0 / slope),
    }
