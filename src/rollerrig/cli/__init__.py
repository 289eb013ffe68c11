"""The ``rollerrig`` command: the front door to the toolkit.

Units at this edge follow rig practice (kN, km/h, mm); everything inside is SI.

One module per concern:

- :mod:`~rollerrig.cli._boundary` — the error boundary around every command (one ``error:``
  line, exit 2; ``internal error``, exit 3; SIGTERM/SIGINT end a command cleanly; each
  ``DomainWarning`` printed once as a ``warning:`` line);
- :mod:`~rollerrig.cli._console` — what is printed (markup off: ``[kN]`` survives);
- :mod:`~rollerrig.cli._outputs` — :class:`staged_outputs` and :func:`command_outputs`: every
  file of a command or none, inside ``--out``, never over an input, one run at a time, with a
  manifest and the run's provenance;
- :mod:`~rollerrig.cli._options` — shared options and an enum for every choice;
- :mod:`~rollerrig.cli._inputs` — reading recordings (whole or streamed) and the truth;
- the commands: :mod:`~rollerrig.cli.contact`, :mod:`~rollerrig.cli.transfer`,
  :mod:`~rollerrig.cli.twin` (``simulate``,
  ``modes``), :mod:`~rollerrig.cli.studies` (``study run|show|list``),
  :mod:`~rollerrig.cli.frame`, :mod:`~rollerrig.cli.recordings` (``analyze``, ``spectrum``,
  ``filters``), :mod:`~rollerrig.cli.rigs` (``rig list``), :mod:`~rollerrig.cli.demo`.

Conventions for a command: raise :class:`UserError` (or a ``ParameterError``) for a bad option,
never ``try`` around the work; do the work inside ``with command_outputs(out, run=..., inputs=...)
as stage:`` writing every file into ``stage.path(name)`` / ``stage.dir``; print results and
``stage.written`` after the block.
"""

from __future__ import annotations

from typing import Annotated

import typer

from rollerrig.cli import calibrate as _calibrate
from rollerrig.cli import contact as _contact
from rollerrig.cli import demo as _demo
from rollerrig.cli import frame as _frame
from rollerrig.cli import recordings as _recordings
from rollerrig.cli import rigs as _rigs
from rollerrig.cli import studies as _studies
from rollerrig.cli import transfer as _transfer
from rollerrig.cli import twin as _twin
from rollerrig.cli._boundary import DEBUG_ENV, BoundaryGroup, UserError
from rollerrig.cli._console import console, err_console, note, set_quiet
from rollerrig.cli._outputs import MAX_OUTPUT_STEM, command_outputs, safe_file_name, staged_outputs

__all__ = [
    "COMMANDS",
    "MAX_OUTPUT_STEM",
    "UserError",
    "app",
    "command_outputs",
    "console",
    "err_console",
    "main",
    "note",
    "safe_file_name",
    "staged_outputs",
]

_SPECTRUM_IN_MEMORY = 1 << 22
"""Samples per channel up to which ``analyze``, ``spectrum`` and ``filters`` read a file whole
(4.2 M: 3.6 min at 19.2 kHz, 4.7 h at 250 Hz); longer files on one time base are streamed in
chunks (bounded memory). One threshold for the three commands (the name is historical); read
at each call (:func:`rollerrig.cli._inputs.in_memory_limit`), so tests may lower it."""


def _version_callback(value: bool) -> None:
    if value:
        from rollerrig import __version__

        console.print(f"rollerrig {__version__}")
        raise typer.Exit()


app = typer.Typer(
    name="rollerrig",
    help="Wheel-roller adhesion rig toolkit: contact mechanics, digital twin, measurements.",
    cls=BoundaryGroup,
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,  # help texts print literally: units such as [kN] survive
)


@app.callback()
def _root(
    version: Annotated[
        bool,
        typer.Option(
            "--version",
            help="Print the version and exit.",
            callback=_version_callback,
            is_eager=True,
        ),
    ] = False,
    debug: Annotated[
        bool,
        typer.Option(
            "--debug",
            help=f"Show the full traceback of an error (also: environment {DEBUG_ENV}=1).",
        ),
    ] = False,
    quiet: Annotated[
        bool,
        typer.Option(
            "--quiet",
            "-q",
            help="No progress lines or bars from any command (also each command's --quiet).",
        ),
    ] = False,
) -> None:
    """Wheel-roller adhesion rig toolkit."""
    set_quiet(quiet)  # every invocation starts from the option given (or not)


COMMANDS = (
    _contact.contact,
    _transfer.transfer,
    _twin.simulate,
    _twin.modes,
    _frame.frame,
    _recordings.analyze,
    _recordings.spectrum,
    _recordings.filters,
    _calibrate.calibrate,
    _demo.demo,
)
"""The commands, in the order ``rollerrig --help`` lists them."""

for _command in COMMANDS:
    app.command()(_command)
app.add_typer(_studies.study_app, name="study")
app.add_typer(_rigs.rig_app, name="rig")


def main() -> None:  # pragma: no cover - console entry point
    app()
