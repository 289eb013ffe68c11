"""The package's one atomic file writer, and the one error type of the output side.

Every file rollerrig writes goes through :func:`atomic_write`: a hidden temporary file in the
target folder, written by a callback, given the mode a new file gets from the umask (or the
mode of the file it replaces), then moved onto the target in one step (:func:`os.replace`; a hard
link when existing files must not be replaced). A reader never sees a half-written file, and a
failure of any kind (an exception in the callback, a full disk, Ctrl-C, ``SystemExit`` from a
signal handler) leaves the previous file intact and no temporary file behind.
"""

from __future__ import annotations

import contextlib
import errno
import os
import secrets
import shutil
import tempfile
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path

from rollerrig._validation import ParameterError, require_flag

__all__ = [
    "OutputError",
    "atomic_write",
    "atomic_write_all",
    "current_umask",
    "file_path",
    "new_file_mode",
]


class OutputError(ParameterError, OSError):
    """An output-side fault (folder not writable, ``--out`` is a file, disk full, ...).

    The message names the path and what to change. It is a :class:`ParameterError` (the
    package's user-facing error) and an :class:`OSError` (what the fault is).
    """


_MAX_NAME = 255  # bytes in one file name on the usual file systems


def current_umask() -> int:
    """The process umask, read without changing it where the system allows (Linux)."""
    with contextlib.suppress(OSError, ValueError):
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    umask = os.umask(0o022)  # no /proc: the classic swap (not thread-safe, brief)
    os.umask(umask)
    return umask


def new_file_mode() -> int:
    """The permission bits a new file gets: ``0o666`` less the umask.

    Examples
    --------
    >>> old = os.umask(0o027)
    >>> oct(new_file_mode())
    '0o640'
    >>> _ = os.umask(old)
    """
    return 0o666 & ~current_umask()


def _temp_prefix(path: Path) -> str:
    """``.<name>.`` for the temporary file, cut so that the whole name stays a legal length."""
    room = _MAX_NAME - len(".tmp" + path.suffix) - 12  # "." + random part + "."
    name = path.name
    while len(name.encode("utf-8", "surrogateescape")) > room:
        name = name[: max(1, len(name) - 8)]
    return f".{name}."


_FULL = {
    errno.ENOSPC: "the disk is full: free space on it, or write elsewhere (--out)",
    errno.EDQUOT: "your disk quota is used up: free space in it, or write elsewhere (--out)",
    errno.EFBIG: "the file is larger than this file system allows: write elsewhere (--out)",
    errno.EROFS: "the file system is read-only: choose a folder you may write to (--out)",
}
"""errno of a failed write -> what to do (the message names the path as well)."""


def _errno(exc: OSError) -> int | None:
    """``exc.errno``; for an error with none (h5py's), ENOSPC/EDQUOT read from its text."""
    if exc.errno is not None:
        return exc.errno
    text = str(exc)
    for code in (errno.ENOSPC, errno.EDQUOT):
        if os.strerror(code) in text:
            return code
    return None


def _os_cause(exc: BaseException) -> OSError | None:
    """The :class:`OSError` with an errno of :data:`_FULL` that ``exc`` is or was raised from
    (libraries such as h5py and pandas wrap the system's error in their own)."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        seen.add(id(exc))
        if isinstance(exc, OSError) and _errno(exc) in _FULL:
            return exc
        exc = exc.__cause__ or exc.__context__
    return None


def _fault(path: Path, exc: OSError, doing: str) -> OutputError:
    """An :class:`OutputError` naming ``path``, the system's reason and what to do."""
    reason = exc.strerror or str(exc) or type(exc).__name__
    hint = ""
    code = _errno(exc)
    if code in _FULL:
        reason = exc.strerror or os.strerror(code)
        hint = f"; {_FULL[code]}; nothing was written"
    elif isinstance(exc, PermissionError):
        hint = "; choose a folder you may write to (--out)"
    elif isinstance(exc, NotADirectoryError | FileExistsError) and doing == "create the folder":
        hint = "; a file is in the way: choose another output folder (--out)"
    elif isinstance(exc, IsADirectoryError):
        hint = "; a folder has this name: remove it or choose another output name"
    return OutputError(f"{path}: cannot {doing}: {reason}{hint}")


_REFUSAL = "pass overwrite=True to replace it"


def _refuse(path: Path) -> FileExistsError:
    return FileExistsError(f"{path} exists; {_REFUSAL}")


