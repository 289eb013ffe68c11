"""Figures: saved atomically with their provenance embedded, then closed."""

from __future__ import annotations

import os
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from rollerrig._validation import ParameterError, require_in_range
from rollerrig.output.atomic import OutputError, atomic_write, file_path
from rollerrig.output.jsonfile import json_text
from rollerrig.output.provenance import is_provenance, provenance

__all__ = [
    "FIGURE_FORMATS",
    "crop_to_drawing",
    "crop_when_saved",
    "figure_provenance",
    "save_figure",
    "typeset_figure_units",
]

FIGURE_FORMATS = ("png", "svg", "pdf")
"""Figure formats that can carry the provenance inside the file."""

PNG_PROVENANCE_KEY = "rollerrig_provenance"
"""PNG text chunk holding the provenance record (JSON)."""


def typeset_figure_units(fig) -> None:
    """Units in every text of ``fig`` typeset as a paper prints them (``N.m`` -> ``N·m``).

    Labels are built from units as recordings and the package store them (``N.m``,
    ``kg.m^2``, ``(N.m)²``); this typesets them once, where every figure passes
    (:func:`rollerrig._display.typeset_units`: only tokens made of unit symbols change, never
    words, file names or numbers). Mathtext (``$...$``) is left as it is.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> fig, ax = plt.subplots()
    >>> _ = ax.set_ylabel("power [(N.m)²]"); _ = ax.set_title("seed-30kmh-dry.tdms, J5 in kg.m^2")
    >>> typeset_figure_units(fig)
    >>> ax.get_ylabel(), ax.get_title()
    ('power [(N·m)²]', 'seed-30kmh-dry.tdms, J5 in kg·m²')
    >>> plt.close(fig)
    """
    from rollerrig._display import typeset_units

    for artist in _labels(fig):
        text = artist.get_text()
        if text and "$" not in text:
            typeset = typeset_units(text)
            if typeset != text:
                artist.set_text(typeset)


def _labels(fig):
    """The texts of ``fig`` that words and units are written in: the figure's and every axes'
    titles, axis labels, texts, annotations and legends (not the tick labels, numbers that
    matplotlib formats; walking every artist cost 0.1 s on the six-panel experiment figure)."""
    yield from fig.texts
    legends = list(fig.legends)
    for ax in fig.axes:
        yield from (ax.title, ax._left_title, ax._right_title)
        yield from (ax.xaxis.label, ax.yaxis.label)
        yield from ax.texts
        if ax.get_legend() is not None:
            legends.append(ax.get_legend())
    for legend in legends:
        yield legend.get_title()
        yield from legend.get_texts()


_PNG_COMPRESS_LEVEL = 3  # zlib level of PNG figures (save_figure)


def _metadata(fmt: str, record: dict[str, Any]) -> dict[str, str]:
    """matplotlib ``savefig(metadata=...)`` for ``fmt`` carrying ``record`` as JSON text."""
    software = f"rollerrig {record.get('version', '')}".strip()
    text = json_text(record)
    if fmt == "png":  # tEXt/iTXt chunks, any key
        return {"Software": software, PNG_PROVENANCE_KEY: text}
    if fmt == "svg":  # Dublin Core in <metadata>
        return {"Creator": software, "Description": text}
    return {"Creator": software, "Subject": text}  # PDF document information


def figure_provenance(path: str | os.PathLike) -> dict[str, Any] | None:
    """The provenance record embedded in a PNG, SVG or PDF written by :func:`save_figure`."""
    import html
    import json
    import re

    p = file_path(path)
    fmt = p.suffix.lower().lstrip(".")
    if fmt == "png":
        from PIL import Image

        with Image.open(p) as im:
            text = im.text.get(PNG_PROVENANCE_KEY)  # type: ignore[attr-defined]
    elif fmt == "svg":
        svg = p.read_text(encoding="utf-8")
        m = re.search(r"<dc:description>(.*?)</dc:description>", svg, re.S)
        text = None if m is None else html.unescape(m.group(1))
    elif fmt == "pdf":
        raw = p.read_bytes()
        m = re.search(rb"/Subject\s*(\((?:\\.|[^\\)])*\)|<[0-9A-Fa-f\s]*>)", raw)
        text = None if m is None else _pdf_string(m.group(1))
    else:
        return None
    return None if text is None else json.loads(text)


def _pdf_string(token: bytes) -> str:
    """Text of a PDF string object (literal ``(...)`` or hex ``<...>``, PDFDoc or UTF-16)."""
    if token.startswith(b"<"):
        data = bytes.fromhex(token[1:-1].decode("ascii"))
    else:
        body, out, i = token[1:-1], bytearray(), 0
        escapes = {b"n": b"\n", b"r": b"\r", b"t": b"\t", b"b": b"\b", b"f": b"\f"}
        while i < len(body):
            c = body[i : i + 1]
            if c == b"\\" and i + 1 < len(body):
                nxt = body[i + 1 : i + 2]
                if nxt.isdigit():
                    j = i + 1
                    while j < min(i + 4, len(body)) and body[j : j + 1].isdigit():
                        j += 1
                    out.append(int(body[i + 1 : j], 8) & 0xFF)
                    i = j
                    continue
                out += escapes.get(nxt, nxt)
                i += 2
                continue
            out += c
            i += 1
        data = bytes(out)
    if data.startswith(b"\xfe\xff"):
        return data[2:].decode("utf-16-be")
    return data.decode("latin-1")


_CROP_ATTRIBUTE = "_rollerrig_crop_to_drawing"


def crop_when_saved(fig) -> None:
    """Have ``fig`` cropped to what is drawn when it is saved (:func:`crop_to_drawing`).

    For a figure that draws past the canvas its layout made: labels placed after
    ``tight_layout`` (:func:`rollerrig.report.labels.label_peaks`), 3D axes, whose projected
    ticks and labels the layout does not see.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure; marked, nothing else changes.
    """
    setattr(fig, _CROP_ATTRIBUTE, True)


