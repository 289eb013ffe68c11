"""xarray's dask probes, deferred until dask is imported (the one-run path of ``simulate``).

xarray asks, for every variable it builds, whether the data is a dask array or collection: the
first question imports ``dask.array`` (:class:`xarray.namedarray.pycompat.DuckArrayModule`), the
second ``dask.base`` (:func:`xarray.namedarray.utils.is_dask_collection`), whenever dask is
installed (the studies extra installs it). A command that never makes a dask array pays for
them all the same (about 0.3 s of a 2 s ``rollerrig simulate``). :func:`dask_probes_deferred`
answers both questions without the import while dask is not imported: nothing can be a dask
array or collection before dask is imported, so the answers are the ones xarray would give;
once something imports dask, xarray's own answers come back.

It touches two private names of xarray; where they are not as expected it changes nothing (the
command is then slower, never wrong). ``tests/cli/test_lazy.py`` checks in a fresh process that
``rollerrig simulate`` imports neither dask nor distributed. The lasting fix is a twin that
builds its Dataset only when asked.
"""

from __future__ import annotations

import contextlib
import importlib
import sys
from collections.abc import Iterator
from typing import Any

__all__ = ["dask_probes_deferred"]


class _DaskModule:
    """What xarray's ``DuckArrayModule("dask")`` says, without importing dask before anything
    else has: no dask array type while ``dask.array`` is not imported."""

    @property
    def type(self) -> tuple[type, ...]:
        array = sys.modules.get("dask.array")
        return (array.Array,) if array is not None else ()

    def _real(self) -> Any:
        from xarray.namedarray.pycompat import DuckArrayModule

        return DuckArrayModule("dask")

    @property
    def module(self) -> Any:
        return self._real().module

    @property
    def version(self) -> Any:
        return self._real().version

    @property
    def available(self) -> bool:
        return self._real().available


@contextlib.contextmanager
def dask_probes_deferred() -> Iterator[None]:
    """Within the block, xarray's dask probes import nothing while dask is not imported.

    Examples
    --------
    >>> import sys, numpy as np, xarray as xr
    >>> with dask_probes_deferred():
    ...     ds = xr.Dataset({"x": ("t", np.zeros(3))})
    >>> float(ds["x"].sum())
    0.0
    """
    if "dask" in sys.modules:  # already paid for: xarray's own probes
        yield
        return
    try:
        pycompat = importlib.import_module("xarray.namedarray.pycompat")
        utils = importlib.import_module("xarray.namedarray.utils")
        cache = pycompat._cached_duck_array_modules
        probe = utils.is_dask_collection
    except (ImportError, AttributeError):  # another xarray: its probes as they are
        yield
        return
    if not isinstance(cache, dict) or "dask" in cache:
        yield
        return

    def is_dask_collection(x: object) -> bool:
        return "dask" in sys.modules and probe(x)

    module = _DaskModule()
    cache["dask"] = module
    utils.is_dask_collection = is_dask_collection
    try:
        yield
    finally:
        if cache.get("dask") is module:
            del cache["dask"]
        if utils.is_dask_collection is is_dask_collection:
            utils.is_dask_collection = probe
