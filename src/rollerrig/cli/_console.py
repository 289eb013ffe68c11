"""What the commands print: two consoles with markup off, and one line per note, warning, error.

Text is printed literally (Rich markup off), so ``[kN]``, ``[channels.torque]`` or
``rollerrig[io]`` survive. Style a part with :class:`rich.text.Text`
(``Text.assemble(("bold part", "bold"), " plain part")``), never with ``[bold]`` markup.

Width: 110 columns for tables. Text lines are word-wrapped at that width on a terminal only;
piped or in a notebook (stdout not a terminal) a line is printed whole, never broken (the
reader's pager or editor wraps it, and a number is never split from its sign or its unit), as
the error console always does. Tables keep their layout either way.

Progress of a long command: one helper for every command, :func:`progress` (a bar with a known
total: ``bar.add_task(...)``, ``bar.update(task, completed=..., info=...)``) or :func:`steps`
(what runs now: ``say("fitting the Polach law")``). On a terminal a live bar or status; piped
or in a notebook (stdout not a terminal) plain lines, never a redrawn bar: one per step, and
for a bar one at each tenth of the way or every :data:`LINE_EVERY_S` seconds; nothing with
``--quiet`` (:func:`set_quiet`; the option :data:`QuietOption`).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Annotated

import typer
from rich.console import Console
from rich.text import Text

__all__ = [
    "LINE_EVERY_S",
    "NOTE_MAX",
    "WIDTH",
    "QuietOption",
    "console",
    "err_console",
    "is_quiet",
    "note",
    "print_error",
    "print_recording_notes",
    "print_removed",
    "print_warning",
    "print_written",
    "progress",
    "set_quiet",
    "short_note",
    "steps",
]

WIDTH = 110
"""Width of the output [characters]: tables are laid out in it; text is word-wrapped at it on a
terminal only."""


class _Console(Console):
    """A :class:`rich.console.Console` whose text is never wrapped when it does not print to a
    terminal: its soft wrap (no word wrapping, no cropping) is on whenever its stream is not a
    TTY, decided at each print (typer's CliRunner and pipes swap the stream). The stream itself
    decides, not ``FORCE_COLOR``/``TTY_COMPATIBLE``: a CI log with colours forced is still a
    pipe that must not get lines broken at 110 characters."""

    @property
    def soft_wrap(self) -> bool:
        if self._soft_wrap_always:
            return True
        isatty = getattr(self.file, "isatty", None)
        try:
            return not (isatty is not None and isatty())
        except ValueError:  # a closed stream
            return True

    @soft_wrap.setter
    def soft_wrap(self, value: bool) -> None:
        self._soft_wrap_always = bool(value)


console = _Console(width=WIDTH, markup=False, highlight=False)
err_console = _Console(stderr=True, markup=False, highlight=False, soft_wrap=True)


NOTE_MAX = 300
"""Longest note on the console [characters] where a written file keeps the note in full."""


def short_note(text: str, full_in: str, limit: int = NOTE_MAX) -> str:
    """``text`` cut to at most about ``limit`` characters for the console, with a pointer to
    where it is kept in full: the finding and its first numbers (the text up to its last
    ``; `` that fits (else ``, ``), open brackets closed), then ``… (in full: <full_in>)``. A
    text that fits is returned as it is.

    Examples
    --------
    >>> short_note("fit: poorly determined: a (x 2; y 3); b 4" * 3, "r.json", limit=60)
    'fit: poorly determined: a (x 2; y 3) … (in full: r.json)'
    """
    text = " ".join(str(text).split())
    if len(text) <= limit:
        return text
    more = f" … (in full: {full_in})"
    room = max(limit - len(more), 40)
    cut = text.rfind("; ", 0, room)  # a clause; a list's item only where none is near
    if cut < room // 2:
        cut = max(cut, text.rfind(", ", 0, room))
    if cut < 0:  # no clause ends in the room: at the last word
        cut = text.rfind(" ", 0, room)
        cut = room if cut < 0 else cut
    head = text[:cut].rstrip(" ;,:")
    depth = 0
    for ch in head:
        depth = depth + 1 if ch == "(" else max(depth - 1, 0) if ch == ")" else depth
    return head + ")" * depth + more


def note(text: str, full_in: str | None = None) -> None:
    """Print a yellow ``note:`` line (the text literally); a long one cut to :data:`NOTE_MAX`
    characters with a pointer where a written file keeps it whole (``full_in``:
    ``"<path>, 'notes'"``)."""
    if full_in is not None:
        text = short_note(text, full_in)
    console.print(Text.assemble(("note: ", "yellow"), str(text)), soft_wrap=True)


def print_warning(text: str) -> None:
    """Print a ``warning:`` line on stderr (a model used outside its domain, ...)."""
    err_console.print(Text.assemble(("warning: ", "bold yellow"), " ".join(str(text).split())))


def print_error(message: str) -> None:
    """Print one red ``error:`` line on stderr."""
    err_console.print(Text.assemble(("error: ", "bold red"), str(message)))


_REPLACED: set[str] = set()


def mark_replaced(paths) -> None:
    """Record that a run of this process replaced these files, already in ``--out`` (an
    earlier run's of the same name: several commands name their outputs by the command
    alone, ``contact-report.json``), for :func:`print_written` to say so."""
    _REPLACED.update(str(p) for p in paths)


def print_written(paths) -> None:
    """One ``wrote <path>`` line per output file, saying where it replaced an earlier run's
    file of that name."""
    for path in paths:
        again = " (replaced an earlier run's)" if str(path) in _REPLACED else ""
        console.print(f"wrote {path}{again}", soft_wrap=True)


def print_removed(paths, kept=()) -> None:
    """One ``removed <path>`` line per earlier run's output that the run removed, as not of
    its results (:meth:`rollerrig.cli._outputs.staged_outputs.supersede`), and a note per such
    file it kept (changed since, or not that run's)."""
    for path in paths:
        console.print(f"removed {path} (an earlier run's, not of these results)", soft_wrap=True)
    for path in kept:
        note(f"{path} is not of these results (kept: changed since it was written, or not "
             "this command's file)")  # fmt: skip


def print_recording_notes(rec) -> None:
    """The reader's notes, interpolated NaN runs, gaps and injected lines, one line each."""
    from rollerrig.analysis.adhesion import recording_note_lines

    for line in recording_note_lines(rec):
        note(f"recording: {line}")


# ------------------------------------------------------------------------------- progress

LINE_EVERY_S = 5.0
"""Least time between two progress lines of a bar when stdout is not a terminal [s] (a line
also at each tenth of the way)."""

_quiet = False


def set_quiet(value: bool) -> None:
    """Progress shown (False) or not (True); the root command resets it at every invocation."""
    global _quiet
    _quiet = bool(value)


def is_quiet() -> bool:
    """Whether ``--quiet`` was given."""
    return _quiet


def _quiet_callback(value: bool) -> bool:
    if value:
        set_quiet(True)
    return value


QuietOption = Annotated[
    bool,
    typer.Option(
        "--quiet",
        "-q",
        help="No progress lines or bars (results, notes, warnings and errors still print).",
        callback=_quiet_callback,
    ),
]
"""``--quiet``: no progress (the option sets :func:`set_quiet`; the command needs no code)."""


@dataclass
class _Task:
    description: str
    total: float | None
    completed: float = 0.0
    info: str = ""
    started: float = 0.0
    shown_at: float = 0.0
    shown_tenth: int = -1
    shown_info: str | None = None


class ProgressLines:
    """The part of :class:`rich.progress.Progress` the commands use (``add_task``, ``update``,
    ``tasks``), printing plain lines: for stdout that is not a terminal, or nothing when
    ``silent``."""

    def __init__(self, out: Console, silent: bool = False, every_s: float = LINE_EVERY_S):
        self.out, self.silent, self.every_s = out, silent, every_s
        self.tasks: list[_Task] = []

    def __enter__(self) -> ProgressLines:
        return self

    def __exit__(self, *exc) -> None:
        return None

    def add_task(self, description: str, total: float | None = None, info: str = "", **_) -> int:
        now = time.monotonic()
        self.tasks.append(_Task(description, total, 0.0, info, now, now))
        self._line(self.tasks[-1], force=True)
        return len(self.tasks) - 1

    def update(self, task_id: int, *, completed=None, total=None, info=None, advance=None, **_):
        task = self.tasks[task_id]
        if total is not None:
            task.total = total
        if completed is not None:
            task.completed = float(completed)
        if advance is not None:
            task.completed += float(advance)
        if info is not None:
            task.info = str(info)
        self._line(task)

    def _line(self, task: _Task, force: bool = False) -> None:
        now = time.monotonic()
        done = task.total is not None and task.completed >= task.total > 0
        if task.total:
            tenth = min(int(10 * task.completed / task.total), 10)
            due = tenth > task.shown_tenth or now - task.shown_at >= self.every_s
        else:
            tenth = -1
            due = task.info != task.shown_info  # a step: one line per step
        if not (force or due or (done and task.shown_tenth < 10)):
            return
        task.shown_at, task.shown_tenth, task.shown_info = now, tenth, task.info
        if self.silent:
            return
        parts = [f"{task.description}:"]
        if task.total:
            parts.append(f"{100 * min(task.completed / task.total, 1.0):3.0f} %")
        if task.info:
            parts.append(task.info)
        parts.append(f"({now - task.started:.1f} s)")
        self.out.print(Text(" ".join(parts)), soft_wrap=True)


def progress(out: Console | None = None):
    """The progress display of every long command (a context manager): a live bar on a
    terminal, plain lines when stdout is piped or in a notebook, nothing with ``--quiet``.

    Use as ``with progress() as bar: task = bar.add_task("simulating", total=30.0,
    info="solving"); bar.update(task, completed=t, info=...)``; a task without a total is a
    status (each new ``info`` a step).
    """
    out = console if out is None else out
    if _quiet:
        return ProgressLines(out, silent=True)
    if not out.is_terminal:
        return ProgressLines(out)
    from rich.progress import BarColumn, Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

    # markup=False: a description or step holds a user's names (a file "load[kN].csv", a
    # frame named "[/bold]"), which Rich would read as markup (dropped, or a MarkupError)
    return Progress(
        SpinnerColumn(),
        TextColumn("{task.description}", markup=False),
        BarColumn(),
        TextColumn("{task.fields[info]}", markup=False),
        TimeElapsedColumn(),
        console=out,
    )


@contextmanager
def steps(description: str, first: str = "starting") -> Iterator[Callable[[str], None]]:
    """Progress of a command made of steps: ``with steps("analyze") as say: say("reading")``.

    A line per step when piped (``analyze: reading (0.0 s)``), a live status on a terminal,
    nothing with ``--quiet``; ``done`` with the time taken at the end. ``say`` is the callback
    the Python API takes (``progress=``).
    """
    with progress() as bar:
        task = bar.add_task(description, total=None, info=first)

        def say(text: str) -> None:
            bar.update(task, info=str(text))

        yield say
        bar.update(task, info="done")
