"""
The release test and what the roller motor's lag does
=====================================================

After a sudden release of the wheel torque the roller-shaft torque T56 rings and overshoots.
Kayaalp fitted the open-loop V/f induction drive with a first-order response lag (c_lp = 2.75
1/s, τ ≈ 0.36 s). The same release with the lag, without it (an ideal induction drive) and with
a speed-controlled servo drive shows how much of the overshoot is the drive's.
"""

import matplotlib.pyplot as plt

import rollerrig as rr

rig = rr.default_rig()
protocol = rr.Protocol.from_steps(
    "release",
    [rr.Hold(0.5), rr.RampTorque(600.0, 1.5), rr.Hold(0.5), rr.ReleaseTorque(), rr.Hold(3.0)],
    normal_load=4300.0,
    roller_speed=30 / 3.6,
)
cases = {
    "induction, lag (Kayaalp)": rr.DriveConfig(roller="induction"),
    "induction, no lag": rr.DriveConfig(roller="induction", roller_lag=0.0),
    "servo (speed-controlled)": rr.DriveConfig(roller="servo"),
}
fig, ax = plt.subplots(figsize=(6, 3.5))
for label, drives in cases.items():
    ds = rr.Simulation(rig, protocol, drives=drives, output_rate=500.0).run()
    t56 = ds["t56"]
    before = float(t56.sel(time=2.4, method="nearest"))
    after = t56.where(ds["time"] > 2.6)
    overshoot = float(-after.min()) / before * 100
    print(f"{label:28s} T56 overshoot after the release: {overshoot:5.1f} %")
    ax.plot(ds["time"], t56, label=label)
ax.set(xlabel="time [s]", ylabel="T56 [N·m]", xlim=(2.0, 6.0))
ax.legend()
fig.tight_layout()
