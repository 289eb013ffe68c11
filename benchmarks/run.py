"""Benchmark of the digital twin: the baseline a user would write against the fast backend.

Run from the repository root:

    python benchmarks/run.py            # full table (about a minute on 2 cores)
    python benchmarks/run.py --quick    # smaller sweep

For the bundled 30 s experiment (seed-30kmh-dry, 250 Hz output) it times

- the baseline: scipy ``solve_ivp`` Radau on the plain Python right-hand side, with scipy's own
  finite-difference Jacobian (what one would write without this package);
- the reference backend: the same scipy Radau on the compiled right-hand side;
- the fast backend (compiled ROS34PW2 W-method) at its default and a tighter setting;
- a sweep of roller-shaft stiffness × motor-lag variants with the parallel batch backend;

and reports wall time, the real-time factor, the speed-up over the baseline and the largest
roller-shaft torque error |ΔT56| against a tight reference (Radau, rtol 1e-10). Compilation
happens once, before timing, and is reported on its own line.
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np


def _t56(inputs, x):
    k56 = inputs.rig.stiffness.roller_shaft
    b56 = inputs.rig.damping.roller_shaft
    return k56 * (x[:, 4] - x[:, 5]) + b56 * (x[:, 11] - x[:, 12])


def _best_of(fn, repeat):
    best, result = np.inf, None
    for _ in range(repeat):
        start = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - start)
    return best, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller sweep, fewer repeats")
    parser.add_argument("--experiment", default="seed-30kmh-dry")
    args = parser.parse_args()

    from rollerrig.rig.assemble import assemble
    from rollerrig.rig.model import DriveConfig
    from rollerrig.solve.fast import integrate_batch, integrate_experiment
    from rollerrig.solve.reference import integrate_reference
    from rollerrig.solve.simulation import Simulation

    sim = Simulation(experiment=args.experiment)
    inputs, t = sim.inputs, sim.times
    duration = sim.protocol.duration
    repeat = 1 if args.quick else 3

    start = time.perf_counter()
    integrate_experiment(inputs, t[:10])
    compile_fast = time.perf_counter() - start

    ref_time, (ref, _) = _best_of(lambda: integrate_reference(inputs, t, rtol=1e-10), 1)
    t56_ref = _t56(inputs, ref)

    rows = []

    def add(label, seconds, x, note=""):
        err = float(np.max(np.abs(_t56(inputs, x) - t56_ref)))
        rows.append((label, seconds, duration / seconds, err, note))

    base_time, (x_base, st_base) = _best_of(
        lambda: integrate_reference(inputs, t, rtol=1e-6, python_rhs=True), 1
    )
    add(
        "baseline: scipy Radau, Python RHS, rtol 1e-6",
        base_time,
        x_base,
        f"{st_base['rhs_evaluations']} RHS calls",
    )
    r_time, (x_r, st_r) = _best_of(lambda: integrate_reference(inputs, t, rtol=1e-6), repeat)
    add(
        "reference: scipy Radau, compiled RHS, rtol 1e-6",
        r_time,
        x_r,
        f"{st_r['rhs_evaluations']} RHS calls",
    )
    for rtol in (1e-5, 1e-6):
        f_time, (x_f, st_f) = _best_of(
            lambda rtol=rtol: integrate_experiment(inputs, t, rtol=rtol), repeat
        )
        add(
            f"fast: ROS34PW2 W-method (numba), rtol {rtol:g}",
            f_time,
            x_f,
            f"{st_f['accepted_steps']} steps",
        )

    coarse = {"h_max": 4e-3}  # one step per 4 ms output interval: faster, less accurate
    c_time, (x_c, st_c) = _best_of(lambda: integrate_experiment(inputs, t, **coarse), repeat)
    add(
        "fast: ROS34PW2, rtol 1e-05, h_max 4 ms (sweeps)",
        c_time,
        x_c,
        f"{st_c['accepted_steps']} steps",
    )

    # Sweep: roller-shaft stiffness × motor lag, one experiment each, parallel threads.
    n_k, n_lag = (3, 2) if args.quick else (6, 4)
    stiffness = 43.5e3 + 20e3 * np.arange(n_k)
    lags = np.linspace(0.0, 0.3635, n_lag)
    variants = [
        assemble(
            inputs.rig.with_overrides({"stiffness.roller_shaft": k}),
            sim.protocol,
            DriveConfig(roller_lag=float(tau)),
        )
        for k in stiffness
        for tau in lags
    ]
    integrate_batch(variants[:2], t[:10])  # compile the parallel batch
    sweep_time, (_, status) = _best_of(lambda: integrate_batch(variants, t), 1)
    sweep_coarse, (_, status_c) = _best_of(lambda: integrate_batch(variants, t, **coarse), 1)

    print()
    print(
        f"rollerrig benchmark: {sim.protocol.name}, {duration:g} s simulated, "
        f"output {sim.output_rate:g} Hz"
    )
    print(
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}"
    )
    print(
        f"tight reference (Radau compiled, rtol 1e-10): {ref_time:.2f} s; "
        f"fast-backend compilation: {compile_fast:.1f} s (once per process)"
    )
    print()
    header = (
        f"{'solver':<52} {'wall [s]':>9} {'x real time':>12} {'speed-up':>9} "
        f"{'max|dT56| [N.m]':>16}  note"
    )
    print(header)
    print("-" * len(header))
    for label, seconds, rt, err, note in rows:
        print(
            f"{label:<52} {seconds:9.3f} {rt:12.1f} {base_time / seconds:9.1f} {err:16.3f}  {note}"
        )
    print()
    print(
        f"sweep: {len(variants)} variants ({n_k} stiffness x {n_lag} lags), "
        f"fast backend default settings, "
        f"{os.cpu_count()} threads: {sweep_time:.2f} s = {len(variants) / sweep_time:.1f} "
        f"experiment-runs/s ({int(np.sum(status == 0))} succeeded)"
    )
    print(
        f"sweep with h_max 4 ms: {sweep_coarse:.2f} s = {len(variants) / sweep_coarse:.1f} "
        f"experiment-runs/s ({int(np.sum(status_c == 0))} succeeded)"
    )


if __name__ == "__main__":
    main()
