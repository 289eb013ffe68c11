"""JSON and text files: the NaN policy (null plus a reason, never NaN), provenance, atomicity.

Moved from tests/report/test_io.py with the code (report/_io.py -> output/jsonfile.py).
"""

import json
import os
import stat

import numpy as np
import pytest

from rollerrig.output import NULL_VALUES_KEY, atomic_write, run_context, write_json, write_text


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
    data.pop("provenance")
    assert data == {"a": [1, 2.5, None]}


def test_a_top_level_object_gets_the_provenance_of_the_run(tmp_path):
    with run_context(command=["rollerrig", "study"], name="release"):
        data = json.loads(write_json(tmp_path / "x.json", {"a": 1}).read_text())
    assert data["provenance"]["command"] == ["rollerrig", "study"]
    assert data["provenance"]["parameters"] == {"name": "release"}
    assert data["provenance"]["software"] == "rollerrig"


def test_an_own_provenance_key_is_kept_and_lists_get_none(tmp_path):
    data = json.loads(write_json(tmp_path / "x.json", {"provenance": {"by": "me"}}).read_text())
    assert data == {"provenance": {"by": "me"}}
    assert json.loads(write_json(tmp_path / "y.json", [1, 2]).read_text()) == [1, 2]


def test_a_top_level_list_with_nan_is_refused_and_nothing_is_written(tmp_path):
    with pytest.raises(ValueError, match="non-finite"):
        write_json(tmp_path / "x.json", [1.0, float("nan")])
    assert list(tmp_path.iterdir()) == []


def test_overwrite_false_refuses(tmp_path):
    write_json(tmp_path / "x.json", {"a": 1})
    with pytest.raises(FileExistsError, match="overwrite=True"):
        write_json(tmp_path / "x.json", {"a": 2}, overwrite=False)
    with pytest.raises(FileExistsError):
        write_text(tmp_path / "x.json", "{}", overwrite=False)
    assert json.loads((tmp_path / "x.json").read_text())["a"] == 1


def test_atomic_write_leaves_nothing_on_failure(tmp_path):
    (tmp_path / "old.txt").write_text("previous")

    def fail(p):
        p.write_text("half")
        raise OSError("disk full")

    with pytest.raises(OSError):
        atomic_write(tmp_path / "old.txt", fail)
    assert [p.name for p in tmp_path.iterdir()] == ["old.txt"]
    assert (tmp_path / "old.txt").read_text() == "previous"


@pytest.mark.parametrize(("umask", "mode"), [(0o022, 0o644), (0o077, 0o600)])
def test_json_and_text_get_the_mode_of_a_new_file(tmp_path, umask, mode):
    # mkstemp alone would leave 0600: a report nobody else can read.
    old = os.umask(umask)
    try:
        paths = [
            write_text(tmp_path / "report.html", "x"),
            write_json(tmp_path / "summary.json", {"a": 1}),
        ]
    finally:
        os.umask(old)
    assert [stat.S_IMODE(p.stat().st_mode) for p in paths] == [mode, mode]


def test_write_text_is_utf8(tmp_path):
    assert write_text(tmp_path / "a.txt", "N·m µ").read_bytes() == "N·m µ".encode()


def test_keys_that_become_one_json_key_are_refused_not_written_twice(tmp_path):
    import re

    from rollerrig._validation import ParameterError

    with pytest.raises(ParameterError, match=re.escape("are the same JSON key")):
        write_json(tmp_path / "x.json", {1: "a", "1": "b"})
    with pytest.raises(ParameterError, match=re.escape("cannot be a JSON key")):
        write_json(tmp_path / "x.json", {(1, 2): "a"})
    assert not (tmp_path / "x.json").exists()


def test_an_own_null_values_key_is_not_overwritten(tmp_path):
    import re

    from rollerrig._validation import ParameterError

    with pytest.raises(
        ParameterError, match=re.escape(f"has a key {NULL_VALUES_KEY!r} of its own")
    ):
        write_json(tmp_path / "x.json", {"a": float("nan"), NULL_VALUES_KEY: 5})
    assert not (tmp_path / "x.json").exists()


def test_what_json_cannot_hold_is_a_parameter_error(tmp_path):
    import re

    from rollerrig._validation import ParameterError

    loop: list = []
    loop.append(loop)
    with pytest.raises(ParameterError, match=re.escape("a circular reference")):
        write_json(tmp_path / "x.json", {"a": loop})
    with pytest.raises(ParameterError, match=re.escape("not JSON serialisable: complex")):
        write_json(tmp_path / "x.json", {"a": 1 + 2j})
    with pytest.raises(ParameterError, match=re.escape("text must be a str, got a bytes")):
        write_text(tmp_path / "x.txt", b"abc")
    assert not list(tmp_path.iterdir())
