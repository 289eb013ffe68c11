"""The on-disk cache of compiled code: where it lives, what invalidates it, bounded, repaired.

Issue 9: numba's cache of the fast backend never hit (functions taking the right-hand side as an
argument), grew by ~1.1 MB per process and broke after ~30 runs. Now every compiled function is
cached under a folder keyed by the compiled sources; these tests check that fresh processes load
the driver instead of compiling it, that the cache stops growing after the first run, and that
damaged cache files are rebuilt instead of failing (in process for a small function, and in
fresh processes for the fast backend's driver).

Issue 23, point 1: a reinstall (new file times) or an install elsewhere (another path) of the
same sources compiled everything again; the package's functions are now found by content.
"""

import importlib.util
import json
import os
import shutil
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numba
import numpy as np
import pytest

from rollerrig.solve import _cache


def _sum_of_squares(x):
    total = 0.0
    for v in x:
        total += v * v
    return total


X = np.arange(5.0)


def _files(folder: Path) -> dict[str, int]:
    return {
        str(p.relative_to(folder)): p.stat().st_size
        for p in sorted(folder.rglob("*"))
        if p.is_file() and p.name != ".last-used"
    }


@pytest.fixture
def cache_folder(tmp_path, monkeypatch):
    """A cache folder of its own for functions compiled by _cache.njit in this test."""
    monkeypatch.setitem(_cache._state, "dir", tmp_path)
    return tmp_path


def test_a_cached_function_is_saved_with_sidecars_and_loaded_by_a_new_dispatcher(cache_folder):
    first = _cache.njit(_sum_of_squares)
    assert first(X) == 30.0
    assert sum(first.stats.cache_misses.values()) == 1
    files = _files(cache_folder)
    data = [name for name in files if name.endswith(".nbc")]
    index = [name for name in files if name.endswith(".nbi")]
    assert len(data) == 1 and len(index) == 1
    assert f"{data[0]}.sha256" in files and f"{index[0]}.sha256" in files
    again = _cache.njit(_sum_of_squares)  # a new dispatcher, as in a new process
    assert again(X) == 30.0
    assert sum(again.stats.cache_hits.values()) == 1
    assert sum(again.stats.cache_misses.values()) == 0
    assert _files(cache_folder) == files  # loading writes nothing
    assert _cache.is_cached(again)


KERNEL = """
def sum_of_squares(x):
    total = 0.0
    for v in x:
        total += v * v
    return total
"""


def _install(site: Path, monkeypatch) -> Path:
    """A package with one compiled source, ``solve/kernel.py``, written into ``site`` as pip
    writes it (new files, new times); _cache takes it for rollerrig's package."""
    package = site / "rollerrig"
    (package / "solve").mkdir(parents=True, exist_ok=True)
    (package / "solve" / "kernel.py").write_text(KERNEL)
    monkeypatch.setattr(_cache, "_PACKAGE", package)
    monkeypatch.setattr(_cache, "SOURCES", ("solve/kernel.py",))
    return package


