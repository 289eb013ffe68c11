"""
The smoothing-filter study
==========================

Which smoothing filter, at which window, gives the CoA with the least error? The study scores
MATLAB-style smoothers (moving average, Gaussian, Butterworth, LOWESS/LOESS, Savitzky–Golay) on
a recorded torque against the truth the twin knows: steady error, transient error and lag.
"""

import rollerrig as rr
from rollerrig.report.filters import study_ranking_figure
from rollerrig.signal.scoring import filter_study

rig = rr.default_rig()
protocol = rr.Protocol.from_steps(
    "ramp-release",
    [rr.Hold(1.0), rr.RampTorque(700.0, 2.0), rr.ReleaseTorque(), rr.Hold(2.0)],
    normal_load=4300.0,
    roller_speed=30 / 3.6,
)
ds = rr.Simulation(rig, protocol, output_rate=500.0).run()
rec, truth = rr.synthetic_recording(ds, sample_rate=250.0, seed=2)
true_t56 = truth["t56"].interp(time=rec.time).values
table = filter_study(rec.time, rec["torque"], truth=true_t56)
for row in table[:5]:
    score = row.score
    print(
        f"{row.rank}. {row.label:15s} cost {score.cost:.3f}: "
        f"noise left {score.noise_left:.3f}, lag {score.lag * 1e3:+.2f} ms"
    )

# %%
fig = study_ranking_figure(table, top=15)
