"""Preload of the local dask workers of a study (``LocalCluster(preload=[...])``).

A Ctrl-C in a terminal goes to every process of its group: the study's own process and each
worker process of its local cluster. The study's process stops the study and closes the
cluster, which ends the workers; a worker that takes the SIGINT itself only prints a
``KeyboardInterrupt`` traceback per process, and then logs the scheduler it can no longer
reach. So each worker takes a SIGINT (from the moment this preload runs) only as the sign to
silence its library loggers (:data:`rollerrig.studies.runner.QUIET_LOGGERS`), and is ended
by its nanny.
"""

from __future__ import annotations

import contextlib
import logging
import signal

__all__ = ["dask_setup"]


def dask_setup(worker) -> None:
    """Called by dask in each worker process as it starts: a SIGINT there silences the
    libraries' loggers and is otherwise ignored."""
    from rollerrig.studies.runner import QUIET_LOGGERS

    def quiet(signum, frame) -> None:
        for name in QUIET_LOGGERS:
            logging.getLogger(name).setLevel(logging.CRITICAL + 1)

    with contextlib.suppress(ValueError):  # not the main thread: leave it to the default
        signal.signal(signal.SIGINT, quiet)
