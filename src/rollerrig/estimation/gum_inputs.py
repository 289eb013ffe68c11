"""The inputs of the corrected CoA's measurement model: their names, their table and the type A
noise level.

Each input (:data:`INPUT_NAMES`) enters the law of propagation of
:mod:`rollerrig.estimation.uncertainty` with its estimate, standard uncertainty, PDF and basis
(:class:`InputQuantity`); the random ones take their level from the recording
(:func:`noise_level`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["INPUT_NAMES", "InputQuantity", "noise_level"]


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


def _input_table(names, u_sys, dist, basis, rig, sigma_t, sigma_p, sigma_c, q_unit, q_basis,
                 p_basis, steady, residual) -> list[InputQuantity]:  # fmt: skip
    """The budget's inputs ``names`` as :class:`InputQuantity` rows, in that order: the
    systematic ones from the rig (``u_sys``, ``dist``, ``basis``), the random ones from their
    type A levels, the residuals from the quiet phases and ``residual``."""
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
