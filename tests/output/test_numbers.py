"""No float noise: the JSON writer and the CSV writer write each float as the shortest text that
reads back as the value rounded to 12 significant digits (``0.1 * 26.39`` -> ``2.639``).

Independent checks: the written token is parsed with Python's ``float`` (JSON: ``json.loads``;
CSV: the ``csv`` module, not the package's reader), its significant digits are counted in the
text, and the error bound is the decimal one of rounding to 12 significant digits, half a unit
in the 12th digit: ``|x' - x| <= 0.5 * 10**(floor(log10|x|) - 11)`` (at most 5e-12 relative;
the brief's 1e-12 holds only for values whose leading digit is 5 or more, so it is not the bound
of 12 digits).
"""

from __future__ import annotations

import csv
import json
import math
import re

import numpy as np
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from rollerrig.output import json_text, write_json, write_table

PROPERTY = settings(
    max_examples=200,
    deadline=None,
    database=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
FINITE = st.floats(allow_nan=False, allow_infinity=False, allow_subnormal=False)


def _half_unit_in_12th_digit(x: float) -> float:
    """Largest error of rounding ``x`` to 12 significant digits, plus the binary rounding of
    the decimal result (one ulp)."""
    if x == 0.0:
        return 0.0
    return 0.5 * 10.0 ** (math.floor(math.log10(abs(x))) - 11) + math.ulp(x)


def _significant_digits(token: str) -> int:
    """Significant digits of a number written as text (``"2.639"`` -> 4, ``"1e-05"`` -> 1)."""
    mantissa = re.split(r"[eE]", token.lstrip("-"))[0].replace(".", "").lstrip("0")
    return max(len(mantissa.rstrip("0")), 1)


def _json_token(value: float) -> str:
    return json_text([value])[1:-1]


@PROPERTY
@given(FINITE)
@example(0.1 * 26.39)
@example(1.000000000005)  # the worst case: leading digit 1, half a unit off
@example(-5e-324 * 0.0)
@example(1.7976931348623157e308)
@example(2.2250738585072014e-308)
def test_json_number_reads_back_within_half_a_unit_in_the_12th_digit(x):
    token = _json_token(x)
    back = json.loads(token)
    assert abs(back - x) <= _half_unit_in_12th_digit(x), (x, token)
    assert _significant_digits(token) <= 12, token
    assert json.loads(_json_token(back)) == back  # written again: the same value


@settings(PROPERTY, max_examples=40)  # a file per example
@given(st.lists(FINITE, min_size=1, max_size=20))
def test_csv_numbers_read_back_within_half_a_unit_in_the_12th_digit(tmp_path, values):
    path = write_table(tmp_path / "x.csv", {"v": (values, "1")}, overwrite=True)
    with path.open(newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["v [-]"]
    tokens = [row[0] for row in rows[1:]]
    for x, token in zip(values, tokens, strict=True):
        assert abs(float(token) - x) <= _half_unit_in_12th_digit(x), (x, token)
        # 12 digits, or exact where rounding would blur the column's steps (epoch times)
        assert _significant_digits(token) <= 12 or float(token) == x, token


def test_the_float_noise_of_a_product_is_not_written(tmp_path):
    x = 0.1 * 26.39
    assert repr(x) == "2.6390000000000002"  # the noise this is about
    data = {"coa [-]": x, "nested": [{"v": np.float64(x)}], "arr": np.array([x, 1 / 3])}
    text = write_json(tmp_path / "x.json", data).read_text()
    assert "2.6390000000000002" not in text
    back = json.loads(text)
    assert back["coa [-]"] == 2.639 and back["nested"][0]["v"] == 2.639
    assert back["arr"] == [2.639, 0.333333333333]
    rows = write_table(tmp_path / "x.csv", {"coa": ([x, 2.0, 1e-5], "1")}).read_text()
    assert rows.splitlines() == ["coa [-]", "2.639", "2.0", "1e-05"]


def test_integers_and_large_or_small_floats_keep_their_value(tmp_path):
    data = {"n": 123456789012345678, "big": 6.02214076e23, "small": 1.602176634e-19, "t": True}
    back = json.loads(write_json(tmp_path / "x.json", data).read_text())
    assert back["n"] == 123456789012345678  # integers exactly, not rounded
    assert back["big"] == 6.02214076e23 and back["small"] == 1.602176634e-19
    assert back["t"] is True


def test_numbers_inside_mappings_json_cannot_write_as_they_are_are_rounded_too():
    from types import MappingProxyType

    text = json_text({"m": MappingProxyType({"x": 0.1 * 26.39}), "s": (0.1 * 26.39,)})
    assert json.loads(text) == {"m": {"x": 2.639}, "s": [2.639]}


def test_a_documented_nan_in_csv_stays_an_empty_cell(tmp_path):
    columns = {"v": ([0.1 * 26.39, float("nan")], "1", "", {"nan_meaning": "not measured"})}
    rows = write_table(tmp_path / "x.csv", columns, time=[0.0, 0.1]).read_text().splitlines()
    assert rows == ["time [s],v [-]", "0.0,2.639", "0.1,"]


def test_csv_keeps_absolute_time_stamps_exact_and_still_rounds_the_other_columns(tmp_path):
    # Epoch seconds at 1 kHz need 13 significant digits: rounding them to 12 would merge
    # samples (found in review: a written recording read back with its time steps 0 or 10 ms).
    t = 1712345678.0 + np.arange(2000) / 1000.0
    noisy = np.full(t.size, 0.1 * 26.39)  # 2.6390000000000002
    path = write_table(tmp_path / "epoch.csv", {"torque": (noisy, "N.m")}, time=t)
    with path.open(newline="", encoding="utf-8") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    header, body = rows[0], rows[1:]
    times = np.array([float(r[header.index(next(h for h in header if h.startswith("time")))])
                      for r in body])  # fmt: skip
    np.testing.assert_array_equal(times, t)  # exact: every stamp distinct, as written
    torque = [r[header.index(next(h for h in header if h.startswith("torque")))] for r in body]
    assert set(torque) == {"2.639"}  # the other column still loses its float noise


def test_a_time_base_whose_stamps_repeat_is_one_recording_error_not_a_crash():
    import pytest

    from rollerrig.recordings.recording import RecordingError
    from rollerrig.recordings.timebase import _rate

    with pytest.raises(RecordingError, match="median step is 0 s"):
        _rate(np.repeat(np.arange(10.0), 10))
