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
import os
from pathlib import Path

from rollerrig.recordings.recording import RecordingError, RecordingFileNotFound

__all__ = ["check_truth", "read_truth"]

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
    try:
        own = json.loads(stored["twin_provenance"])["rig"]["sha256"]
        given = json.loads(attrs["provenance"])["rig"]["sha256"]
        if own != given:
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
