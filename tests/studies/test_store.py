"""The study store: one entry per point, atomic chunks, resumable, refuses what it is not."""

import json
import os
import stat

import numpy as np
import pytest

from rollerrig.studies import store as store_module
from rollerrig.studies.store import DAMAGED, StoreError, StudyStore, open_study, remove_store


def _store(path, n=5):
    return StudyStore.create(
        path,
        attrs={"study": "demo", "study_sha256": "abc", "design": "grid"},
        parameters={
            "load": (np.linspace(4e3, 2e4, n), {"units": "N"}),
            "friction": (np.array(["dry", "wet"] * n)[:n], {"units": ""}),
        },
        labels=[f"p{i}" for i in range(n)],
        metrics={"peak_coa": {"units": "1", "nan_meaning": "failed"}},
    )


def test_points_written_in_any_order_are_read_back(tmp_path):
    s = _store(tmp_path / "d.zarr")
    s.record([(3, "ok", "", {"peak_coa": 0.3}), (0, "solver failed", "why", {})])
    s.record([(1, "invalid parameters", "k < 0", {})])
    ds = s.dataset()
    assert list(ds.status.values) == [
        "solver failed", "invalid parameters", "pending", "ok", "pending",
    ]  # fmt: skip
    assert ds.reason.values[0] == "why" and ds.peak_coa.values[3] == 0.3
    assert np.isnan(ds.peak_coa.values[[0, 1, 2, 4]]).all()
    assert list(ds.friction.values) == ["dry", "wet", "dry", "wet", "dry"]
    assert ds["load"].attrs["units"] == "N" and ds.attrs["study"] == "demo"
    reread = open_study(tmp_path / "d.zarr")
    assert list(reread.status.values) == list(ds.status.values)


def test_a_reopened_store_resumes_only_the_pending_points(tmp_path):
    s = _store(tmp_path / "d.zarr")
    s.record([(i, "ok", "", {"peak_coa": 0.1 * i}) for i in (0, 2)])
    s.flush()
    again = StudyStore.open(tmp_path / "d.zarr", study_sha256="abc")
    assert again.pending().tolist() == [1, 3, 4]
    with pytest.raises(StoreError, match="holds another study"):
        StudyStore.open(tmp_path / "d.zarr", study_sha256="other")


def test_unflushed_points_are_lost_but_written_ones_are_intact(tmp_path):
    s = _store(tmp_path / "d.zarr")
    s.record([(0, "ok", "", {"peak_coa": 0.5})])
    s.flush()
    s.record([(1, "ok", "", {"peak_coa": 0.6})])  # a crash now: point 1 is not written
    assert open_study(tmp_path / "d.zarr").status.values.tolist()[:2] == ["ok", "pending"]


def test_files_have_normal_permissions(tmp_path):
    old = os.umask(0o022)
    try:
        s = _store(tmp_path / "d.zarr")
        s.record([(0, "ok", "", {"peak_coa": 0.5})])
        s.flush()
    finally:
        os.umask(old)
    modes = {
        stat.S_IMODE(p.stat().st_mode) for p in (tmp_path / "d.zarr").rglob("*") if p.is_file()
    }
    assert modes == {0o644}


def test_a_folder_that_is_not_a_store_is_refused(tmp_path):
    (tmp_path / "x.zarr").mkdir()
    (tmp_path / "x.zarr" / "notes.txt").write_text("hello")
    with pytest.raises(StoreError, match="not a rollerrig study store"):
        open_study(tmp_path / "x.zarr")
    with pytest.raises(StoreError, match="not a rollerrig study store"):
        StudyStore.open(tmp_path / "x.zarr")


def test_what_is_not_a_store_is_said_in_words_not_zarrs_exception(tmp_path):
    # "GroupNotFoundError: No group found in store PosixPath(...)" for the folder given to
    # study run as --out (a review, 2026-12-03).
    (tmp_path / "out").mkdir()
    _store(tmp_path / "out" / "study-d.zarr")
    (tmp_path / "a-file.zarr").write_text("x")
    expected = {
        tmp_path / "out": " but a folder holding study-d.zarr: give "
        + str(tmp_path / "out" / "study-d.zarr"),
        tmp_path / "none.zarr": ": nothing there; give the study-NAME.zarr folder",
        tmp_path / "a-file.zarr": ": a file, and a store is a folder; give",
    }
    for path, words in expected.items():
        with pytest.raises(StoreError) as err:
            open_study(path)
        assert str(err.value).startswith(f"{path}: not a rollerrig study store{words}")
        assert "Error" not in str(err.value)


