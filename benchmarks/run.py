"""Benchmark of the digital twin against the targets of issue 9, printed as a table.

Run from the repository root:

    python benchmarks/run.py            # full table (about 3 minutes on 2 cores)
    python benchmarks/run.py --quick    # smaller sweep, fewer repeats
    python benchmarks/run.py --no-cli   # skip the fresh-process `rollerrig simulate` timings

It measures, in one run on this machine:

- ``rollerrig simulate`` (default experiment, all outputs) in a fresh process, wall time:
  cold (an empty compile cache: the first run after an install compiles the fast backend) and
  warm (the cache filled by the cold run), and the size of the cache after each run;
- for the bundled 30 s experiment (seed-30kmh-dry, 250 Hz output): the user baseline (scipy
  ``solve_ivp`` Radau on the plain Python right-hand side with scipy's own finite-difference
  Jacobian, rtol 1e-6: what one would write without this package), the reference backend (the
  same Radau on the compiled right-hand side) and the fast backend (compiled ROS34PW2) at its
  default (dense output, h_max 0.9 ms) and other settings: solve-only wall time (best of
  a few, compiled code loaded before), real-time factor, speed-up over the baseline and the
  largest roller-shaft torque error max |ΔT56| against a tight reference (Radau, compiled,
  rtol 1e-10);
- a sweep of roller-shaft stiffness × motor-lag variants with the parallel batch backend:
  experiment-runs per second on this machine's cores;

and ends with the targets of issue 9, each with the measured value and whether it is met.
Timings are wall times of this machine (other load on it slows them); nothing here is a test.
"""

from __future__ import annotations

import argparse
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

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


def _folder_bytes(folder: Path) -> int:
    return sum(p.stat().st_size for p in folder.rglob("*") if p.is_file())


_IMPORTS = (
    "import rollerrig.cli, rollerrig.solve.simulation, rollerrig.solve.results, "
    "rollerrig.report.twin, rollerrig.rig.linear, matplotlib.pyplot, xarray, h5netcdf, numba"
)
"""What ``rollerrig simulate`` imports before it solves (the floor of a fresh process)."""


