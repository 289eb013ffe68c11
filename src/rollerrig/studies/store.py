"""The study store: one entry per point, written as points finish, resumable.

A store is a zarr group (a folder, ``<study>.zarr``) holding, along one dimension ``point``:

- one array per varied quantity, named by its key (SI values, or names), attribute ``units``;
- ``label``: the point's short label; ``status``: ``"ok"``, ``"solver failed"``,
  ``"invalid parameters"`` or ``"pending"`` (not run yet); ``reason``: why, for the others,
  and for an ``ok`` point the domain warnings of its setup (``"warning: ..."``), if any;
- one array per metric (:mod:`rollerrig.studies.metrics`), NaN where the status is not ``ok``
  or the metric is undefined for that point (attribute ``nan_meaning``);

and, as group attributes, the study (its file's text and SHA-256, design, parameters, metrics,
grid shape or sample design) and the provenance of the run that created it.

Why zarr: each chunk is its own file, written atomically (a temporary file renamed), so a study
killed at any moment leaves a store whose finished points are intact; resuming runs only the
points still ``pending``. Results are buffered and written every few seconds
(:data:`FLUSH_SECONDS`): an interruption loses at most that much work.

A store proves its completeness: every chunk is written as a file, even one that holds only
the fill value (zarr leaves those out by default, and reads a missing chunk as the fill value,
so a chunk file lost to a partial copy would otherwise read as "ok, no value"). A finished
point whose results chunk file (a metric's, the reason's) is missing is ``"damaged"``
(:data:`DAMAGED`): :func:`open_study` reports it so, with the missing files as its reason, and
a resumed run computes it again (:meth:`StudyStore.reset_damaged`). A missing chunk file of the
design (a varied quantity, the labels) is a :class:`StoreError`.
"""

from __future__ import annotations

import json
import os
import shutil
import time
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path

import numpy as np

from rollerrig._optional import require
from rollerrig._validation import ParameterError
from rollerrig.output import json_text

__all__ = [
    "DAMAGED",
    "FLUSH_SECONDS",
    "STATUSES",
    "StoreError",
    "StudyStore",
    "open_study",
    "remove_store",
]

STATUSES = ("ok", "solver failed", "invalid parameters", "pending")
"""The status a point can have in a store."""
FLUSH_SECONDS = 2.0
"""Finished points are written to the store at least this often [s]."""
DAMAGED = "damaged"
"""Status :func:`open_study` gives a finished point whose stored results are missing (a lost
chunk file); a resumed run computes it again."""
FORMAT_VERSION = 2
"""Version of the store layout (attribute ``rollerrig_study_store``). Version 2 writes every
chunk as a file (version 1 left out chunks of fill values, so a lost chunk could not be told
from an empty one)."""
_ALL_CHUNKS = {"write_empty_chunks": True}
"""zarr array configuration of every write: a chunk of fill values is a file too."""
MAX_METADATA_BYTES = 64 * 2**20
"""Largest ``zarr.json`` that :func:`remove_store` reads to check what it removes [bytes]."""


class StoreError(ParameterError):
    """A study store cannot be created, opened or resumed; the message says why and what to do."""


def _zarr():
    return require("zarr", purpose="the study store")


def _chunk(n: int) -> int:
    """Chunk length [points]: about 1000 points a chunk, never more than the study."""
    return max(1, min(n, 1024))


