"""The ``rollerrig`` console script's entry: Ctrl-C from the first moment.

The command's modules (typer, click, rich, numpy) take about 0.2 s to import, before the
command's own signal handling (:mod:`rollerrig.cli._boundary`) is in place; a Ctrl-C in that
time printed a ``KeyboardInterrupt`` traceback through the import machinery. Here, importing
only the standard library, SIGINT ends the process at once with exit code 130 (128 + SIGINT)
until the command takes over.
"""

from __future__ import annotations

import signal
import sys


def _interrupted(signum, frame) -> None:
    sys.stderr.write("interrupted\n")
    raise SystemExit(128 + signum)


def main() -> None:
    """Run the ``rollerrig`` command (:func:`rollerrig.cli.main`)."""
    try:
        previous = signal.signal(signal.SIGINT, _interrupted)
    except ValueError:  # not the main thread: nothing to guard
        previous = None
    try:
        from rollerrig.cli import main as command
    finally:
        if previous is not None:
            signal.signal(signal.SIGINT, previous)
    command()
