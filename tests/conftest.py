"""Shared test setup: the folder of this file is importable, so tests can use the fixture
builders of ``vendor_files`` (files as real acquisition software writes them)."""

import os
import sys
import tempfile
from pathlib import Path

_TESTS = str(Path(__file__).resolve().parent)
if _TESTS not in sys.path:
    sys.path.insert(0, _TESTS)

# numba's on-disk cache of the fast solver grows with every process and eventually breaks
# (issue 9: "ReferenceError: underlying object has vanished" in numba's caching). Until that is
# fixed, each test session compiles into a cache of its own, so a cache left broken by earlier
# runs on the same machine cannot fail the suite. A NUMBA_CACHE_DIR the user sets is respected.
if "NUMBA_CACHE_DIR" not in os.environ:
    os.environ["NUMBA_CACHE_DIR"] = tempfile.mkdtemp(prefix="rollerrig-test-numba-")
