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
import tempfile
from collections.abc import Callable
from pathlib import Path

from rollerrig._validation import ParameterError

__all__ = ["OutputError", "atomic_write", "current_umask", "new_file_mode"]


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


def _refuse(path: Path) -> FileExistsError:
    return FileExistsError(f"{path} exists; pass overwrite=True to replace it")


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
        The folder cannot be created or written, ``path`` is a folder, the disk is full, ...
        (any :class:`OSError` while writing); the message names the path.

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
    path = Path(path)
    if not overwrite and os.path.lexists(path):
        raise _refuse(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except FileExistsError as exc:  # a file where a folder should be
        raise _fault(path.parent, exc, "create the folder") from exc
    except OSError as exc:
        raise _fault(path.parent, exc, "create the folder") from exc
    if path.is_dir():
        raise _fault(path, IsADirectoryError(21, "Is a directory"), "write the file")
    try:
        fd, name = tempfile.mkstemp(
            dir=path.parent, prefix=_temp_prefix(path), suffix=f".tmp{path.suffix}"
        )
    except OSError as exc:
        raise _fault(path, exc, "create a file in its folder") from exc
    os.close(fd)
    tmp = Path(name)
    written = tmp
    try:
        result = write(tmp)
        if isinstance(result, str | os.PathLike):  # the library chose the name (asammdf)
            written = Path(result)
        try:
            mode = path.stat().st_mode & 0o777 if path.is_file() else new_file_mode()
        except OSError:
            mode = new_file_mode()
        os.chmod(written, mode)
        _commit(written, path, overwrite)
    except FileExistsError as exc:
        if str(exc).endswith("pass overwrite=True to replace it"):
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
    finally:
        for leftover in {tmp, written}:
            with contextlib.suppress(OSError):
                leftover.unlink()
    return path
