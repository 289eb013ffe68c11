"""
The corrected CoA and its uncertainty budget
============================================

The rig's CoA carries the roller's inertia and its bearing loss; the analysis corrects it (the
roller's equation of motion, F_x r_r = T56 + J5 α5 + R05) and states the expanded uncertainty
U (k = 2, JCGM 100) of every corrected value, with the budget of each phase: which input
(torque sensor class, air-spring area, radii, J5, bearing loss, the arm) contributes what.
A short test is simulated, recorded as the rig's DAQ would (250 Hz, noise, motor lines) and
analysed, with the twin's truth beside it.
"""

import rollerrig as rr
from rollerrig.report.analysis import coa_uncertainty_figure, rig_versus_corrected_figure

rig = rr.default_rig()
protocol = rr.Protocol.from_steps(
    "two-ramps",
    [rr.Hold(1.0), rr.Repeat(2, [rr.RampTorque(850.0, 2.0), rr.ReleaseTorque(), rr.Hold(1.5)])],
    normal_load=4300.0,
    roller_speed=30 / 3.6,
)
ds = rr.Simulation(rig, protocol, output_rate=500.0).run()
rec, truth = rr.synthetic_recording(ds, sample_rate=250.0, seed=1)
result = rr.analyze(rec, rig=rig, truth=truth, run_study=False)
print([phase.name for phase in result.phases])

# %%
# Rig CoA, corrected CoA and the truth
# ------------------------------------
fig = rig_versus_corrected_figure(result, truth)

# %%
# The expanded uncertainty along the test, and the budget
# -------------------------------------------------------
fig = coa_uncertainty_figure(result)
budget = result.coa_uncertainty
for note in budget.notes[:5]:
    print("note:", note)