def file_path(path, name: str = "path") -> Path:
    """``path`` (a file to write or to read) as a :class:`~pathlib.Path`, or an
    :class:`OutputError` that names it.

    A str or path-like (of text) is a path; anything else (None, a number, bytes) had reached
    :class:`pathlib.Path`'s bare TypeError. An empty path and one holding a NUL character
    (which no system accepts: a bare ValueError) are refused too.

    Examples
    --------
    >>> file_path("out/run.csv")
    PosixPath('out/run.csv')
    >>> file_path(None)
    Traceback (most recent call last):
    ...
    rollerrig.output.atomic.OutputError: path must be a file path (str or Path), got None
    """
    text = os.fspath(path) if isinstance(path, str | os.PathLike) else None
    if not isinstance(text, str):
        got = repr(path) if len(repr(path)) <= 60 else f"a {type(path).__name__}"
        raise OutputError(f"{name} must be a file path (str or Path), got {got}")
    if not text:
        raise OutputError(f"{name} must be a file path (str or Path), got an empty path")
    if "\0" in text:
        raise OutputError(f"{text!r}: {name} holds a NUL character, which no file name may hold")
    return Path(text)


def _commit(tmp: Path, dst: Path, overwrite: bool) -> None:
    """Move ``tmp`` onto ``dst``; without ``overwrite`` refuse an existing ``dst``."""
    if overwrite:
        os.replace(tmp, dst)
        return
    try:
        os.link(tmp, dst)  # atomic, and refuses to replace an existing file
    except FileExistsError:
        raise _refuse(dst) from None
    except OSError:  # a file system without hard links
        if os.path.lexists(dst):
            raise _refuse(dst) from None
        os.replace(tmp, dst)
        return
    tmp.unlink()


