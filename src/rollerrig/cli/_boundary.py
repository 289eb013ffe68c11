"""The error boundary around every command: one line per error, signals, warnings.

- A :class:`~rollerrig._validation.ParameterError` (so also ``RecordingError`` and
  ``OutputError``), :class:`UserError`, ``FileNotFoundError``, an ``ImportError`` of an optional
  package (naming the extra to install, :mod:`rollerrig._optional`) or another ``OSError``
  becomes one red ``error:`` line and exit code 2; any other exception one ``internal error``
  line (type and message, "please report") and exit code 3. No traceback unless ``--debug`` or
  ``ROLLERRIG_DEBUG=1``.
- SIGTERM and SIGINT end the command through ``SystemExit`` (exit code 128 + the signal's
  number), so every ``finally`` runs: staged outputs and temporary files are removed. While a
  command's outputs are moved into ``--out`` (:func:`signals_deferred`) a signal waits until the
  set is complete.
- Each :class:`~rollerrig._warnings.DomainWarning` (a model used outside its domain of
  validity) is printed once as a ``warning:`` line.
"""

from __future__ import annotations

import contextlib
import importlib
import os
import re
import signal
import sys
import threading
import traceback
import warnings
from collections.abc import Iterator
from types import ModuleType
from typing import NoReturn

import typer
from rich.text import Text
from typer.core import TyperGroup

from rollerrig._optional import missing_extra_message
from rollerrig._validation import ParameterError
from rollerrig._warnings import DomainWarning
from rollerrig.cli._console import err_console, print_error, print_warning

__all__ = [
    "DEBUG_ENV",
    "ISSUES_URL",
    "SIGNALS",
    "BoundaryGroup",
    "Interrupted",
    "UserError",
    "command_line",
    "current_context",
    "debug_wanted",
    "domain_warnings_printed",
    "fail",
    "plain_usage_error",
    "signals_deferred",
    "signals_end_the_command",
    "user_message",
    "warnings_printed",
]

DEBUG_ENV = "ROLLERRIG_DEBUG"
ISSUES_URL = "the rollerrig issue tracker"
SIGNALS = (signal.SIGTERM, signal.SIGINT)
"""Signals that end a command cleanly (staged outputs and temporary files removed)."""


class UserError(Exception):
    """A problem with what the user gave (option, file, folder): printed as one error line."""


class Interrupted(SystemExit):
    """A command ended by SIGTERM or SIGINT; exit code 128 + the signal's number."""

    def __init__(self, signum: int):
        super().__init__(128 + signum)
        self.signum = signum

    def __str__(self) -> str:
        name = signal.Signals(self.signum).name
        return f"interrupted by {name}; --out holds no partial output of this run"


def fail(message: str) -> NoReturn:
    """Print one error line (literally, no markup) and exit with code 2."""
    print_error(message)
    raise typer.Exit(code=2)


def _os_message(exc: OSError) -> str:
    what = exc.strerror or str(exc)
    names = [str(n) for n in (exc.filename, exc.filename2) if n is not None]
    if isinstance(exc, FileNotFoundError) and names:
        return f"file not found: {names[0]}"
    return f"{what}: {' -> '.join(names)}" if names else what


def user_message(exc: BaseException, command: str | None = None) -> str | None:
    """The one-line message of a user-side error, or None for an internal error.

    ``command``: the command that failed, to name the extra its job needs.
    """
    if isinstance(exc, ParameterError | UserError):
        return str(exc)
    if isinstance(exc, ImportError):
        text = missing_extra_message(exc, command)
        if text is not None:
            return text
        if "rollerrig[" in str(exc):  # a reader that already names the extra to install
            return str(exc)
        module = (exc.name or "").split(".")[0]
        if module in ("", "rollerrig"):
            return None  # rollerrig's own import broke: an internal error
        return f"{exc} (a package rollerrig needs is missing; reinstall rollerrig)"
    if isinstance(exc, OSError):
        return _os_message(exc)
    return None


def _click(part: str) -> ModuleType:
    """``click.<part>`` of the click typer runs on (recent typer ships its own copy)."""
    base = typer.Context.__mro__[1].__module__.rsplit(".", 1)[0]  # "click" or "typer._click"
    return importlib.import_module(f"{base}.{part}")


def current_context() -> typer.Context | None:
    """The click context of the running command, or None outside one."""
    return _click("globals").get_current_context(silent=True)


