"""A command's outputs: all or none, inside ``--out``, never over an input, one run at a time.

``with staged_outputs(out, inputs=[...], run="contact") as stage:`` wraps the work of a command:

- ``out`` is checked and created (a file in the way or a folder one may not write to is one
  :class:`~rollerrig.output.OutputError` naming the path), and locked (``.rollerrig.lock``,
  ``fcntl.flock``): a second run into the same ``out`` while this one runs is one error naming
  the pid of the run that holds it;
- files are written into ``stage.dir`` (``stage.path(name)`` gives a safe name), a hidden
  folder inside ``out``;
- when the block ends without an exception, every staged file is checked (an output name taken
  by a folder, an output that would replace one of the command's input files: one error, before
  anything moves), the run's manifest ``<run>-run.json`` is added (every file with its SHA-256
  and size, the provenance of the run), and everything is moved into ``out`` (``os.replace``,
  atomic per file; signals wait until the set is complete, the manifest moves last);
- on an exception (SIGTERM and SIGINT included) the staging folder is removed and ``out`` is as
  before (removed again if the run created it).
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path

from rollerrig.cli._boundary import command_line, signals_deferred, warnings_printed
from rollerrig.cli._console import mark_replaced
from rollerrig.output import OutputError
from rollerrig.output.names import (
    MAX_OUTPUT_STEM,
    safe_file_name,
    safe_file_stem,
    unique_file_stems,
)

try:
    import fcntl
except ImportError:  # pragma: no cover - not on Windows: runs into one --out are not locked
    fcntl = None

__all__ = [
    "LOCK_NAME",
    "MAX_OUTPUT_STEM",
    "STAGE_PREFIX",
    "command_outputs",
    "safe_file_name",
    "safe_file_stem",
    "staged_outputs",
    "unique_file_stems",
]

LOCK_NAME = ".rollerrig.lock"
"""Lock file in ``--out`` while a run writes there (holds the run's pid)."""
STAGE_PREFIX = ".rollerrig-stage-"
"""Name prefix of the hidden staging folders inside ``--out``."""


def _reason(exc: OSError) -> str:
    return exc.strerror or str(exc) or type(exc).__name__


def _same_file(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return a.resolve() == b.resolve()


class _RunLock:
    """``fcntl.flock`` on ``<folder>/.rollerrig.lock``; the file holds the pid and is removed on
    release (a run that finds the file replaced after locking it locks the new one)."""

    def __init__(self, folder: Path):
        self.path = folder / LOCK_NAME
        self.fd: int | None = None

    def acquire(self) -> None:
        if fcntl is None:  # pragma: no cover
            return
        while True:
            try:
                fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o666)
            except OSError as exc:
                hint = (
                    "; choose a folder you may write to" if isinstance(exc, PermissionError) else ""
                )
                raise OutputError(
                    f"--out {self.path.parent}: cannot write there: {_reason(exc)}{hint}"
                ) from None
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                holder = os.read(fd, 32).decode("ascii", "replace").strip() or "unknown"
                os.close(fd)
                raise OutputError(
                    f"--out {self.path.parent} is in use by another rollerrig run (pid {holder}); "
                    "wait for it to end or choose another --out"
                ) from None
            try:
                same = os.fstat(fd).st_ino == os.stat(self.path).st_ino
            except FileNotFoundError:
                same = False
            if same:
                break
            os.close(fd)  # the run before us removed the file between our open and lock
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode("ascii"))
        self.fd = fd

    def release(self) -> None:
        if self.fd is None:
            return
        with contextlib.suppress(OSError):
            self.path.unlink()
        os.close(self.fd)
        self.fd = None


