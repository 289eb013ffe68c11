"""Benchmark of studies at scale (issue 11), printed as a table.

Run from the repository root:

    python benchmarks/bench_studies.py            # about 5 minutes on 2 cores
    python benchmarks/bench_studies.py --quick    # 1000-point large study, fewer points each
    python benchmarks/bench_studies.py --crossover    # only the fixed costs (2-4 min on 2 cores)

It measures, in one run on this machine, on grids of the release test (one ramp to 600 N.m,
hold, sudden release at 30 km/h; k56 x c_lp x load x speed) at the studies' own settings
(:func:`rollerrig.solve.fast.sweep_settings`: ETDRK4 at a 2.2 ms step, held to 0.1 N.m of
T56):

- the plain baseline a user would write: a Python loop of ``rollerrig.Simulation(...).run()``
  (the fast solver, one point after the other, a labelled dataset each) and the overshoot
  computed from it;
- ``run_study`` with the local executor (one process, numba threads over the cores);
- ``run_study`` on a local dask cluster of 1 and of 2 workers (one thread each): points/s,
  and the scaling efficiency rate(2) / (2 rate(1));
- a study of 10 000 points on 2 dask workers, with its wall time (workers' start, the store,
  everything ``rollerrig study run`` does except the figures);
- fixed costs against per-point costs (issue 20): studies of a few sizes on the local executor
  and on a local dask cluster of one worker per core, each run's start-up timed apart
  (:attr:`rollerrig.studies.StudyRun.fixed_cost`: the solver's load in this process; the
  cluster's start, the workers' warm-up and the cluster's close), the per-point cost of the
  rest, the ratio dask/local of the wall times, the size where dask starts to pay (measured,
  and as ``executor="auto"``'s rule estimates it from the per-point Python work measured here)
  and what ``"auto"`` chooses at each size.

Rates are points per second of wall time of the whole ``run_study`` call (cluster start
included, so small studies understate the steady rate; the steady rate is printed beside it).
Nothing here is a test: other load on the machine slows it.
"""

from __future__ import annotations

import argparse
import os
import platform
import tempfile
import time
from pathlib import Path


def _grid(n_k: int, n_c: int, n_load: int, n_speed: int) -> str:
    return f"""
name = "bench"
experiment = "release-test"
[grid]
"stiffness.roller_shaft" = {{ start = 43.5, stop = 143.5, num = {n_k}, unit = "kN.m/rad" }}
"induction_motor.response_lag_clp" = {{ start = 1.375, stop = 100, num = {n_c}, scale = "log" }}
load = {{ start = 4.3, stop = 20, num = {n_load}, unit = "kN" }}
speed = {{ start = 10, stop = 30, num = {n_speed}, unit = "km/h" }}
[outputs]
metrics = ["release_overshoot", "true_release_overshoot", "coa_bias_rms", "settling_time"]
"""


def _baseline(spec, limit: int) -> tuple[float, int]:
    """A user's loop: one Simulation per point, overshoot from its dataset."""
    import rollerrig
    from rollerrig.studies.design import design_points, point_setup
    from rollerrig.studies.metrics import release_overshoots

    table = design_points(spec)
    rig, base = rollerrig.default_rig(), rollerrig.load_protocol(spec.experiment)
    start = time.perf_counter()
    for i in range(limit):
        r, p, d = point_setup(rig, base, table.point(i))
        ds = rollerrig.Simulation(r, p, d, output_rate=1000.0).run()
        release_overshoots(ds, p)
    return time.perf_counter() - start, limit


def _run(spec, **kw):
    from rollerrig.studies import run_study

    steady = []

    def seen(p):
        steady.append((time.perf_counter(), p.done))

    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        result = run_study(spec, store=Path(tmp) / "s.zarr", progress=seen, **kw)
    wall = time.perf_counter() - start
    # Steady rate: from the first finished batch to the last (no cluster start, no warm-up).
    done = [(t, d) for t, d in steady if d > 0]
    rate = (done[-1][1] - done[0][1]) / (done[-1][0] - done[0][0]) if len(done) > 2 else None
    return result, wall, rate


