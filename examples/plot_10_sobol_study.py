"""
A Sobol' study of the measuring error
=====================================

Which rig parameter matters most for the release overshoot and the CoA's bias? A study file
names the parameters with their distributions and the metrics; ``run_study`` samples them
(Sobol', Saltelli's scheme), runs the twin at every point and computes the Sobol' indices.
The bundled ``sensitivity`` study has 1792 points; this one is a small version (64 base
points, three parameters) on the local executor (``executor="dask"`` for a cluster).
"""

from pathlib import Path

import rollerrig as rr
from rollerrig.report.studies import study_figures
from rollerrig.studies.sensitivity import sobol_indices

Path("small-sobol.toml").write_text(
    """name = "small-sobol"
description = "release overshoot: k56, AM lag, load"
experiment = "release-test"
[sample]
method = "sobol"
n = 32
seed = 1
second_order = false
[sample.parameters]
load = { distribution = "uniform", low = 4.3, high = 20.0, unit = "kN" }
[sample.parameters."stiffness.roller_shaft"]
distribution = "uniform"
low = 43.5
high = 143.5
unit = "kN.m/rad"
[sample.parameters."induction_motor.response_lag_clp"]
distribution = "loguniform"
low = 1.375
high = 100.0
unit = "1/s"
[outputs]
metrics = ["release_overshoot", "coa_bias_rms"]
""",
    encoding="utf-8",
)
run = rr.run_study("small-sobol.toml", store="small-sobol.zarr", executor="local", restart=True)
print(", ".join(f"{n} {status}" for status, n in run.counts.items()), f"in {run.wall_time:.1f} s")
for metric in ("release_overshoot", "coa_bias_rms"):
    for row in sobol_indices(run.dataset, metric).rows():
        print(
            f"{metric:17s} {row['parameter']:32s} S1 {row['S1']:+.3f} ± {row['S1_conf']:.3f}"
            f"  ST {row['ST']:.3f} ± {row['ST_conf']:.3f}"
        )

# %%
# The figures ``rollerrig study show`` writes: scatter plots and the Sobol' bars
# ------------------------------------------------------------------------------
figures = study_figures(run.dataset, ["release_overshoot"])
print(list(figures))
