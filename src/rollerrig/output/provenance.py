"""Provenance records: what made a file (package version and commit, command, inputs, rig).

:func:`provenance` gives the record every writer of :mod:`rollerrig.output` stores with its file.
What a run reads (the command line, input files with their SHA-256, the rig parameter set, the
channel map) is set once per run with :func:`run_context`; files written inside it record it.
The CLI opens one per command; from Python, without one, the record holds ``sys.argv`` and no
inputs.
"""

from __future__ import annotations

import contextlib
import contextvars
import functools
import hashlib
import json
import os
import platform
import subprocess
import sys
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.output.atomic import file_path

__all__ = [
    "RunContext",
    "current_run",
    "file_record",
    "file_sha256",
    "jsonable",
    "package_commit",
    "provenance",
    "rig_record",
    "rig_sha256",
    "run_context",
]

GIT_TIMEOUT_S = 2.0
"""Longest wait for one ``git`` call when finding the package's commit [s]."""


def jsonable(obj: Any) -> Any:
    """``json.dumps`` ``default=`` hook: numpy values and arrays, paths, dates, sets, mappings.

    Examples
    --------
    >>> json.dumps({"a": np.float64(1.5), "p": Path("x")}, default=jsonable)
    '{"a": 1.5, "p": "x"}'
    """
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, os.PathLike):
        return os.fspath(obj)
    if hasattr(obj, "isoformat"):
        return obj.isoformat()
    if isinstance(obj, set | frozenset | tuple):
        return list(obj)
    if isinstance(obj, Mapping):
        return dict(obj.items())
    if hasattr(obj, "to_dict"):
        return obj.to_dict()
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def file_sha256(path: str | os.PathLike) -> str:
    """SHA-256 hex digest of a file, read in chunks (the file is only read).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "x"
    >>> _ = f.write_bytes(b"abc")
    >>> file_sha256(f)[:16]
    'ba7816bf8f01cfea'
    """
    p = file_path(path).resolve()
    st = p.stat()  # a missing file: FileNotFoundError, naming it
    # A run hashes its inputs once for the provenance and the reader hashes the recording
    # again: the same file, unchanged (size and modification time), is read only once.
    return _sha256_of(str(p), st.st_size, st.st_mtime_ns)


@functools.lru_cache(maxsize=64)
def _sha256_of(path: str, size: int, mtime_ns: int) -> str:
    """SHA-256 of ``path``; ``size`` and ``mtime_ns`` only key the cache."""
    with open(path, "rb") as fh:
        return hashlib.file_digest(fh, "sha256").hexdigest()


def file_record(path: str | os.PathLike) -> dict[str, Any]:
    """``{"path", "sha256", "bytes"}`` of an input file (absolute path)."""
    p = Path(path)
    return {"path": str(p.resolve()), "sha256": file_sha256(p), "bytes": p.stat().st_size}


def rig_sha256(rig: Any) -> str:
    """SHA-256 of a rig parameter set: canonical JSON (sorted keys) of ``rig.to_dict()``.

    Two parameter sets with the same values (SI) have the same hash, whatever file or text
    they came from. ``rig`` may also be the dict itself.

    Examples
    --------
    >>> rig_sha256({"b": 1.0, "a": {"x": 2}}) == rig_sha256({"a": {"x": 2}, "b": 1.0})
    True
    """
    data = rig.to_dict() if hasattr(rig, "to_dict") else dict(rig)
    text = json.dumps(data, sort_keys=True, separators=(",", ":"), default=jsonable)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def rig_record(rig: Any) -> dict[str, Any] | None:
    """``{"name", "sha256"}`` of a rig parameter set, a rig dict or a rig TOML file."""
    if rig is None:
        return None
    if isinstance(rig, str | os.PathLike):
        rec = file_record(rig)
        return {"name": Path(rig).stem, "sha256": rec["sha256"], "path": rec["path"]}
    meta = getattr(rig, "meta", None)
    name = getattr(meta, "name", None)
    if name is None and isinstance(rig, Mapping):
        name = (rig.get("meta") or {}).get("name")
    return {"name": name, "sha256": rig_sha256(rig)}


