"""A cold start's compilation on two cores: the ETDRK4 driver's machine code split between this
process and a helper process (issue 20).

numba compiles one function after another, in one process, on one core: the first run after an
install (``rollerrig simulate``, the README's first command) spent about a minute compiling the
default ETDRK4 driver on this project's 2-core machine while the other core idled. Much of that
work does not depend on the rest. The right-hand side and its kernels are needed by everything
that evaluates the model. The φ-functions of the linear blocks, the eigenvalues of the
stability estimate, the output window and the model's terms along a series are not. Every one
of them is a dispatcher of its own, cached on disk (:mod:`rollerrig.solve._cache`), and numba
looks in the cache whenever a caller asks a dispatcher for a signature it has not compiled. So
a helper process compiles the independent functions into the shared cache while this process
compiles the right-hand side (phase 1). Once that is cached, the helper compiles the functions
that call it (the segment's preparation with its stability estimate, the rates along a series)
while this process compiles the segment's step loop (phase 2). The driver then loads the
helper's functions from the cache instead of compiling them.

Measured on this project's 2-core machine (2026-12-02, a slow day; ``Simulation.run`` of the
default experiment in a fresh process with an empty cache, numba's compile events): 62.5 s on
one core (``taskset``), 39.0 s with the helper, results the same to the bit; the helper's
phase-1 functions were about 14 s, this process's right-hand side and workspace about 17 s.
``rollerrig demo``'s first run in clean clones: 71.2 and 67.6 s, where the commit before took
93.2 and 84.1 s. ``benchmarks/run.py`` prints the cold ``rollerrig simulate``. What is left is
sequential: the right-hand side, the step loop into which it is inlined (about 10 s), the
driver around them (about 5 s).

The test session compiles the drivers once before its workers start (``tests/_precompile.py``),
in two processes, each of which then starts a helper of its own: four on two cores for the
first minute of a cold test run.

Nothing depends on the helper. Where it cannot start, fails, times out, or finds another cache
folder than this process (it checks), this process compiles what is missing itself: the same
functions from the same source, so the same machine code. The helper runs only for ETDRK4 with
nothing of its driver compiled or cached, with a cache folder to share, and with at least two
cores.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np

__all__ = ["HELPER_TIMEOUT", "compile_in_parallel"]

HELPER_TIMEOUT = 300.0
"""Longest wait for the helper [s]. After it the helper is stopped and this process compiles
what is missing (the helper took about 20 s on a slow day of a 2-core machine)."""

_GO = b"go\n"  # this process to the helper: the right-hand side and the workspace are cached
_TRIED: set[bool] = set()  # the models (dq or not) this process has tried it for: once each


def _model_dispatchers(dq: bool):
    """ETDRK4's dispatchers of one model: ``(bound driver, workspace, prepare, segment)``."""
    from rollerrig.solve import etdrk4

    if dq:
        from rollerrig.solve._compiled_dq import RIG_DQ as model

        name = "rig_dq"
    else:
        from rollerrig.solve._compiled import RIG as model

        name = "rig"
    workspace, prepare, segment = etdrk4.bind(model, name)
    return model, workspace, prepare, segment


def _types(*args):
    """numba's types of these arguments, as a compiled caller passes them (C-contiguous
    arrays, 64-bit integers and floats)."""
    from numba import typeof

    return tuple(typeof(a) for a in args)


def _sample(n_states: int, n_params: int, table_shape: tuple[int, int]) -> dict:
    """Arrays with the types the driver passes (their values are never used: nothing runs)."""
    return {
        "x": np.zeros(n_states),
        "p": np.zeros(n_params),
        "tables": np.zeros(table_shape),
        "t": np.zeros(3),
        "xs": np.zeros((3, n_states)),
    }


def _helper_first(a: dict, window) -> list:
    """The helper's phase 1, ``(dispatcher, argument types)``: nothing here calls the
    right-hand side (``window``: the driver's output window, ``fast._segment_window``)."""
    from rollerrig.solve import _compiled, etdrk4

    m = etdrk4.MAX_BLOCK
    coef = np.zeros((7, m, m))
    n = a["x"].size
    return [
        (etdrk4._block_coefficients, _types(coef[0], 1, 1.0, coef, coef)),
        (etdrk4.eigenvalues_of_coupled_part, _types(np.zeros((n, n)))),
        (etdrk4.rk4_stable_step, _types(np.zeros(2, dtype=np.complex128), 1.0)),
        (window, _types(a["t"], 1, 0.0, 1.0, a["x"], a["xs"])),
        (_compiled.rig_terms_series, _types(a["t"], a["xs"], a["p"], a["tables"], a["xs"])),
    ]


def _caller_first(a: dict, model) -> list:
    """This process's phase 1: the right-hand side (with the kernels it inlines)."""
    return [(model.rhs, _types(0.0, a["x"], a["p"], a["tables"], a["x"]))]


