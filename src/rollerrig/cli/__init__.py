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
  ``filters``), :mod:`~rollerrig.cli.rigs` (``rig list``, ``rig show``), :mod:`~rollerrig.cli.demo`;
  registered by name in :data:`COMMANDS`, each module imported only when its command runs or a
  help lists it (a new command: its function in a module, one line in :data:`COMMANDS`).

Conventions for a command: raise :class:`UserError` (or a ``ParameterError``) for a bad option,
never ``try`` around the work; do the work inside ``with command_outputs(out, run=..., inputs=...)
as stage:`` writing every file into ``stage.path(name)`` / ``stage.dir``; print results and
``stage.written`` after the block.
"""

from __future__ import annotations

import gc
import importlib
from collections.abc import Iterator, Mapping, MutableMapping
from typing import Annotated

import click
import typer
from typer.main import get_command_from_info, get_group_from_info
from typer.models import CommandInfo, TyperInfo

from rollerrig.cli._boundary import DEBUG_ENV, BoundaryGroup, UserError
from rollerrig.cli._console import console, err_console, note, set_quiet
from rollerrig.cli._outputs import MAX_OUTPUT_STEM, command_outputs, safe_file_name, staged_outputs

__all__ = [
    "COMMANDS",
    "MAX_OUTPUT_STEM",
    "LazyCommands",
    "UserError",
    "app",
    "command_outputs",
    "console",
    "err_console",
    "load_command",
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


COMMANDS: dict[str, str] = {
    "contact": "contact:contact",
    "transfer": "transfer:transfer",
    "simulate": "twin:simulate",
    "modes": "twin:modes",
    "frame": "frame:frame",
    "analyze": "recordings:analyze",
    "spectrum": "recordings:spectrum",
    "filters": "recordings:filters",
    "calibrate": "calibrate:calibrate",
    "demo": "demo:demo",
    "study": "studies:study_app",
    "rig": "rigs:rig_app",
}
"""The commands, in the order ``rollerrig --help`` lists them: name -> ``module:object`` in
:mod:`rollerrig.cli` (a command function, or a :class:`typer.Typer` of subcommands). A command's
module is imported when that command runs or a help lists it, never before: ``rollerrig
simulate`` does not pay for the imports of ``calibrate`` or ``study``."""


def load_command(name: str):
    """The function (or sub-:class:`typer.Typer`) of the command ``name`` (a key of
    :data:`COMMANDS`), importing its module.

    Examples
    --------
    >>> load_command("simulate").__module__
    'rollerrig.cli.twin'
    """
    module, attribute = COMMANDS[name].split(":")
    return getattr(importlib.import_module(f"rollerrig.cli.{module}"), attribute)


class LazyCommands(BoundaryGroup):
    """The root command: the error boundary (:class:`~rollerrig.cli._boundary.BoundaryGroup`)
    over the commands of :data:`COMMANDS`, each built from its module when it is first asked
    for (to run it, or to list it in a help), with the settings of :data:`app`. Every name is
    known before any is built, so a mistyped command is still answered with the close ones."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.commands = _CommandTable(self.commands)

    def list_commands(self, ctx: click.Context) -> list[str]:
        return list(self.commands)  # the names alone: nothing is imported to list them


class _CommandTable(MutableMapping):
    """Name -> click command: the commands of :data:`COMMANDS` built on first access."""

    def __init__(self, built: Mapping[str, click.Command]) -> None:
        self._built = dict(built)

    def __getitem__(self, name: str) -> click.Command:
        if name not in self._built:
            if name not in COMMANDS:
                raise KeyError(name)
            self._built[name] = _click_command(name, load_command(name))
        return self._built[name]

    def __iter__(self) -> Iterator[str]:
        return iter({**dict.fromkeys(COMMANDS), **dict.fromkeys(self._built)})

    def __len__(self) -> int:
        return len({*COMMANDS, *self._built})

    def __setitem__(self, name: str, command: click.Command) -> None:
        self._built[name] = command

    def __delitem__(self, name: str) -> None:
        raise TypeError(f"the command {name!r} cannot be removed")


def _click_command(name: str, target) -> click.Command:
    """The click command typer builds for ``target`` registered as ``app.command()(target)``
    or ``app.add_typer(target, name=name)`` would be (same options, help and settings)."""
    settings = {
        "pretty_exceptions_short": app.pretty_exceptions_short,
        "rich_markup_mode": app.rich_markup_mode,
    }
    if isinstance(target, typer.Typer):
        info = TyperInfo(target, name=name)
        return get_group_from_info(info, suggest_commands=app.suggest_commands, **settings)
    return get_command_from_info(CommandInfo(name=name, callback=target), **settings)


app = typer.Typer(
    name="rollerrig",
    help="Wheel-roller adhesion rig toolkit: contact mechanics, digital twin, measurements.",
    cls=LazyCommands,
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


def main() -> None:
    """The ``rollerrig`` console command: runs :data:`app`, then leaves the process's objects
    out of the interpreter's exit-time garbage collection.

    Why: while CPython tears its modules down at exit, it runs the cyclic garbage collector
    several times, and with numpy, scipy, numba and matplotlib loaded each pass visits every
    object they made: about half a second of a three-second ``rollerrig simulate``, spent
    after the last file was written. :func:`gc.freeze` moves every live object to the
    permanent generation, which those passes skip; the operating system takes the memory
    back at exit anyway. Only this console entry does it: a Python caller of :data:`app`
    (tests, notebooks) keeps its collector as it was.
    """
    try:
        app()
    finally:
        gc.freeze()