def _compile(package: Path):
    """The kernel of a fresh import of ``package`` (as in a new process), made by _cache.njit."""
    path = package / "solve" / "kernel.py"
    spec = importlib.util.spec_from_file_location(f"kernel_{abs(hash(str(path)))}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return _cache.njit(module.sum_of_squares)


def _counts(fn) -> tuple[int, int]:
    return sum(fn.stats.cache_hits.values()), sum(fn.stats.cache_misses.values())


@pytest.fixture
def sites(tmp_path, cache_folder):
    """A folder for installs beside (not inside) the test's cache folder."""
    folder = tmp_path.parent / f"{tmp_path.name}-sites"
    folder.mkdir()
    yield folder
    shutil.rmtree(folder, ignore_errors=True)


def test_a_reinstall_of_the_same_sources_loads_the_cache(cache_folder, sites, monkeypatch):
    """Issue 23, point 1: ``pip install .`` again writes the same sources with new times."""
    from numba.core import caching

    def mtime_stamp(locator):  # numba's stamp in older releases (0.68.1 hashes the content)
        st = os.stat(locator._py_file)
        return st.st_mtime, st.st_size

    monkeypatch.setattr(caching._SourceFileBackedLocatorMixin, "get_source_stamp", mtime_stamp)
    package = _install(sites / "site", monkeypatch)
    first = _compile(package)
    assert first(X) == 30.0 and _counts(first) == (0, 1)
    files = _files(cache_folder)
    later = time.time() + 3600
    _install(sites / "site", monkeypatch)
    os.utime(package / "solve" / "kernel.py", (later, later))
    again = _compile(package)
    assert again(X) == 30.0 and _counts(again) == (1, 0)  # loaded, not compiled
    assert _files(cache_folder) == files


def test_the_same_sources_at_another_path_load_the_same_cache(cache_folder, sites, monkeypatch):
    """Issue 23, point 1: another environment (another path) with the same sources: the key
    folder names their content, so their files are found there whatever the path."""
    first = _compile(_install(sites / "venv-a", monkeypatch))
    assert first(X) == 30.0 and _counts(first) == (0, 1)
    files = _files(cache_folder)
    other = _compile(_install(sites / "venv-b", monkeypatch))
    assert other(X) == 30.0 and _counts(other) == (1, 0)
    assert _files(cache_folder) == files and _cache.is_cached(other)
    # Under the source's folder in the package, not under a hash of the install's path.
    assert {str(Path(name).parent) for name in files} == {"solve"}
    assert next(name for name in files if name.endswith(".nbi")).startswith(
        "solve/kernel.sum_of_squares-2.py"
    )
    edited = sites / "venv-c" / "rollerrig" / "solve" / "kernel.py"
    _install(sites / "venv-c", monkeypatch)
    edited.write_text(KERNEL + "# another content, the same function\n")
    changed = _compile(edited.parents[1])  # the index is stamped with the content
    assert changed(X) == 30.0 and _counts(changed) == (0, 1)


def test_numba_locates_every_other_function_as_before(cache_folder, sites, monkeypatch):
    """The locator answers only for the package's compiled sources, and only inside njit."""
    here = _cache.njit(_sum_of_squares)  # a function of the tests, not of SOURCES
    assert Path(here.stats.cache_path).parent == cache_folder
    assert Path(here.stats.cache_path).name.startswith("solve_")  # numba's path hash
    package = _install(sites / "site", monkeypatch)
    ours = _compile(package)
    assert Path(ours.stats.cache_path) == cache_folder / "solve"
    monkeypatch.setattr(numba.config, "CACHE_DIR", str(sites / "plain"))
    plain = numba.njit(cache=True)(ours.py_func)  # numba's njit, not rollerrig's
    assert Path(plain.stats.cache_path).parent == sites / "plain"


def _truncate_data(folder):
    for p in folder.rglob("*.nbc"):
        p.write_bytes(p.read_bytes()[: p.stat().st_size // 2])


def _garble_index(folder):
    for p in folder.rglob("*.nbi"):
        p.write_bytes(np.random.default_rng(1).bytes(p.stat().st_size))


def _flip_a_byte_of_data(folder):
    for p in folder.rglob("*.nbc"):
        raw = bytearray(p.read_bytes())
        raw[len(raw) // 2] ^= 0xFF
        p.write_bytes(bytes(raw))


def _empty_index(folder):
    for p in folder.rglob("*.nbi"):
        p.write_bytes(b"")


def _remove_sidecars(folder):
    for p in folder.rglob("*.sha256"):
        p.unlink()


def _index_from_another_numba(folder):
    import pickle

    for p in folder.rglob("*.nbi"):
        p.write_bytes(pickle.dumps("0.1.0") + b"whatever follows")


@pytest.mark.parametrize(
    "damage",
    [
        _truncate_data,
        _garble_index,
        _flip_a_byte_of_data,
        _empty_index,
        _remove_sidecars,
        _index_from_another_numba,
    ],
)
def test_a_damaged_cache_is_rebuilt_not_fatal(cache_folder, damage):
    _cache.njit(_sum_of_squares)(X)
    damage(cache_folder)
    rebuilt = _cache.njit(_sum_of_squares)
    assert rebuilt(X) == 30.0  # no exception: compiled again
    assert sum(rebuilt.stats.cache_misses.values()) == 1
    loaded = _cache.njit(_sum_of_squares)
    assert loaded(X) == 30.0
    assert sum(loaded.stats.cache_hits.values()) == 1  # saved again, intact


def test_njit_leaves_numba_config_as_it_was(cache_folder):
    before = numba.config.CACHE_DIR
    fn = _cache.njit(_sum_of_squares)
    assert numba.config.CACHE_DIR == before  # numba functions of other packages unaffected
    assert Path(fn.stats.cache_path).is_relative_to(cache_folder)


def test_every_compiled_module_is_part_of_the_key():
    from rollerrig.rig import model
    from rollerrig.solve import _compiled, fast  # noqa: F401  (creates the compiled functions)

    package = Path(_cache.__file__).resolve().parents[1]
    compiled = {Path(fn.__code__.co_filename).resolve() for fn in _compiled._KERNELS}
    compiled.add(Path(model.rig_rhs.__code__.co_filename).resolve())
    compiled |= {
        Path(f).resolve()
        for f in _cache._compiled_files
        if Path(f).resolve().is_relative_to(package)
    }
    listed = {(package / rel).resolve() for rel in _cache.SOURCES}
    assert compiled <= listed, sorted(str(p) for p in compiled - listed)
    assert all(p.is_file() for p in listed)


def test_the_key_follows_the_compiled_sources(tmp_path):
    package = Path(_cache.__file__).resolve().parents[1]
    copy = tmp_path / "rollerrig"
    for rel in _cache.SOURCES:
        (copy / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(package / rel, copy / rel)
    parts = {"rollerrig": "1.0", "numba": numba.__version__}
    key = _cache._digest(copy, parts)
    assert key == _cache._digest(package, parts) and len(key) == 16
    (copy / "cli.py").write_text("# not compiled\n")
    assert _cache._digest(copy, parts) == key
    model = copy / "rig" / "model.py"
    model.write_text(model.read_text() + "\n# an edit of the model\n")
    assert _cache._digest(copy, parts) != key  # a called module changed: new folder
    assert _cache._digest(package, {**parts, "rollerrig": "1.1"}) != key  # a new release


@pytest.mark.skipif(sys.platform in ("win32", "darwin"), reason="XDG layout")
def test_cache_root_respects_numba_cache_dir_then_xdg_then_home(tmp_path, monkeypatch):
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "numba"))
    assert _cache.cache_root() == tmp_path / "numba" / "rollerrig"
    monkeypatch.delenv("NUMBA_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert _cache.cache_root() == tmp_path / "xdg" / "rollerrig" / "numba"
    monkeypatch.setenv("XDG_CACHE_HOME", "relative/is/ignored")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert _cache.cache_root() == tmp_path / "home" / ".cache" / "rollerrig" / "numba"


def test_an_unwritable_cache_falls_back_to_the_temporary_directory_then_to_none(
    tmp_path, monkeypatch
):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    monkeypatch.delitem(_cache._state, "dir", raising=False)
    monkeypatch.setattr(_cache, "cache_root", lambda: blocker / "cache")
    monkeypatch.setattr(_cache.tempfile, "gettempdir", lambda: str(tmp_path / "tmp"))
    folder = _cache.cache_dir()
    assert folder is not None and folder.is_relative_to(tmp_path / "tmp")
    assert folder.name == _cache.cache_key()
    monkeypatch.delitem(_cache._state, "dir")
    monkeypatch.setattr(_cache.tempfile, "gettempdir", lambda: str(blocker))
    with pytest.warns(RuntimeWarning, match="no writable private cache folder"):
        assert _cache.cache_dir() is None
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert _cache.njit(_sum_of_squares)(X) == 30.0  # compiled, not cached


POSIX = pytest.mark.skipif(not hasattr(os, "getuid"), reason="ownership checks are POSIX's")
OTHER_UID = 65534  # "nobody"


def _fallback(tmp_path, monkeypatch):
    """Force the temporary-directory candidate (the user's cache cannot be created) and
    return the predictable folder another user could plant there."""
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    monkeypatch.delitem(_cache._state, "dir", raising=False)
    monkeypatch.setattr(_cache, "cache_root", lambda: blocker / "cache")
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    monkeypatch.setattr(_cache.tempfile, "gettempdir", lambda: str(tmp))
    return tmp / f"rollerrig-numba-{os.getuid()}"


@POSIX
def test_folders_the_cache_creates_are_private(tmp_path, monkeypatch):
    planted = _fallback(tmp_path, monkeypatch)
    monkeypatch.setattr(os, "umask", os.umask)  # restored by monkeypatch
    old = os.umask(0o000)  # the most permissive umask: the folders are 0700 regardless
    try:
        folder = _cache.cache_dir()
    finally:
        os.umask(old)
    assert folder == planted / _cache.cache_key()
    for p in (folder, planted):
        assert p.stat().st_mode & 0o777 == 0o700


@POSIX
@pytest.mark.parametrize(
    "plant",
    [
        pytest.param(lambda p: (p.mkdir(), p.chmod(0o777)), id="world-writable"),
        pytest.param(lambda p: (p.mkdir(), p.chmod(0o770)), id="group-writable"),
        pytest.param(
            lambda p: (p.parent.joinpath("elsewhere").mkdir(mode=0o700), p.symlink_to("elsewhere")),
            id="symbolic-link",
        ),
        pytest.param(lambda p: p.write_text("x"), id="a-file"),
    ],
)
def test_a_planted_cache_folder_is_refused_and_nothing_is_cached(tmp_path, monkeypatch, plant):
    """Issue 24, point 1: another local user who makes the predictable temporary folder first
    must not get code run by the victim (numba's index files are pickles)."""
    planted = _fallback(tmp_path, monkeypatch)
    plant(planted)
    with pytest.warns(RuntimeWarning, match="no writable private cache folder"):
        assert _cache.cache_dir() is None
    assert not (planted / _cache.cache_key()).exists() or planted.is_symlink()


@POSIX
@pytest.mark.skipif(os.geteuid() != 0 if hasattr(os, "geteuid") else True, reason="needs chown")
def test_a_cache_folder_owned_by_another_user_is_refused(tmp_path, monkeypatch):
    planted = _fallback(tmp_path, monkeypatch)
    (planted / _cache.cache_key()).mkdir(parents=True, mode=0o700)
    planted.chmod(0o700)
    for p in (planted, planted / _cache.cache_key()):
        os.chown(p, OTHER_UID, OTHER_UID)
    with pytest.warns(RuntimeWarning, match="belongs to user id 65534"):
        assert _cache.cache_dir() is None


@POSIX
def test_a_folder_above_writable_by_others_without_sticky_bit_is_refused(tmp_path, monkeypatch):
    above = tmp_path / "shared"
    above.mkdir()
    above.chmod(0o777)  # anyone could rename the cache away and put their own in its place
    monkeypatch.delitem(_cache._state, "dir", raising=False)
    monkeypatch.setattr(_cache, "cache_root", lambda: above / "rollerrig")
    monkeypatch.setattr(_cache.tempfile, "gettempdir", lambda: str(tmp_path / "a-file"))
    (tmp_path / "a-file").write_text("x")
    with pytest.warns(RuntimeWarning, match="written by others and has no sticky bit"):
        assert _cache.cache_dir() is None
    above.chmod(0o1777)  # as /tmp: the sticky bit keeps others from renaming what is inside
    monkeypatch.delitem(_cache._state, "dir")
    assert _cache.cache_dir() == above / "rollerrig" / _cache.cache_key()


@POSIX
def test_a_planted_file_in_a_private_folder_is_not_loaded(cache_folder):
    """A file writable by others (or not the user's) is discarded and compiled again, even with a
    matching sidecar: the sidecar proves nothing about who wrote the pair."""
    first = _cache.njit(_sum_of_squares)
    assert first(X) == 30.0
    index = next(cache_folder.rglob("*.nbi"))
    index.chmod(0o666)
    again = _cache.njit(_sum_of_squares)
    assert again(X) == 30.0
    assert sum(again.stats.cache_misses.values()) == 1  # compiled, not loaded
    assert sum(again.stats.cache_hits.values()) == 0
    assert next(cache_folder.rglob("*.nbi")).stat().st_mode & 0o022 == 0  # rewritten, private


def test_older_key_folders_are_pruned(tmp_path):
    now = time.time()
    for age, name in enumerate(["a" * 16, "b" * 16, "c" * 16, "d" * 16]):
        (tmp_path / name).mkdir()
        (tmp_path / name / ".last-used").touch()
        os.utime(tmp_path / name / ".last-used", (now - 100 * (age + 1),) * 2)
    (tmp_path / "not-a-key").mkdir()  # left alone
    current = tmp_path / ("0" * 16)
    current.mkdir()
    _cache._prune(tmp_path, current)
    kept = sorted(p.name for p in tmp_path.iterdir())
    assert kept == sorted([current.name, "a" * 16, "b" * 16, "not-a-key"])
    assert _cache.KEEP == 3


def test_files_earlier_versions_left_beside_the_sources_are_removed(tmp_path, monkeypatch):
    pycache = tmp_path / "solve" / "__pycache__"
    pycache.mkdir(parents=True)
    legacy = ["fast._integrate-55.py311.nbi", "_wdriver.integrate-308.py311.12.nbc"]
    kept = ["fast.cpython-311.pyc", "results.build-3.py311.nbi", "notes.txt"]
    for name in legacy + kept:
        (pycache / name).write_bytes(b"x")
    monkeypatch.setattr(_cache, "_PACKAGE", tmp_path)
    _cache._remove_legacy()
    assert sorted(p.name for p in pycache.iterdir()) == sorted(kept)


# ---------------------------------------------------------------------------------------------
# The fast backend in fresh processes
# ---------------------------------------------------------------------------------------------
# The ROS34PW2 driver, not the default ETDRK4 one: the same cache mechanism (a driver whose
# right-hand side is a module global, its callees cached apart) at half the compile time
# (35 s cold against 73 s; these tests compile it twice).
RUN = """
import json, time
import numpy as np
t0 = time.perf_counter()
from rollerrig.experiment import Hold, Protocol, RampTorque, ReleaseTorque
from rollerrig.rig import default_rig
from rollerrig.rig.assemble import assemble
from rollerrig.solve import fast
before = fast._cache.is_cached(fast._integrate)
p = Protocol.from_steps(
    "one-second", [Hold(0.2), RampTorque(300.0, 0.3), ReleaseTorque(), Hold(0.48)],
    normal_load=4300.0, roller_speed=30 / 3.6,
)
x, _ = fast.integrate_experiment(
    assemble(default_rig(), p), np.linspace(0.0, 0.98, 246), method="ros34pw2"
)
s = fast._integrate.stats
print(json.dumps({
    "hits": sum(s.cache_hits.values()), "misses": sum(s.cache_misses.values()),
    "compiled_before": before, "x": x[::10].ravel().tolist(), "wall": time.perf_counter() - t0,
}))
"""


def _run(cache: Path) -> dict:
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    done = subprocess.run(
        [sys.executable, "-c", RUN], env=env, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.fixture(scope="module")
def fresh_runs(tmp_path_factory):
    """Three fresh processes on one cache: their reports and the cache files after each (the
    cache used to grow in every process; two later processes show that it stops).

    The cache starts as a copy of this session's when that holds the driver already (a full
    run compiles it once before the workers start: conftest.py), else empty; the first run then
    loads or compiles it, and each test below asserts what follows from which.
    """
    from rollerrig.solve import fast

    cache = tmp_path_factory.mktemp("numba")
    session = _cache.cache_dir()
    warm = session is not None and _cache.is_cached(fast._integrate)
    if warm:
        shutil.copytree(session, cache / "rollerrig" / session.name)
    runs, files = [], []
    for _ in range(3):
        runs.append(_run(cache))
        files.append(_files(cache))
    return cache, runs, files, warm


@pytest.mark.slow
def test_fresh_processes_load_the_driver_and_the_cache_stops_growing(fresh_runs):
    _, runs, files, warm = fresh_runs
    first, later = runs[0], runs[1:]
    if warm:  # a copy of the session's cache: even the first process loads the driver
        assert first["hits"] == 1 and first["misses"] == 0 and first["compiled_before"]
    else:
        assert first["misses"] == 1 and first["hits"] == 0 and not first["compiled_before"]
    assert files[0]  # the cache holds the driver
    for run, after in zip(later, files[1:], strict=True):
        assert run["hits"] == 1 and run["misses"] == 0 and run["compiled_before"]
        assert after == files[0]  # same files, same sizes: nothing appended
        assert run["x"] == first["x"]


@pytest.mark.slow
def test_a_damaged_driver_cache_is_rebuilt_in_a_fresh_process(fresh_runs, tmp_path):
    cache, runs, _, _ = fresh_runs
    damaged = tmp_path / "numba"
    shutil.copytree(cache, damaged)
    touched = 0
    for p in damaged.rglob("*"):  # the machine code a warm run loads
        if ("fast._integrate-" in p.name or "model.rig_rhs-" in p.name) and p.suffix in (
            ".nbc",
            ".nbi",
        ):
            raw = p.read_bytes()
            p.write_bytes(raw[: len(raw) // 2] if p.suffix == ".nbc" else raw[::-1])
            touched += 1
    assert touched >= 4
    repaired = _run(damaged)
    assert repaired["misses"] == 1 and repaired["x"] == runs[0]["x"]
    again = _run(damaged)
    assert again["hits"] == 1 and again["misses"] == 0


class _OptLevelSeen(numba.core.event.Listener):
    """numba's optimisation level at the start of each compilation (numba's compile events)."""

    def __init__(self):
        self.levels = []

    def on_start(self, event):
        self.levels.append(int(numba.core.config.OPT))

    def on_end(self, event):
        pass


def _plus_one(x):
    return x + 1.0


@pytest.mark.parametrize("user_level", [None, "1"])
def test_the_package_compiles_at_its_own_opt_level_unless_the_user_sets_one(
    monkeypatch, user_level
):
    # A dispatcher as the package makes its own (the path of _wdriver._compiled_copy without
    # a cache): compiled at COMPILE_OPT_LEVEL, numba's level as it was afterwards; a NUMBA_OPT
    # of the user's wins (numba reads it again at each compilation).
    if user_level is None:
        monkeypatch.delenv("NUMBA_OPT", raising=False)
    else:
        monkeypatch.setenv("NUMBA_OPT", user_level)
    numba.core.config.reload_config()
    before = numba.core.config.OPT
    try:
        dispatcher = numba.njit(_plus_one)
        _cache._compile_at_opt_level(dispatcher)
        seen = _OptLevelSeen()
        with numba.core.event.install_listener("numba:compile", seen):
            assert dispatcher(1.0) == 2.0
        expected = _cache.COMPILE_OPT_LEVEL if user_level is None else int(user_level)
        assert seen.levels and set(seen.levels) == {expected}
        assert numba.core.config.OPT == before
        assert type(numba.core.config.OPT) is type(before)
    finally:
        monkeypatch.undo()
        numba.core.config.reload_config()  # numba's level from the environment as it was
