"""
The seed's adhesion experiment on the digital twin
==================================================

The bundled ``seed-30kmh-dry`` experiment of Kayaalp's dissertation: 30 km/h, 4.3 kN, three
ramps of the wheel torque past the adhesion peak, each ended by a sudden release. The twin
gives the truth at the contact beside what the rig measures: the rig's CoA (T56 over r_r S)
differs from the contact's by the roller's inertia, the bearing loss, the shaft's oscillation
and the swinging arm's load transfer.
"""

import matplotlib.pyplot as plt

import rollerrig as rr
from rollerrig.report.twin import experiment_figure

rig = rr.default_rig()
protocol = rr.load_protocol("seed-30kmh-dry")
print(protocol.name, f"{protocol.duration:.1f} s")
ds = rr.Simulation(rig, protocol, output_rate=250.0).run()
print(
    f"peak CoA at the contact {float(ds['coa'].max()):.3f}, "
    f"as the rig reports it {float(ds['measured_coa'].max()):.3f}"
)

# %%
# Truth beside what the rig measures
# ----------------------------------
fig = experiment_figure(ds)

# %%
# The error of the rig's CoA over the test
# ----------------------------------------
fig, ax = plt.subplots(figsize=(6, 3))
ax.plot(ds["time"], ds["measured_coa"] - ds["coa"])
ax.set(xlabel="time [s]", ylabel="rig CoA − contact CoA [-]")
fig.tight_layout()
