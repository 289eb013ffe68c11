"""
Explained spectra and the order map
===================================

Every line of the torque spectrum is attributed: rotation orders of wheel and roller, the
motors' electrical lines (PMSM pole pairs, the induction motor's supply and slip), the chain's
torsional modes. Free rolling at several speeds, recorded as the demo writes it, gives the
order map: a line that moves with speed is an order, one that stays is a mode or a pump.
"""

import rollerrig as rr
from rollerrig.report.spectra import order_map_figure, spectrum_figure
from rollerrig.signal.workflow import explain_recording, explain_recordings

rig = rr.default_rig()
recordings = []
for kmh in (10, 20, 30):
    protocol = rr.Protocol.from_steps(
        f"free-{kmh}", [rr.Hold(6.0)], normal_load=4300.0, roller_speed=kmh / 3.6
    )
    ds = rr.Simulation(rig, protocol, output_rate=1200.0).run()
    rec, _ = rr.synthetic_recording(ds, sample_rate=600.0, seed=kmh)
    recordings.append(rec)

explained = explain_recording(recordings[-1], "torque", rig)
print(explained.format_table()[:1500])

# %%
fig = spectrum_figure(explained, max_frequency=150.0)

# %%
# The order map over the three speeds
# -----------------------------------
spectra = explain_recordings(recordings, "torque", rig)
fig = order_map_figure(spectra.order_map(), roller_radius=rig.geometry.roller_radius_x)
