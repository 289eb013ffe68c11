"""The on-disk cache of the compiled fast backend: where it lives, what invalidates it, repair.

Every compiled function of the package is made by :func:`njit` (``numba.njit`` with
``cache=True``) so that a fresh process loads the machine code instead of compiling it (about
20 s on 2 cores for the driver of the fast backend). numba's own choice of folder does not fit a
package: it writes beside the source (``__pycache__``, unwritable in many installs) and checks
only the source of the function itself, so an edit in a function it calls from another module
(the model in ``rig/model.py``, the contact and drive kernels) would leave stale machine code.
So the package picks the folder:

``<base>/<key>/``, with

- **base**: ``$NUMBA_CACHE_DIR/rollerrig`` when the user sets ``NUMBA_CACHE_DIR``, else the
  user's cache folder plus ``rollerrig/numba``: ``$XDG_CACHE_HOME`` or ``~/.cache`` (Linux),
  ``~/Library/Caches`` (macOS), ``%LOCALAPPDATA%`` (Windows). If it cannot be written, a folder
  in the temporary directory; if neither can, nothing is cached (a warning says so).
- **key**: a hash of the package's version, numba's and Python's versions and the source of
  every module whose code is compiled (:data:`SOURCES`). A new release or an edit of any of
  them selects a new folder, so machine code of other sources is never loaded.

**Private, or not at all.** numba's index files are pickles: whoever can write a file that the
cache loads runs code as the user. So a folder is used only when it is the user's own: every
folder the package creates is made ``0700``; the ``rollerrig`` folder and the key folder must be
owned by the user and not writable by group or others, and every folder above them must be owned
by the user or root and not writable by others unless it has the sticky bit (as ``/tmp`` has).
A folder that fails this (planted in the temporary directory by another user, a symbolic link, a
shared folder) is refused with a warning that says why; the next candidate is tried, and if none
is private nothing is cached. Each file is checked again before it is loaded: it must be a
regular file owned by the user and writable by nobody else. (On Windows the per-user folders are
private by their access lists and these checks are skipped.)

Growth is bounded: each function is compiled once per key for its one signature, so a folder
stops growing after the first run; the :data:`KEEP` most recently used key folders are kept and
older ones are removed (as are the files earlier versions left in ``__pycache__``).

Damage is repaired, never fatal: every file numba writes gets a SHA-256 sidecar
(``<file>.sha256``). Before numba loads a function, files whose content does not match their
sidecar are removed; an index or data file numba cannot read (truncated, garbled, written by
another numba) is removed as well. The function is then compiled again and saved again.

numba reads its cache folder when a ``cache=True`` function is created, so :func:`njit` sets
``numba.config.CACHE_DIR`` for that moment only; numba functions of other packages in the same
process keep their own cache.

**The same sources hit the same files, wherever they are installed.** numba's own locator files
a function under a hash of its source file's absolute path, and older numba releases (this
package allows 0.59; 0.68.1 hashes the content) stamp its index with the file's modification
time and size: an install in another environment (another path), or with those releases a
reinstall (new times), of the very same sources compiled everything again (about 70 s). The key
folder already names the content, so rollerrig's functions get a locator of their own
(:func:`_locator`, put first in numba's list of locators): the files of ``solve/fast.py`` go to
``<key>/solve/``, and the index is stamped with the SHA-256 of the file's content. It answers
only while :func:`njit` creates a dispatcher and only for a function defined in one of
:data:`SOURCES` of this package; every other function (of rollerrig's tests, of other packages)
gets numba's locators as before.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import shutil
import stat
import sys
import tempfile
import threading
import warnings
from pathlib import Path

__all__ = ["KEEP", "SOURCES", "cache_dir", "cache_key", "cache_root", "is_cached", "njit"]

SOURCES = (
    "solve/_cache.py",
    "solve/_compiled.py",
    "solve/_compiled_dq.py",
    "solve/_wdriver.py",
    "solve/ros34pw.py",
    "solve/etdrk4.py",
    "solve/fast.py",
    "rig/model.py",
    "rig/model_dq.py",
    "contact/creep.py",
    "contact/kinematics.py",
    "drives/induction.py",
    "drives/induction_dq.py",
    "drives/vf.py",
    "drives/pmsm.py",
    "drives/servo.py",
)
"""Source files (relative to the package) whose code the fast backend compiles; their content
is part of the cache key. tests/solve/test__cache.py checks that every compiled kernel's module
is listed."""

KEEP = 3
"""Key folders kept side by side (the current one and the most recently used others): a few
installs or checkouts in use at the same time do not evict each other's cache."""

