"""Atomic output writing and provenance records shared by every writer of the package."""

from __future__ import annotations

import json
import os
import platform
import tempfile
from collections.abc import Callable
from datetime import UTC, datetime
from pathlib import Path

import numpy as np

__all__ = ["NULL_VALUES_KEY", "atomic_write", "provenance", "save_figure", "write_json"]


def provenance(**parameters) -> dict:
    """A provenance record: package version, time, platform and the given parameters."""
    from rollerrig import __version__

    return {
        "software": "rollerrig",
        "version": __version__,
        "created_utc": datetime.now(UTC).isoformat(timespec="seconds"),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "parameters": parameters,
    }


def atomic_write(path: str | os.PathLike, write: Callable[[Path], None]) -> Path:
    """Call ``write(tmp_path)`` and move the result onto ``path`` in one step.

    A reader never sees a half-written file, and a failure leaves any previous file intact.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}-", suffix=path.suffix, dir=path.parent)
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        write(tmp_path)
        # mkstemp makes the file 0600; an output is a new file like any other, readable by
        # group/others as the umask allows (colleagues, a web server serving the report).
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp_path, 0o666 & ~umask)
        os.replace(tmp_path, path)
    finally:
        if tmp_path.exists():
            tmp_path.unlink()
    return path


def _json_default(obj):
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


NULL_VALUES_KEY = "null_values"
"""Key under which :func:`write_json` lists the non-finite numbers it wrote as null."""


def _finite_json(obj, where: str, replaced: list):
    """``obj`` with every NaN/inf float replaced by None, each replacement recorded."""
    if isinstance(obj, dict):
        return {k: _finite_json(v, f"{where}/{k}", replaced) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_finite_json(v, f"{where}/{i}", replaced) for i, v in enumerate(obj)]
    if isinstance(obj, np.ndarray):
        return _finite_json(obj.tolist(), where, replaced)
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not np.isfinite(obj):
        replaced.append({"at": where or "/", "was": repr(obj)})
        return None
    return obj


def write_json(path: str | os.PathLike, obj) -> Path:
    """Write ``obj`` as indented JSON, atomically; never NaN or inf.

    NaN policy: JSON has no NaN or inf, and the package never writes them. Producers give
    ``None`` with a reason beside it wherever a number cannot be given; a non-finite float
    that still arrives here is written as ``null`` and listed, with its location (a
    ``/``-separated path) and its value, under the top-level key ``"null_values"`` (so a
    ``null`` never goes unexplained). A top-level value other than a dict holding a
    non-finite number is refused (``ValueError``), as is anything ``json`` cannot write.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = write_json(pathlib.Path(tempfile.mkdtemp()) / "x.json", {"a": float("nan")})
    >>> json.loads(p.read_text())["null_values"][0]["at"]
    '/a'
    """
    replaced: list = []
    clean = _finite_json(obj, "", replaced)
    if replaced:
        if not isinstance(clean, dict):
            raise ValueError(
                f"{path}: non-finite numbers at {[r['at'] for r in replaced]} and no top-level "
                "object to state why they are null"
            )
        clean[NULL_VALUES_KEY] = [
            {**r, "why": "not a finite number; written as null"} for r in replaced
        ]
    text = json.dumps(clean, indent=2, default=_json_default, allow_nan=False)
    return atomic_write(path, lambda p: p.write_text(text + "\n", encoding="utf-8"))


def save_figure(
    fig, path: str | os.PathLike, *, dpi: int = 150, metadata: dict | None = None
) -> Path:
    """Save a matplotlib figure atomically (format from the suffix), with text metadata, and
    close it."""
    path = Path(path)
    fmt = path.suffix.lstrip(".") or "png"
    meta = {"Software": "rollerrig"}
    if metadata and fmt == "png":
        meta.update({k: json.dumps(v, default=_json_default) for k, v in metadata.items()})
    written = atomic_write(
        path,
        lambda p: fig.savefig(p, format=fmt, dpi=dpi, bbox_inches="tight", metadata=meta),
    )
    import matplotlib.pyplot as plt

    plt.close(fig)  # a long session (CLI, demo, tests) must not pile up open figures
    return written
