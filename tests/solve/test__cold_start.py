"""A cold start's compilation on two cores (issue 20, :mod:`rollerrig.solve._cold_start`).

The split saves time only where each function is compiled, by the helper or by the caller
beforehand, for exactly the argument types the driver later asks for: a function compiled for
other types is compiled again when the driver is typed (no error, no gain). These tests read
the on-disk cache's index after a run and check that it holds the split's types, and only
those for the functions that only the ETDRK4 driver calls.
"""

import numpy as np
import pytest

from rollerrig.experiment import load_protocol
from rollerrig.rig import default_rig
from rollerrig.rig.assemble import assemble
from rollerrig.solve import _cache, _cold_start, fast


@pytest.fixture(scope="module")
def inputs():
    inputs = assemble(default_rig(), load_protocol("release-test"))
    fast.integrate_experiment(inputs, np.array([0.0, 0.01]))  # compiled, or loaded from cache
    return inputs


def _cached_signatures(dispatcher):
    cache = getattr(dispatcher, "_cache", None)
    if cache is None or not hasattr(cache, "_cache_file"):
        pytest.skip("no on-disk cache in this session")
    return {key[0] for key in cache._cache_file._load_index()}


def _plan(inputs):
    a = _cold_start._sample(
        inputs.initial_state.size, inputs.segments[0].params.size, inputs.tables.shape
    )
    model, workspace, prepare, segment = _cold_start._model_dispatchers(False)
    _, relinearise, static, dynamic, weights, limit = fast._exp_settings(
        inputs, None, None, None, None
    )[1:]
    ws = workspace(inputs.initial_state.size, static, dynamic)
    first = _cold_start._helper_first(a, fast._segment_window)
    second = _cold_start._helper_second(a, prepare, ws)
    # Called by the ETDRK4 driver only, so cached for the driver's types alone.
    exclusive = first[:3] + _cold_start._caller_second(a, segment, ws, relinearise, weights,
                                                       limit) + second[:1]  # fmt: skip
    # Called from elsewhere too (ROS34PW2, the truth channels, Python).
    shared = _cold_start._caller_first(a, model) + first[3:] + second[1:]
    return exclusive, shared


def test_the_split_compiles_for_the_types_the_driver_passes(inputs):
    exclusive, shared = _plan(inputs)
    assert len(exclusive) == 5 and len(shared) == 4
    for dispatcher, types in exclusive:
        assert _cached_signatures(dispatcher) == {types}, dispatcher.py_func.__name__
    for dispatcher, types in shared:
        assert types in _cached_signatures(dispatcher), dispatcher.py_func.__name__


def test_no_helper_where_the_driver_is_there_already(inputs, monkeypatch):
    monkeypatch.setattr(_cold_start, "_TRIED", set())
    settings = fast._exp_settings(inputs, None, None, None, None)[1:]
    asked = []

    def needed():
        asked.append(True)
        return fast._will_compile(fast._driver(False, 0))

    assert not _cold_start.compile_in_parallel(inputs, settings, False, needed)
    # Once a process and model: no second look.
    assert not _cold_start.compile_in_parallel(inputs, settings, False, needed)
    assert len(asked) <= 1


def test_the_helper_compiles_nothing_into_another_cache_folder(tmp_path, monkeypatch):
    monkeypatch.setattr(_cache, "cache_dir", lambda: tmp_path / "mine")
    compiled = []
    monkeypatch.setattr(_cold_start, "_compile", compiled.append)
    helper = _cold_start._helper
    assert helper(str(tmp_path / "theirs"), False, 22, 10, (3, 4), None, None) == 3
    assert compiled == []