def crop_to_drawing(fig, tight: bool | None = None) -> str | None:
    """``bbox_inches`` for ``fig.savefig``: ``"tight"`` to crop to what is drawn, else None.

    With ``tight`` None (the default of every figure the package saves), a figure is cropped
    when it has no layout of its own or asked for it (:func:`crop_when_saved`).
    ``tight_layout()`` and the constrained layout (``fig.get_layout_engine()`` is set after
    either) place every axes, label, title and axes legend inside the canvas; cropping such a
    figure trims a margin of a few pixels and costs a second, draw-only pass over all its
    artists: up to 0.8 s a figure (the demo's 19 figures, all cropped 12.6 s, none 9.2 s; its
    spectra, which ask for cropping, keep it). Checked over the 177 figures the CLI, report,
    output and frame tests save: nothing else is drawn outside the canvas.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure about to be saved.
    tight : bool, optional
        True: crop; False: keep the canvas; None: decide as above.

    Returns
    -------
    str or None
        ``"tight"`` or None, for ``bbox_inches``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> fig, ax = plt.subplots()
    >>> crop_to_drawing(fig)
    'tight'
    >>> fig.tight_layout()
    >>> crop_to_drawing(fig), crop_to_drawing(fig, tight=True)
    (None, 'tight')
    >>> crop_when_saved(fig)
    >>> crop_to_drawing(fig)
    'tight'
    >>> plt.close(fig)
    """
    if tight is None:
        tight = getattr(fig, _CROP_ATTRIBUTE, False) or fig.get_layout_engine() is None
    return "tight" if tight else None


def save_figure(
    fig,
    path: str | os.PathLike,
    *,
    dpi: int = 150,
    tight: bool | None = None,
    metadata: dict[str, Any] | None = None,
    overwrite: bool = True,
) -> Path:
    """Save a matplotlib figure atomically, with its provenance embedded, and close it.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        Closed after saving (also when saving fails): a long session must not pile up figures.
    path : str or path-like
        Target; the format follows the suffix: ``.png`` (text chunk ``rollerrig_provenance``),
        ``.svg`` (``dc:description``) or ``.pdf`` (document ``Subject``), each holding the
        record as JSON (:func:`figure_provenance` reads it back).
    dpi : int
        Resolution of raster output [dots per inch].
    tight : bool, optional
        Crop to what is drawn (``bbox_inches="tight"``: the figure is drawn once more to find
        it) or keep the figure's own size and layout, drawn once. Default:
        :func:`crop_to_drawing` (crop only a figure without a layout of its own, or one marked
        by :func:`crop_when_saved`). A figure laid out with ``tight_layout()`` that then gets
        texts or legends outside its axes (``fig.text``, ``fig.legend``, a later suptitle)
        needs ``tight=True`` or :func:`crop_when_saved`, else they may be cut.
    metadata : dict, optional
        A provenance record (:func:`rollerrig.output.provenance`) to embed as it is, or extra
        parameters for a new one.
    overwrite : bool
        Replace an existing file (default).

    Raises
    ------
    OutputError
        Another suffix (no place for the provenance), or the file cannot be written.

    Examples
    --------
    >>> import tempfile, pathlib, matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> fig, ax = plt.subplots()
    >>> p = save_figure(fig, pathlib.Path(tempfile.mkdtemp()) / "f.png", metadata={"run": 1})
    >>> figure_provenance(p)["parameters"]
    {'run': 1}
    """
    try:
        path = file_path(path)  # None had been a bare TypeError, the figure left open
        fmt = path.suffix.lower().lstrip(".")
        if fmt not in FIGURE_FORMATS:
            raise OutputError(
                f"{path}: figures are written as {', '.join('.' + f for f in FIGURE_FORMATS)} "
                "(formats that carry the provenance); change the suffix"
            )
        if not hasattr(fig, "savefig"):
            raise ParameterError(
                f"{path}: fig must be a matplotlib Figure, got a {type(fig).__name__}"
            )
        # A dpi of 0 or NaN reached matplotlib's own error; 1e7 its image-size error.
        dpi = require_in_range(
            "dpi",
            dpi,
            1.0,
            10_000.0,
            "dots per inch",
            low_inclusive=True,
            high_inclusive=True,
            single=True,
        )
        if metadata is not None and not isinstance(metadata, Mapping):
            raise ParameterError(
                f"{path}: metadata must be a dict (a provenance record or extra parameters), "
                f"got a {type(metadata).__name__}"
            )
        record = metadata if is_provenance(metadata) else provenance(**(metadata or {}))
        meta = _metadata(fmt, dict(record))  # type: ignore[arg-type]
        typeset_figure_units(fig)
        # PNG at zlib level 3, not PIL's 6: the experiment figure's encoding takes 38 against
        # 70 ms for a file 3 % larger (208 against 202 KiB, 2026-12-01; level 9: 300 ms).
        extra = {"pil_kwargs": {"compress_level": _PNG_COMPRESS_LEVEL}} if fmt == "png" else {}
        return atomic_write(
            path,
            lambda p: fig.savefig(
                p,
                format=fmt,
                dpi=dpi,
                bbox_inches=crop_to_drawing(fig, tight),
                metadata=meta,
                **extra,
            ),
            overwrite=overwrite,
        )
    finally:
        # A long session (CLI, demo, tests) must not pile up open figures. Only pyplot holds
        # figures open: without it imported there is none to close (and no import to pay).
        pyplot = sys.modules.get("matplotlib.pyplot")
        if pyplot is not None:
            pyplot.close(fig)