def _caller_second(a: dict, segment, ws, relinearise: int, weights, limit: float) -> list:
    """This process's phase 2: the segment's step loop (its calls of the right-hand side are
    inlined)."""
    counts = np.zeros(5, dtype=np.int64)
    divisors = np.ones(2)
    divisors.setflags(write=False)  # a global array of the driver's: a constant to numba
    args = (0.0, 1.0, 1, a["t"], a["p"], a["tables"], int(relinearise), 1, ws, a["xs"], counts,
            weights, float(limit), divisors, 1)  # fmt: skip
    return [(segment, _types(*args))]


def _helper_second(a: dict, prepare, ws) -> list:
    """The helper's phase 2: what calls the right-hand side apart from the step loop (the
    segment's preparation and stability estimate, the rates along a series)."""
    from rollerrig.solve import _compiled

    return [
        (prepare, _types(a["x"], 0.0, 1.0, a["p"], a["tables"], 1.0, 1, ws, np.zeros(2))),
        (_compiled.rig_rates_series, _types(a["t"], a["xs"], a["p"], a["tables"], a["xs"])),
    ]


def _compile(pairs) -> None:
    for dispatcher, types in pairs:
        dispatcher.compile(types)


def compile_in_parallel(inputs, settings, dq: bool, needed) -> bool:
    """Compile ETDRK4's driver for ``inputs`` on two cores where a run would compile it (once
    a process and model).

    Parameters
    ----------
    inputs : ModelInputs
        The run's inputs (their array shapes and the model: rig or dq).
    settings : tuple
        ETDRK4's settings ``(step, relinearise, static blocks, dynamic blocks, error weights,
        error limit)`` (:func:`rollerrig.solve.fast._exp_settings` without the method's code).
    dq : bool
        The model with the dq roller drive.
    needed : callable
        ``needed()`` is True when a run would compile the driver (neither compiled in this
        process nor in the cache); asked once a process and model.

    Returns
    -------
    bool
        True when a helper process took part. Either way the caller's run then compiles (or
        loads) whatever is still missing.
    """
    from rollerrig._machine import available_cores
    from rollerrig.solve import _cache

    if dq in _TRIED:
        return False
    _TRIED.add(dq)
    if available_cores() < 2 or not needed():
        return False
    folder = _cache.cache_dir()
    if folder is None:
        return False
    n_states = inputs.initial_state.size
    n_params = inputs.segments[0].params.size
    shape = inputs.tables.shape
    import rollerrig

    root = str(Path(rollerrig.__file__).parents[1])  # the helper imports this very package
    command = [sys.executable, "-c", _BOOTSTRAP, str(folder), str(int(dq)), str(n_states),
               str(n_params), str(shape[0]), str(shape[1]), root]  # fmt: skip
    try:
        proc = subprocess.Popen(
            command, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
        )
    except OSError:
        return False
    try:
        model, workspace, _, segment = _model_dispatchers(dq)
        a = _sample(n_states, n_params, shape)
        _compile(_caller_first(a, model))
        _, relinearise, static, dynamic, weights, limit = settings
        ws = workspace(n_states, static, dynamic)  # compiled here, loaded by the helper
        try:
            proc.stdin.write(_GO)
            proc.stdin.close()
        except OSError:
            pass
        _compile(_caller_second(a, segment, ws, relinearise, weights, limit))
        proc.wait(timeout=HELPER_TIMEOUT)
    except subprocess.TimeoutExpired:
        pass
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return True


def _helper(folder: str, dq: bool, n_states: int, n_params: int, shape: tuple[int, int],
            window, static_blocks) -> int:  # fmt: skip
    """The helper's work (see the module; ``window`` and ``static_blocks`` the driver's, from
    :mod:`rollerrig.solve.fast`); exit status 0, or 3 where its cache folder is not the
    caller's (then it compiles nothing)."""
    from rollerrig.solve import _cache

    if str(_cache.cache_dir()) != folder:
        return 3
    a = _sample(n_states, n_params, shape)
    _compile(_helper_first(a, window))
    if sys.stdin.readline().encode() != _GO:  # the caller gave up: nothing of phase 2
        return 0
    _, workspace, prepare, _ = _model_dispatchers(dq)
    ws = workspace(n_states, static_blocks, np.array([[0, 1, -1]], dtype=np.int64))
    _compile(_helper_second(a, prepare, ws))
    return 0


def helper_main(window, static_blocks) -> None:
    """The helper process's entry (its arguments on the command line, see
    :func:`compile_in_parallel`): :func:`rollerrig.solve.fast._cold_start_helper` calls it."""
    folder, dq, n_states, n_params, rows, cols = sys.argv[1:7]
    shape = (int(rows), int(cols))
    sys.exit(_helper(folder, dq == "1", int(n_states), int(n_params), shape, window,
                     static_blocks))  # fmt: skip


_BOOTSTRAP = (
    "import sys; root = sys.argv.pop(); "
    "root in sys.path or sys.path.insert(0, root); "
    "from rollerrig.solve.fast import _cold_start_helper; _cold_start_helper()"
)
"""The helper's command: as :data:`rollerrig.report.figure_process._BOOTSTRAP`, the folder the
caller imported rollerrig from first on its path where the helper would not find it anyway."""
