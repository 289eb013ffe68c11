"""Optional packages and the extra that installs each: the one table, and the one error.

rollerrig's core install (numpy, scipy, matplotlib, pydantic, typer, rich) computes contact
mechanics and the rig's modes. The other jobs need optional packages, installed by extras named
after the job (``pyproject.toml``):

- ``twin``: simulate the rig (``simulate``, ``modes``, the demo) and write its results;
- ``io``: read and write what acquisition software writes (TDMS, MDF4, MATLAB v7.3, CSV,
  Parquet, Excel .xlsx) and the NetCDF/JSON results of ``analyze``, ``spectrum`` and ``filters``;
- ``frame``: the static and modal FE check of the rig's frame (``frame``);
- ``studies``: run studies at scale (``study run``) on dask, with the resumable store and
  sensitivity indices;
- ``all``: all of them.

:func:`require` imports an optional module or raises :class:`MissingExtraError` naming the
extra; :func:`missing_extra_message` turns any ``ImportError`` of an optional module into the
same sentence (the command line's error boundary uses it).

Examples
--------
>>> extra_for("nptdms"), extra_for("xarray", job="twin"), extra_for("xarray", job="io")
('io', 'twin', 'io')
"""

from __future__ import annotations

import importlib
from types import ModuleType

__all__ = [
    "DISTRIBUTIONS",
    "EXTRAS",
    "JOBS",
    "MissingExtraError",
    "extra_for",
    "missing_extra_message",
    "require",
]

EXTRAS: dict[str, frozenset[str]] = {
    "twin": frozenset({"numba", "xarray", "pandas", "h5netcdf", "h5py", "threadpoolctl"}),
    "io": frozenset(
        {"nptdms", "asammdf", "h5py", "pandas", "pyarrow", "xarray", "h5netcdf", "openpyxl"}
    ),
    "studies": frozenset(
        {
            "numba",
            "xarray",
            "pandas",
            "h5netcdf",
            "h5py",
            "threadpoolctl",
            "dask",
            "distributed",
            "SALib",
            "zarr",
        }
    ),
    "frame": frozenset({"Pynite"}),
}
"""Extra -> the optional modules it installs (import names; the same as the distribution
names except those in :data:`DISTRIBUTIONS`). Must agree with
``[project.optional-dependencies]`` of ``pyproject.toml`` (a test checks it); ``all`` installs
every extra."""

DISTRIBUTIONS: dict[str, str] = {"Pynite": "PyNiteFEA"}
"""Import name -> distribution name, where they differ."""

JOBS: dict[str, str] = {
    "simulate": "twin",
    "study": "studies",
    "frame": "frame",
    "modes": "twin",
    "analyze": "io",
    "spectrum": "io",
    "filters": "io",
    "calibrate": "all",
    "demo": "all",
}
"""Command -> the extra its job needs (a module in several extras is named by the job's)."""


class MissingExtraError(ImportError):
    """An optional package is not installed; the message names the extra that installs it.

    Attributes: ``name`` (the module), ``extra`` (the extra named), ``purpose`` (what needs
    it) and ``chosen`` (False when the extra was ``all`` only because several extras hold
    the module: a command then names its own job's extra instead).
    """

    def __init__(self, module: str, extra: str, purpose: str = "", *, chosen: bool = True):
        super().__init__(_sentence(module, extra, purpose), name=module)
        self.extra, self.purpose, self.chosen = extra, purpose, chosen


def extra_for(module: str, job: str | None = None) -> str | None:
    """The extra that installs ``module`` (its top-level name), or None if no extra does.

    ``job``: a command name (see :data:`JOBS`) or an extra; among several extras holding the
    module, the job's is named, else ``all``.
    """
    top = module.split(".")[0]
    holders = sorted(extra for extra, modules in EXTRAS.items() if top in modules)
    if not holders:
        return None
    wanted = JOBS.get(job or "", job)
    if wanted in holders or (wanted == "all" and holders):
        return wanted
    return holders[0] if len(holders) == 1 else "all"


def _sentence(module: str, extra: str, purpose: str) -> str:
    what = purpose or "this"
    return f"{what} needs {module}: pip install 'rollerrig[{extra}]'"


def require(module: str, extra: str | None = None, purpose: str = "") -> ModuleType:
    """Import ``module``, or raise :class:`MissingExtraError` naming the extra to install.

    Parameters
    ----------
    module : str
        Module to import, e.g. ``"nptdms"`` or ``"pyarrow.parquet"``.
    extra : str, optional
        The extra to name; default: the one :data:`EXTRAS` lists for the module.
    purpose : str
        What needs it, as the start of the sentence: ``"reading TDMS files"`` gives
        "reading TDMS files needs nptdms: pip install 'rollerrig[io]'".

    Examples
    --------
    >>> require("json").__name__
    'json'
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        top = (getattr(exc, "name", None) or module).split(".")[0]
        named = extra or extra_for(top) or "all"
        raise MissingExtraError(top, named, purpose, chosen=extra is not None) from exc


def missing_extra_message(exc: ImportError, job: str | None = None) -> str | None:
    """The sentence for an ``ImportError`` of an optional module, or None for another one.

    ``job``: the command that failed (``"simulate"``); the sentence starts with
    ``rollerrig <job>`` and names the job's extra. A :class:`MissingExtraError` keeps its own
    sentence, with the job's extra where it named ``all`` only for want of a job.
    """
    if isinstance(exc, MissingExtraError):
        if exc.chosen or exc.extra != "all" or not job:
            return str(exc)
        return _sentence(exc.name, extra_for(exc.name, job) or "all", exc.purpose)
    module = (getattr(exc, "name", None) or "").split(".")[0]
    extra = extra_for(module, job) if module else None
    if extra is None:
        return None
    return _sentence(module, extra, f"rollerrig {job}" if job else "")