def debug_wanted(ctx: typer.Context) -> bool:
    return bool(ctx.params.get("debug")) or os.environ.get(DEBUG_ENV, "") not in ("", "0")


# ------------------------------------------------------------------------------------ signals

_SIGNALS_STATE = {"deferring": 0, "pending": [], "received": None}
"""Signals received inside :func:`signals_deferred` (handlers run in the main thread only)."""


def _on_signal(signum, frame) -> None:
    if _SIGNALS_STATE["deferring"]:
        _SIGNALS_STATE["pending"].append(signum)  # raised when the critical section ends
        return
    for s in SIGNALS:  # a second signal must not cut the clean-up short
        signal.signal(s, signal.SIG_IGN)
    # Remembered: raised inside a callback from compiled code (numba compiling through LLVM),
    # the exception is swallowed there and the library fails with an error of its own, which
    # the boundary must still report as this interruption.
    _SIGNALS_STATE["received"] = signum
    raise Interrupted(signum)


def _quiet_unraisable(previous):
    """``sys.unraisablehook`` that drops our own :class:`Interrupted` (see :func:`_on_signal`)
    instead of printing a traceback; every other unraisable exception goes to ``previous``."""

    def hook(unraisable) -> None:
        if isinstance(unraisable.exc_value, Interrupted):
            return
        previous(unraisable)

    return hook


