"""The parameters of the contact-torque estimators: the process models, their default noises and
priors, when a time-varying gain counts as settled, and the values given checked (finite,
positive or non-negative, in SI units, the message naming the parameter and its unit).

Shared by the causal filter (:mod:`rollerrig.estimation.kalman`) and the smoothers
(:mod:`rollerrig.estimation.smoother`); how the defaults were chosen:
:mod:`rollerrig.estimation.estimator`.
"""

from __future__ import annotations

import math

from rollerrig._validation import ParameterError

__all__ = [
    "DEFAULT_PROCESS_NOISE",
    "DEFAULT_TORQUE_NOISE",
    "INITIAL_ACCELERATION_SD",
    "INITIAL_SPEED_SD",
    "MODELS",
]

MODELS = ("random_walk", "integrated_random_walk")
"""Process models of the contact torque: a random walk (default) or an integrated one."""

DEFAULT_PROCESS_NOISE = {"random_walk": 3e4, "integrated_random_walk": 1e7}
"""Default spectral density of the contact torque's process noise by model: random walk
[N².m²/s] (d increments of variance q·h per step h), integrated random walk [N².m²/s³]
(on the slope). Chosen on synthetic recordings (module docstring)."""

DEFAULT_TORQUE_NOISE = 1.0
"""Default standard deviation of the white noise of the torque sensor [N.m]: 0.03 % of the
default rig's 3000 N.m range, a strain-gauge torque flange's noise floor (the noise of
:class:`rollerrig.recordings.synthetic.DisturbanceModel`)."""

INITIAL_SPEED_SD = 1e3
"""Prior standard deviation of the roller speed at the first sample [rad/s] (unknown)."""

INITIAL_ACCELERATION_SD = 10.0
"""Prior standard deviation of the roller's acceleration at the first sample, for the smoother
[rad/s²] (a recording may start in a transient; the causal filter starts from the steady
state's uncertainty of the contact torque instead)."""

_GAIN_TOLERANCE = 1e-9  # a time-varying gain within this fraction of the steady one has settled
_MAX_SETTLING = 200_000  # samples of time-varying gain at most (they settle in far fewer)


def _check_model(model: str) -> str:
    if model not in MODELS:
        raise ParameterError(f"model must be one of {MODELS}, got {model!r}")
    return model


def _positive(name: str, value, unit: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a number [{unit}], got {value!r}") from None
    if not (math.isfinite(v) and v > 0.0):
        raise ParameterError(f"{name} must be finite and > 0 [{unit}], got {value!r}")
    return v


def _nonnegative(name: str, value, unit: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a number [{unit}], got {value!r}") from None
    if not (math.isfinite(v) and v >= 0.0):
        raise ParameterError(f"{name} must be finite and >= 0 [{unit}], got {value!r}")
    return v


def _roller_parameters(
    sample_rate,
    counts_per_rev,
    roller_inertia,
    bearing_friction,
    bearing_radius,
    roller_weight,
    roller_radius,
    regularisation_speed,
) -> dict:
    """The validated rate, encoder, roller and bearing parameters, by name, in SI units."""
    return {
        "sample_rate": _positive("sample_rate", sample_rate, "Hz"),
        "counts_per_rev": _positive("counts_per_rev", counts_per_rev, "1"),
        "roller_inertia": _positive("roller_inertia", roller_inertia, "kg.m^2"),
        "bearing_friction": _nonnegative("bearing_friction", bearing_friction, "1"),
        "bearing_radius": _nonnegative("bearing_radius", bearing_radius, "m"),
        "roller_weight": _nonnegative("roller_weight", roller_weight, "N"),
        "roller_radius": _positive("roller_radius", roller_radius, "m"),
        "regularisation_speed": _positive("regularisation_speed", regularisation_speed, "rad/s"),
    }
