"""The one atomic writer: nothing partial, mode from the umask, refusals, one clear error."""

import errno
import os
import stat

import pytest

from rollerrig._validation import ParameterError
from rollerrig.output import OutputError, atomic_write
from rollerrig.output.atomic import new_file_mode


def _write(text):
    return lambda p: p.write_text(text)


def test_writes_and_replaces_in_one_step(tmp_path):
    f = atomic_write(tmp_path / "a.txt", _write("one"))
    assert f == tmp_path / "a.txt" and f.read_text() == "one"
    atomic_write(f, _write("two"))
    assert f.read_text() == "two"
    assert [p.name for p in tmp_path.iterdir()] == ["a.txt"]


def test_creates_missing_folders(tmp_path):
    f = atomic_write(tmp_path / "x" / "y" / "a.txt", _write("z"))
    assert f.read_text() == "z"


@pytest.mark.parametrize(("umask", "mode"), [(0o022, 0o644), (0o077, 0o600), (0o027, 0o640)])
def test_mode_follows_the_umask(tmp_path, umask, mode):
    old = os.umask(umask)
    try:
        assert new_file_mode() == mode
        f = atomic_write(tmp_path / "report.html", _write("x"))
    finally:
        os.umask(old)
    assert stat.S_IMODE(f.stat().st_mode) == mode


def test_a_replaced_file_keeps_its_mode(tmp_path):
    f = tmp_path / "a.txt"
    f.write_text("old")
    f.chmod(0o640)
    atomic_write(f, _write("new"))
    assert stat.S_IMODE(f.stat().st_mode) == 0o640


@pytest.mark.parametrize(
    ("error", "expected"),
    [
        (OSError("disk full"), OutputError),
        (RuntimeError("bug"), RuntimeError),
        (KeyboardInterrupt(), KeyboardInterrupt),
    ],
)
def test_nothing_left_after_an_exception_and_the_old_file_kept(tmp_path, error, expected):
    (tmp_path / "old.txt").write_text("previous")

    def fail(p):
        p.write_text("half")
        raise error

    with pytest.raises(expected):
        atomic_write(tmp_path / "old.txt", fail)
    assert [p.name for p in tmp_path.iterdir()] == ["old.txt"]
    assert (tmp_path / "old.txt").read_text() == "previous"


def test_system_exit_from_a_signal_handler_leaves_nothing(tmp_path):
    def fail(p):
        p.write_text("half")
        raise SystemExit(143)

    with pytest.raises(SystemExit):
        atomic_write(tmp_path / "fig.png", fail)
    assert list(tmp_path.iterdir()) == []


def test_an_oserror_while_writing_is_an_output_error_naming_the_path(tmp_path):
    def fail(p):
        raise OSError(28, "No space left on device")

    with pytest.raises(OutputError, match=r"a\.txt: cannot write the file: No space left") as e:
        atomic_write(tmp_path / "a.txt", fail)
    assert isinstance(e.value, ParameterError) and isinstance(e.value, OSError)
    assert list(tmp_path.iterdir()) == []


def test_overwrite_false_refuses_an_existing_file(tmp_path):
    f = tmp_path / "a.txt"
    f.write_text("mine")
    with pytest.raises(FileExistsError, match="overwrite=True"):
        atomic_write(f, _write("theirs"), overwrite=False)
    assert f.read_text() == "mine"
    assert [p.name for p in tmp_path.iterdir()] == ["a.txt"]
    assert atomic_write(tmp_path / "b.txt", _write("new"), overwrite=False).read_text() == "new"


def test_overwrite_false_refuses_a_file_that_appears_while_writing(tmp_path):
    f = tmp_path / "a.txt"

    def racing(p):
        p.write_text("mine")
        f.write_text("theirs")  # another writer got there first

    with pytest.raises(FileExistsError):
        atomic_write(f, racing, overwrite=False)
    assert f.read_text() == "theirs"
    assert [p.name for p in tmp_path.iterdir()] == ["a.txt"]


def test_a_parent_that_is_a_file_is_one_output_error(tmp_path):
    (tmp_path / "out").write_text("not a folder")
    with pytest.raises(OutputError, match=r"out: cannot create the folder.*--out"):
        atomic_write(tmp_path / "out" / "a.txt", _write("x"))
    with pytest.raises(OutputError, match="cannot create the folder"):
        atomic_write(tmp_path / "out" / "deeper" / "a.txt", _write("x"))


