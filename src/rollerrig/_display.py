"""Notebook manners: a short ``repr`` and a small escaped HTML table for the result objects.

:class:`~rollerrig.recordings.recording.Recording`,
:class:`~rollerrig.analysis.findings.TestAnalysis`,
:class:`~rollerrig.rig.parameters.RigParameters` and
:class:`~rollerrig.calibrate.result.Calibration` hold arrays and nested tables; their
``repr`` is a few lines (what the object is, its size, the results a reader looks for first)
and their ``_repr_html_`` a table of the same, every text HTML-escaped.
"""

from __future__ import annotations

import html
import math
from collections.abc import Iterable, Sequence

__all__ = ["fmt", "html_table", "pretty_unit", "short_list", "text_block"]

MAX_ROWS = 24
"""Rows an HTML table shows at most; the rest are counted in its last row."""


def fmt(value, digits: int = 4) -> str:
    """A number as a reader writes it: ``digits`` significant digits, no float noise.

    Parameters
    ----------
    value : float, int, str or None
        The value; None and NaN show as ``—``, a string as it is.
    digits : int, optional
        Significant digits.

    Returns
    -------
    str

    Examples
    --------
    >>> fmt(2.6390000000000002), fmt(None), fmt(83500.0), fmt(3)
    ('2.639', '—', '8.35e+04', '3')
    """
    if value is None:
        return "—"
    if isinstance(value, bool | str):
        return str(value)
    if isinstance(value, int):
        return str(value)
    try:
        x = float(value)
    except (TypeError, ValueError):
        return str(value)
    if math.isnan(x):
        return "—"
    return f"{x:.{digits}g}"


def pretty_unit(unit: str) -> str:
    """A unit as typeset: ``kg.m^2`` -> ``kg·m²``, ``N.m/rad`` -> ``N·m/rad``.

    Examples
    --------
    >>> pretty_unit("kg.m^2"), pretty_unit("N.m.s/rad"), pretty_unit("1")
    ('kg·m²', 'N·m·s/rad', '1')
    """
    text = str(unit).replace(".", "·")
    for power, sup in (("^-1", "⁻¹"), ("^2", "²"), ("^3", "³")):
        text = text.replace(power, sup)
    return text


def short_list(items: Sequence[str], limit: int = 6) -> str:
    """``a, b, c, … (+4 more)``: the first ``limit`` items and how many more there are."""
    items = [str(i) for i in items]
    if len(items) <= limit:
        return ", ".join(items)
    return f"{', '.join(items[:limit])}, … (+{len(items) - limit} more)"


def text_block(title: str, lines: Iterable[str]) -> str:
    """The ``repr``: a title line and indented lines under it."""
    return "\n".join([title, *(f"  {line}" for line in lines)])


def html_table(
    title: str,
    rows: Sequence[Sequence[object]],
    header: Sequence[str] | None = None,
    note: str = "",
) -> str:
    """A small HTML table with a title (every cell escaped), for ``_repr_html_``.

    Parameters
    ----------
    title : str
        What the object is (bold, above the table).
    rows : sequence of sequences
        Cells, shown with :func:`str`; at most :data:`MAX_ROWS` rows, the rest counted.
    header : sequence of str, optional
        Column titles.
    note : str, optional
        A line under the table (small).

    Returns
    -------
    str
        HTML.

    Examples
    --------
    >>> print(html_table("<rig>", [("J [kg·m²]", "1 < 2")]))  # doctest: +NORMALIZE_WHITESPACE
    <div><b>&lt;rig&gt;</b><table><tr><td style="text-align:left">J [kg·m²]</td><td
    style="text-align:left">1 &lt; 2</td></tr></table></div>
    """
    e = html.escape
    cell = 'style="text-align:left"'
    parts = [f"<div><b>{e(title)}</b><table>"]
    if header:
        parts.append("<tr>" + "".join(f"<th {cell}>{e(str(h))}</th>" for h in header) + "</tr>")
    shown = list(rows)[:MAX_ROWS]
    for row in shown:
        parts.append("<tr>" + "".join(f"<td {cell}>{e(str(c))}</td>" for c in row) + "</tr>")
    if len(rows) > MAX_ROWS:
        width = max(len(r) for r in rows)
        parts.append(f'<tr><td colspan="{width}">… {len(rows) - MAX_ROWS} more rows</td></tr>')
    parts.append("</table>")
    if note:
        parts.append(f"<small>{e(note)}</small>")
    parts.append("</div>")
    return "".join(parts)
