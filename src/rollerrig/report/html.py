"""A self-contained HTML report: figures embedded as PNG, tables, provenance; no external assets."""

from __future__ import annotations

import base64
import html
import io
import json
import os
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from rollerrig._display import number, typeset_units
from rollerrig._validation import ParameterError, require_in_range, require_whole
from rollerrig.output import write_text

__all__ = ["HtmlReport", "math_html", "prose", "relative_paths"]

# The page never scrolls sideways: the column is at most 1100 px and narrower on a narrower
# window; a table wider than the column scrolls inside its own box (its first column stays in
# view), long words and paths wrap, figures shrink to the column.
_CSS = """
*, *::before, *::after { box-sizing: border-box; }
body { font-family: system-ui, -apple-system, Segoe UI, sans-serif; margin: 2em auto;
       padding: 0 1.5em; max-width: 1100px; color: #222; line-height: 1.45;
       overflow-wrap: break-word; }
h1 { font-size: 1.6em; border-bottom: 2px solid #444; padding-bottom: .2em; }
h2 { font-size: 1.25em; margin-top: 2em; border-bottom: 1px solid #bbb; }
.table { max-width: 100%; overflow-x: auto; margin: .8em 0; }
table { border-collapse: collapse; font-size: .88em; font-variant-numeric: tabular-nums; }
th, td { border: 1px solid #ccc; padding: .25em .5em; text-align: left; vertical-align: top; }
th { background: #f0f0f0; font-weight: 600; }
td.n, th.n { text-align: right; white-space: nowrap; }
td:first-child, th:first-child { position: sticky; left: 0; background: #fff; }
th:first-child { background: #f0f0f0; }
figure { margin: 1em 0; } figure img { max-width: 100%; height: auto; border: 1px solid #ddd; }
figcaption { font-size: .88em; color: #555; }
.note { background: #fff8e0; border-left: 4px solid #e0b000; padding: .5em 1em; }
.math { font-family: "Latin Modern Math", "STIX Two Math", "Cambria Math", serif; }
pre { background: #f7f7f7; padding: .8em; overflow-x: auto; font-size: .8em;
      white-space: pre-wrap; }
"""

_NUM = ' class="n"'
_E_NUMBER = re.compile(r"^[-+]?\d+(?:\.\d*)?e[-+]?\d+$")
_SUBSCRIPT = re.compile(
    r"(?<![\w&;])([A-Za-zμαδσγηΔ][A-Za-z0-9]*)_(\{[^}]*\}|[A-Za-z0-9αμ]+(?:,[a-z](?![\w]))?)"
)
_E_IN_TEXT = re.compile(r"(?<![\w.])[-+]?\d+(?:\.\d+)?e[-+]\d+(?![\w.])")
_BOUND = re.compile(r"^(?:[<>≤≥] ?)?[-+−]?\d[\d.]*(?: × 10[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+)?$")
_PROSE = (
    (re.compile(r"\bmu0\b"), "μ0"),
    (re.compile(r"\bmu(?=\(|'s\b|\b)"), "μ"),
    (re.compile(r"\bJ\^T J\b"), "JᵀJ"),
    (re.compile(r"(?<=± )inf\b|\binf(?= x )"), "∞"),
    (re.compile(r"(?<=[\d∞⁰¹²³⁴⁵⁶⁷⁸⁹]) x (?=[\w(])"), " × "),
    (re.compile(r"(?<![\w.])x(?=\d)"), "×"),
)


def prose(text: str) -> str:
    """Running text as typeset (plain text, not escaped): units (``N.m`` -> ``N·m``), ``mu``
    -> ``μ``, ``J^T J`` -> ``JᵀJ``, ``0.5 x the peak`` -> ``0.5 × the peak``.

    Examples
    --------
    >>> prose("mu's fall from mu0 (x31.5, 0.50 x the peak, 3 N.m, J^T J, 8.68e+32)")
    "μ's fall from μ0 (×31.5, 0.50 × the peak, 3 N·m, JᵀJ, 8.68 × 10³²)"
    >>> prose("2.589e-12 ± inf; an error of inf x its value")
    '2.589 × 10⁻¹² ± ∞; an error of ∞ × its value'
    """
    text = _E_IN_TEXT.sub(lambda m: number(float(m.group(0))), typeset_units(text))
    for pattern, replacement in _PROSE:
        text = pattern.sub(replacement, text)
    return text