def test_a_target_that_is_a_folder_is_one_output_error(tmp_path):
    (tmp_path / "a.png").mkdir()
    with pytest.raises(OutputError, match="a folder has this name"):
        atomic_write(tmp_path / "a.png", _write("x"))
    assert [p.name for p in tmp_path.iterdir()] == ["a.png"]


@pytest.mark.skipif(os.geteuid() == 0, reason="root ignores file permissions")
def test_a_read_only_folder_is_one_output_error(tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        with pytest.raises(OutputError, match=r"ro.*Permission denied"):
            atomic_write(ro / "a.txt", _write("x"))
        assert list(ro.iterdir()) == []
    finally:
        ro.chmod(0o755)


def test_a_folder_that_refuses_new_files_is_one_output_error(tmp_path, monkeypatch):
    # What a read-only folder gives a normal user (root, running these tests, is never refused).
    import rollerrig.output.atomic as atomic

    def refuse(**kwargs):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(atomic.tempfile, "mkstemp", lambda **kw: refuse(**kw))
    with pytest.raises(OutputError, match="Permission denied; choose a folder you may write"):
        atomic_write(tmp_path / "a.txt", _write("x"))


def test_a_long_name_gets_a_legal_temporary_name(tmp_path):
    name = "x" * 240 + ".json"
    seen = []
    f = atomic_write(tmp_path / name, lambda p: seen.append(p.name) or p.write_text("{}"))
    assert f.read_text() == "{}"
    assert len(seen[0].encode()) <= 255 and seen[0].startswith(".x")
    assert seen[0].endswith(".tmp.json")


def test_the_temporary_file_is_hidden_in_the_target_folder(tmp_path):
    seen = []
    atomic_write(tmp_path / "run.tdms", lambda p: seen.append(p) or p.write_bytes(b""))
    assert seen[0].parent == tmp_path
    assert seen[0].name.startswith(".run.tdms.") and seen[0].name.endswith(".tmp.tdms")


def test_a_callback_may_name_the_file_it_wrote(tmp_path):
    def write(p):
        other = p.with_name(p.name + ".real")
        other.write_text("via library")
        return other

    f = atomic_write(tmp_path / "a.mf4", write)
    assert f.read_text() == "via library"
    assert [p.name for p in tmp_path.iterdir()] == ["a.mf4"]


def _fails_after_writing(exc):
    def write(tmp):
        tmp.write_text("half a file")  # a partial file, as a full disk leaves it
        raise exc

    return write


@pytest.mark.parametrize(
    ("exc", "hint"),
    [
        (OSError(errno.ENOSPC, "No space left on device"), "the disk is full"),
        (OSError(errno.EDQUOT, "Disk quota exceeded"), "disk quota is used up"),
        (OSError(errno.EROFS, "Read-only file system"), "read-only"),
        (PermissionError(errno.EACCES, "Permission denied"), "a folder you may write to"),
        # h5py: an OSError without errno, the system's text inside its own
        (OSError("Unable to synchronously create file (No space left on device)"), "disk is full"),
    ],
)
def test_a_full_disk_names_the_path_and_what_to_do_and_leaves_nothing(tmp_path, exc, hint):
    """Issue 24, point 9: a full disk named no path."""
    target = tmp_path / "run-analysis.nc"
    target.write_text("previous")
    with pytest.raises(OutputError) as info:
        atomic_write(target, _fails_after_writing(exc))
    message = str(info.value)
    assert message.startswith(f"{target}: cannot write the file") and hint in message, message
    assert "--out" in message
    assert [p.name for p in tmp_path.iterdir()] == ["run-analysis.nc"]
    assert target.read_text() == "previous"


def test_a_library_error_raised_from_a_full_disk_names_the_path(tmp_path):
    def write(tmp):
        tmp.write_text("half")
        try:
            raise OSError(errno.ENOSPC, "No space left on device")
        except OSError as exc:
            raise RuntimeError("HDF5 error while flushing") from exc

    with pytest.raises(OutputError, match=r"x\.nc: cannot write the file: No space left"):
        atomic_write(tmp_path / "x.nc", write)
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(RuntimeError, match="unrelated"):  # other errors pass unchanged
        atomic_write(tmp_path / "y.nc", _fails_after_writing(RuntimeError("unrelated")))
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------------------------
# Paths and arguments of the wrong kind: one clear error, nothing written
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("path", [5, None, b"out.txt", 3.5, ""])
def test_a_path_that_is_not_one_is_an_output_error_naming_it(tmp_path, monkeypatch, path):
    """None, an int or bytes had reached pathlib's bare TypeError."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(OutputError, match="path must be a file path"):
        atomic_write(path, _write("x"))
    assert list(tmp_path.iterdir()) == []


def test_a_nul_character_and_a_name_too_long_are_output_errors_naming_the_path(tmp_path):
    """A NUL had been a bare ValueError, a 300-character name a bare OSError (is_dir)."""
    with pytest.raises(OutputError, match="NUL character"):
        atomic_write(str(tmp_path / "a\0b.txt"), _write("x"))
    long = tmp_path / ("a" * 300 + ".txt")
    with pytest.raises(OutputError, match=r"aaaa\.txt: cannot write the file: File name too"):
        atomic_write(long, _write("x"))
    with pytest.raises(OutputError, match="cannot create the folder: File name too long"):
        atomic_write(tmp_path / ("d" * 300) / "x.txt", _write("x"))
    assert list(tmp_path.iterdir()) == []


def test_a_missing_folder_is_created_and_one_that_cannot_be_is_named(tmp_path):
    """Missing folders are created (as documented); a file in the way is named, nothing left."""
    assert atomic_write(tmp_path / "a" / "b" / "c.txt", _write("x")).read_text() == "x"
    (tmp_path / "file").write_text("keep")
    with pytest.raises(OutputError, match=r"file: cannot create the folder"):
        atomic_write(tmp_path / "file" / "c.txt", _write("x"))
    assert (tmp_path / "file").read_text() == "keep"


def test_a_write_that_is_not_callable_and_an_overwrite_that_is_text_are_refused(tmp_path):
    """write="text" had been a bare TypeError; overwrite="no" had replaced the file."""
    (tmp_path / "a.txt").write_text("old")
    with pytest.raises(ParameterError, match="write must be a function"):
        atomic_write(tmp_path / "a.txt", "new")
    with pytest.raises(ParameterError, match="overwrite must be True or False, got 'no'"):
        atomic_write(tmp_path / "a.txt", _write("new"), overwrite="no")
    assert (tmp_path / "a.txt").read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["a.txt"]


def test_numpys_bools_are_an_overwrite_flag(tmp_path):
    """np.True_ and np.False_ (a comparison's result) had been accepted before the flag was
    checked, and are True and False; the check refuses text and numbers only."""
    import numpy as np

    (tmp_path / "a.txt").write_text("old")
    with pytest.raises(FileExistsError):
        atomic_write(tmp_path / "a.txt", _write("new"), overwrite=np.False_)
    assert (tmp_path / "a.txt").read_text() == "old"
    atomic_write(tmp_path / "a.txt", _write("new"), overwrite=np.True_)
    assert (tmp_path / "a.txt").read_text() == "new"
    with pytest.raises(ParameterError, match="overwrite must be True or False, got 1"):
        atomic_write(tmp_path / "a.txt", _write("x"), overwrite=1)


def test_write_all_puts_the_first_file_back_when_the_second_cannot_be_moved(tmp_path, monkeypatch):
    from rollerrig.output.atomic import atomic_write_all

    a, b = tmp_path / "a.csv", tmp_path / "a.json"
    atomic_write_all([(a, _write("old a")), (b, _write("old b"))])
    real = os.replace

    def refuse_b(src, dst, *args, **kwargs):
        if os.fspath(dst) == os.fspath(b):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real(src, dst, *args, **kwargs)

    monkeypatch.setattr(os, "replace", refuse_b)
    with pytest.raises(OutputError, match=r"a\.json: cannot write the file: No space left"):
        atomic_write_all([(a, _write("new a")), (b, _write("new b"))])
    monkeypatch.undo()
    assert (a.read_text(), b.read_text()) == ("old a", "old b")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv", "a.json"]


def test_write_all_writes_nothing_when_a_later_file_fails_while_written(tmp_path):
    from rollerrig.output.atomic import atomic_write_all

    def fail(p):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    with pytest.raises(OutputError, match="nothing was written"):
        atomic_write_all([(tmp_path / "a.csv", _write("a")), (tmp_path / "a.json", fail)])
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(ParameterError, match="given twice"):
        atomic_write_all([(tmp_path / "a", _write("a")), (tmp_path / "a", _write("b"))])
    with pytest.raises(ParameterError, match="sequence of"):
        atomic_write_all("a.csv")