class staged_outputs:  # a context manager that reads as a function
    """Write all files of one command together, or none of them (see the module docstring).

    Parameters
    ----------
    out : path
        The output folder (``--out``).
    inputs : iterable of paths
        The command's input files (recordings, channel map, rig, protocol, replayed trace,
        truth): an output whose final path is one of them is refused.
    run : str, optional
        Name of the run's manifest, ``<run>-run.json``; none without it.

    Attributes
    ----------
    dir : Path
        The staging folder: write the outputs here.
    written : list of Path
        The final paths, once the block has ended without an exception (manifest last).
    removed : list of Path
        Files of ``out`` named by :meth:`supersede` that the commit removed (an earlier run's
        output this run did not write again).
    kept : list of Path
        Files named by :meth:`supersede` that stay: not, or no longer as written, in the
        earlier run's manifest (changed since, or another command's file of that name).
    """

    def __init__(
        self,
        out: str | os.PathLike,
        *,
        inputs: Iterable[str | os.PathLike | None] = (),
        run: str | None = None,
    ):
        self.out = Path(out)
        self.inputs = [Path(p) for p in inputs if p is not None]
        self.run = run
        self.dir: Path | None = None
        self.written: list[Path] = []
        self._lock = _RunLock(self.out)
        self._created: list[Path] = []
        self._issued: dict[str, str] = {}  # casefolded safe name -> the name asked for
        self._superseded: list[Path] = []
        self.removed: list[Path] = []
        self.kept: list[Path] = []

    # ------------------------------------------------------------------ enter

    def __enter__(self) -> staged_outputs:
        out = self.out
        if out.exists() and not out.is_dir():
            raise OutputError(f"--out {out} is a file, not a folder; give a folder")
        for source in self.inputs:
            if source.is_dir() and _within(out, source):
                raise OutputError(
                    f"--out {out} is inside the input {source}: outputs would be written into "
                    "it; choose another --out"
                )
        missing = out
        while not missing.exists() and missing != missing.parent:
            self._created.insert(0, missing)
            missing = missing.parent
        try:
            out.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            self._remove_created()
            raise OutputError(
                f"--out {out}: cannot create the folder: {_reason(exc)}; choose another --out"
            ) from None
        try:
            self._lock.acquire()
            for stale in out.glob(f"{STAGE_PREFIX}*"):  # left by a killed run (we hold the lock)
                shutil.rmtree(stale, ignore_errors=True)
            self.dir = Path(tempfile.mkdtemp(prefix=f"{STAGE_PREFIX}{os.getpid()}-", dir=out))
        except BaseException:
            self._lock.release()
            self._remove_created()
            raise
        return self

    # ------------------------------------------------------------------ names

    def path(self, name: str) -> Path:
        """Staged path of the output file ``name``: a plain file name, made safe, checked.

        Names come from user data (an experiment's name, a recording's stem) and are made safe
        by :func:`~rollerrig.output.names.safe_file_name` (letters and digits of any script,
        ``.``, ``_``, ``-`` and ``+`` kept, every other character ``_``, so ``../x`` cannot
        leave ``out``; at most 255 bytes). A name whose final path is a folder or one of the
        inputs is refused here already, and so is a second name of this run that becomes the
        same file (also where only the case differs, as Windows and macOS compare names): one
        output never replaces another silently.
        """
        safe = safe_file_name(name)
        first = self._issued.setdefault(safe.casefold(), str(name))
        if first != str(name):
            raise OutputError(
                f"two outputs of this run would both be written to {self.out / safe} "
                f"({first!r} and {str(name)!r}); give the inputs names that differ in a letter "
                "or digit, or write them to different --out folders"
            )
        staged = self.dir / safe
        self._check(self.final(staged))
        return staged

    def supersede(self, name: str) -> None:
        """An output of this command, of an earlier run, that this run does not write again
        (``--no-figure``: the figure of the same name would stay beside the new results): the
        commit removes the file ``out/name`` with the new files, all or none, and
        :attr:`removed` lists it. Only a file the earlier run's manifest (``<run>-run.json``,
        the same run name) lists, unchanged since (its SHA-256), goes; any other file of that
        name stays (:attr:`kept`), and so does an input, a folder or a name this run writes."""
        self._superseded.append(self.out / safe_file_name(name))

    def final(self, staged: str | os.PathLike) -> Path:
        """Where a staged path ends up in ``out``."""
        return self.out / Path(staged).relative_to(self.dir)

    def _check(self, dest: Path) -> None:
        if dest.is_dir():
            raise OutputError(f"output {dest} is a folder; remove it or choose another --out")
        if dest.exists():
            for source in self.inputs:
                if source.exists() and _same_file(dest, source):
                    raise OutputError(
                        f"output {dest} would replace the input file {source}; choose another "
                        "--out (or another name for what is written)"
                    )

    # ------------------------------------------------------------------ exit

    def __exit__(self, exc_type, exc, tb) -> None:
        committed = False
        try:
            if exc_type is None:
                self._commit()
                committed = True
        finally:
            shutil.rmtree(self.dir, ignore_errors=True)
            self._lock.release()
            if not committed:
                self._remove_created()

    def _commit(self) -> None:
        files = sorted(p for p in self.dir.rglob("*") if p.is_file())
        files = [p for p in files if not p.name.startswith(".")]  # writers' temporaries
        for src in files:  # every clash is found before anything is moved
            self._check(self.final(src))
        written = {self.final(src) for src in files}
        stale = []
        for p in dict.fromkeys(self._superseded):
            if p in written or not p.is_file():
                continue
            if self._earlier_runs(p) and not any(
                s.exists() and _same_file(p, s) for s in self.inputs
            ):
                stale.append(p)
            else:
                self.kept.append(p)
        if self.run is not None:
            files.append(self._manifest(files, stale))  # moved last: present means complete
        # All or none: an old file of the same name gets a second name in the stage first (a
        # hard link: it stays in place until the new one atomically replaces it), and where
        # any move fails the new files are taken out and the old ones put back. One file that
        # could not be replaced had left the new results beside the old figure and manifest,
        # and the old results lost.
        replaced = self.dir / ".replaced"
        placed: list[tuple[Path, Path | None]] = []  # (dest, its old file's second name)
        removed: list[Path] = []
        with signals_deferred():
            for dest in stale:  # moved aside, as a replaced file; gone with the stage
                try:
                    replaced.mkdir(exist_ok=True)
                    old = replaced / str(len(placed))
                    os.replace(dest, old)
                except OSError as exc:
                    what = f"{dest}: cannot remove an earlier run's file"
                    raise self._failed(placed, what, exc) from None
                placed.append((dest, old))
                removed.append(dest)
            for src in files:
                dest = self.final(src)
                try:
                    dest.parent.mkdir(parents=True, exist_ok=True)
                    old = None
                    if os.path.lexists(dest):  # a dangling link too
                        replaced.mkdir(exist_ok=True)
                        old = replaced / str(len(placed))
                        _second_name(dest, old)
                    os.replace(src, dest)  # dest is the old file or the new one, never absent
                except OSError as exc:
                    raise self._failed(placed, f"{dest}: cannot write the file", exc) from None
                placed.append((dest, old))
            self.written.extend(dest for dest, _ in placed[len(removed) :])
            self.removed.extend(removed)
            mark_replaced(dest for dest, old in placed[len(removed) :] if old is not None)

    def _failed(self, placed, what: str, exc: OSError) -> OutputError:
        """The commit's moves undone (:meth:`_roll_back`) and the error that says what failed
        and where the old files are."""
        where = self._roll_back(placed)
        return OutputError(
            f"{what}: {_reason(exc)}; "
            + (
                f"nothing in {self.out} was changed"
                if where is None
                else f"some old files could not be put back: they are in {where}"
            )
        )

    def _earlier_runs(self, path: Path) -> bool:
        """Whether ``path`` is a plain file that the earlier run's manifest (this run's name)
        lists with the SHA-256 it has now."""
        import json

        from rollerrig.output import file_sha256

        if self.run is None or path.is_symlink():
            return False
        try:
            doc = json.loads((self.out / safe_file_name(f"{self.run}-run.json")).read_text())
            listed = {f["file"]: f["sha256"] for f in doc["files"]}
            return listed.get(path.relative_to(self.out).as_posix()) == file_sha256(path)
        except (OSError, ValueError, KeyError, TypeError):
            return False

    def _roll_back(self, placed) -> Path | None:
        """Undo a commit's moves, last first: a new file removed, an old one put back. Where
        an old file cannot be put back, the stage is kept under a name no later run removes,
        and returned (None: all undone)."""
        failed = False
        for dest, old in reversed(placed):
            try:
                if old is None:
                    os.unlink(dest)
                else:
                    os.replace(old, dest)
            except OSError:
                failed = failed or old is not None
        if not failed:
            return None
        kept = self.out / f".rollerrig-replaced-{os.getpid()}"
        with contextlib.suppress(OSError):
            os.replace(self.dir / ".replaced", kept)
            return kept
        return self.dir / ".replaced"

    def _manifest(self, files: list[Path], removed: list[Path]) -> Path:
        """``<run>-run.json`` in the stage: the run's files with SHA-256 and size, provenance."""
        from rollerrig.output import file_sha256, write_json

        name = safe_file_name(f"{self.run}-run.json")
        staged = self.dir / name
        self._check(self.final(staged))
        listed = [
            {
                "file": self.final(p).relative_to(self.out).as_posix(),
                "sha256": file_sha256(p),
                "bytes": p.stat().st_size,
            }
            for p in files
        ]
        doc = {
            "run": self.run,
            "folder": str(self.out.resolve()),
            "files": listed,
            "warnings": warnings_printed(),
            **(
                {"removed": [p.relative_to(self.out).as_posix() for p in removed]}
                if removed
                else {}
            ),
            "note": "the files this run wrote into this folder; a later run may replace some",
        }
        write_json(staged, doc)
        return staged

    def _remove_created(self) -> None:
        """Remove the folders this run created, where they are empty."""
        for folder in reversed(self._created):
            with contextlib.suppress(OSError):
                folder.rmdir()
        self._created = []