def math_html(text: str) -> str:
    """Escaped HTML of a formula written with ``_`` subscripts: ``F_x r_r`` -> F<sub>x</sub>
    r<sub>r</sub>; ``e_{res}`` for a subscript of several letters.

    Examples
    --------
    >>> math_html("N = S + W_d + σ (h/l) F_x, e_res,s")
    'N = S + W<sub>d</sub> + σ (h/l) F<sub>x</sub>, e<sub>res,s</sub>'
    """
    escaped = html.escape(prose(text), quote=False)
    return _SUBSCRIPT.sub(lambda m: f"{m.group(1)}<sub>{m.group(2).strip('{}')}</sub>", escaped)


def _header(text: str) -> str:
    """A column title: units typeset, a dimensionless unit (``[-]``, ``[1]``) dropped."""
    text = re.sub(r"\s*\[(?:-|1)\]", "", str(text))
    return prose(text)


def _text(where: str, name: str, value) -> str:
    """``value`` if it is a str, else the error naming it (None had been written as "None",
    a number had reached html.escape's bare AttributeError)."""
    if not isinstance(value, str):
        raise ParameterError(f"{where}: {name} must be a str, got {_short(value)}")
    return value


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else f"a {type(value).__name__}"


def _listed(where: str, name: str, value, what: str) -> list:
    """``value`` (any iterable but a str) as a list, else the error naming it (a str had been
    taken letter by letter: a table of one-letter rows)."""
    if isinstance(value, str | bytes | Mapping) or not isinstance(value, Iterable):
        raise ParameterError(f"{where}: {name} must be a list of {what}, got {_short(value)}")
    return list(value)


