"""
Reading a LabVIEW TDMS, an INCA/CANape MDF4 and a German bench CSV
==================================================================

Your DAQ's files, read into SI units through a *channel map*: a small TOML file that says which
column is which quantity, in which unit, and how the file is laid out. Here three files are
written as the tools write them (a LabVIEW waveform TDMS without a time channel, an MDF4 with a
``time`` master per raster group as INCA and CANape store it, and a CSV with ``;``, decimal
commas, a units row and day-first dates as a German bench exports it), each read with its map.
"""

import datetime as dt

import matplotlib.pyplot as plt
import numpy as np
from asammdf import MDF, Signal
from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

import rollerrig as rr

fs = 250.0  # [Hz]
t = np.arange(0, 4.0, 1 / fs)
torque = 300 + 250 * np.clip(t - 1, 0, 2) / 2 + 3 * np.sin(2 * np.pi * 14.7 * t)  # [N.m]
rpm_roller = np.full_like(t, 176.0)  # 30 km/h on the 452 mm roller [1/min]
rpm_wheel = rpm_roller * 0.452 / 0.348 * 1.002
pressure = np.full_like(t, 0.86)  # [bar]: 4.3 kN on 0.05 m²

# %%
# LabVIEW "Write to TDMS" with waveforms: no time channel, ``wf_increment`` per channel
# ---------------------------------------------------------------------------------------
wf = {
    "wf_increment": 1 / fs,
    "wf_start_offset": 0.0,
    "wf_start_time": np.datetime64("2024-08-05T11:46:13"),
}
with TdmsWriter("labview.tdms") as writer:
    writer.write_segment(
        [
            RootObject({"name": "adhesion test"}),
            GroupObject("Adhesion test"),
            ChannelObject("Adhesion test", "Torque roller", torque, {**wf, "unit_string": "Nm"}),
            ChannelObject("Adhesion test", "n roller", rpm_roller, {**wf, "unit_string": "1/min"}),
            ChannelObject("Adhesion test", "n wheel", rpm_wheel, {**wf, "unit_string": "1/min"}),
            ChannelObject("Adhesion test", "p air", pressure, {**wf, "unit_string": "bar"}),
        ]
    )
with open("labview-map.toml", "w", encoding="utf-8") as f:
    f.write("""description = "LabVIEW waveform TDMS"
[channels.torque]
column = "Adhesion test/Torque roller"
unit = "N.m"
[channels.roller_speed]
column = "Adhesion test/n roller"
unit = "rpm"
[channels.wheel_speed]
column = "Adhesion test/n wheel"
unit = "rpm"
[channels.air_spring_pressure]
column = "Adhesion test/p air"
unit = "bar"
""")
tdms = rr.read_recording("labview.tdms", "labview-map.toml", validate="lenient")
print(tdms)

# %%
# INCA / CANape MDF4: one group per raster, each with its own ``time`` master
# ----------------------------------------------------------------------------
mdf = MDF(version="4.10")
fast = t  # the 4 ms raster
slow = t[::25]  # the 100 ms raster
mdf.append(
    [
        Signal(torque, fast, name="Torque", unit="Nm"),
        Signal(rpm_roller, fast, name="n_Roller", unit="1/min"),
        Signal(rpm_wheel, fast, name="n_Wheel", unit="1/min"),
    ],
    acq_name="4ms",
)
mdf.append([Signal(pressure[::25], slow, name="p_Air", unit="bar")], acq_name="100ms")
mdf.save("canape.mf4", overwrite=True)
with open("canape-map.toml", "w", encoding="utf-8") as f:
    f.write("""description = "CANape MDF4, two rasters"
[channels.torque]
column = "Torque"
unit = "N.m"
[channels.roller_speed]
column = "n_Roller"
unit = "rpm"
[channels.wheel_speed]
column = "n_Wheel"
unit = "rpm"
[channels.air_spring_pressure]
column = "p_Air"
unit = "bar"
""")
mf4 = rr.read_recording("canape.mf4", "canape-map.toml", validate="lenient")
print(mf4)

# %%
# A German bench CSV: ``;``, decimal commas, a units row, day-first timestamps
# -----------------------------------------------------------------------------
start = dt.datetime(2024, 8, 12, 23, 59, 58)
rows = ["Zeit;Drehmoment;Drehzahl Rolle;Drehzahl Rad;Druck", ";Nm;U/min;U/min;bar"]
for i in range(0, t.size, 25):  # 10 Hz bench channels, across midnight
    stamp = (start + dt.timedelta(seconds=t[i])).strftime("%d.%m.%y %H:%M:%S.%f")[:-4]
    values = [torque[i], rpm_roller[i], rpm_wheel[i], pressure[i]]
    rows.append(stamp + ";" + ";".join(f"{v:.3f}".replace(".", ",") for v in values))
with open("pruefstand.csv", "w", encoding="latin-1") as f:
    f.write("\n".join(rows) + "\n")
with open("bench-map.toml", "w", encoding="utf-8") as f:
    f.write("""description = "German bench CSV"
[file]
separator = ";"
decimal = ","
header_row = 0
units_row = 1
encoding = "latin-1"
dayfirst = true
[time]
column = "Zeit"
[channels.torque]
column = "Drehmoment"
unit = "N.m"
[channels.roller_speed]
column = "Drehzahl Rolle"
unit = "U/min"
[channels.wheel_speed]
column = "Drehzahl Rad"
unit = "U/min"
[channels.air_spring_pressure]
column = "Druck"
unit = "bar"
""")
csv = rr.read_recording("pruefstand.csv", "bench-map.toml", validate="lenient")
print(csv)

# %%
# The three, in SI units on one plot
# ----------------------------------
fig, ax = plt.subplots(figsize=(6, 3.5))
for rec, label in ((tdms, "TDMS"), (mf4, "MDF4"), (csv, "bench CSV")):
    ax.plot(rec.time - rec.time[0], rec["torque"], label=label)
ax.set(xlabel="time [s]", ylabel="torque [N·m]")
ax.legend()
fig.tight_layout()
