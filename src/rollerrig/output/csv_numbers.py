"""Numbers in CSV files: rounded to 12 significant digits (no float noise), except where that
would blur a column (absolute time stamps), which is then written exactly.

Data precision: a rounded value read back is off by at most half a unit in its 12th
significant digit (5e-12 relative), and no column loses more than a thousandth of its smallest
step: 1712345678.001 s (epoch seconds at 1 kHz) needs 13 digits, so such a column keeps them.
"""

from __future__ import annotations

import numpy as np

from rollerrig.output.jsonfile import SIGNIFICANT_DIGITS, json_number

__all__ = ["csv_number", "csv_text"]


def csv_number(value: float) -> str:
    """The text of a number in a CSV file: the shortest that reads back as ``value`` rounded to
    :data:`SIGNIFICANT_DIGITS` significant digits (no float noise); ``""`` for NaN.

    Examples
    --------
    >>> csv_number(0.1 * 26.39), csv_number(2.0), csv_number(1 / 3), csv_number(float("nan"))
    ('2.639', '2.0', '0.333333333333', '')
    """
    x = float(value)
    if not np.isfinite(x):
        return "" if np.isnan(x) else repr(x)
    return repr(json_number(x))


_RESOLUTION_KEPT = 1e-3
"""Largest rounding error of a CSV column, as a fraction of its smallest nonzero step [-]."""


def _keeps_resolution(values: np.ndarray) -> bool:
    """Whether rounding ``values`` to :data:`SIGNIFICANT_DIGITS` digits moves none of them by
    more than :data:`_RESOLUTION_KEPT` of the column's smallest nonzero step.

    Rounding removes float noise; it must not merge samples. Absolute (epoch) time stamps are
    the case: 1712345678.001 s at 1 kHz needs 13 digits, so such a column is written in full.
    """
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size < 2:
        return True
    steps = np.abs(np.diff(v))
    steps = steps[steps > 0.0]
    if steps.size == 0:
        return True
    worst = float(np.max(np.abs(v))) * 0.5 * 10.0 ** (1 - SIGNIFICANT_DIGITS)
    return worst <= _RESOLUTION_KEPT * float(np.min(steps))


def csv_text(values) -> np.ndarray:
    """A float column as it goes into a CSV file: the values themselves (rounded on writing by
    :func:`csv_number`), or, where rounding would blur the column (:func:`_keeps_resolution`),
    each value as the shortest text that reads back exactly (``""`` for NaN).

    Examples
    --------
    >>> csv_text(np.array([0.5, 1.5]))
    array([0.5, 1.5])
    >>> csv_text(1712345678.0 + np.array([0.0, 0.001]))[1]
    '1712345678.001'
    """
    v = np.asarray(values, dtype=float)
    if _keeps_resolution(v):
        return v
    return np.array(["" if np.isnan(x) else repr(float(x)) for x in v], dtype=object)
