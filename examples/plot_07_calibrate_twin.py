"""
Calibrating the twin to a recording
===================================

``calibrate`` replays the recorded wheel-torque request through the twin and fits the rig keys
you name to the recorded T56 and encoder speeds: each value with its standard error (Newey–West),
the correlations, the residuals' whiteness, and warnings for what the recording cannot identify.
Here the recording is made by a twin whose roller-shaft stiffness is 20 % above the bundled
rig's; the calibration should find it.
"""

import rollerrig as rr
from rollerrig.calibrate import calibrate
from rollerrig.report.calibration import calibration_figure

rig = rr.default_rig()
true_rig = rig.with_overrides({"stiffness.roller_shaft": (52.2, "kN.m/rad")})
protocol = rr.Protocol.from_steps(
    "calibration-run",
    [rr.Hold(0.5), rr.RampTorque(500.0, 1.0), rr.ReleaseTorque(), rr.Hold(1.5)],
    normal_load=4300.0,
    roller_speed=30 / 3.6,
)
ds = rr.Simulation(true_rig, protocol, output_rate=500.0).run()
rec, _ = rr.synthetic_recording(ds, sample_rate=250.0, seed=3)

cal = calibrate(rec, ["stiffness.roller_shaft"], rig=rig, max_iterations=5)
print(cal)
for p in cal.parameters.values():
    print(f"{p.key}: {p.value:.4g} ± {p.standard_error:.2g} (true 5.22e+04)")

# %%
fig = calibration_figure(cal.fit_dataset())