_PACKAGE = Path(__file__).resolve().parents[1]
_STAMP = ".last-used"
_SIDECAR = ".sha256"
_LOCK = threading.Lock()
_state: dict[str, object] = {}


def cache_root() -> Path:
    """Folder that holds the key folders (see the module docstring)."""
    user = os.environ.get("NUMBA_CACHE_DIR")
    if user:
        return Path(user).expanduser() / "rollerrig"
    home = Path.home()
    if sys.platform == "win32":
        base = Path(os.environ.get("LOCALAPPDATA") or home / "AppData" / "Local")
    elif sys.platform == "darwin":
        base = home / "Library" / "Caches"
    else:
        xdg = os.environ.get("XDG_CACHE_HOME", "")
        base = Path(xdg) if os.path.isabs(xdg) else home / ".cache"
    return base / "rollerrig" / "numba"


def _key_parts() -> dict[str, object]:
    import numba

    from rollerrig import __version__

    return {
        "rollerrig": __version__,
        "numba": numba.__version__,
        "python": f"{sys.implementation.name}-{sys.version_info[0]}.{sys.version_info[1]}"
        f"{getattr(sys, 'abiflags', '')}",
        "sources": list(SOURCES),
    }


def _digest(package: Path, parts: dict[str, object]) -> str:
    """16 hexadecimal digits of SHA-256 over ``parts`` and the content of :data:`SOURCES`."""
    digest = hashlib.sha256(json.dumps(parts, sort_keys=True).encode())
    for rel in SOURCES:
        digest.update(rel.encode() + b"\0")
        try:
            digest.update((package / rel).read_bytes())
        except OSError:
            digest.update(b"<missing>")
    return digest.hexdigest()[:16]


def cache_key() -> str:
    """Hash of the versions and of the compiled sources: 16 hexadecimal digits."""
    if "key" not in _state:
        parts = _key_parts()
        _state["key"] = _digest(_PACKAGE, parts)
        _state["key_parts"] = parts
    return str(_state["key"])


_POSIX = hasattr(os, "getuid")


def _owner_problem(path: Path, *, own: bool) -> str | None:
    """Why ``path`` (a folder) could be written by someone else, or None.

    ``own``: the folder is the cache's own (must be the user's and writable by nobody else);
    otherwise it is a folder above it (the user's or root's, and writable by others only with
    the sticky bit, so that nobody else can rename what is inside).
    """
    try:
        st = os.lstat(path)
    except OSError as exc:
        return f"{path}: {exc.strerror or exc}"
    if stat.S_ISLNK(st.st_mode):
        return f"{path} is a symbolic link"
    if not stat.S_ISDIR(st.st_mode):
        return f"{path} is not a folder"
    uid = os.getuid()
    if own:
        if st.st_uid != uid:
            return f"{path} belongs to user id {st.st_uid}, not to this user ({uid})"
        if st.st_mode & 0o022:
            return f"{path} can be written by its group or by others (mode {st.st_mode & 0o777:o})"
        return None
    if st.st_uid not in (0, uid):
        return f"{path} belongs to user id {st.st_uid}, neither this user nor root"
    if st.st_mode & 0o002 and not st.st_mode & stat.S_ISVTX:
        return f"{path} can be written by others and has no sticky bit"
    return None


def _make_private(folder: Path) -> None:
    """Create ``folder`` and its missing parents, each made ``0700`` (not the umask's mode)."""
    missing = []
    p = folder
    while not os.path.lexists(p):
        missing.append(p)
        if p.parent == p:
            break
        p = p.parent
    for p in reversed(missing):
        with contextlib.suppress(FileExistsError):  # another process made it: checked below
            os.mkdir(p, 0o700)
            if _POSIX:
                os.chmod(p, 0o700)


def _private_problem(root: Path, folder: Path) -> str | None:
    """Make ``root`` and then ``folder`` (its key folder) where missing and say why they are not
    private, or None (see the module docstring). Nothing is made inside a folder that fails."""
    for own, check_above in ((root, True), (folder, False)):
        try:
            _make_private(own)
        except OSError as exc:
            return f"cannot create {own}: {exc.strerror or exc}"
        if not _POSIX:
            continue
        problem = _owner_problem(own, own=True)
        if check_above:
            # The folders above, as the system resolves them (a link above is the user's choice).
            real = Path(os.path.realpath(root.parent))
            for above in (real, *real.parents):
                problem = problem or _owner_problem(above, own=False)
        if problem:
            return problem
    try:
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as exc:
        return f"cannot write in {folder}: {exc.strerror or exc}"
    return None


