"""The inputs of the contact-torque estimators: the sampled torque, encoder counts and normal
load checked (numbers, 1-D, finite, one per sample, the load > 0), and the roller bearing's loss
torque R05 that joins the shaft torque T56 as the roller's input."""

from __future__ import annotations

import numpy as np

from rollerrig.recordings.recording import RecordingError

__all__: list[str] = []


def _bearing(load, speed, friction, radius, weight, w_reg):
    return friction * radius * (weight + load) * np.tanh(speed / w_reg)


def _array(name: str, value, unit: str, what: str) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise RecordingError(f"{name} must be numbers [{unit}] ({what})") from None
    if arr.ndim > 1:
        raise RecordingError(f"{name} must be 1-D [{unit}] ({what}), got shape {arr.shape}")
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size:
        raise RecordingError(
            f"{name} has {bad.size} NaN/inf sample(s), the first at index {bad[0]} [{unit}] "
            f"({what}); the estimator needs finite samples: fill or cut the gaps first "
            "(read_recording(..., lenient=True) interpolates short ones)"
        )
    return arr


def _inputs(torque, roller_counts, normal_load):
    """The validated sample arrays (T56, counts, load per sample) of the batch functions."""
    t56 = _array("torque", torque, "N.m", "roller-shaft torque T56")
    c = _array("roller_counts", roller_counts, "1", "cumulative roller encoder counts")
    n_load = _array("normal_load", normal_load, "N", "normal load")
    if t56.ndim == 0:
        raise RecordingError("torque must be an array of samples [N.m], got a single number")
    n = t56.size
    if n == 0:
        raise RecordingError("torque has no samples: the estimator needs at least one")
    if c.shape != t56.shape:
        raise RecordingError(
            f"roller_counts has {c.size} samples and torque {n}: give both on the same "
            "time axis (same length)"
        )
    if n_load.ndim == 0:
        n_load = np.full(n, float(n_load))
    elif n_load.shape != t56.shape:
        raise RecordingError(
            f"normal_load has {n_load.size} samples and torque {n}: give one load per sample "
            "or a single number"
        )
    if np.any(n_load <= 0.0):
        i = int(np.flatnonzero(n_load <= 0.0)[0])
        raise RecordingError(
            f"normal_load must be > 0 [N] at every sample (CoA = F_x r_r/(r_r N)); sample {i} "
            f"is {n_load[i]:g} N: cut the unloaded part first"
        )
    return t56, c, n_load