# --------------------------------------------------------------------------- package commit


def _git(args: list[str], where: Path) -> str | None:
    """stdout of ``git -C where ...``, or None when git is missing, slow or fails."""
    try:
        done = subprocess.run(
            ["git", "-C", str(where), *args],
            capture_output=True,
            text=True,
            timeout=GIT_TIMEOUT_S,
            check=False,
            env={**os.environ, "GIT_OPTIONAL_LOCKS": "0"},  # a status must not take locks
        )
    except (OSError, subprocess.SubprocessError):
        return None
    return done.stdout.strip() if done.returncode == 0 else None


def _pip_commit() -> tuple[str | None, str]:
    """The commit pip recorded at installation (``direct_url.json``), or None and why."""
    from importlib import metadata

    try:
        raw = metadata.distribution("rollerrig").read_text("direct_url.json")
    except metadata.PackageNotFoundError:
        return None, "rollerrig is not installed and its source is not in a git work tree"
    if not raw:
        return None, "installed without a source URL (from an index or a wheel): no commit known"
    try:
        info = json.loads(raw)
    except json.JSONDecodeError:
        return None, "the installation's direct_url.json is not valid JSON"
    commit = (info.get("vcs_info") or {}).get("commit_id")
    if commit:
        return str(commit), "recorded by pip at installation (direct_url.json)"
    if (info.get("dir_info") or {}).get("editable"):
        return None, "editable installation of a folder that is not a git work tree"
    return None, f"installed from {info.get('url', 'a local path')} without version control"


@functools.cache
def package_commit() -> tuple[str | None, str]:
    """(commit, how it was found) of the rollerrig source that runs; cached per process.

    From the git work tree holding the package's files (``git rev-parse HEAD``, with
    ``-dirty`` appended when ``git status --porcelain`` of the source folder lists changes),
    else from :data:`BUILD_COMMIT_FILE` (written into a wheel built from a git checkout),
    else from the commit pip recorded (``direct_url.json`` of the installed distribution), else
    None and the reason.
    """
    package = Path(__file__).resolve().parent.parent  # .../rollerrig
    tracked = _git(["ls-files", "--", "__init__.py"], package)
    if tracked:
        head = _git(["rev-parse", "HEAD"], package)
        if head:
            status = _git(["status", "--porcelain", "--", str(package.parent)], package)
            if status is None:
                return head, "git work tree (could not tell whether it has changes)"
            if status:
                return f"{head}-dirty", "git work tree with uncommitted changes"
            return head, "git work tree"
    recorded = _build_commit(package / BUILD_COMMIT_FILE)
    if recorded:
        return recorded, "recorded when the package was built from a git checkout"
    return _pip_commit()


BUILD_COMMIT_FILE = "_build_commit.txt"
"""File in the installed package holding the commit it was built from (written by setup.py)."""


def _build_commit(path: Path) -> str | None:
    """The commit written into the package at build time, or None."""
    try:
        text = path.read_text(encoding="ascii").strip()
    except (OSError, UnicodeDecodeError):
        return None
    return text or None


# --------------------------------------------------------------------------- run context


@dataclass(frozen=True)
class RunContext:
    """What one run reads; recorded by :func:`provenance` (see :func:`run_context`)."""

    command: list[str] | None = None
    inputs: dict[str, dict[str, Any]] = field(default_factory=dict)
    rig: dict[str, Any] | None = None
    channel_map: dict[str, Any] | None = None
    parameters: dict[str, Any] = field(default_factory=dict)


_RUN: contextvars.ContextVar[RunContext | None] = contextvars.ContextVar(
    "rollerrig_run", default=None
)


def current_run() -> RunContext | None:
    """The :class:`RunContext` in effect, or None outside :func:`run_context`."""
    return _RUN.get()


