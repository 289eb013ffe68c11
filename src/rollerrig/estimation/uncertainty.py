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
N_c), and these inputs (:data:`~rollerrig.estimation.gum_inputs.INPUT_NAMES`):

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
(``residual_release``, :class:`~rollerrig.estimation.release_residual.CorrectionResidual`,
stated from the twin). Residual terms are treated as correlated over one correction window.

Law of propagation (JCGM 100 §5.1-5.2): u²(μ) = Σ c_i² u²(x_i), with covariances between
calibrated parameters (§5.2.2); U = k u, k = 2. Monte Carlo (JCGM 101 §7): draws of every
input from its PDF through the full model; adaptive (§7.9) in runs of M = 10⁴ until twice the
standard deviation of the run means of y, u and the interval ends is below the numerical
tolerance δ of u (two significant digits, §7.9.2). Validation (JCGM 101 §8): the LPU interval
y ± U against the MC 95 % probabilistically symmetric interval, d_low and d_high ≤ δ. A
rectangular input that dominates makes the output flat-topped: then y ± 2u is wider than the
95 % interval (conservative) and the §8 check fails on the shape, not on the linearity, which
the agreement of u itself shows.

This module propagates (:func:`corrected_coa_uncertainty`); the inputs' names and table are in
:mod:`~rollerrig.estimation.gum_inputs`, the calibrated ones' covariance in
:mod:`~rollerrig.estimation.calibrated_inputs`, the stated release residual in
:mod:`~rollerrig.estimation.release_residual`, the result type in
:mod:`~rollerrig.estimation.coa_uncertainty` and the Monte Carlo in
:mod:`~rollerrig.estimation.montecarlo`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from rollerrig.estimation.calibrated_inputs import MODEL_KEYS, calibration_covariance
from rollerrig.estimation.choice import uniform_rate
from rollerrig.estimation.coa_uncertainty import COVERAGE_FACTOR, CoaUncertainty
from rollerrig.estimation.filterweights import (
    BandedFilter,
    after_encoder_speed,
    savitzky_golay_matrix,
)
from rollerrig.estimation.gum_inputs import INPUT_NAMES, InputQuantity, _input_table, noise_level
from rollerrig.estimation.montecarlo import (
    K95,
    MonteCarloResult,
    jcgm101_validation,
    monte_carlo,
    numerical_tolerance,
)
from rollerrig.estimation.release_residual import CorrectionResidual, release_residual_from_truth
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
        rig recorded them, ``air_spring_pressure`` [Pa] and ``roller_encoder_counts`` [-]), on
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
        ``calibration.json`` content
        (:func:`~rollerrig.estimation.calibrated_inputs.calibration_covariance`).
    residual : CorrectionResidual, optional
        The stated release residual; default
        :class:`~rollerrig.estimation.release_residual.CorrectionResidual` ().

    Returns
    -------
    CoaUncertainty
    """
    residual = residual or CorrectionResidual()
    t = np.asarray(recording.time, dtype=float)
    n = t.size
    fs = uniform_rate(recording, "the CoA uncertainty")  # a gap is refused, not taken for one step
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