def _one_group_grid(n_k: int, n_c: int) -> str:
    """A grid of rig keys only: every point in one protocol group (batches of the same size
    at every study size)."""
    return f"""
name = "bench-fixed"
experiment = "release-test"
[grid]
"stiffness.roller_shaft" = {{ start = 43.5, stop = 143.5, num = {n_k}, unit = "kN.m/rad" }}
"induction_motor.response_lag_clp" = {{ start = 1.375, stop = 100, num = {n_c}, scale = "log" }}
"""


def _serial_s(spec) -> tuple[float, float]:
    """Median per-point Python work (setup and metrics) of one local batch [s], and the share
    of a core this process got in it (as ``executor="auto"`` measures them)."""
    import statistics

    import numpy as np

    from rollerrig import default_rig, load_protocol
    from rollerrig.studies.design import design_points
    from rollerrig.studies.executor_choice import cpu_share
    from rollerrig.studies.runner import run_batch

    table = design_points(spec)
    points = [(i, table.point(i)) for i in range(min(16, len(table)))]
    timing: dict = {}
    protocol = load_protocol(spec.experiment)
    run_batch(default_rig(), protocol, points, spec.metrics, spec.output_rate, spec.h_max,
              timing=timing)  # fmt: skip
    share = cpu_share(timing["serial_cpu_s"], timing["serial_s"])
    return float(statistics.median(np.asarray(timing["serial_s"]))), share


