"""Shared test setup: the folder of this file is importable, so tests can use the fixture
builders of ``vendor_files`` (files as real acquisition software writes them)."""

import os
import sys
import tempfile
from pathlib import Path

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