@contextlib.contextmanager
def run_context(
    *,
    command: list[str] | None = None,
    inputs: Mapping[str, str | os.PathLike] | None = None,
    rig: Any = None,
    channel_map: str | os.PathLike | None = None,
    **parameters: Any,
) -> Iterator[RunContext]:
    """Set what :func:`provenance` records for every file written inside the ``with`` block.

    Parameters
    ----------
    command : list of str, optional
        The command line (``sys.argv`` when omitted).
    inputs : mapping of role -> path, optional
        Input files (recording, protocol, replayed torque, ...); each is hashed once, here.
    rig : RigParameters, dict or path, optional
        The rig parameter set (its name and :func:`rig_sha256`) or its TOML file.
    channel_map : path, optional
        The channel-map file (path and SHA-256).
    **parameters
        Run parameters, merged under those given to :func:`provenance`.

    Examples
    --------
    >>> with run_context(command=["rollerrig", "contact"], load_kn=50.0):
    ...     record = provenance(out="x")
    >>> record["command"], record["parameters"]
    (['rollerrig', 'contact'], {'load_kn': 50.0, 'out': 'x'})
    """
    if isinstance(command, str | bytes) or not (
        command is None or isinstance(command, list | tuple)
    ):  # a str had been recorded as its characters: ['r', 'o', 'l', ...]
        raise ParameterError(
            f"command must be a list of str (the command line's words), got {command!r}"
        )
    if inputs is not None and not isinstance(inputs, Mapping):
        raise ParameterError(
            f"inputs must be a mapping of role -> path, got a {type(inputs).__name__}"
        )
    run = RunContext(
        command=[str(c) for c in (sys.argv if command is None else command)],
        inputs={str(role): file_record(p) for role, p in (inputs or {}).items()},
        rig=rig_record(rig),
        channel_map=(
            None
            if channel_map is None
            else {k: v for k, v in file_record(channel_map).items() if k != "bytes"}
        ),
        parameters=dict(parameters),
    )
    token = _RUN.set(run)
    try:
        yield run
    finally:
        _RUN.reset(token)


def provenance(**parameters: Any) -> dict[str, Any]:
    """A provenance record for a file written now.

    Keys: ``software``, ``version``, ``commit`` (with ``commit_note`` when it is null),
    ``created_utc``, ``python``, ``numpy``, ``command``, ``inputs`` (role -> ``{"path",
    "sha256", "bytes"}``), ``rig`` (``{"name", "sha256"}`` or null), ``channel_map``
    (``{"path", "sha256"}`` or null) and ``parameters`` (the run's, then these). Cheap: the
    commit is found once per process, inputs are hashed when the run context opens.

    Examples
    --------
    >>> r = provenance(fs=250.0)
    >>> r["software"], r["parameters"], sorted(r)[:3]
    ('rollerrig', {'fs': 250.0}, ['channel_map', 'command', 'commit'])
    """
    from rollerrig import __version__

    run = _RUN.get() or RunContext(command=[str(a) for a in sys.argv])
    commit, how = package_commit()
    record: dict[str, Any] = {
        "software": "rollerrig",
        "version": __version__,
        "commit": commit,
    }
    if commit is None:
        record["commit_note"] = how
    record.update(
        {
            "created_utc": datetime.now(UTC).isoformat(timespec="seconds"),
            "python": platform.python_version(),
            "numpy": np.__version__,
            "command": list(run.command or []),
            "inputs": {k: dict(v) for k, v in run.inputs.items()},
            "rig": None if run.rig is None else dict(run.rig),
            "channel_map": None if run.channel_map is None else dict(run.channel_map),
            "parameters": {**run.parameters, **parameters},
        }
    )
    return record


def is_provenance(obj: Any) -> bool:
    """Whether ``obj`` is already a record made by :func:`provenance`."""
    return isinstance(obj, Mapping) and obj.get("software") == "rollerrig" and "version" in obj