@dataclass
class HtmlReport:
    """Collects sections and writes one HTML file with everything embedded.

    Examples
    --------
    >>> r = HtmlReport("Test")
    >>> r.paragraph("Hello")
    >>> r.table(["a", "b"], [[1, 2.5]])
    >>> "<table>" in r.render()
    True
    """

    title: str
    parts: list[str] = field(default_factory=list)

    def __post_init__(self) -> None:
        _text("HtmlReport", "title", self.title)

    def heading(self, text: str) -> None:
        self.parts.append(f"<h2>{html.escape(_text('HtmlReport.heading', 'text', text))}</h2>")

    def paragraph(self, text: str, note: bool = False, math: bool = False) -> None:
        """A paragraph of text, typeset (:func:`prose`); ``math``: ``_`` marks subscripts
        (:func:`math_html`)."""
        _text("HtmlReport.paragraph", "text", text)
        cls = ' class="note"' if note else ""
        body = math_html(text) if math else html.escape(prose(text), quote=False)
        self.parts.append(f"<p{cls}>{body}</p>")

    def table(
        self,
        header: Sequence[str],
        rows: Sequence[Sequence],
        digits: int = 4,
        math_columns: Sequence[int] = (),
    ) -> None:
        """A table in its own box (it scrolls inside it when wider than the page).

        Numbers are rounded to ``digits`` significant digits (:func:`rollerrig._display.number`,
        powers of ten as × 10ⁿ) and right-aligned, NaN/inf shown as "n/a", None as "–"; texts
        are typeset (units, μ: :func:`prose`), those of ``math_columns`` as formulas
        (:func:`math_html`); titles lose a dimensionless unit (``[-]``). A row may be shorter
        than ``header``, never longer.
        """
        where = "HtmlReport.table"
        header = _listed(where, "header", header, "column titles")
        rows = [
            _listed(where, f"rows[{i}]", row, "cells")
            for i, row in enumerate(_listed(where, "rows", rows, "rows (lists of cells)"))
        ]
        long = next((i for i, row in enumerate(rows) if len(row) > len(header)), None)
        if long is not None:
            raise ParameterError(
                f"{where}: rows[{long}] has {len(rows[long])} cells for {len(header)} columns "
                f"(header {header})"
            )
        digits = require_whole("digits", digits, minimum=1, maximum=17)
        math_columns = [
            require_whole(f"math_columns[{k}]", j, minimum=0)
            for k, j in enumerate(_listed(where, "math_columns", math_columns, "column numbers"))
        ]

        def cell(v, column: int) -> tuple[str, bool]:
            if isinstance(v, bool):
                return html.escape(str(v)), False
            if isinstance(v, float | np.floating):
                # No NaN/inf in a report: a number that cannot be given shows as "n/a".
                return (number(float(v), digits) if np.isfinite(v) else "n/a"), True
            if isinstance(v, int | np.integer):
                return str(int(v)), True
            if v is None:
                return "–", False
            text = str(v)
            if _E_NUMBER.match(text):  # a number formatted by the caller in e-notation
                return number(float(text), digits), True
            if _BOUND.match(text):  # a number formatted by the caller: "0.89", "< 0.001"
                return html.escape(text, quote=False), True
            if column in math_columns:
                return math_html(text), False
            return html.escape(prose(text), quote=False), False

        cells = [[cell(v, j) for j, v in enumerate(row)] for row in rows]
        # A column of numbers (at least half its cells) is right-aligned, its texts too.
        numeric = [
            bool(cells) and 2 * sum(row[j][1] for row in cells if j < len(row)) >= len(cells)
            for j in range(len(header))
        ]
        head = "".join(
            f"<th{_NUM if numeric[j] and j else ''}>{html.escape(_header(h))}</th>"
            for j, h in enumerate(header)
        )
        body = "".join(
            "<tr>"
            + "".join(
                f"<td{_NUM if num or (j and numeric[j]) else ''}>{text}</td>"
                for j, (text, num) in enumerate(row)
            )
            + "</tr>"
            for row in cells
        )
        self.parts.append(
            f'<div class="table"><table><thead><tr>{head}</tr></thead>'
            f"<tbody>{body}</tbody></table></div>"
        )

    def figure(self, fig, caption: str = "", dpi: int = 110) -> None:
        """The figure embedded as PNG at ``dpi`` [dots per inch], in [1, 10 000], with its
        ``caption``; the figure is closed. A wrong argument is refused before anything is
        drawn, and the figure is left open (the caller may draw it again)."""
        from rollerrig.output.figures import crop_to_drawing, typeset_figure_units

        if not hasattr(fig, "savefig"):
            raise ParameterError(
                f"HtmlReport.figure: fig must be a matplotlib Figure, got {_short(fig)}"
            )
        _text("HtmlReport.figure", "caption", caption)
        # As save_figure: 0, a negative dpi or NaN reached matplotlib's own errors, 1e9 its
        # image-size error, text a bare TypeError, True a font error.
        if isinstance(dpi, bool | np.bool_ | str | bytes):
            raise ParameterError(f"dpi must be a number [dots per inch], got {dpi!r}")
        dpi = require_in_range(
            "dpi", dpi, 1.0, 10_000.0, "dots per inch",
            low_inclusive=True, high_inclusive=True, single=True,
        )  # fmt: skip
        typeset_figure_units(fig)  # as every saved figure (found: the spectra read (N.m)²)
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=dpi, bbox_inches=crop_to_drawing(fig))
        data = base64.b64encode(buf.getvalue()).decode("ascii")
        import matplotlib.pyplot as plt

        plt.close(fig)
        self.parts.append(
            f'<figure><img alt="{html.escape(caption)}" src="data:image/png;base64,{data}"/>'
            f"<figcaption>{html.escape(caption)}</figcaption></figure>"
        )

    def provenance(self, record: dict, relative_to: str | os.PathLike | None = None) -> None:
        """The provenance record; with ``relative_to`` (the report's folder), every absolute
        path in it is written relative to that folder (no home directories in a report that
        is shared)."""
        if not isinstance(record, Mapping):
            raise ParameterError(
                f"HtmlReport.provenance: record must be a dict (a provenance record), got "
                f"{_short(record)}"
            )
        if relative_to is not None and not isinstance(relative_to, str | os.PathLike):
            raise ParameterError(
                f"HtmlReport.provenance: relative_to must be a folder (str or Path), got "
                f"{_short(relative_to)}"
            )
        self.heading("Provenance")
        if relative_to is not None:
            record = relative_paths(record, relative_to)
        text = json.dumps(record, indent=2, default=str)
        self.parts.append(f"<pre>{html.escape(text)}</pre>")

    def render(self) -> str:
        body = "\n".join(self.parts)
        return (
            "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
            f"<title>{html.escape(self.title)}</title><style>{_CSS}</style></head>"
            f"<body><h1>{html.escape(self.title)}</h1>\n{body}\n</body></html>\n"
        )

    def write(self, path: str | os.PathLike) -> Path:
        """Write the report atomically (:func:`rollerrig.output.write_text`)."""
        return write_text(path, self.render())


def relative_paths(value, base: str | os.PathLike):
    """``value`` (nested dicts, lists, strings) with every absolute path made relative to
    ``base``.

    Examples
    --------
    >>> relative_paths({"path": "/home/ann/run/x.tdms", "cmd": ["rr", "--out", "/home/ann/run"],
    ...                 "n": 3, "url": "https://example.org/a"}, "/home/ann/run")
    {'path': 'x.tdms', 'cmd': ['rr', '--out', '.'], 'n': 3, 'url': 'https://example.org/a'}
    """
    if not isinstance(base, str | os.PathLike):
        raise ParameterError(f"relative_paths: base must be a folder (str or Path), got {base!r}")
    base = os.path.abspath(base)
    if isinstance(value, dict):
        return {k: relative_paths(v, base) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return type(value)(relative_paths(v, base) for v in value)
    if isinstance(value, str) and os.path.isabs(value) and "\n" not in value:
        return os.path.relpath(value, base)
    return value