def _prepare(path: Path, overwrite: bool) -> None:
    """Refuse an existing ``path`` (unless ``overwrite``) or a folder there; create its folder."""
    if not overwrite and os.path.lexists(path):
        raise _refuse(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:  # a file where a folder should be, no permission, ...
        raise _fault(path.parent, exc, "create the folder") from exc
    try:
        is_dir = path.is_dir()
    except OSError as exc:  # a name too long for the file system
        raise _fault(path, exc, "write the file") from exc
    if is_dir:
        raise _fault(path, IsADirectoryError(21, "Is a directory"), "write the file")


def _temporary(path: Path) -> Path:
    """A new hidden empty file beside ``path``, for its content."""
    try:
        fd, name = tempfile.mkstemp(
            dir=path.parent, prefix=_temp_prefix(path), suffix=f".tmp{path.suffix}"
        )
    except OSError as exc:
        raise _fault(path, exc, "create a file in its folder") from exc
    os.close(fd)
    return Path(name)


@contextlib.contextmanager
def _faults(path: Path) -> Iterator[None]:
    """Any fault of writing ``path`` as an :class:`OutputError` naming it (a refusal of an
    existing file, and any error that is not the system's, as they are)."""
    try:
        yield
    except FileExistsError as exc:
        if str(exc).endswith(_REFUSAL):
            raise
        raise _fault(path, exc, "write the file") from exc
    except OutputError:
        raise
    except OSError as exc:
        raise _fault(path, exc, "write the file") from exc
    except Exception as exc:  # a library's own error around a full disk, say
        cause = _os_cause(exc)
        if cause is None:
            raise
        raise _fault(path, cause, "write the file") from exc


def _staged(path: Path, tmp: Path, write: Callable[[Path], Path | None]) -> Path:
    """Call ``write(tmp)``; the file it wrote (``tmp``, or the one it names) with the mode
    ``path`` has (or a new file gets)."""
    result = write(tmp)
    written = Path(result) if isinstance(result, str | os.PathLike) else tmp  # asammdf
    try:
        mode = path.stat().st_mode & 0o777 if path.is_file() else new_file_mode()
    except OSError:
        mode = new_file_mode()
    os.chmod(written, mode)
    return written


def _flag(name: str, value, path: Path | None) -> None:
    """:func:`~rollerrig._validation.require_flag`, the message naming ``path`` (the text
    "no" had meant yes: replace)."""
    require_flag(name if path is None else f"{path}: {name}", value)


def _callable(write, path: Path) -> None:
    if not callable(write):
        raise ParameterError(
            f"{path}: write must be a function that writes the file it is given, got a "
            f"{type(write).__name__}"
        )


def atomic_write(
    path: str | os.PathLike,
    write: Callable[[Path], Path | None],
    *,
    overwrite: bool = True,
) -> Path:
    """Call ``write(tmp)`` and move the file it wrote onto ``path`` in one step.

    Parameters
    ----------
    path : str or path-like
        The target file. Missing parent folders are created.
    write : callable
        Writes the content to the temporary path it is given (same folder, hidden name
        ``.<name>.<random>.tmp<suffix>``, same suffix as ``path``). When it returns a path
        (the library it calls chose the file name: asammdf), that file is moved instead; any
        other return value is ignored.
    overwrite : bool
        Replace an existing file (default). With False an existing file is refused
        (:class:`FileExistsError`), atomically: no window in which another writer's file is
        replaced.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    FileExistsError
        ``path`` exists and ``overwrite`` is False.
    OutputError
        ``path`` is not a file path (None, a number, bytes: :func:`file_path`), the folder
        cannot be created or written, ``path`` is a folder, the disk is full, ... (any
        :class:`OSError` while writing); the message names the path.

    Notes
    -----
    The file gets the mode of the file it replaces, else ``0o666`` less the umask (the mode of
    any new file; :func:`tempfile.mkstemp` alone would leave ``0o600``). The temporary file is
    removed on every exception, ``KeyboardInterrupt`` and ``SystemExit`` included.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> p = atomic_write(d / "a.txt", lambda tmp: tmp.write_text("hello"))
    >>> p.read_text(), [f.name for f in d.iterdir()]
    ('hello', ['a.txt'])
    """
    path = file_path(path)
    _callable(write, path)
    _flag("overwrite", overwrite, path)
    _prepare(path, overwrite)
    tmp = _temporary(path)
    written = tmp
    try:
        with _faults(path):
            written = _staged(path, tmp, write)
            _commit(written, path, overwrite)
    finally:
        for leftover in {tmp, written}:
            with contextlib.suppress(OSError):
                leftover.unlink()
    return path


def _backup(path: Path) -> Path:
    """A second name (hidden, beside it) for the file at ``path``, to put it back from."""
    while True:
        backup = path.with_name(f"{_temp_prefix(path)}{secrets.token_hex(4)}.bak")
        try:
            os.link(path, backup, follow_symlinks=False)
        except FileExistsError:
            continue
        except OSError:  # a file system without hard links: a copy
            if os.path.lexists(backup):
                continue
            shutil.copy2(path, backup, follow_symlinks=False)
        return backup


def atomic_write_all(
    writes: Sequence[tuple[str | os.PathLike, Callable[[Path], Path | None]]],
    *,
    overwrite: bool = True,
) -> list[Path]:
    """Write several files (a table and its sidecar) so that a failure leaves all old or none.

    Each ``write`` is called as for :func:`atomic_write`; only when every file is written in
    full are they moved onto their targets, one after the other. When a move fails, the files
    already moved are put back (the old file from a second name made beforehand, a new one
    removed), so the caller finds the files it had: all new, or all as they were.

    Parameters
    ----------
    writes : sequence of (path, write)
        The targets, distinct, and the function that writes each (see :func:`atomic_write`).
    overwrite : bool
        Replace existing files (default); with False any existing target is refused.

    Returns
    -------
    list of Path
        The targets.

    Raises
    ------
    FileExistsError, OutputError
        As :func:`atomic_write`; nothing is changed.

    Notes
    -----
    No file system moves two files in one step: for the instant between the moves a reader may
    see the new first file beside the old second one. The guarantee is that of the outcome:
    when this function returns every file is new; when it raises every file is as it was
    (unless putting one back fails too, e.g. the disk vanished: the error then says which).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = atomic_write_all([(d / "a.csv", lambda t: t.write_text("x")),
    ...                       (d / "a.json", lambda t: t.write_text("{}"))])
    >>> sorted(f.name for f in d.iterdir())
    ['a.csv', 'a.json']
    """
    if isinstance(writes, str | bytes) or not isinstance(writes, Sequence):
        raise ParameterError(
            f"writes must be a sequence of (path, write) pairs, got a {type(writes).__name__}"
        )
    targets: list[tuple[Path, Callable]] = []
    for k, pair in enumerate(writes):
        if not (isinstance(pair, Sequence) and not isinstance(pair, str) and len(pair) == 2):
            raise ParameterError(f"writes[{k}] must be a (path, write) pair, got {pair!r}")
        path = file_path(pair[0], f"writes[{k}] path")
        _callable(pair[1], path)
        targets.append((path, pair[1]))
    _flag("overwrite", overwrite, targets[0][0] if targets else None)
    paths = [os.path.abspath(p) for p, _ in targets]
    if len(set(paths)) < len(paths):
        twice = next(p for p in paths if paths.count(p) > 1)
        raise ParameterError(f"{twice}: given twice; each file is written once")
    for path, _ in targets:
        _prepare(path, overwrite)
    leftovers: list[Path] = []
    backups: dict[Path, Path] = {}
    moved: list[Path] = []
    try:
        staged = []
        for path, write in targets:
            tmp = _temporary(path)
            leftovers.append(tmp)
            with _faults(path):
                written = _staged(path, tmp, write)
            leftovers.append(written)
            staged.append((path, written))
        for path, written in staged:
            with _faults(path):
                if overwrite and os.path.lexists(path):
                    backups[path] = _backup(path)
                _commit(written, path, overwrite)
            moved.append(path)
    except BaseException as exc:
        for path in reversed(moved):  # put back what was there
            try:
                if path in backups:
                    os.replace(backups.pop(path), path)
                else:
                    path.unlink()
            except OSError as undo:
                exc.add_note(f"{path}: could not be put back as it was: {undo}")
        raise
    finally:
        for leftover in {*leftovers, *backups.values()}:
            with contextlib.suppress(OSError):
                leftover.unlink()
    return [path for path, _ in targets]
