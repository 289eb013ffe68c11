"""Benchmark of the creep laws: one creep curve of 100 creepages per law, on one core.

Run from the repository root:

    python benchmarks/bench_creep_laws.py

Pins numpy's thread pools to one thread (set before numpy is imported), warms each law once,
then reports the median and best wall time of repeated calls for a 100-point creep curve on the
Eurosprinter ellipse of CONTACT's tractcurv example (a = 6.30 mm, b = 12.61 mm, 106.7 kN), with
the default grid (30 x 30 strips): pure longitudinal creep, and combined creepage with spin.
The target of issue 19 is a FASTSIM curve of 100 creepages in under 10 ms on one core.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import statistics  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from rollerrig.contact.fastsim import fastsim  # noqa: E402
from rollerrig.contact.strip import fastrip  # noqa: E402

KW = dict(
    semi_axis_x=6.3036e-3,
    semi_axis_y=12.6072e-3,
    normal_load=106.7e3,
    shear_modulus=82e9,
    poisson=0.28,
)


def _time(fn, repeats=30):
    fn()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times) * 1e3, min(times) * 1e3


def main() -> None:
    s = np.linspace(0.0, 0.05, 100)
    mu = 0.36 * (0.62 * np.exp(-0.7 * 10.0 * s) + 0.38)
    cases = {
        "fastsim, xi only": lambda: fastsim(s, friction=0.33, **KW),
        "fastsim, xi + eta + spin": lambda: fastsim(s, 0.5 * s, 2.0 * s, friction=0.33, **KW),
        "modified fastsim, xi only": lambda: fastsim(
            s, friction=mu, k0=0.54, alpha_inf=0.02, beta=0.62, **KW
        ),
        "fastrip, xi only": lambda: fastrip(s, friction=0.33, **KW),
        "fastrip, xi + eta + spin": lambda: fastrip(s, 0.5 * s, 2.0 * s, friction=0.33, **KW),
    }
    print(f"{'law (100 creepages, 30 x 30 grid)':40s} {'median [ms]':>12s} {'best [ms]':>10s}")
    for name, fn in cases.items():
        med, best = _time(fn)
        print(f"{name:40s} {med:12.2f} {best:10.2f}")


if __name__ == "__main__":
    main()
