"""Output writing: the JSON NaN policy (null plus a reason, never NaN) and atomic writes."""

import json
import os
import stat

import numpy as np
import pytest

from rollerrig.report._io import NULL_VALUES_KEY, atomic_write, write_json


def test_non_finite_numbers_become_null_with_their_place_and_value(tmp_path):
    obj = {
        "a": 1.5,
        "peaks": [{"coherence": float("nan")}, {"coherence": np.float64(0.3)}],
        "arr": np.array([1.0, np.inf]),
        "n": np.int64(3),
    }
    path = write_json(tmp_path / "x.json", obj)
    text = path.read_text()
    assert "NaN" not in text and "Infinity" not in text
    data = json.loads(text)
    assert data["peaks"][0]["coherence"] is None and data["peaks"][1]["coherence"] == 0.3
    assert data["arr"] == [1.0, None] and data["n"] == 3
    places = {(r["at"], r["was"]) for r in data[NULL_VALUES_KEY]}
    assert places == {("/peaks/0/coherence", "nan"), ("/arr/1", "inf")}
    assert all(r["why"] for r in data[NULL_VALUES_KEY])
    assert np.isnan(obj["peaks"][0]["coherence"])  # the input is not modified


def test_finite_json_has_no_null_values_key(tmp_path):
    data = json.loads(write_json(tmp_path / "x.json", {"a": [1, 2.5, None]}).read_text())
    assert data == {"a": [1, 2.5, None]}


def test_a_top_level_list_with_nan_is_refused_and_nothing_is_written(tmp_path):
    with pytest.raises(ValueError, match="non-finite"):
        write_json(tmp_path / "x.json", [1.0, float("nan")])
    assert list(tmp_path.iterdir()) == []


def test_atomic_write_leaves_nothing_on_failure(tmp_path):
    (tmp_path / "old.txt").write_text("previous")

    def fail(p):
        p.write_text("half")
        raise OSError("disk full")

    with pytest.raises(OSError):
        atomic_write(tmp_path / "old.txt", fail)
    assert [p.name for p in tmp_path.iterdir()] == ["old.txt"]
    assert (tmp_path / "old.txt").read_text() == "previous"


def test_html_tables_show_no_nan():
    from rollerrig.report.html import HtmlReport

    r = HtmlReport("t")
    r.table(["a", "b", "c"], [[float("nan"), np.float64(np.inf), None], [1.5, "[kN]", 2]])
    text = r.render()
    assert "nan" not in text.lower().replace("n/a", "") and "inf" not in text
    assert text.count("n/a") == 2 and "[kN]" in text


def test_atomic_write_gives_the_mode_of_a_new_file(tmp_path):
    # mkstemp alone would leave 0600: a report nobody else can read.
    old = os.umask(0o022)
    try:
        path = atomic_write(tmp_path / "report.html", lambda p: p.write_text("x"))
    finally:
        os.umask(old)
    assert stat.S_IMODE(path.stat().st_mode) == 0o644