def _file_is_private(path: Path) -> bool:
    """True for a regular file of this user that nobody else can write (always on Windows)."""
    if not _POSIX:
        return True
    try:
        st = os.lstat(path)
    except OSError:
        return False
    return stat.S_ISREG(st.st_mode) and st.st_uid == os.getuid() and not st.st_mode & 0o022


def _prune(root: Path, current: Path) -> None:
    """Keep the current key folder and the KEEP − 1 most recently used others."""

    def last_used(folder: Path) -> float:
        try:
            return (folder / _STAMP).stat().st_mtime
        except OSError:
            try:
                return folder.stat().st_mtime
            except OSError:
                return 0.0

    try:
        others = [
            p for p in root.iterdir() if p.is_dir() and p.name != current.name and len(p.name) == 16
        ]
    except OSError:
        return
    others.sort(key=last_used, reverse=True)
    for folder in others[KEEP - 1 :]:
        shutil.rmtree(folder, ignore_errors=True)


def _remove_legacy() -> None:
    """Remove numba cache files that rollerrig before issue 9 wrote beside its sources.

    They were written to ``__pycache__`` (``<module>.<function>-<line>.pyXY[.N].nbi/.nbc``) and
    grew with every process; nothing reads them any more.
    """
    stems = {Path(rel).stem for rel in SOURCES}
    for folder in {(_PACKAGE / rel).parent / "__pycache__" for rel in SOURCES}:
        try:
            names = os.listdir(folder)
        except OSError:
            continue
        for name in names:
            if name.endswith((".nbi", ".nbc")) and name.split(".", 1)[0] in stems:
                with contextlib.suppress(OSError):
                    (folder / name).unlink()


def cache_dir() -> Path | None:
    """The key folder of this process (created; older key folders pruned), or None.

    None when no folder can be written: then nothing is cached and every process compiles.
    """
    if "dir" in _state:
        return _state["dir"]  # type: ignore[return-value]
    key = cache_key()
    uid = os.getuid() if hasattr(os, "getuid") else os.environ.get("USERNAME", "user")
    candidates = (cache_root(), Path(tempfile.gettempdir()) / f"rollerrig-numba-{uid}")
    chosen = None
    refused = []
    for root in candidates:
        folder = root / key
        problem = _private_problem(root, folder)
        if problem is None:
            chosen = folder
            break
        refused.append(problem)
    if chosen is None:
        warnings.warn(
            f"rollerrig: no writable private cache folder ({'; '.join(refused)}); the fast "
            "solver compiles in every process (about 20 s). Set NUMBA_CACHE_DIR to a folder "
            "of your own that only you can write.",
            RuntimeWarning,
            stacklevel=2,
        )
    elif refused and not refused[0].startswith("cannot "):
        # Refused for its owner or mode (not merely absent or read-only): the user should know.
        warnings.warn(
            f"rollerrig: the compile cache is in {chosen}, not in {candidates[0]} ({refused[0]})",
            RuntimeWarning,
            stacklevel=2,
        )
    else:
        with contextlib.suppress(OSError):
            (chosen / _STAMP).touch()
            about = chosen / "key.json"
            if not about.exists():
                about.write_text(json.dumps(_state["key_parts"], indent=1) + "\n")
        _prune(chosen.parent, chosen)
    _remove_legacy()
    _state["dir"] = chosen
    return chosen


# ---------------------------------------------------------------------------------------------
# Damage: SHA-256 sidecars, unreadable files removed
# ---------------------------------------------------------------------------------------------
def _files(cache) -> list[Path]:
    """Index and data files of one function's numba cache (not the sidecars)."""
    folder = Path(cache.cache_path)
    base = getattr(getattr(cache, "_impl", None), "filename_base", None)
    try:
        names = os.listdir(folder)
    except OSError:
        return []
    found = []
    for name in names:
        if name.endswith(_SIDECAR) or ".tmp." in name:
            continue
        if (
            base is None
            or name == f"{base}.nbi"
            or (name.startswith(f"{base}.") and name.endswith(".nbc"))
        ):
            found.append(folder / name)
    return found


def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _intact(cache) -> bool:
    """True when every file of the function is private (see :func:`_file_is_private`) and
    matches its sidecar."""
    for path in _files(cache):
        if not (_file_is_private(path) and _file_is_private(path.parent / (path.name + _SIDECAR))):
            return False
        try:
            if (path.parent / (path.name + _SIDECAR)).read_text().strip() != _sha256(path):
                return False
        except (OSError, UnicodeDecodeError):
            return False
    return True