def _second_name(path: Path, alias: Path) -> None:
    """Give the file ``path`` the second name ``alias`` (a hard link; a copy where the file
    system has none), the file itself left in place."""
    try:
        os.link(path, alias, follow_symlinks=False)
    except OSError:
        if os.path.islink(path):
            os.symlink(os.readlink(path), alias)
        else:
            shutil.copy2(path, alias)


def _within(path: Path, folder: Path) -> bool:
    """Whether ``path`` is ``folder`` or lies inside it (links resolved)."""
    try:
        path.resolve().relative_to(folder.resolve())
    except ValueError:
        return False
    return True


@contextlib.contextmanager
def command_outputs(
    out: str | os.PathLike,
    *,
    run: str,
    inputs: Mapping[str, str | os.PathLike | None] | None = None,
    rig=None,
    channel_map: str | os.PathLike | None = None,
    **parameters,
) -> Iterator[staged_outputs]:
    """A command's run: its provenance and its staged outputs, in one ``with``.

    Opens :func:`rollerrig.output.run_context` (the command line, the ``inputs`` (role ->
    path; None is left out) hashed once, the rig parameter set, the channel map, the
    ``parameters``), so that every file written inside carries them, and
    :class:`staged_outputs` on ``out`` with those inputs protected and the manifest
    ``<run>-run.json``.
    """
    from rollerrig.output import run_context

    given = {role: Path(p) for role, p in (inputs or {}).items() if p is not None}
    if channel_map is not None:
        given.setdefault("channel_map", Path(channel_map))
    # a folder given as an input (a study's store) is protected from --out, not hashed
    files = {role: p for role, p in given.items() if role != "channel_map" and not p.is_dir()}
    with (
        run_context(
            command=command_line(),
            inputs=files,
            rig=rig,
            channel_map=channel_map,
            **parameters,
        ),
        staged_outputs(out, inputs=given.values(), run=run) as stage,
    ):
        yield stage