@contextlib.contextmanager
def signals_end_the_command() -> Iterator[None]:
    """SIGTERM/SIGINT raise :class:`Interrupted` inside the block (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.getsignal(s) for s in SIGNALS}
    _SIGNALS_STATE["pending"].clear()
    _SIGNALS_STATE["received"] = None
    for s in SIGNALS:
        signal.signal(s, _on_signal)
    previous_hook = sys.unraisablehook
    sys.unraisablehook = _quiet_unraisable(previous_hook)
    try:
        yield
    finally:
        sys.unraisablehook = previous_hook
        for s, handler in previous.items():
            signal.signal(s, handler)


@contextlib.contextmanager
def signals_deferred() -> Iterator[None]:
    """A signal received inside the block ends the command when the block is over.

    For a step that must not stop half-way (moving a run's outputs into ``--out``). Without the
    handlers of :func:`signals_end_the_command` (the Python API) it changes nothing.
    """
    _SIGNALS_STATE["deferring"] += 1
    try:
        yield
    finally:
        _SIGNALS_STATE["deferring"] -= 1
    pending = _SIGNALS_STATE["pending"]
    if pending and not _SIGNALS_STATE["deferring"]:
        signum = pending[0]
        pending.clear()
        _on_signal(signum, None)


# ------------------------------------------------------------------------------------ warnings


_WARNINGS: list[list[str]] = []
"""The warnings printed by the running command (innermost last)."""


def warnings_printed() -> list[str]:
    """The ``warning:`` lines the running command printed so far (for its run manifest)."""
    return list(_WARNINGS[-1]) if _WARNINGS else []


@contextlib.contextmanager
def domain_warnings_printed() -> Iterator[list[str]]:
    """Print each distinct DomainWarning once as a ``warning:`` line; yields the texts.

    Other warnings go where they went before (their filters are untouched).
    """
    seen: list[str] = []
    with warnings.catch_warnings():
        previous = warnings.showwarning
        warnings.filterwarnings("always", category=DomainWarning)

        def show(message, category, filename, lineno, file=None, line=None):
            if issubclass(category, DomainWarning):
                text = " ".join(str(message).split())
                if text not in seen:
                    seen.append(text)
                    print_warning(text)
                return
            previous(message, category, filename, lineno, file, line)

        warnings.showwarning = show
        _WARNINGS.append(seen)
        try:
            yield seen
        finally:
            _WARNINGS.pop()


# ------------------------------------------------------------------------------------ boundary


def _pass_through() -> tuple[type[BaseException], ...]:
    """Exits, usage errors and aborts: they keep click's/typer's own handling."""
    exceptions = _click("exceptions")
    names = ("ClickException", "Exit", "Abort")
    found = {getattr(exceptions, n) for n in names if hasattr(exceptions, n)}
    found |= {typer.Exit, typer.Abort}
    if hasattr(typer, "TyperException"):
        found.add(typer.TyperException)
    return tuple(found)


_PASS_THROUGH = _pass_through()

_NOT_ONE_OF = re.compile(r"^(?:Value error, )?(?P<given>'.*') is not one of (?P<choices>.*?)\.?$")


_BOUNDS = {
    "greater_than": ("gt", ">"),
    "greater_than_equal": ("ge", ">="),
    "less_than": ("lt", "<"),
    "less_than_equal": ("le", "<="),
}
"""pydantic's bound errors: the key of the bound in the error's context, and its sign."""


def plain_usage_error(exc: BaseException) -> None:
    """Say a bad option value in the user's words, in place (a ``BadParameter``'s message).

    typer checks option values with pydantic, whose messages read "Value error, 'x' is not
    one of 'a', 'b'." or "Input should be a valid number, unable to parse string as a
    number". They become "'x' is not one of a, b; did you mean 'a'?" and "'abc' is not a
    number". Other messages are left as they are.

    Parameters
    ----------
    exc : BaseException
        The usage error; only a ``BadParameter`` is changed.
    """
    from rollerrig._validation import did_you_mean

    if not isinstance(exc, _click("exceptions").BadParameter):
        return
    message = str(exc.message)
    errors = []
    with contextlib.suppress(Exception):  # a ValidationError of typer's coercion, if any
        errors = list(exc.__cause__.errors())
    first = errors[0] if errors else {}
    given = first.get("input")
    shown = repr(given) if isinstance(given, str) else repr(str(given))
    kind = first.get("type", "")
    match = _NOT_ONE_OF.match(message)
    if match is not None:
        choices = re.findall(r"'([^']*)'", match["choices"])
        name = match["given"][1:-1]
        exc.message = (
            f"{match['given']} is not one of {', '.join(choices)}"
            f"{did_you_mean(name, choices, style=';')}"
        )
    elif kind in ("float_parsing", "float_type", "finite_number"):
        exc.message = f"{shown} is not a number"
    elif kind in ("int_parsing", "int_type", "int_from_float"):
        exc.message = f"{shown} is not a whole number"
    elif kind in ("bool_parsing", "bool_type"):
        exc.message = f"{shown} is not a yes/no value (true, false, 1, 0)"
    elif kind in _BOUNDS:
        key, sign = _BOUNDS[kind]
        bound = (first.get("ctx") or {}).get(key)
        exc.message = f"must be {sign} {bound}, got {given}"
    elif message.startswith("Value error, "):
        exc.message = message.removeprefix("Value error, ")
    elif message.startswith("Input should be "):
        exc.message = f"{shown}: must be {message.removeprefix('Input should be ')}"


ARGV_KEY = "rollerrig.argv"
"""Key of ``click.Context.meta`` holding the command line as given."""


def command_line() -> list[str]:
    """The command line of the running command (``rollerrig`` and its arguments, as given).

    Taken from the arguments click parsed (under a test runner ``sys.argv`` is the runner's);
    ``sys.argv`` outside a command.
    """

    ctx = current_context()
    argv = None if ctx is None else ctx.meta.get(ARGV_KEY)
    return list(argv) if argv is not None else [str(a) for a in sys.argv]


class BoundaryGroup(TyperGroup):
    """The error boundary of every command (see the module docstring)."""

    def parse_args(self, ctx: typer.Context, args: list[str]) -> list[str]:
        ctx.meta[ARGV_KEY] = [ctx.info_name or "rollerrig", *args]
        return super().parse_args(ctx, args)

    def invoke(self, ctx: typer.Context):
        try:
            with signals_end_the_command(), domain_warnings_printed():
                return super().invoke(ctx)
        except _PASS_THROUGH as exc:
            plain_usage_error(exc)
            raise
        except Interrupted as exc:
            print_error(str(exc))
            raise
        except Exception as exc:  # the boundary: everything else ends as one line
            received = _SIGNALS_STATE["received"]
            if received is not None:  # a library's error after our signal was swallowed
                interrupted = Interrupted(received)
                if debug_wanted(ctx):
                    traceback.print_exception(exc)
                print_error(str(interrupted))
                raise interrupted from None
            message = user_message(exc, ctx.invoked_subcommand)
            if debug_wanted(ctx):
                traceback.print_exception(exc)
            if message is not None:
                print_error(message)
                raise typer.Exit(code=2) from None
            text = " ".join(str(exc).split()) or "(no message)"
            err_console.print(
                Text.assemble(
                    ("internal error: ", "bold red"),
                    f"{type(exc).__name__}: {text} (please report this to {ISSUES_URL}, "
                    f"with the output of the same command run with --debug)",
                )
            )
            raise typer.Exit(code=3) from None