def _discard(cache) -> None:
    """Remove the function's index, data files and sidecars (it is compiled again)."""
    for path in _files(cache):
        for p in (path, path.parent / (path.name + _SIDECAR)):
            with contextlib.suppress(OSError):
                p.unlink()


def _seal(cache) -> None:
    """Write the sidecars of the function's files (atomically)."""
    for path in _files(cache):
        sidecar = path.parent / (path.name + _SIDECAR)
        tmp = sidecar.with_name(f"{sidecar.name}.tmp.{os.getpid()}")
        try:
            tmp.write_text(_sha256(path) + "\n")
            os.replace(tmp, sidecar)
        except OSError:
            with contextlib.suppress(OSError):
                tmp.unlink()


def _guard(dispatcher) -> None:
    """Make the dispatcher's cache check sidecars on load and repair instead of failing."""
    cache = getattr(dispatcher, "_cache", None)
    if cache is None or not hasattr(cache, "cache_path") or not hasattr(cache, "load_overload"):
        return
    load, save = cache.load_overload, cache.save_overload

    def load_overload(sig, target_context):
        if not _intact(cache):
            _discard(cache)
            return None
        try:
            return load(sig, target_context)
        except Exception:  # unreadable index or data: compile again
            _discard(cache)
            return None

    def save_overload(sig, data):
        try:
            save(sig, data)
        except Exception:  # an index numba cannot read: start it again
            _discard(cache)
            try:
                save(sig, data)
            except Exception as exc:
                warnings.warn(
                    f"rollerrig: cannot write the compile cache in {cache.cache_path} "
                    f"({type(exc).__name__}: {exc}); the next process compiles again",
                    RuntimeWarning,
                    stacklevel=2,
                )
                return
        _seal(cache)

    cache.load_overload = load_overload
    cache.save_overload = save_overload


# ---------------------------------------------------------------------------------------------
# The locator: files found by the content of the sources, not by the install's path or times
# ---------------------------------------------------------------------------------------------
_creating = threading.local()
"""``folder``: the key folder while :func:`njit` creates a dispatcher in this thread."""


def _source_name(py_file: str) -> str | None:
    """The name in :data:`SOURCES` of ``py_file`` when it is a compiled source of this
    package, else None."""
    try:
        rel = Path(py_file).resolve().relative_to(_PACKAGE.resolve()).as_posix()
    except (OSError, RuntimeError, ValueError):
        return None
    return rel if rel in SOURCES else None


def _locator():
    """The numba cache locator of rollerrig's compiled functions, registered on first use.

    Made here rather than at import because numba is imported only by the fast backend (an
    optional extra). It is put first in numba's list of locators, which numba consults when a
    ``cache=True`` dispatcher is created; it declines (``from_function`` returns None) unless
    :func:`njit` is creating the dispatcher in this thread and the function is defined in one of
    :data:`SOURCES`, so numba's own locators serve everything else. Where numba's internals
    differ (no list to join), or the user names numba's locators in
    ``NUMBA_CACHE_LOCATOR_CLASSES``, numba's locators place the package's functions as before
    (in the key folder but per install path, for numba's default list).
    """
    if "locator" in _state:
        return _state["locator"]
    from numba.core import caching

    class ContentLocator(caching._CacheLocator):
        """Cache files of ``<package>/<rel>`` in ``<key folder>/<folder of rel>``, stamped with
        the content of the source file (numba's locators use its absolute path and, in older
        releases, its modification time)."""

        def __init__(self, py_func, py_file, folder, stamp):
            self._py_file = py_file  # numba names it in its warnings
            self._lineno = py_func.__code__.co_firstlineno
            self._cache_path = str(folder)
            self._stamp = stamp

        def ensure_cache_path(self):
            _make_private(Path(self._cache_path))
            tempfile.TemporaryFile(dir=self._cache_path).close()

        def get_cache_path(self):
            return self._cache_path

        def get_source_stamp(self):
            return self._stamp

        def get_disambiguator(self):
            return str(self._lineno)

        @classmethod
        def from_function(cls, py_func, py_file):
            folder = getattr(_creating, "folder", None)
            rel = None if folder is None else _source_name(py_file)
            if rel is None:
                return None
            try:
                # The same sources give the same stamp wherever and whenever they were written.
                stamp = hashlib.sha256(Path(py_file).read_bytes()).hexdigest()
                locator = cls(py_func, py_file, folder / Path(rel).parent, stamp)
                locator.ensure_cache_path()
            except OSError:  # unreadable source or folder: numba's locators, as before
                return None
            return locator

    impl = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl", None)
    classes = getattr(impl, "_locator_classes", None)
    if isinstance(classes, list):
        classes.insert(0, ContentLocator)
    _state["locator"] = ContentLocator
    return ContentLocator