def test_a_bad_status_is_a_programming_error(tmp_path):
    s = _store(tmp_path / "d.zarr")
    with pytest.raises(ValueError, match="status"):
        s.record([(0, "great", "", {})])


def test_a_damaged_chunk_is_a_store_error_that_says_what_to_do(tmp_path):
    s = _store(tmp_path / "d.zarr")
    s.record([(0, "ok", "", {"peak_coa": 0.5})])
    s.flush()
    chunk = next((tmp_path / "d.zarr" / "peak_coa" / "c").iterdir())
    chunk.write_bytes(chunk.read_bytes()[:5])  # a truncated write by another tool
    with pytest.raises(StoreError, match=r"damaged.*--restart"):
        open_study(tmp_path / "d.zarr")
    with pytest.raises(StoreError, match="damaged"):
        StudyStore.open(tmp_path / "d.zarr", study_sha256="abc").dataset()


# --------------------------------------------------------------------------------------------
# --restart removes only a study store of this study (issue 24, point 2)
# --------------------------------------------------------------------------------------------


def _plant(kind, path, elsewhere):
    """Plant at ``path`` something that is not a store of study "demo"; returns a file whose
    survival proves nothing was removed."""
    zarr = pytest.importorskip("zarr")
    if kind == "foreign zarr store":
        group = zarr.open_group(path, mode="w")
        group.attrs["title"] = "someone's data"
        group.create_array("x", shape=(3,), dtype="f8")[:] = [1.0, 2.0, 3.0]
        return path / "zarr.json"
    if kind == "plain folder":
        path.mkdir()
        (path / "thesis.tex").write_text("years of work")
        return path / "thesis.tex"
    if kind == "file":
        path.write_text("not a folder")
        return path
    if kind == "symlink to a study store":
        _store(elsewhere / "demo.zarr")  # a genuine store of "demo", reached through a link
        path.symlink_to(elsewhere / "demo.zarr", target_is_directory=True)
        return elsewhere / "demo.zarr" / "zarr.json"
    if kind == "store of another study":
        StudyStore.create(
            path, attrs={"study": "other", "study_sha256": "x"}, parameters={},
            labels=["a"], metrics={"peak_coa": {"units": "1"}},
        )  # fmt: skip
        return path / "zarr.json"
    if kind == "zarr.json that claims a store in a file":
        path.mkdir()
        claim = {"rollerrig_study_store": "2", "study": "demo"}
        (path / "zarr.json").write_text(json.dumps({"node_type": "array", "attributes": claim}))
        (path / "data.bin").write_bytes(b"\x00" * 10)
        return path / "data.bin"
    raise AssertionError(kind)


@pytest.mark.parametrize(
    ("kind", "why"),
    [
        ("foreign zarr store", "not a rollerrig study store"),
        ("plain folder", "not a rollerrig study store"),
        ("file", "a file, not a study store"),
        ("symlink to a study store", "a symbolic link"),
        ("store of another study", "the store of another study ('other', not 'demo')"),
        ("zarr.json that claims a store in a file", "not a rollerrig study store"),
    ],
)
def test_restart_refuses_what_is_not_a_store_of_this_study_and_removes_nothing(tmp_path, kind, why):
    path = tmp_path / "out" / "study-demo.zarr"
    path.parent.mkdir()
    (tmp_path / "elsewhere").mkdir()
    witness = _plant(kind, path, tmp_path / "elsewhere")
    before = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*"))
    with pytest.raises(StoreError) as info:
        remove_store(path, study="demo")
    assert str(info.value).startswith(f"{path}: ") and why in str(info.value)
    assert "nothing was removed" in str(info.value)
    assert witness.exists()
    assert sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*")) == before


def test_restart_removes_a_store_of_this_study_whole_and_nothing_else(tmp_path):
    s = _store(tmp_path / "study-demo.zarr")
    s.record([(0, "ok", "", {"peak_coa": 0.5})])
    s.flush()
    outside = tmp_path / "outside.txt"
    outside.write_text("keep")
    (tmp_path / "study-demo.zarr" / "link").symlink_to(outside)  # removed as a link, not followed
    remove_store(tmp_path / "study-demo.zarr", study="demo")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["outside.txt"]
    assert outside.read_text() == "keep"
    remove_store(tmp_path / "study-demo.zarr", study="demo")  # nothing there: nothing to do


