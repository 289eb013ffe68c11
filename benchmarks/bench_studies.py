"""Benchmark of studies at scale (issue 11), printed as a table.

Run from the repository root:

    python benchmarks/bench_studies.py            # about 5 minutes on 2 cores
    python benchmarks/bench_studies.py --quick    # 1000-point large study, fewer points each

It measures, in one run on this machine, on grids of the release test (one ramp to 600 N.m,
hold, sudden release at 30 km/h; k56 x c_lp x load x speed) at the studies' default accuracy
(largest step :data:`rollerrig.solve.fast.SWEEP_H_MAX`, max |ΔT56| <= 1 N.m):

- the plain baseline a user would write: a Python loop of ``rollerrig.Simulation(...).run()``
  (the fast solver, one point after the other, a labelled dataset each) and the overshoot
  computed from it;
- ``run_study`` with the local executor (one process, numba threads over the cores);
- ``run_study`` on a local dask cluster of 1 and of 2 workers (one thread each): points/s,
  and the scaling efficiency rate(2) / (2 rate(1));
- a study of 10 000 points on 2 dask workers, with its wall time (workers' start, the store,
  everything ``rollerrig study run`` does except the figures).

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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller studies")
    parser.add_argument("--large", type=int, default=None, help="points of the large study")
    args = parser.parse_args()

    from rollerrig.solve.fast import SWEEP_H_MAX
    from rollerrig.studies.studyfile import study_from_toml_string

    small = study_from_toml_string(_grid(4, 4, 3, 3) if not args.quick else _grid(3, 3, 2, 2))
    large_n = args.large or (1000 if args.quick else 10_000)
    side = round(large_n**0.25)
    large = study_from_toml_string(_grid(side, side, side, large_n // side**3))

    print(f"rollerrig studies benchmark on {platform.node()} ({os.cpu_count()} cores), "
          f"h_max {SWEEP_H_MAX * 1e3:g} ms, release test 6.52 s at 1 kHz output")  # fmt: skip
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


if __name__ == "__main__":
    main()
