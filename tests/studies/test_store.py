"""The study store: one entry per point, atomic chunks, resumable, refuses what it is not."""

import os
import stat

import numpy as np
import pytest

from rollerrig.studies.store import StoreError, StudyStore, open_study


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
