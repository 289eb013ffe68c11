"""The twin's truth of a synthetic recording: read and checked once, for the CLI and the API.

A truth is a NetCDF file (``*-truth.nc``, written beside a synthetic recording) or its
:class:`xarray.Dataset` with the true contact CoA ``coa`` over ``time``; the analysis reports the
error of the rig's and the corrected CoA against it. One written by another model serves: it
needs only those two. An analysis' own NetCDF has a ``coa`` too (the measured one): taken as the
truth it gave "truth errors" of the analysis against itself, so what marks an analysis is
refused.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Iterable, Mapping
from pathlib import Path

from rollerrig._validation import show_value
from rollerrig.output.jsonfile import SIGNIFICANT_DIGITS
from rollerrig.recordings.recording import RecordingError, RecordingFileNotFound

__all__ = ["check_truth", "read_truth", "recorded_rig", "rig_mismatch"]

_REMEDY = "give the *-truth.nc written beside the synthetic recording"


def check_truth(ds, source: str = "truth"):
    """``ds`` if it is usable as the truth of an analysis; a :class:`RecordingError` naming
    ``source`` and what is wrong otherwise.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> ds = xr.Dataset({"coa": ("time", np.zeros(3))}, coords={"time": np.arange(3.0)})
    >>> check_truth(ds) is ds
    True
    >>> check_truth(ds.rename({"coa": "mu"}))
    Traceback (most recent call last):
    ...
    rollerrig.recordings.recording.RecordingError: truth: a dataset without the variable 'coa' (the true contact CoA); give the *-truth.nc written beside the synthetic recording
    """  # noqa: E501
    if not (hasattr(ds, "attrs") and hasattr(ds, "data_vars")):
        raise RecordingError(
            f"{source}: must be an xarray.Dataset or the path of a NetCDF file, got "
            f"{type(ds).__name__}"
        )
    if "coa" not in ds or "time" not in ds:
        what = "'coa' (the true contact CoA)" if "coa" not in ds else "'time'"
        raise RecordingError(f"{source}: a dataset without the variable {what}; {_REMEDY}")
    if "coa_corrected" in ds or "analysis_notes" in ds.attrs:
        raise RecordingError(
            f"{source}: an analysis' output (its 'coa' is the measured CoA, not the "
            f"contact's); {_REMEDY}, or a NetCDF of the true contact CoA 'coa' over 'time'"
        )
    return ds


def truth_mismatch(recording_metadata: dict, truth) -> str | None:
    """Why ``truth`` is not the twin's truth of the recording whose metadata is
    ``recording_metadata`` (a synthetic recording stores the twin's rig, its hash and the
    noise seed it was made with), or None where nothing says so.

    ``analyze --truth`` with the truth of another run (the demo's perturbed rig beside its
    unperturbed recording) had compared the analysis with that run's CoA without a word.
    """
    stored = recording_metadata.get("stored_metadata") or {}
    attrs = getattr(truth, "attrs", {}) or {}
    found = []
    own = (recorded_rig(recording_metadata) or {}).get("sha256")
    try:
        given = json.loads(attrs["provenance"])["rig"]["sha256"]
        if own is not None and own != given:
            found.append(f"the rig (sha256 {given[:12]}… against the recording's {own[:12]}…)")
    except (KeyError, TypeError, ValueError):
        pass
    seed, given_seed = stored.get("seed"), attrs.get("synthetic_seed")
    if seed is not None and given_seed is not None and str(seed) != str(given_seed):
        found.append(f"the noise seed ({given_seed} against the recording's {seed})")
    experiment, given_exp = stored.get("experiment"), attrs.get("experiment")
    if isinstance(experiment, dict):
        experiment = experiment.get("name")
    if experiment and given_exp and str(experiment) not in str(given_exp):
        found.append(f"the experiment ({given_exp!r} against {experiment!r})")
    if not found:
        return None
    return (
        "the truth given is not this recording's: it differs in "
        + " and ".join(found)
        + "; its comparisons (the *_vs_true figures, the truth's coverage) are against another "
        "run; give the *-truth.nc written beside this recording"
    )


_SAME_RTOL = 10.0 ** (1 - SIGNIFICANT_DIGITS)
"""Relative tolerance of "the same value" between the rig a recording stores and the rig in use
[-]: a file keeps 12 significant digits (1256.6370614359173 is read back as 1256.63706144)."""

_FIRST_KEYS = (
    "geometry.roller_radius_x",
    "geometry.wheel_radius_x",
    "sensors.air_spring_effective_area",
    "sensors.encoder_pulses_per_revolution",
    "sensors.encoder_quadrature_factor",
    "inertia.roller",
)
"""The keys the CoA, the creep and the normal load are derived with: named first when the rigs
differ in them."""

_SHOWN_KEYS = 3
"""Most differing keys a rig mismatch names (then "and N more")."""


def _json_or_dict(raw) -> dict | None:
    if isinstance(raw, Mapping):
        return dict(raw)
    if isinstance(raw, str):
        try:
            value = json.loads(raw)
        except ValueError:
            return None
        return value if isinstance(value, dict) else None
    return None


def _flat_values(rig: Mapping) -> dict:
    """``{section.key: value}`` of a rig dict's sections outside ``[meta]``."""
    return {
        f"{section}.{key}": value
        for section, values in rig.items()
        if section != "meta" and isinstance(values, Mapping)
        for key, value in values.items()
    }