# ---------------------------------------------------------------------------------------------
# The decorator
# ---------------------------------------------------------------------------------------------
_compiled_files: set[str] = set()


COMPILE_OPT_LEVEL = 2
"""Level of LLVM's optimisation passes for the package's compiled code [-] (numba's default is
3; the target machine's code generation stays at numba's level).

Level 3 adds little to scalar code like this model's but costs compile time. Measured on a
cold compile of the default ETDRK4 driver (2026-12-01, this project's 2-core machine, three
pairs): 55, 55 and 49 s of CPU at level 3 against 50, 47 and 41 s at 2; ``benchmarks/run.py``'s
cold compile of both methods 73 -> 67 s. The solves are as fast (ETDRK4, ROS34PW2 and the dq
drive within 2 %, the best of 4 s of runs each, three pairs) and their results (those, and the
hard case) the same to the bit.

It applies to what the package's dispatchers compile, callees included (a right-hand side of
the user's given to :func:`rollerrig.solve.ros34pw.bind` is compiled with its driver), not to
other numba functions of the process; a level the user gave numba (``NUMBA_OPT``, or ``opt``
in ``.numba_config.yaml``) wins. numba's cache does not record the level: code compiled at one
level is loaded whatever the level of the process that loads it."""


def _user_opt_level() -> bool:
    """True when the user gave numba an optimisation level: ``NUMBA_OPT`` in the environment,
    or ``opt`` in ``.numba_config.yaml`` (numba's reloader holds both as ``NUMBA_OPT``)."""
    from numba.core import config

    reloader = getattr(config, "_env_reloader", None)
    return "NUMBA_OPT" in os.environ or "NUMBA_OPT" in getattr(reloader, "old_environ", {})


@contextlib.contextmanager
def _at_opt_level():
    """numba's optimisation level set to :data:`COMPILE_OPT_LEVEL` while the package compiles
    (numba reads it for every module it optimises); under numba's compiler lock, so that no
    other thread compiles meanwhile at the package's level. Afterwards the level is put back
    unless numba changed it meanwhile (a compilation re-reads numba's settings where the
    environment changed: the level it read is the user's and stays). Unchanged where the user
    gave a level (:func:`_user_opt_level`)."""
    if _user_opt_level():
        yield
        return
    from numba.core import config
    from numba.core.compiler_lock import global_compiler_lock

    with global_compiler_lock:
        saved = config.OPT
        ours = type(saved)(COMPILE_OPT_LEVEL)
        config.OPT = ours
        try:
            yield
        finally:
            if config.OPT is ours:
                config.OPT = saved


def _compile_at_opt_level(dispatcher) -> None:
    """Make ``dispatcher`` compile (and compile its callees) at :data:`COMPILE_OPT_LEVEL`."""
    compile_ = dispatcher.compile

    def compile(sig):
        with _at_opt_level():
            return compile_(sig)

    dispatcher.compile = compile


def njit(fn=None, **options):
    """``numba.njit(cache=True, **options)`` with the cache in :func:`cache_dir`.

    Use as ``@njit`` or ``@njit(parallel=True)``. Without a writable folder the function is
    compiled without a cache.
    """
    import numba

    def decorate(f):
        _compiled_files.add(os.path.abspath(f.__code__.co_filename))
        folder = cache_dir()
        if folder is None:
            dispatcher = numba.njit(**options)(f)
            _compile_at_opt_level(dispatcher)
            return dispatcher
        with _LOCK:
            _locator()
            saved = numba.config.CACHE_DIR
            numba.config.CACHE_DIR = str(folder)
            _creating.folder = folder
            try:
                dispatcher = numba.njit(cache=True, **options)(f)
            finally:
                numba.config.CACHE_DIR = saved
                _creating.folder = None
        _guard(dispatcher)
        _compile_at_opt_level(dispatcher)
        return dispatcher

    return decorate if fn is None else decorate(fn)


def is_cached(dispatcher) -> bool:
    """True when the dispatcher's cache holds sealed machine code (a call will likely load it
    instead of compiling; a different signature or CPU still compiles)."""
    cache = getattr(dispatcher, "_cache", None)
    if cache is None or not hasattr(cache, "cache_path"):
        return False
    files = _files(cache)
    return any(p.suffix == ".nbc" for p in files) and _intact(cache)
