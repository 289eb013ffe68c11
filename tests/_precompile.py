"""Compile the fast backend's drivers into the test session's cache, in parallel, once.

Without this, every pytest-xdist worker that first runs a simulation compiles the same drivers
at the same time (about 155 s of CPU for the four on 2 cores, measured cold: the ETDRK4 driver
73 s, the dq model's 59 s, the ROS34PW2 drivers 12 s and 10 s after them; the parallel batch
drivers, 45 s and 36 s more, are gone: the batch runs the single drivers in threads). The
controller runs this script in two processes, each compiling a chain of drivers whose callees
the chain itself compiles first, so no function is compiled twice; the workers then load
everything from the cache. Used by ``conftest.py`` on a full run only.

Run as ``python tests/_precompile.py GROUP`` with GROUP ``plain`` or ``dq``.
"""

from __future__ import annotations

import sys

GROUPS = ("plain", "dq")
"""The default model's drivers, and the dq roller drive's model's."""

DRIVERS = ("etdrk4", "ros34pw2")
"""Both: ROS34PW2's driver is ETDRK4's fallback too (called from Python when a segment needs it,
so a run of the default experiment alone would not compile it).
:func:`rollerrig.solve.fast.integrate_batch` runs these same drivers in threads."""


def pending(group: str) -> bool:
    """True when a driver of ``group`` (with ``plain``, or a truth series) is not in the cache
    yet."""
    from rollerrig.solve import _cache, _compiled, fast

    done = all(fast.is_compiled(dq=group == "dq", method=m) for m in DRIVERS)
    if group == "plain":
        series = (_compiled.rig_terms_series, _compiled.rig_rates_series)
        done = done and all(_cache.is_cached(f) for f in series)
    return not done


def compile_group(group: str) -> None:
    """Run a 10 ms simulation through each driver of ``group`` (compiling what is missing)."""
    import numpy as np

    from rollerrig.experiment import load_protocol
    from rollerrig.rig import default_rig
    from rollerrig.rig.assemble import assemble
    from rollerrig.rig.model import DriveConfig
    from rollerrig.solve.fast import integrate_experiment

    drives = DriveConfig(roller="induction_dq") if group == "dq" else None
    inputs = assemble(default_rig(), load_protocol("release-test"), drives=drives)
    t = np.array([0.0, 0.01])
    for driver in DRIVERS:
        x, _ = integrate_experiment(inputs, t, method=driver)
    if group == "plain":
        # The truth channels' series (rig_terms_series, rig_rates_series, a few s to
        # compile), which every Simulation.run calls, for either model: compiled once here,
        # not in each worker.
        from rollerrig.solve.results import evaluate_terms

        evaluate_terms(inputs, t, x)


if __name__ == "__main__":
    compile_group(sys.argv[1])
