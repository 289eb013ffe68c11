"""Shared test setup: the folder of this file is importable, so tests can use the fixture
builders of ``vendor_files`` (files as real acquisition software writes them)."""

import os
import sys
import tempfile
from pathlib import Path

import pytest
from hypothesis import settings

_TESTS = str(Path(__file__).resolve().parent)
if _TESTS not in sys.path:
    sys.path.insert(0, _TESTS)

# The compiled fast backend is cached on disk by rollerrig.solve._cache: one folder per hash of
# the compiled sources (an edit selects a new folder), repaired when damaged, at most a few kept.
# Test sessions share a cache of their own in the temporary directory, apart from the user's
# (~/.cache/rollerrig), and warm after the first session. A NUMBA_CACHE_DIR the user sets is
# respected (rollerrig then keeps its folders in $NUMBA_CACHE_DIR/rollerrig).
if "NUMBA_CACHE_DIR" not in os.environ:
    _user = os.getuid() if hasattr(os, "getuid") else os.environ.get("USERNAME", "user")
    os.environ["NUMBA_CACHE_DIR"] = str(Path(tempfile.gettempdir()) / f"rollerrig-tests-{_user}")


# Property tests draw new examples on every run, which finds defects (a 1-ulp difference that
# a bit-exact check had missed for days, 2026-12-01) but makes a clean clone's run a lottery.
# Under CI (the variable CI set, as .ci/run and most CI services do) they draw the same
# examples every time; past findings stay as @example()s or in Hypothesis' own database.
settings.register_profile("ci", derandomize=True)
if os.environ.get("CI"):
    settings.load_profile("ci")


def pytest_configure(config):
    """Keep the file order of :func:`pytest_collection_modifyitems` when xdist hands files out.

    ``--dist loadfile`` otherwise sorts the files by their number of tests (xdist's
    ``--loadscope-reorder``, on by default), which hands out last the files of one or two
    long tests (a calibration's coverage over 10 recordings, the demo, the docs build) and
    leaves one worker running them while the other has nothing left to do.
    """
    if hasattr(config.option, "loadscopereorder"):
        config.option.loadscopereorder = False


def pytest_collection_modifyitems(config, items):
    """On an xdist worker, order the files as the workers should get them: files that hold a
    test marked ``slow`` first, then the others, each group by number of tests (most first, as
    xdist's own reorder does), the tests of a file in their order. Every worker collects the
    same order, which the controller keeps (:func:`pytest_configure`); a run without xdist
    keeps pytest's order."""
    if not hasattr(config, "workerinput"):
        return
    files: dict[str, list] = {}
    for item in items:
        files.setdefault(item.nodeid.split("::", 1)[0], []).append(item)

    def weight(tests):
        return (not any(t.get_closest_marker("slow") for t in tests), -len(tests))

    items[:] = [t for tests in sorted(files.values(), key=weight) for t in tests]


def pytest_sessionstart(session):
    """On a full run (``pytest`` with no paths), compile the fast backend once, before workers.

    pytest-xdist's workers would otherwise each compile the same drivers at the same time (about
    250 s of CPU each on a cold cache). The controller compiles the two models' drivers in two
    processes at once (:mod:`_precompile`); the workers then load them. A run of chosen tests
    skips this and compiles only what it uses. Workers (``workerinput``) never do it.
    """
    import subprocess

    config = session.config
    if hasattr(config, "workerinput") or config.args_source != pytest.Config.ArgsSource.TESTPATHS:
        return
    import _precompile

    todo = [g for g in _precompile.GROUPS if _precompile.pending(g)]
    if not todo:
        return
    script = str(Path(__file__).with_name("_precompile.py"))
    reporter = config.pluginmanager.get_plugin("terminalreporter")
    if reporter is not None:
        reporter.write_line(f"compiling the fast backend's drivers once ({', '.join(todo)}) ...")
    runs = [subprocess.Popen([sys.executable, script, g]) for g in todo]
    for run in runs:
        run.wait()
