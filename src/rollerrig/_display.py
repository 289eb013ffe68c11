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
import re
from collections.abc import Iterable, Sequence

__all__ = [
    "DIMENSIONLESS",
    "DIMENSIONLESS_LABEL",
    "fmt",
    "html_table",
    "is_dimensionless",
    "key_words",
    "labelled",
    "number",
    "pretty_unit",
    "short_list",
    "text_block",
    "typeset_units",
    "unit_label",
]

DIMENSIONLESS = "1"
"""The unit value of a dimensionless quantity or a count (CF-1.10 and UDUNITS: ``"1"``); the
rule of the two spellings is stated in :mod:`rollerrig.units`, which exports these helpers (they
live here, in the lowest layer, so that the output writers and the registry share them)."""

DIMENSIONLESS_LABEL = "[-]"
"""The dimensionless unit inside a name or label (``"creep [-]"``)."""

_DIMENSIONLESS_SPELLINGS = frozenset({"1", "-"})

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


_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def number(value, digits: int = 4) -> str:
    """A number as typeset in a table: ``digits`` significant digits, powers of ten as
    ``× 10ⁿ`` outside 0.001-99 999, no float noise, ``-0`` shown as ``0``.

    Parameters
    ----------
    value : float, int, str or None
        The value; None and NaN show as ``—``, a string as it is.
    digits : int, optional
        Significant digits.

    Examples
    --------
    >>> number(7.748e-06), number(2.6390000000000002), number(83500.0), number(-0.0)
    ('7.748 × 10⁻⁶', '2.639', '83500', '0')
    >>> number(1234567.0), number(0.00123456), number(1e-9), number(float("inf"))
    ('1.235 × 10⁶', '0.001235', '10⁻⁹', '∞')
    """
    if value is None or isinstance(value, bool | str | int):
        return fmt(value, digits)
    try:
        x = float(value)
    except (TypeError, ValueError):
        return str(value)
    if math.isnan(x):
        return "—"
    if math.isinf(x):
        return "∞" if x > 0 else "−∞"
    if x == 0:
        return "0"
    if 1e-3 <= abs(x) < 1e5:
        decimals = digits - 1 - math.floor(math.log10(abs(x)))
        text = f"{round(x, decimals):.{max(decimals, 0)}f}"
        return text.rstrip("0").rstrip(".") if "." in text else text
    mantissa, exponent = f"{x:.{digits - 1}e}".split("e")
    mantissa = mantissa.rstrip("0").rstrip(".")
    power = f"10{str(int(exponent)).translate(_SUPERSCRIPT)}"
    return power if mantissa == "1" else f"{mantissa} × {power}"


_UNIT = r"(?:kg|N|m|mm|rad|s|ms|W|V|A|Pa|kN|Hz|J)"
_COMPOUND_UNIT = re.compile(
    rf"(?<![\w.])(?<![A-Za-z_]/){_UNIT}(?:\^-?[123])?(?:[./]{_UNIT}(?:\^-?[123])?)*(?![\w^])"
)
_INITIALS = re.compile(r"[A-Z](?:\.[A-Z])+")
"""``J.J``, ``A.A``: a name's initials, not newton-metres (found in review)."""


def typeset_units(text: str) -> str:
    """Units in running text typeset: ``N.m`` -> ``N·m``, ``kg.m^2`` -> ``kg·m²``.

    Only tokens made of unit symbols joined by ``.`` or carrying a power change; words, file
    names and paths (``data/V.m``), initials (``J.J. Kalker``) and numbers are left as they
    are.

    Examples
    --------
    >>> typeset_units("1.732 N.m and 45 kg.m^2 of rig.toml, area 0.05 m^2, 3 rad/s^2.")
    '1.732 N·m and 45 kg·m² of rig.toml, area 0.05 m², 3 rad/s².'
    >>> typeset_units("Kalker J.J. (1990), A.A. Shabana, data/V.m, v1.2, 1/s^2, (N.m)²")
    'Kalker J.J. (1990), A.A. Shabana, data/V.m, v1.2, 1/s², (N·m)²'
    """

    def one(match: re.Match) -> str:
        token = match.group(0)
        if _INITIALS.fullmatch(token):
            return token
        return pretty_unit(token) if ("." in token or "^" in token) else token

    return _COMPOUND_UNIT.sub(one, str(text))


_WORDS = {"coa": "CoA", "rms": "RMS", "vs": "vs.", "mu": "μ", "mu0": "μ0", "max": "largest"}


def key_words(key: str) -> str:
    """A result's key as words: ``rig_coa_vs_true_rms [-]`` -> ``rig CoA vs. true, RMS``.

    Underscores become spaces, abbreviations their usual spelling; a unit in brackets is
    typeset (:func:`pretty_unit`) and a dimensionless one (``[-]``, ``[1]``) dropped.

    Examples
    --------
    >>> key_words("rig_coa_vs_true_rms [-]"), key_words("free_rolling")
    ('rig CoA vs. true, RMS', 'free rolling')
    >>> key_words("coa_smoother_chain_vs_true_max [-]"), key_words("inertia [kg.m^2]")
    ('CoA smoother chain vs. true, largest', 'inertia [kg·m²]')
    """
    name, _, unit = str(key).partition(" [")
    unit = unit.rstrip("]")
    words = [_WORDS.get(w, w) for w in name.split("_") if w]
    if len(words) > 1 and words[-1] in ("RMS", "largest") and "vs." in words:
        words[-2] += ","
    text = " ".join(words)
    if unit and unit not in ("-", "1", ""):
        text += f" [{pretty_unit(unit)}]"
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


def is_dimensionless(unit: str | None) -> bool:
    """Whether ``unit`` is a spelling of the dimensionless unit (``"1"``, ``"-"``; not ``None``
    or ``""``, which mean *no unit*, a label column of text).

    Examples
    --------
    >>> is_dimensionless("1"), is_dimensionless("-"), is_dimensionless(""), is_dimensionless("m")
    (True, True, False, False)
    """
    return isinstance(unit, str) and unit.strip() in _DIMENSIONLESS_SPELLINGS


def unit_label(unit: str | None) -> str:
    """``unit`` in brackets as names and labels show it: ``[N.m]``; ``[-]`` when dimensionless
    (:data:`DIMENSIONLESS_LABEL`); ``""`` for no unit (``None`` or ``""``).

    Examples
    --------
    >>> unit_label("N.m"), unit_label("1"), unit_label(None)
    ('[N.m]', '[-]', '')
    """
    if unit is None or not str(unit).strip():
        return ""
    if is_dimensionless(unit):
        return DIMENSIONLESS_LABEL
    return f"[{str(unit).strip()}]"


def labelled(name: str, unit: str | None) -> str:
    """A name with its unit, the one spelling of column headers, JSON keys and table headings:
    ``"torque [N.m]"``, ``"creep [-]"`` (dimensionless), ``"phase"`` (no unit).

    Examples
    --------
    >>> labelled("torque", "N.m"), labelled("creep", "1"), labelled("phase", None)
    ('torque [N.m]', 'creep [-]', 'phase')
    """
    label = unit_label(unit)
    return f"{name} {label}" if label else str(name)