def cli_timings(experiment: str, warm_runs: int) -> dict:
    """Wall time of ``rollerrig simulate`` in fresh processes on an empty, then filled cache."""
    work = Path(tempfile.mkdtemp(prefix="rollerrig-bench-"))
    try:
        env = {**os.environ, "NUMBA_CACHE_DIR": str(work / "numba")}
        walls, sizes = [], []
        for i in range(1 + warm_runs):
            command = [sys.executable, "-m", "rollerrig.cli", "simulate", "-e", experiment]
            command += ["--out", str(work / f"out{i}")]
            start = time.perf_counter()
            done = subprocess.run(command, env=env, capture_output=True, text=True)
            walls.append(time.perf_counter() - start)
            if done.returncode != 0:
                raise RuntimeError(f"rollerrig simulate failed:\n{done.stdout}\n{done.stderr}")
            sizes.append(_folder_bytes(work / "numba"))
        # The floor under the warm run: a fresh process importing what `simulate` imports.
        floor = []
        for _ in range(warm_runs):
            start = time.perf_counter()
            subprocess.run([sys.executable, "-c", _IMPORTS], env=env, check=True)
            floor.append(time.perf_counter() - start)
        return {
            "cold": walls[0],
            "warm": min(walls[1:]),
            "walls": walls,
            "sizes": sizes,
            "imports": min(floor),
        }
    finally:
        shutil.rmtree(work, ignore_errors=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller sweep, fewer repeats")
    parser.add_argument("--no-cli", action="store_true", help="skip the fresh-process timings")
    parser.add_argument("--experiment", default="seed-30kmh-dry")
    args = parser.parse_args()

    cli = None if args.no_cli else cli_timings(args.experiment, 2 if args.quick else 3)

    import numba

    from rollerrig.rig.assemble import assemble
    from rollerrig.rig.model import DriveConfig
    from rollerrig.solve import fast
    from rollerrig.solve.fast import SWEEP_H_MAX, integrate_batch, integrate_experiment
    from rollerrig.solve.reference import integrate_reference
    from rollerrig.solve.simulation import Simulation

    sim = Simulation(experiment=args.experiment)
    inputs, t = sim.inputs, sim.times
    duration = sim.protocol.duration
    repeat = 2 if args.quick else 5

    was_cached = fast.is_compiled()
    start = time.perf_counter()
    integrate_experiment(inputs, t[:10])
    load_fast = time.perf_counter() - start

    ref_time, (ref, _) = _best_of(lambda: integrate_reference(inputs, t, rtol=1e-10), 1)
    t56_ref = _t56(inputs, ref)

    rows = []

    def add(label, seconds, x, note=""):
        err = float(np.max(np.abs(_t56(inputs, x) - t56_ref)))
        rows.append((label, seconds, duration / seconds, err, note))
        return err

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
    fast_rows = {}
    for label, options in (
        ("fast: ROS34PW2 (numba), dense output (default)", {}),
        ("fast: ROS34PW2, rtol 1e-06", {"rtol": 1e-6}),
        (f"fast: ROS34PW2, h_max {SWEEP_H_MAX * 1e3:g} ms (sweeps)", {"h_max": SWEEP_H_MAX}),
        ("fast: ROS34PW2, h_max 4 ms", {"h_max": 4e-3}),
    ):
        run = lambda o=options: integrate_experiment(inputs, t, **o)  # noqa: E731
        f_time, (x_f, st_f) = _best_of(run, repeat)
        err = add(label, f_time, x_f, f"{st_f['accepted_steps']} steps")
        fast_rows[label] = (f_time, err, st_f["accepted_steps"])
    f_time, f_err, fast_rows_steps = fast_rows["fast: ROS34PW2 (numba), dense output (default)"]

    # The dq roller drive (issue 13): its own 29-state compiled model, default settings.
    dq_sim = Simulation(experiment=args.experiment, drives=DriveConfig(roller="induction_dq"))
    dq_inputs = dq_sim.inputs
    integrate_experiment(dq_inputs, t[:10])  # load (or compile) its driver first
    dq_ref = _t56(dq_inputs, integrate_reference(dq_inputs, t, rtol=1e-10)[0])
    dq_time, (x_dq, st_dq) = _best_of(lambda: integrate_experiment(dq_inputs, t), repeat)
    dq_err = float(np.max(np.abs(_t56(dq_inputs, x_dq) - dq_ref)))

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
    batch_cached = fast.is_compiled(batch=True)
    start = time.perf_counter()
    integrate_batch(variants[:2], t[:10])
    load_batch = time.perf_counter() - start
    sweeps = []
    for label, options in (
        ("default settings", {}),
        (f"sweep setting h_max {SWEEP_H_MAX * 1e3:g} ms", {"h_max": SWEEP_H_MAX}),
    ):
        seconds, (_, stats) = _best_of(lambda o=options: integrate_batch(variants, t, **o), 1)
        ok = sum(s["status"] == 0 for s in stats)
        one = integrate_experiment(inputs, t, **options)[0]
        sweeps.append((label, seconds, len(variants) / seconds, ok, _dt56(inputs, one, t56_ref)))

    threads = numba.get_num_threads()
    print()
    print(
        f"rollerrig benchmark: {sim.protocol.name}, {duration:g} s simulated, "
        f"output {sim.output_rate:g} Hz"
    )
    print(
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}, numba {numba.__version__}"
    )
    print(f"tight reference (Radau compiled, rtol 1e-10): {ref_time:.2f} s")
    print(
        f"fast backend in this process: {'loaded from the cache' if was_cached else 'compiled'}"
        f" in {load_fast:.2f} s (single run), batch "
        f"{'loaded' if batch_cached else 'compiled'} in {load_batch:.2f} s"
    )
    if cli is not None:
        sizes = ", ".join(f"{s / 1e6:.2f}" for s in cli["sizes"])
        walls = ", ".join(f"{w:.2f}" for w in cli["walls"])
        print(
            f"`rollerrig simulate -e {args.experiment}` in fresh processes: cold (empty cache) "
            f"{cli['cold']:.2f} s, warm {cli['warm']:.2f} s (runs: {walls} s); cache size after "
            f"each run: {sizes} MB"
        )
    print()
    header = (
        f"{'solver (solve only)':<52} {'wall [s]':>9} {'x real time':>12} {'vs baseline':>12} "
        f"{'max|dT56| [N.m]':>16}  note"
    )
    print(header)
    print("-" * len(header))
    for label, seconds, rt, err, note in rows:
        print(
            f"{label:<52} {seconds:9.3f} {rt:12.1f} {base_time / seconds:11.1f}x "
            f"{err:16.3f}  {note}"
        )
    print(
        f"{'fast, dq roller drive (29 states), default':<52} {dq_time:9.3f} "
        f"{duration / dq_time:12.1f} {base_time / dq_time:11.1f}x {dq_err:16.3f}  "
        f"{st_dq['accepted_steps']} steps; error against its own Radau rtol 1e-10"
    )
    print()
    for label, seconds, rate, ok, err in sweeps:
        print(
            f"sweep, {label}: {len(variants)} variants ({n_k} stiffness x {n_lag} lags), "
            f"{threads} threads: {seconds:.2f} s = {rate:.1f} experiment-runs/s "
            f"({ok} succeeded; max|dT56| {err:.2f} N.m on the default variant)"
        )

    sweep_rate, sweep_err = sweeps[0][2], sweeps[0][4]
    good = [s for s in sweeps if s[4] <= 1.0]
    best_good = max(good, key=lambda s: s[2]) if good else None
    targets = []
    if cli is not None:
        growth = max(cli["sizes"]) - min(cli["sizes"])
        targets += [
            ("1  simulate, fresh process, warm cache", "<= 3 s", f"{cli['warm']:.2f} s",
             cli["warm"] <= 3.0),
            ("1  simulate, fresh process, empty cache", "<= 30 s", f"{cli['cold']:.2f} s",
             cli["cold"] <= 30.0),
            ("4  cache size after runs 2.. vs run 1", "constant", f"{growth:+d} bytes",
             growth == 0),
        ]  # fmt: skip
    targets += [
        ("2  default accuracy max|dT56| vs Radau 1e-10", "<= 0.1 N.m", f"{f_err:.3f} N.m",
         f_err <= 0.1),
        ("2  default solve-only real-time factor", ">= 1000x", f"{duration / f_time:.0f}x",
         duration / f_time >= 1000),
        ("2  default vs user baseline (same run)", ">= 300x", f"{base_time / f_time:.0f}x",
         base_time / f_time >= 300),
        (f"3  sweep runs/s on {threads} threads at <= 1 N.m", ">= 100/s",
         f"{best_good[2]:.1f}/s ({best_good[0]}, {best_good[4]:.2f} N.m)" if best_good
         else f"none <= 1 N.m ({sweep_rate:.1f}/s at {sweep_err:.2f} N.m)",
         bool(best_good) and best_good[2] >= 100),
    ]  # fmt: skip
    print()
    header = f"{'issue 9 target':<48} {'wanted':>10} {'measured':>36}  met"
    print(header)
    print("-" * len(header))
    for name, wanted, measured, met in targets:
        print(f"{name:<48} {wanted:>10} {measured:>36}  {'yes' if met else 'NO'}")
    steps = fast_rows_steps
    per_step = f_time / steps * 1e9
    print()
    print("why a target is missed, in this run's numbers:")
    if cli is not None and cli["warm"] > 3.0:
        print(
            f"- 1: a fresh process only importing numpy, scipy, xarray, matplotlib, numba and "
            f"rollerrig takes {cli['imports']:.2f} s of the {cli['warm']:.2f} s; the rest is "
            "loading the compiled solver, the solve, the NetCDF file and the figure"
        )
    if duration / f_time < 1000 or base_time / f_time < 300:
        from rollerrig.rig.model import N_STATES as n

        print(
            f"- 2: the default solve is {steps} steps of ROS34PW2 at {per_step:.0f} ns each "
            f"(4 right-hand sides and 4 {n}x{n} products, {n} states with the frame's two); "
            f"1000x real time needs <= "
            f"{duration / 1000 * 1e3:.1f} ms, 300x this baseline <= {base_time / 300 * 1e3:.1f} ms "
            f"({base_time / 300 / steps * 1e9:.0f} ns a step). The accuracy is set by the phase "
            "drift of the 13.8 Hz shaft mode (third order in the step): meeting both at once "
            "needs a method exact on that linear mode (exponential) or of fourth order"
        )
    if not (bool(best_good) and best_good[2] >= 100):
        print(
            f"- 3: {threads} threads; a sweep point costs what a single run at h_max "
            f"{SWEEP_H_MAX * 1e3:g} ms costs; other load on this machine takes threads away"
        )


def _dt56(inputs, x, t56_ref):
    return float(np.max(np.abs(_t56(inputs, x) - t56_ref)))


if __name__ == "__main__":
    main()
