"""The calibrated rig keys that are inputs of the corrected CoA: their values, standard errors
and covariance as ``calibration.json`` gives them (:func:`calibration_covariance`), for the law
of propagation of :mod:`rollerrig.estimation.uncertainty`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from rollerrig._validation import ParameterError

__all__ = ["MODEL_KEYS", "calibration_covariance"]


MODEL_KEYS = {
    "sensors.air_spring_effective_area": "air_spring_area",
    "geometry.roller_radius_x": "roller_radius",
    "inertia.roller": "roller_inertia",
    "bearing.friction_coefficient": "bearing_friction",
    "bearing.roller_bearing_radius": "bearing_radius",
    "bearing.roller_subsystem_weight": "roller_weight",
}
"""Calibrated rig keys that are inputs of the corrected CoA -> input name."""


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
        if key not in MODEL_KEYS and not key.startswith(("polach.", "fastsim.")):
            notes.append(f"{key}: calibrated, not an input of the corrected CoA (used in the rig)")
    return values, used, cov, names, notes
