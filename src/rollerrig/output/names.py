"""Safe names of output files: one function, used by every writer of a name from user data.

A name that comes from user data (a study's name, an experiment's name, a recording's stem)
becomes a file name in the output folder only through :func:`safe_file_name`, so that no name
can leave the folder (``../x``, ``a/b``), hide a file (a leading dot), or exceed what file
systems accept.
"""

from __future__ import annotations

import re

__all__ = ["MAX_OUTPUT_STEM", "safe_file_name"]

MAX_OUTPUT_STEM = 120
"""Longest output file stem [characters] (the suffix is kept whole)."""


def safe_file_name(name: str) -> str:
    """``name`` as a plain, portable file name.

    Every character other than letters, digits, ``.``, ``_``, ``-`` and ``+`` becomes ``_``
    (so a path separator cannot make a folder), leading dots are dropped (a hidden name would
    be taken for a writer's temporary file, and ``..`` must not climb out of the output
    folder), an empty name becomes ``_``, and the stem is cut to :data:`MAX_OUTPUT_STEM`
    characters (file systems refuse names over 255 bytes).

    Examples
    --------
    >>> safe_file_name("../escaped.nc"), safe_file_name("run 05 [wet].png")
    ('_escaped.nc', 'run_05__wet_.png')
    >>> safe_file_name("study-x/../../../escaped.zarr"), safe_file_name("")
    ('study-x_.._.._.._escaped.zarr', '_')
    """
    text = re.sub(r"[^A-Za-z0-9._+-]", "_", str(name)).lstrip(".") or "_"
    stem, dot, suffix = text.rpartition(".")
    if not dot or not stem:
        stem, suffix = text, ""
    stem = stem[:MAX_OUTPUT_STEM]
    return f"{stem}.{suffix}" if suffix else stem