def recorded_rig(recording_metadata: Mapping) -> dict | None:
    """The rig a recording states it was made on, or None where it states none.

    A synthetic recording stores the twin's provenance (``twin_provenance``: the rig's name,
    :func:`rollerrig.output.rig_sha256` and its parameters) and the rig's parameters
    (``rig``); after a round trip through a file they are in ``stored_metadata``. A recording
    may also state ``rig`` as ``{"name", "sha256"}``.

    Returns
    -------
    dict or None
        ``{"name": str | None, "sha256": str | None, "values": {dotted key: value} | None}``.

    Examples
    --------
    >>> recorded_rig({"rig": {"name": "r", "sha256": "ab"}})
    {'name': 'r', 'sha256': 'ab', 'values': None}
    >>> recorded_rig({}) is None
    True
    """
    name = sha = values = None
    stored = recording_metadata.get("stored_metadata")
    holders = [recording_metadata] + ([stored] if isinstance(stored, Mapping) else [])
    for holder in holders:
        prov = _json_or_dict(holder.get("twin_provenance")) or {}
        record = prov.get("rig") if isinstance(prov.get("rig"), Mapping) else {}
        rig = holder.get("rig") if isinstance(holder.get("rig"), Mapping) else {}
        full = prov.get("rig_parameters") or next(
            (r for r in (record, rig) if "geometry" in r), None
        )  # a provenance written before 0.1.0 keeps the parameters as its "rig"
        sha = sha or record.get("sha256") or rig.get("sha256")
        name = name or record.get("name") or rig.get("name")
        if isinstance(full, Mapping):
            name = name or (full.get("meta") or {}).get("name")
            values = values or _flat_values(full)
    if not (name or sha or values):
        return None
    return {
        "name": None if name is None else str(name),
        "sha256": None if sha is None else str(sha),
        "values": values or None,
    }


def _same(a, b) -> bool:
    if isinstance(a, list | tuple) and isinstance(b, list | tuple):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    numbers = (int, float)
    if isinstance(a, numbers) and isinstance(b, numbers) and not isinstance(a, bool):
        return math.isclose(float(a), float(b), rel_tol=_SAME_RTOL, abs_tol=0.0)
    return a == b


def _shown(value) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    return show_value(value)


def rig_mismatch(recording_metadata: Mapping, rig, ignore: Iterable[str] = ()) -> str | None:
    """Why ``rig`` is not the rig the recording states it was made on (:func:`recorded_rig`),
    naming both rigs, or None where they agree or the recording states no rig.

    Compared by their values where the recording stores them (the keys in ``ignore``, such as
    those a calibration replaces, left out; a renamed copy of the same values is the same rig),
    else by :func:`rollerrig.output.rig_sha256`, else by name. Analysed with another rig's
    radii, air-spring area and encoders, a recording had given a hold's CoA of 2.37 without a
    word.

    Examples
    --------
    >>> from rollerrig.rig.parameters import default_rig
    >>> rig_mismatch({"rig": {"name": "other-rig"}}, default_rig())[:40]
    'the recording states it was made on rig '
    """
    from rollerrig.output import rig_sha256
    from rollerrig.rig.parameters import rig_values

    there = recorded_rig(recording_metadata)
    if there is None:
        return None
    here_sha = rig_sha256(rig)
    if there["sha256"] is not None and there["sha256"] == here_sha:
        return None
    what = ""
    if there["values"] is not None:
        skip = set(ignore)
        here_values = rig_values(rig)
        differ = [
            k
            for k, v in there["values"].items()
            if k not in skip and k in here_values and not _same(v, here_values[k])
        ]
        if not differ:
            return None
        differ.sort(key=lambda k: _FIRST_KEYS.index(k) if k in _FIRST_KEYS else len(_FIRST_KEYS))
        shown = ", ".join(
            f"{k} ({_shown(there['values'][k])} there, {_shown(here_values[k])} here)"
            for k in differ[:_SHOWN_KEYS]
        )
        more = len(differ) - _SHOWN_KEYS
        what = f": they differ in {shown}" + (f" and {more} more key(s)" if more > 0 else "")
    elif there["sha256"] is None and there["name"] == rig.meta.name:
        return None  # the same name and nothing else to compare
    there_sha = "" if there["sha256"] is None else f" (sha256 {there['sha256'][:12]}…)"
    return (
        f"the recording states it was made on rig {there['name'] or '(unnamed)'!r}"
        f"{there_sha}, the analysis uses rig {rig.meta.name!r} (sha256 {here_sha[:12]}…){what}; "
        "the creep, the normal load and the CoA are derived with the rig in use: analyse with "
        "the rig the recording was made on (--rig), unless the change is meant"
    )


def read_truth(path: str | os.PathLike, source: str | None = None):
    """The truth in the NetCDF file ``path``, checked (:func:`check_truth`).

    Parameters
    ----------
    path : path
        The ``*-truth.nc`` file.
    source : str, optional
        How errors name the file (default: the path as given).

    Raises
    ------
    RecordingFileNotFound
        No such file (also a :class:`FileNotFoundError`).
    RecordingError
        Not a NetCDF file, or not a truth (:func:`check_truth`).
    """
    import h5netcdf  # noqa: F401  (missing: the boundary names the extra, not "not NetCDF")
    import xarray as xr

    path = Path(path)
    source = str(path) if source is None else source
    if not path.is_file():
        raise RecordingFileNotFound(f"{source}: truth file not found")
    try:
        ds = xr.load_dataset(path, engine="h5netcdf")
    except Exception as exc:  # any failure of the NetCDF reader: not a usable truth file
        raise RecordingError(
            f"{source}: not a NetCDF file ({type(exc).__name__}: "
            f"{' '.join(str(exc).split())[:200]}); {_REMEDY}"
        ) from None
    ds.encoding.setdefault("source", str(path))
    return check_truth(ds, source)