def test_a_store_of_an_older_format_asks_for_restart(tmp_path):
    zarr = pytest.importorskip("zarr")
    _store(tmp_path / "d.zarr")
    zarr.open_group(tmp_path / "d.zarr", mode="r+").attrs["rollerrig_study_store"] = "1"
    with pytest.raises(StoreError, match=r"older rollerrig \(store version 1.*--restart"):
        StudyStore.open(tmp_path / "d.zarr")
    remove_store(tmp_path / "d.zarr", study="demo")  # --restart may remove it
    assert not (tmp_path / "d.zarr").exists()


# --------------------------------------------------------------------------------------------
# A store proves its completeness: a lost chunk file is "damaged", never "ok, no value"
# (issue 24, point 5)
# --------------------------------------------------------------------------------------------


@pytest.fixture
def small_chunks(monkeypatch):
    """Chunks of 2 points, so that a store of 5 has 3 chunks."""
    monkeypatch.setattr(store_module, "_chunk", lambda n: min(n, 2))


def _finished(path, n=5, failed=()):
    s = _store(path, n)
    s.record(
        [(i, "solver failed", "why", {}) if i in failed else (i, "ok", "", {"peak_coa": 0.1 * i})
         for i in range(n)]
    )  # fmt: skip
    s.flush()
    return s


def test_a_lost_metric_chunk_file_makes_its_finished_points_damaged(tmp_path, small_chunks):
    _finished(tmp_path / "d.zarr")
    (tmp_path / "d.zarr" / "peak_coa" / "c" / "1").unlink()  # points 2 and 3
    ds = open_study(tmp_path / "d.zarr")
    assert ds.status.values.tolist() == ["ok", "ok", DAMAGED, DAMAGED, "ok"]
    assert "peak_coa/c/1" in ds.reason.values[2] and ds.reason.values[0] == ""
    assert np.isnan(ds.peak_coa.values[2:4]).all() and ds.peak_coa.values[4] == 0.4
    again = StudyStore.open(tmp_path / "d.zarr", study_sha256="abc")
    assert again.pending().tolist() == [2, 3] and again.missing == ("peak_coa/c/1",)
    assert again.status().tolist()[2] == DAMAGED
    # Reset in the store before they are computed again: an interruption now leaves them
    # pending, never "ok" without their values.
    assert again.reset_damaged() == 2
    reopened = StudyStore.open(tmp_path / "d.zarr", study_sha256="abc")
    assert reopened.pending().tolist() == [2, 3] and reopened.missing == ()
    reopened.record([(2, "ok", "", {"peak_coa": 0.2}), (3, "ok", "", {"peak_coa": 0.3})])
    reopened.flush()
    ds = open_study(tmp_path / "d.zarr")
    assert ds.status.values.tolist() == ["ok"] * 5
    assert ds.peak_coa.values.tolist() == pytest.approx([0.0, 0.1, 0.2, 0.3, 0.4])


def test_a_lost_reason_chunk_file_is_damage_too(tmp_path):
    _finished(tmp_path / "d.zarr")  # every reason empty: zarr would not have written it
    (tmp_path / "d.zarr" / "reason" / "c" / "0").unlink()
    assert set(open_study(tmp_path / "d.zarr").status.values) == {DAMAGED}


def test_chunks_of_fill_values_are_written_so_nothing_reads_as_damaged(tmp_path, small_chunks):
    # Points 0-1 failed (their metric chunk holds only NaN, zarr's fill value); a lost status
    # chunk file only makes its points pending again.
    _finished(tmp_path / "d.zarr", failed=(0, 1))
    assert (tmp_path / "d.zarr" / "peak_coa" / "c" / "0").is_file()
    assert open_study(tmp_path / "d.zarr").status.values.tolist()[:2] == ["solver failed"] * 2
    (tmp_path / "d.zarr" / "status" / "c" / "2").unlink()
    ds = open_study(tmp_path / "d.zarr")
    assert ds.status.values.tolist() == ["solver failed"] * 2 + ["ok"] * 2 + ["pending"]


@pytest.mark.parametrize("lost", ["label/c/0", "load/c/1", "friction/c/2"])
def test_a_lost_chunk_file_of_the_design_is_a_store_error(tmp_path, small_chunks, lost):
    _finished(tmp_path / "d.zarr")
    (tmp_path / "d.zarr" / lost).unlink()
    with pytest.raises(StoreError, match=rf"design are missing \({lost}\).*--restart"):
        open_study(tmp_path / "d.zarr")
    with pytest.raises(StoreError, match=lost):
        StudyStore.open(tmp_path / "d.zarr")