def crossover(sizes: tuple[tuple[int, int], ...]) -> None:
    """Fixed and per-point costs of local and dask in one run; where dask starts to pay."""
    from rollerrig.studies.executor_choice import (
        MARGIN,
        available_cores,
        choose_executor,
        dask_fixed_cost,
    )
    from rollerrig.studies.studyfile import study_from_toml_string

    cores = available_cores()
    load = os.getloadavg()[0]
    print(f"fixed against per-point costs: local executor and a local dask cluster of {cores} "
          f"workers ({cores} cores by affinity; load average {load:.1f})")  # fmt: skip
    rows, per_point, fixed = [], {"local": [], "dask": []}, []
    serial = None
    for n_k, n_c in sizes:
        spec = study_from_toml_string(_one_group_grid(n_k, n_c))
        n = spec.size
        walls = {}
        for executor in ("local", "dask"):
            kw = {"workers": cores} if executor == "dask" else {}
            r, wall, _ = _run(spec, executor=executor, **kw)
            fc = r.fixed_cost
            start = fc.get("solver_load_s", 0.0) + fc.get("cluster_start_s", 0.0)
            warm = fc.get("worker_warm_up_s", 0.0)
            close = fc.get("cluster_close_s", 0.0)
            pp = (r.wall_time - start - warm - close) / n
            per_point[executor].append((n, pp))
            walls[executor] = wall
            if executor == "dask":
                fixed.append(start + warm + close)
            rows.append([executor, n, wall, start, warm, close, pp])
        serial, share = _serial_s(spec)  # at each size: the load changes
        auto = choose_executor(n - 16, cores=cores, serial_s=serial, share=share).executor
        faster = min(walls, key=walls.get)
        rows[-2] += [1.0, auto, faster]
        rows[-1] += [walls["dask"] / walls["local"], auto, faster]
    print()
    print(f"{'executor':<9} {'points':>7} {'wall [s]':>9} {'start [s]':>10} "
          f"{'warm-up [s]':>12} {'close [s]':>10} {'per point [ms]':>15} {'x local':>8} "
          f"{'auto':>6} {'faster':>7}")  # fmt: skip
    for ex, n, wall, start, warm, close, pp, ratio, auto, faster in rows:
        print(f"{ex:<9} {n:>7} {wall:>9.2f} {start:>10.2f} {warm:>12.2f} {close:>10.2f} "
              f"{pp * 1e3:>15.1f} {ratio:>8.2f} {auto:>6} {faster:>7}")  # fmt: skip
    # Per-point costs of the largest size (its start-up weighs least).
    pp_local, pp_dask = per_point["local"][-1][1], per_point["dask"][-1][1]
    t_fixed = sorted(fixed)[len(fixed) // 2]
    print()
    print(f"start-up of dask (median of {len(fixed)}): {t_fixed:.1f} s (the rule's estimate: "
          f"{dask_fixed_cost(cores, cores):.1f} s); per point: local {pp_local * 1e3:.1f} ms, "
          f"dask {pp_dask * 1e3:.1f} ms")  # fmt: skip
    if pp_local > pp_dask:
        print(f"measured crossover: dask pays from about {t_fixed / (pp_local - pp_dask):.0f} "
              "points")  # fmt: skip
    else:
        print("measured crossover: none (dask's points are not cheaper than local ones here)")
    print(f"per-point Python work {serial * 1e3:.1f} ms at a share of {share:.2f} of a core; "
          f"start-up on a free core: {t_fixed * share:.1f} s (the rule's "
          f"{dask_fixed_cost(cores, cores):.1f} s)")  # fmt: skip
    # Here, and on the same machine quiet (the Python work then takes its CPU time).
    for a, s in ((share, serial), (1.0, serial * share)):
        saving = s * (1 - 1 / max(1.0, a * cores))
        if saving > 0:
            est = dask_fixed_cost(cores, cores, a) / saving
            print(f"the rule at a share of {a:.2f} ({s * 1e3:.1f} ms a point): saving "
                  f"{saving * 1e3:.1f} ms a point, break-even at about {est:.0f} points, auto "
                  f"takes dask from about {MARGIN * est:.0f}")  # fmt: skip
        else:
            print(f"the rule at a share of {a:.2f}: no free core for dask, auto stays local")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller studies")
    parser.add_argument("--large", type=int, default=None, help="points of the large study")
    parser.add_argument(
        "--crossover", action="store_true", help="only the fixed and per-point costs"
    )
    args = parser.parse_args()
    if args.crossover:
        crossover(((4, 8), (8, 16), (16, 25)))
        return

    from rollerrig.solve.fast import SWEEP_EXP_STEP
    from rollerrig.studies.studyfile import study_from_toml_string

    small = study_from_toml_string(_grid(4, 4, 3, 3) if not args.quick else _grid(3, 3, 2, 2))
    large_n = args.large or (1000 if args.quick else 10_000)
    side = round(large_n**0.25)
    large = study_from_toml_string(_grid(side, side, side, large_n // side**3))

    print(f"rollerrig studies benchmark on {platform.node()} ({os.cpu_count()} cores), "
          f"the sweeps' settings (ETDRK4 at {SWEEP_EXP_STEP * 1e3:g} ms), "
          "release test 6.52 s at 1 kHz output")  # fmt: skip
    rows = []
    _run(small, executor="local")  # load the compiled code into this process first
    base_s, base_n = _baseline(small, 16 if not args.quick else 8)
    base_rate = base_n / base_s
    rows.append(("baseline: loop of Simulation().run()", base_n, base_s, base_rate, None))
    r, wall, steady = _run(small, executor="local")
    rows.append((f"local executor ({r.workers} numba threads)", r.computed, wall, r.rate, steady))
    rates = {}
    for workers in (1, 2):
        r, wall, steady = _run(small, executor="dask", workers=workers)
        rates[workers] = steady or r.rate
        rows.append((f"dask, {workers} worker(s)", r.computed, wall, r.rate, steady))
    r, wall, steady = _run(large, executor="dask", workers=2)
    rows.append((f"dask, 2 workers, large study ({r.computed} points)", r.computed, wall, r.rate,
                 steady))  # fmt: skip
    large_failed = sum(v for k, v in r.counts.items() if k != "ok")

    print()
    print(f"{'run':<48} {'points':>7} {'wall [s]':>9} {'points/s':>9} {'steady/s':>9} "
          f"{'x baseline':>10}")  # fmt: skip
    for name, n, wall, rate, steady in rows:
        steady_text = f"{steady:9.1f}" if steady else f"{'-':>9}"
        print(f"{name:<48} {n:>7} {wall:>9.1f} {rate:>9.1f} {steady_text} "
              f"{(steady or rate) / base_rate:>10.1f}")  # fmt: skip
    efficiency = rates[2] / (2 * rates[1])
    print()
    print(f"scaling efficiency, 2 dask workers against 1 (steady rates): {efficiency:.0%}")
    print(f"large study: {rows[-1][1]} points in {rows[-1][2]:.1f} s wall "
          f"({large_failed} not ok)")  # fmt: skip
    print()
    crossover(((4, 8), (8, 16), (16, 25)) if not args.quick else ((4, 4), (8, 16)))


if __name__ == "__main__":
    main()
