"""Safe names of output files: one function, used by every writer of a name from user data.

A name that comes from user data (a study's name, an experiment's name, a recording's stem)
becomes a file name in the output folder only through :func:`safe_file_name`, so that no name
can leave the folder (``../x``, ``a/b``), hide a file (a leading dot), be refused by a common
file system (Windows' forbidden characters and reserved names, over 255 bytes), or exceed what
file systems accept. Letters and digits of any script are kept (``试验一``, ``Messdaten_ä``), so
that two recordings whose names differ only in non-ASCII letters keep different outputs.

Where several inputs of one command give output names, :func:`unique_file_stems` makes them
distinct (``run-1``, ``run-2``) after they were made safe, so that no output replaces another.
"""

from __future__ import annotations

import unicodedata
from collections import Counter
from collections.abc import Iterable

from rollerrig._validation import require_names

__all__ = [
    "MAX_INPUT_STEM",
    "MAX_NAME_BYTES",
    "MAX_OUTPUT_STEM",
    "safe_file_name",
    "safe_file_stem",
    "unique_file_stems",
]

MAX_OUTPUT_STEM = 200
"""Longest output file stem [bytes of UTF-8; for ASCII, characters] (the suffix is kept)."""

MAX_INPUT_STEM = 120
"""Longest stem taken from an input's name [bytes of UTF-8] (:func:`safe_file_stem`): writers
append their own endings (``-filter-ranking.png``, ``-2``), which must fit under
:data:`MAX_OUTPUT_STEM`, so that two outputs of one input never lose what tells them apart."""

MAX_NAME_BYTES = 255
"""Longest file name [bytes of UTF-8] that common file systems accept (ext4, APFS, NTFS)."""

_KEPT = frozenset("._+-")
_WINDOWS_RESERVED = frozenset(
    {"CON", "PRN", "AUX", "NUL"}
    | {f"{dev}{n}" for dev in ("COM", "LPT") for n in (*"123456789", "¹", "²", "³")}
)


def _cut(text: str, limit: int) -> str:
    """``text`` cut to at most ``limit`` bytes of UTF-8, at a character boundary."""
    data = text.encode("utf-8")
    if len(data) <= limit:
        return text
    return data[:limit].decode("utf-8", "ignore")


def _plain(name: str) -> str:
    """NFC; letters, digits (any script) and ``._+-`` kept, the rest ``_``; no edge dots."""
    text = unicodedata.normalize("NFC", str(name))
    text = "".join(c if c.isalnum() or c in _KEPT else "_" for c in text)
    return text.strip(".")


def _not_reserved(stem: str) -> str:
    """A Windows device name (``CON``, ``nul.tar``, ``COM1``) with a ``_`` after it."""
    head, dot, rest = stem.partition(".")
    return f"{head}_{dot}{rest}" if head.upper() in _WINDOWS_RESERVED else stem


def safe_file_name(name: str) -> str:
    """``name`` as a plain, portable file name.

    The name is put in Unicode normal form C (a decomposed ``a`` + ``¨`` from macOS is one
    ``ä``); letters and digits of every script (:meth:`str.isalnum`), ``.``, ``_``, ``-`` and
    ``+`` are kept, every other character becomes ``_`` (path separators, control characters,
    spaces and what Windows forbids, ``<>:"/\\|?*``, so a name cannot make a folder); leading
    dots are dropped (a hidden name would be taken for a writer's temporary file, and ``..``
    must not climb out of the output folder) and trailing dots too (Windows drops them); a
    Windows reserved device name (``CON``, ``nul.txt``, ``COM1``) gets a ``_``; an empty name
    becomes ``_``; and the stem is cut to :data:`MAX_OUTPUT_STEM` bytes of UTF-8, the whole
    name to :data:`MAX_NAME_BYTES` (file systems refuse names over 255 bytes).

    Examples
    --------
    >>> safe_file_name("../escaped.nc"), safe_file_name("run 05 [wet].png")
    ('_escaped.nc', 'run_05__wet_.png')
    >>> safe_file_name("study-x/../../../escaped.zarr"), safe_file_name("")
    ('study-x_.._.._.._escaped.zarr', '_')
    >>> safe_file_name("试验一-spectrum.png"), safe_file_name("con.json")
    ('试验一-spectrum.png', 'con_.json')
    """
    text = _plain(name) or "_"
    stem, dot, suffix = text.rpartition(".")
    if not dot or not stem:
        stem, suffix = text, ""
    stem = _not_reserved(_cut(stem, MAX_OUTPUT_STEM).rstrip(".") or "_")
    if suffix:
        suffix = _cut(suffix, MAX_NAME_BYTES - len(stem.encode("utf-8")) - 1).rstrip(".")
    return f"{stem}.{suffix}" if suffix else stem


def safe_file_stem(name: str) -> str:
    """``name`` (an input's stem, a study's name) as the safe start of output names.

    The rules of :func:`safe_file_name`, with the whole name taken as the stem (``run.v2`` has
    no suffix here) and cut to :data:`MAX_INPUT_STEM` bytes, so that a writer's ending fits.

    >>> safe_file_stem("Messdaten ä.v2"), safe_file_stem("nul")
    ('Messdaten_ä.v2', 'nul_')
    """
    return _not_reserved(_cut(_plain(name), MAX_INPUT_STEM).rstrip(".") or "_")


def _key(name: str) -> str:
    """What a case-insensitive file system (Windows, macOS) compares."""
    return name.casefold()


def unique_file_stems(names: Iterable[str]) -> list[str]:
    """Each of ``names`` made safe (:func:`safe_file_stem`) and distinct from the others.

    A safe name that two or more inputs share (identical stems, or stems that differ only in
    characters made ``_``, or only in case, which Windows and macOS do not tell apart) gets the
    input's position: ``run-1``, ``run-2``; one that is unique stays as it is.

    >>> unique_file_stems(["run", "run", "a b", "a_b", "试验一"])
    ['run-1', 'run-2', 'a_b-3', 'a_b-4', '试验一']

    A single name is refused (it had been taken letter by letter, ``"run"`` as three names),
    as :func:`rollerrig.output.varnames.storable_names` refuses it.
    """
    names = require_names("names", names)
    safe = [safe_file_stem(n) for n in names]
    counts = Counter(_key(s) for s in safe)
    taken = {_key(s) for s in safe if counts[_key(s)] == 1}
    result = []
    for i, s in enumerate(safe):
        if counts[_key(s)] == 1:
            result.append(s)
            continue
        tag, extra = f"-{i + 1}", 0
        candidate = _cut(s, MAX_INPUT_STEM - len(tag)) + tag
        while _key(candidate) in taken:  # e.g. inputs "x", "x" and "x-1"
            extra += 1
            tag = f"-{i + 1}-{extra}"
            candidate = _cut(s, MAX_INPUT_STEM - len(tag)) + tag
        taken.add(_key(candidate))
        result.append(candidate)
    return result
