"""Preload of the local dask workers of a study (``LocalCluster(preload=[...])``).

A Ctrl-C in a terminal goes to every process of its group: the study's own process and each
worker process of its local cluster. The study's process stops the study and closes the
cluster, which ends the workers; a worker that takes the SIGINT itself only prints a
``KeyboardInterrupt`` traceback per process. So each worker ignores SIGINT (from the moment
this preload runs) and is ended by its nanny.
"""

from __future__ import annotations

import contextlib
import signal

__all__ = ["dask_setup"]


def dask_setup(worker) -> None:
    """Called by dask in each worker process as it starts: ignore SIGINT there."""
    with contextlib.suppress(ValueError):  # not the main thread: leave it to the default
        signal.signal(signal.SIGINT, signal.SIG_IGN)
