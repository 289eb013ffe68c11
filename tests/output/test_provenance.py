"""Provenance records: version and commit, command, inputs with SHA-256, rig hash, channel map."""

import hashlib
import importlib
import json
import subprocess
import sys

import pytest

from rollerrig.output import file_sha256, provenance, rig_sha256, run_context
from rollerrig.rig.parameters import default_rig

# the module (the package exports its function of the same name)
prov = importlib.import_module("rollerrig.output.provenance")

KEYS = {
    "software",
    "version",
    "commit",
    "created_utc",
    "python",
    "numpy",
    "command",
    "inputs",
    "rig",
    "channel_map",
    "parameters",
}


def test_record_has_every_key_and_is_json():
    record = provenance(fs=250.0)
    assert KEYS <= set(record)
    assert record["software"] == "rollerrig" and record["parameters"] == {"fs": 250.0}
    assert record["command"] == [str(a) for a in sys.argv]  # no run context: sys.argv
    assert record["inputs"] == {} and record["rig"] is None and record["channel_map"] is None
    assert record["commit"] is not None or record["commit_note"]
    json.dumps(record, allow_nan=False)


def test_file_sha256_matches_hashlib_and_streams(tmp_path):
    data = bytes(range(256)) * 9000  # > one chunk
    f = tmp_path / "x.bin"
    f.write_bytes(data)
    assert file_sha256(f) == hashlib.sha256(data).hexdigest()


def test_rig_sha256_is_canonical_and_sees_every_value():
    rig = default_rig()
    assert rig_sha256(rig) == rig_sha256(rig.to_dict())
    reordered = dict(reversed(list(rig.to_dict().items())))
    assert rig_sha256(reordered) == rig_sha256(rig)
    stiffer = rig.with_overrides({"stiffness.roller_shaft": 50e3})
    assert rig_sha256(stiffer) != rig_sha256(rig)
    assert len(rig_sha256(rig)) == 64


def test_run_context_records_command_inputs_rig_and_map(tmp_path):
    rec = tmp_path / "run.csv"
    rec.write_bytes(b"time,torque\n0,1\n")
    cmap = tmp_path / "map.toml"
    cmap.write_text("[time]\n")
    rig = default_rig()
    with run_context(
        command=["rollerrig", "analyze", str(rec)],
        inputs={"recording": rec},
        rig=rig,
        channel_map=cmap,
        lenient=False,
    ) as run:
        record = provenance(out="x")
        rec.write_bytes(b"changed")  # hashed once, on entry: the record says what was read
        assert provenance()["inputs"]["recording"]["sha256"] == run.inputs["recording"]["sha256"]
    assert record["command"] == ["rollerrig", "analyze", str(rec)]
    assert record["inputs"]["recording"] == {
        "path": str(rec.resolve()),
        "sha256": hashlib.sha256(b"time,torque\n0,1\n").hexdigest(),
        "bytes": 16,
    }
    assert record["rig"] == {"name": rig.meta.name, "sha256": rig_sha256(rig)}
    assert record["channel_map"] == {"path": str(cmap.resolve()), "sha256": file_sha256(cmap)}
    assert record["parameters"] == {"lenient": False, "out": "x"}
    # outside the block: back to no context
    assert provenance()["inputs"] == {} and provenance()["rig"] is None


def test_run_contexts_nest_and_restore():
    with run_context(command=["a"]):
        with run_context(command=["b"]):
            assert provenance()["command"] == ["b"]
        assert provenance()["command"] == ["a"]


def test_a_rig_file_is_recorded_by_its_hash(tmp_path):
    f = tmp_path / "myrig.toml"
    f.write_text("x = 1\n")
    with run_context(command=[], rig=f):
        assert provenance()["rig"]["name"] == "myrig"
        assert provenance()["rig"]["sha256"] == file_sha256(f)


def test_commit_of_the_source_tree_matches_git():
    prov.package_commit.cache_clear()
    commit, how = prov.package_commit()
    package = prov.Path(prov.__file__).resolve().parent.parent
    try:
        head = subprocess.run(
            ["git", "-C", str(package), "rev-parse", "HEAD"],
            capture_output=True,
            text=True,
            timeout=5,
            check=False,
        )
        tracked = subprocess.run(
            ["git", "-C", str(package), "ls-files", "__init__.py"],
            capture_output=True,
            text=True,
            timeout=5,
            check=False,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        pytest.skip("git not available")
    if head.returncode != 0 or not tracked:
        pytest.skip("the package does not run from a git work tree here")
    assert commit.removesuffix("-dirty") == head.stdout.strip()
    assert "git work tree" in how
    assert prov.package_commit() == (commit, how)  # cached


def test_commit_recorded_at_build_time(monkeypatch, tmp_path):
    # An installed wheel is not in a work tree; setup.py wrote the commit into the package.
    monkeypatch.setattr(prov, "_git", lambda args, where: None)
    (tmp_path / "built.txt").write_text("0123abcd-dirty\n", encoding="ascii")
    monkeypatch.setattr(prov, "BUILD_COMMIT_FILE", str(tmp_path / "built.txt"))
    prov.package_commit.cache_clear()
    try:
        commit, how = prov.package_commit()
    finally:
        prov.package_commit.cache_clear()
    assert commit == "0123abcd-dirty" and "built from a git checkout" in how


def test_commit_without_git_falls_back_to_pip_record(monkeypatch, tmp_path):
    monkeypatch.setattr(prov, "_git", lambda args, where: None)  # no git, or not a work tree
    monkeypatch.setattr(prov, "BUILD_COMMIT_FILE", str(tmp_path / "absent.txt"))

    class Dist:
        def __init__(self, text):
            self.text = text

        def read_text(self, name):
            return self.text

    from importlib import metadata

    cases = [
        (
            json.dumps({"url": "https://x", "vcs_info": {"vcs": "git", "commit_id": "abc123"}}),
            ("abc123", "direct_url.json"),
        ),
        (json.dumps({"url": "file:///src", "dir_info": {"editable": True}}), (None, "editable")),
        (None, (None, "index or a wheel")),
    ]
    for text, (commit, note) in cases:
        monkeypatch.setattr(metadata, "distribution", lambda name, t=text: Dist(t))
        prov.package_commit.cache_clear()
        got, how = prov.package_commit()
        assert got == commit and note in how
        record = provenance()
        assert record["commit"] == commit
        assert (commit is None) == ("commit_note" in record)
    prov.package_commit.cache_clear()


def test_git_missing_is_tolerated(monkeypatch):
    def missing(*args, **kwargs):
        raise FileNotFoundError("git")

    monkeypatch.setattr(prov.subprocess, "run", missing)
    assert prov._git(["rev-parse", "HEAD"], prov.Path(".")) is None

    def slow(*args, **kwargs):
        raise subprocess.TimeoutExpired("git", 2.0)

    monkeypatch.setattr(prov.subprocess, "run", slow)
    assert prov._git(["rev-parse", "HEAD"], prov.Path(".")) is None


def test_a_command_given_as_one_str_is_refused_not_recorded_letter_by_letter():
    import re

    from rollerrig._validation import ParameterError

    with pytest.raises(ParameterError, match=re.escape("command must be a list of str")):
        with run_context(command="rollerrig simulate"):
            pass
    with pytest.raises(ParameterError, match=re.escape("inputs must be a mapping of role")):
        with run_context(inputs=["a.csv"]):
            pass
