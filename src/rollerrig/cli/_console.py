"""What the commands print: two consoles with markup off, and one line per note, warning, error.

Text is printed literally (Rich markup off), so ``[kN]``, ``[channels.torque]`` or
``rollerrig[io]`` survive. Style a part with :class:`rich.text.Text`
(``Text.assemble(("bold part", "bold"), " plain part")``), never with ``[bold]`` markup.
"""

from __future__ import annotations

from rich.console import Console
from rich.text import Text

__all__ = [
    "console",
    "err_console",
    "note",
    "print_error",
    "print_recording_notes",
    "print_warning",
    "print_written",
]

console = Console(width=110, markup=False, highlight=False)
err_console = Console(stderr=True, markup=False, highlight=False, soft_wrap=True)


def note(text: str) -> None:
    """Print a yellow ``note:`` line (the text literally)."""
    console.print(Text.assemble(("note: ", "yellow"), str(text)), soft_wrap=True)


def print_warning(text: str) -> None:
    """Print a ``warning:`` line on stderr (a model used outside its domain, ...)."""
    err_console.print(Text.assemble(("warning: ", "bold yellow"), " ".join(str(text).split())))


def print_error(message: str) -> None:
    """Print one red ``error:`` line on stderr."""
    err_console.print(Text.assemble(("error: ", "bold red"), str(message)))


def print_written(paths) -> None:
    """One ``wrote <path>`` line per output file."""
    for path in paths:
        console.print(f"wrote {path}", soft_wrap=True)


def print_recording_notes(rec) -> None:
    """The reader's notes, interpolated NaN runs, gaps and injected lines, one line each."""
    from rollerrig.analysis.adhesion import recording_note_lines

    for line in recording_note_lines(rec):
        note(f"recording: {line}")
