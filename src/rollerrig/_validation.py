"""Validation at the boundary: clear errors that name the parameter, its unit and allowed range.

Physics kernels never validate (they must stay cheap and compilable); the public functions that
wrap them call these helpers first.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "ParameterError",
    "require_finite",
    "require_in_range",
    "require_nonnegative",
    "require_positive",
]


class ParameterError(ValueError):
    """A parameter is non-physical: its message names the parameter and the allowed range."""


def _as_float_array(name: str, value) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{name} must be a number, got {value!r}") from exc
    return arr


def require_finite(name: str, value, unit: str = "") -> np.ndarray:
    """Return ``value`` as a float array, raising :class:`ParameterError` on NaN or inf."""
    arr = _as_float_array(name, value)
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"{name} must be finite{_unit(unit)}, got {_show(arr)}")
    return arr


def require_positive(name: str, value, unit: str = "") -> np.ndarray:
    """Return ``value`` as a float array, raising unless every element is finite and > 0."""
    arr = require_finite(name, value, unit)
    if np.any(arr <= 0.0):
        raise ParameterError(f"{name} must be > 0{_unit(unit)}, got {_show(arr)}")
    return arr


def require_nonnegative(name: str, value, unit: str = "") -> np.ndarray:
    """Return ``value`` as a float array, raising unless every element is finite and >= 0."""
    arr = require_finite(name, value, unit)
    if np.any(arr < 0.0):
        raise ParameterError(f"{name} must be >= 0{_unit(unit)}, got {_show(arr)}")
    return arr


def require_in_range(
    name: str,
    value,
    low: float,
    high: float,
    unit: str = "",
    *,
    low_inclusive: bool = False,
    high_inclusive: bool = False,
) -> np.ndarray:
    """Return ``value`` as a float array, raising unless every element lies in the interval.

    The message states the interval in standard notation, e.g. ``(0, 0.5)`` or ``(0, 1]``.
    """
    arr = require_finite(name, value, unit)
    above = arr >= low if low_inclusive else arr > low
    below = arr <= high if high_inclusive else arr < high
    if not np.all(above & below):
        interval = (
            f"{'[' if low_inclusive else '('}{low:g}, {high:g}{']' if high_inclusive else ')'}"
        )
        raise ParameterError(f"{name} must lie in {interval}{_unit(unit)}, got {_show(arr)}")
    return arr


def _unit(unit: str) -> str:
    return f" [{unit}]" if unit else ""


def _show(arr: np.ndarray) -> str:
    if arr.ndim == 0:
        return f"{float(arr):g}"
    bad = arr.ravel()
    return np.array2string(bad[:6], precision=4) + (" ..." if bad.size > 6 else "")