class StudyStore:
    """A study store on disk (create with :meth:`create`, reopen with :meth:`open`).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp()) / "demo.zarr"
    >>> store = StudyStore.create(
    ...     folder, attrs={"study": "demo", "study_sha256": "x"},
    ...     parameters={"load": (np.array([4300.0, 20e3]), {"units": "N"})},
    ...     labels=["load = 4.3 kN", "load = 20 kN"],
    ...     metrics={"peak_coa": {"units": "1"}})
    >>> store.pending().tolist()
    [0, 1]
    >>> store.record([(1, "ok", "", {"peak_coa": 0.42})]); store.flush()
    >>> StudyStore.open(folder, study_sha256="x").pending().tolist()
    [0]
    """

    def __init__(self, path: Path, group):
        self.path = Path(path)
        self._group = group
        self._buffer: list[tuple[int, str, str, Mapping[str, float]]] = []
        self._flushed = time.monotonic()
        self.metrics: tuple[str, ...] = tuple(json.loads(group.attrs["metrics"]))
        self.size = int(group["status"].shape[0])
        self.damaged, self.missing = _damage(group)

    # ------------------------------------------------------------------ create / open

    @classmethod
    def create(
        cls,
        path: str | os.PathLike,
        *,
        attrs: Mapping[str, object],
        parameters: Mapping[str, tuple[np.ndarray, Mapping[str, str]]],
        labels: Sequence[str],
        metrics: Mapping[str, Mapping[str, str]],
    ) -> StudyStore:
        """Create a store (the folder must not exist).

        Parameters
        ----------
        path : path
            The store's folder (``.zarr``).
        attrs : mapping
            Group attributes (the study, the provenance); values that are not text are stored
            as JSON text.
        parameters : mapping
            Key -> (values per point, attributes with ``units``).
        labels : sequence of str
            One per point.
        metrics : mapping
            Metric name -> attributes (``units``, ``long_name``, ``nan_meaning``).
        """
        zarr = _zarr()
        path = Path(path)
        n = len(labels)
        chunk = _chunk(n)
        tmp = path.with_name(f".{path.name}.creating-{os.getpid()}")
        group = zarr.open_group(tmp, mode="w")
        for key, (values, a) in parameters.items():
            values = np.asarray(values)
            kind = str if values.dtype.kind in "OUS" else "f8"
            arr = group.create_array(key, shape=(n,), chunks=(chunk,), dtype=kind)
            arr = arr.with_config(_ALL_CHUNKS)
            arr[:] = values.astype(str) if kind is str else values.astype(float)
            arr.attrs.update(dict(a))
        for name, fill in (("label", ""), ("status", "pending"), ("reason", "")):
            arr = group.create_array(name, shape=(n,), chunks=(chunk,), dtype=str, fill_value=fill)
            if name == "label":
                arr.with_config(_ALL_CHUNKS)[:] = np.asarray(labels, dtype=str)
        for name, a in metrics.items():
            arr = group.create_array(
                name, shape=(n,), chunks=(chunk,), dtype="f8", fill_value=np.nan
            )
            arr.attrs.update(dict(a))
        plain = {k: v if isinstance(v, str) else json.dumps(v) for k, v in attrs.items()}
        plain["parameters"] = json.dumps(list(parameters))
        plain["metrics"] = json.dumps(list(metrics))
        plain["rollerrig_study_store"] = str(FORMAT_VERSION)
        group.attrs.update(plain)
        # Whole or not at all: the folder appears under its name only once complete.
        os.replace(tmp, path)
        return cls(path, zarr.open_group(path, mode="r+"))

    @classmethod
    def open(cls, path: str | os.PathLike, *, study_sha256: str | None = None) -> StudyStore:
        """Reopen a store to resume it; with ``study_sha256``, check it holds that study.

        Finished points whose results chunk files are missing are listed in ``damaged`` (the
        missing files in ``missing``): :meth:`status` gives them as :data:`DAMAGED` and
        :meth:`pending` includes them; :meth:`reset_damaged` marks them pending in the store.
        """
        path = Path(path)
        group = _open_group(path, "r+")
        if study_sha256 is not None and group.attrs.get("study_sha256") != study_sha256:
            raise StoreError(
                f"{path}: this store holds another study (the study file changed since it was "
                f"started: {group.attrs.get('study_origin', '?')}); run with --restart to start "
                "again, or choose another --out"
            )
        return cls(path, group)

    # ------------------------------------------------------------------ points

    def status(self) -> np.ndarray:
        """Status of every point (:data:`DAMAGED` for a point whose results are missing)."""
        status = _text(_read(self._group, "status"))
        return _marked(status, self.damaged, DAMAGED)

    def pending(self) -> np.ndarray:
        """Indices of the points not yet run, or damaged (excluding those in the write
        buffer)."""
        buffered = {i for i, *_ in self._buffer}
        todo = np.flatnonzero(np.isin(self.status(), ("pending", DAMAGED)))
        return np.array([i for i in todo if i not in buffered], dtype=int)

    def reset_damaged(self) -> int:
        """Mark the damaged points pending in the store (so that an interruption while they
        are computed again cannot leave them ``ok`` without their values); returns how many."""
        n = int(self.damaged.size)
        if n:
            self._write("status", self.damaged, np.array(["pending"] * n))
            self._write("reason", self.damaged, np.array([""] * n))
            self.damaged = np.array([], dtype=int)
        return n

    def record(self, rows: Iterable[tuple[int, str, str, Mapping[str, float]]]) -> None:
        """Add finished points ``(index, status, reason, metrics)``; written by :meth:`flush`
        (called here when :data:`FLUSH_SECONDS` have passed since the last write)."""
        for row in rows:
            if row[1] not in STATUSES[:-1]:
                raise ValueError(f"point {row[0]}: status {row[1]!r} not in {STATUSES[:-1]}")
            self._buffer.append(row)
        if time.monotonic() - self._flushed >= FLUSH_SECONDS:
            self.flush()

    def flush(self) -> None:
        """Write the buffered points (metrics and reasons first, the status last: a point
        whose status says it finished has its numbers)."""
        self._flushed = time.monotonic()
        if not self._buffer:
            return
        rows = sorted(self._buffer, key=lambda r: r[0])
        index = np.array([r[0] for r in rows])
        for name in self.metrics:
            values = np.array([r[3].get(name, np.nan) for r in rows], dtype=float)
            self._write(name, index, values)
        self._write("reason", index, np.array([r[2] for r in rows], dtype=str))
        self._write("status", index, np.array([r[1] for r in rows], dtype=str))
        self._buffer.clear()

    def note_run(self, record: Mapping[str, object]) -> None:
        """Append one run's record (where it ran and why, its timings) to the store's ``runs``
        attribute, a JSON list: one entry per run that computed points."""
        runs = json.loads(self._group.attrs.get("runs", "[]"))
        runs.append(dict(record))
        self._group.attrs["runs"] = json_text(runs)  # the package's JSON: no NaN, no noise

    def _write(self, name: str, index: np.ndarray, values: np.ndarray) -> None:
        arr = self._group[name].with_config(_ALL_CHUNKS)
        chunk = arr.chunks[0]
        # One write per chunk touched (a chunk is rewritten whole, atomically): points of one
        # batch may be strided over the grid, and a write per point would rewrite a chunk each.
        for c in np.unique(index // chunk):
            lo, hi = int(c * chunk), int(min(self.size, (c + 1) * chunk))
            sel = (index >= lo) & (index < hi)
            current = _read(self._group, name, slice(lo, hi))
            current[index[sel] - lo] = values[sel]
            arr[lo:hi] = current

    # ------------------------------------------------------------------ reading

    def dataset(self):
        """The store as an ``xarray.Dataset`` (dimension ``point``)."""
        self.flush()
        return _dataset(self._group)


def _text(values) -> np.ndarray:
    """Text read from zarr (numpy's StringDType) as a plain unicode array."""
    return np.asarray(np.asarray(values).tolist(), dtype=str).reshape(np.shape(values))


def _is_text(arr) -> bool:
    return np.dtype(arr.dtype).kind in "OUST"


def _read(group, name: str, where: slice = slice(None)) -> np.ndarray:
    """Values of one array of a store; a damaged chunk is a :class:`StoreError`, not a codec's
    exception."""
    try:
        return group[name][where]
    except Exception as exc:  # zarr and its codecs raise many types for a damaged chunk
        raise StoreError(
            f"{group.store}: the stored values of {name!r} cannot be read ({type(exc).__name__}: "
            f"{exc}); the store is damaged: run again with --restart to compute the study anew"
        ) from None


def _damage(group) -> tuple[np.ndarray, tuple[str, ...]]:
    """``(points, files)``: the finished points whose results chunk files are missing, and
    those files (relative to the store); a missing chunk file of the design is a
    :class:`StoreError`.

    ``flush`` writes each touched chunk of every metric and of ``reason`` before the chunk of
    ``status``, and every chunk is a file (format version 2): a ``status`` chunk file without
    its companions means they were lost after they were written.
    """
    root = getattr(group.store, "root", None)
    if root is None:  # not a folder: nothing to check (the package writes folders only)
        return np.array([], dtype=int), ()
    root = Path(root)
    attrs = group.attrs
    status = group["status"]
    n, chunk = int(status.shape[0]), int(status.chunks[0])
    count = -(-n // chunk)

    def missing(name: str) -> list[int]:
        arr = group[name]
        return [
            c
            for c in range(count)
            if not (root / arr.path / arr.metadata.encode_chunk_key((c,))).is_file()
        ]

    def file(name: str, c: int) -> str:
        return f"{name}/{group[name].metadata.encode_chunk_key((c,))}"

    design = [*json.loads(attrs["parameters"]), "label"]
    lost = [file(name, c) for name in design for c in missing(name)]
    if lost:
        shown = ", ".join(lost[:5]) + (f" and {len(lost) - 5} more" if len(lost) > 5 else "")
        raise StoreError(
            f"{root}: the store is damaged: chunk files of the design are missing ({shown}); "
            "run again with --restart to compute the study anew"
        )
    written = set(range(count)) - set(missing("status"))
    lost: dict[int, list[str]] = {}
    for name in [*json.loads(attrs["metrics"]), "reason"]:
        for c in missing(name):
            if c in written:
                lost.setdefault(c, []).append(file(name, c))
    points, files = [], []
    for c in sorted(lost):
        lo, hi = c * chunk, min(n, (c + 1) * chunk)
        finished = np.flatnonzero(_text(_read(group, "status", slice(lo, hi))) != "pending")
        if finished.size:  # a chunk whose points are all pending has nothing to lose
            points.extend(lo + finished)
            files.extend(lost[c])
    return np.array(points, dtype=int), tuple(files)


def _dataset(group):
    xr = require("xarray", purpose="reading a study store")
    damaged, lost = _damage(group)
    attrs = dict(group.attrs)
    data = {}
    for key in json.loads(attrs["parameters"]):
        arr = group[key]
        values = _read(group, key)
        data[key] = (
            "point",
            _text(values) if _is_text(arr) else np.asarray(values, dtype=float),
            dict(arr.attrs),
        )
    for name in ("label", "status", "reason"):
        data[name] = ("point", _text(_read(group, name)))
    for name in json.loads(attrs["metrics"]):
        data[name] = ("point", np.asarray(_read(group, name), dtype=float), dict(group[name].attrs))
    if damaged.size:
        reason = _one_line(
            f"its results are missing from the store (lost chunk files: {', '.join(lost)}); "
            "study run into the same --out computes it again"
        )
        data["status"] = ("point", _marked(data["status"][1], damaged, DAMAGED))
        data["reason"] = ("point", _marked(data["reason"][1], damaged, reason))
        for name in json.loads(attrs["metrics"]):
            data[name][1][damaged] = np.nan
        attrs["damaged_files"] = json.dumps(list(lost))
    n = int(group["status"].shape[0])
    return xr.Dataset(data, coords={"point": np.arange(n)}, attrs=attrs)


def open_study(path: str | os.PathLike):
    """Read a study store as an ``xarray.Dataset``.

    Parameters
    ----------
    path : path
        The store's folder (``<study>.zarr``, written by ``rollerrig study run``).

    Returns
    -------
    xarray.Dataset
        Dimension ``point``; the varied quantities, ``label``, ``status``, ``reason`` and the
        metrics as variables; the study and provenance as attributes (JSON text).

    Raises
    ------
    StoreError
        When the folder is not a study store.
    """
    return _dataset(
        _open_group(Path(path), "r", "give the study-NAME.zarr folder that study run wrote")
    )


def _marked(values: np.ndarray, index: np.ndarray, text: str) -> np.ndarray:
    """``values`` (text) with ``text`` at ``index`` (the array widened to hold it)."""
    mask = np.zeros(values.shape, dtype=bool)
    mask[index] = True
    return np.where(mask, text, values).astype(str)


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def _not_a_store(path: Path, hint: str) -> StoreError | None:
    """The error for a path that cannot be a study store, said in words before zarr is asked
    (whose errors name its own exception types: "GroupNotFoundError: No group found in store
    PosixPath(...)"), or None where zarr is to decide."""
    where = f"{path}: not a rollerrig study store"
    if not path.exists():
        return StoreError(f"{where}: nothing there; {hint}")
    if not path.is_dir():
        return StoreError(f"{where}: a file, and a store is a folder; {hint}")
    if (path / "zarr.json").is_file() or (path / ".zgroup").is_file():
        return None
    # The folder given for --out: the stores study run wrote into it are what was meant
    inside = sorted(p.name for p in path.glob("*.zarr") if (p / "zarr.json").is_file())
    if inside:
        shown = ", ".join(inside[:5]) + (f" and {len(inside) - 5} more" if len(inside) > 5 else "")
        return StoreError(f"{where} but a folder holding {shown}: give {path / inside[0]}")
    return StoreError(f"{where}: a folder without the store's zarr.json; {hint}")


def _open_group(path: Path, mode: str, hint: str = "remove it or choose another --out"):
    """The zarr group of a study store of this version, or :class:`StoreError`."""
    problem = _not_a_store(path, hint)
    if problem is not None:
        raise problem
    zarr = _zarr()
    try:
        group = zarr.open_group(path, mode=mode)
        version = group.attrs.get("rollerrig_study_store")
    except Exception as exc:  # zarr raises several types for a folder that is not a store
        raise StoreError(
            f"{path}: not a rollerrig study store ({type(exc).__name__}: {exc}); {hint}"
        ) from None
    if isinstance(version, str) and version.isdigit() and int(version) < FORMAT_VERSION:
        raise StoreError(
            f"{path}: a study store written by an older rollerrig (store version {version}, "
            f"this one reads {FORMAT_VERSION}); run the study again with --restart"
        )
    if version != str(FORMAT_VERSION):
        raise StoreError(
            f"{path}: not a rollerrig study store of this version (found {version!r}); {hint}"
        )
    return group


def _store_attributes(path: Path) -> dict | None:
    """The group attributes of the zarr store at ``path`` read from its ``zarr.json`` (a plain
    file, at most :data:`MAX_METADATA_BYTES`), or None when it has none."""
    meta = path / "zarr.json"
    try:
        if not meta.is_file() or meta.is_symlink() or meta.stat().st_size > MAX_METADATA_BYTES:
            return None
        doc = json.loads(meta.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError):
        return None
    if not isinstance(doc, dict) or doc.get("node_type") != "group":
        return None
    attrs = doc.get("attributes")
    return attrs if isinstance(attrs, dict) else None


def remove_store(path: str | os.PathLike, *, study: str) -> None:
    """Remove the study store at ``path`` (``--restart``), only if it is one of study ``study``.

    Anything else at ``path`` (a symbolic link, a file, a plain folder, a zarr store that is
    not a rollerrig study store, the store of another study) is refused with a
    :class:`StoreError` naming it, and nothing is removed. The store is first renamed to a
    hidden name beside it (so an interruption never leaves half a store under its name), then
    removed without following symbolic links. Nothing at ``path``: nothing to do.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> (folder / "photos").mkdir()
    >>> remove_store(folder / "photos", study="demo")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    rollerrig.studies.store.StoreError: .../photos: not a rollerrig study store; nothing was ...
    """
    path = Path(path)
    keep = "nothing was removed; remove it yourself or choose another --out"
    if path.is_symlink():
        raise StoreError(f"{path}: a symbolic link, not a study store folder; {keep}")
    if not path.exists():
        return
    if not path.is_dir():
        raise StoreError(f"{path}: a file, not a study store; {keep}")
    attrs = _store_attributes(path)
    if attrs is None or "rollerrig_study_store" not in attrs:
        raise StoreError(f"{path}: not a rollerrig study store; {keep}")
    if attrs.get("study") != study:
        raise StoreError(
            f"{path}: the store of another study ({attrs.get('study')!r}, not {study!r}); {keep}"
        )
    doomed = path.with_name(f".{path.name}.removing-{os.getpid()}")
    os.replace(path, doomed)
    shutil.rmtree(doomed)
