"""
A Polach fit on a creep curve read from a CSV file
==================================================

Creep–CoA points, as a lab has them from a test or digitises them from a published figure
(WebPlotDigitizer and similar tools export two columns, creep and CoA), are fitted with
Polach's creep law: μ0, A, B, k_A and k_S with their standard errors, the correlations, and the
checks that say whether the points determine them.

**Where the data come from.** rollerrig ships no measured creep curve: the points below are
*synthetic*, Polach's dry set of Polach (2005, Wear 258, Table 2) evaluated on the Pardubice
rig at 10 kN and 30 km/h, with 2 % multiplicative noise, written to the CSV a digitiser would
export. One speed and creep to about four times the peak's: the fit's checks then say which
parameters such a curve cannot determine (a ``PolachFitWarning``), as they would on real points.
Replace ``points.csv`` by your own file; the fit and its checks are the same. Because the
truth is known here, the fit's distance to it is printed in standard errors.
"""

import matplotlib.pyplot as plt
import numpy as np

from rollerrig.contact import POLACH_DRY, polach_creep_curve
from rollerrig.fit import creep_stiffness_for_rig, fit_polach
from rollerrig.rig.parameters import default_rig

rig = default_rig()
g = rig.geometry
load, speed = 10e3, 30 / 3.6  # [N], [m/s]

rng = np.random.default_rng(7)
creep = np.sort(np.concatenate([np.linspace(0.0005, 0.01, 12), np.linspace(0.012, 0.15, 16)]))
true = polach_creep_curve(
    creep,
    load,
    speed,
    g.wheel_radius_x,
    g.wheel_radius_y,
    g.roller_radius_x,
    g.roller_radius_y,
    POLACH_DRY,
)
coa = true.adhesion_coefficient * (1 + 0.02 * rng.standard_normal(creep.size))
np.savetxt(
    "points.csv",
    np.column_stack([creep, coa]),
    delimiter=",",
    header="creep [-],CoA [-]",
    comments="",
)

# %%
# Read the points and fit
# -----------------------
data = np.loadtxt("points.csv", delimiter=",", skiprows=1)
stiffness = creep_stiffness_for_rig(load, rig)  # G a b C11 of the rig's contact [N]
fit = fit_polach(data[:, 0], data[:, 1], load, stiffness, rolling_speed=speed)
print(fit.parameters)
print("standard errors:", {k: round(float(v), 3) for k, v in fit.stderr.items()})
print("identifiable:", fit.identifiable, "| RMSE:", round(float(fit.rmse), 4))
distance = fit.truth_distance(POLACH_DRY)
print("distance to the truth [σ]:", {k: round(v["sigma"], 2) for k, v in distance.items()})

# %%
# The points, the fit and the truth
# ---------------------------------
s = np.linspace(0, 0.15, 300)
fitted = polach_creep_curve(
    s,
    load,
    speed,
    g.wheel_radius_x,
    g.wheel_radius_y,
    g.roller_radius_x,
    g.roller_radius_y,
    fit.parameters,
)
fig, ax = plt.subplots(figsize=(6, 3.5))
ax.plot(data[:, 0] * 100, data[:, 1], "o", ms=4, label="points (synthetic)")
ax.plot(s * 100, fitted.adhesion_coefficient, label="Polach fit")
ax.plot(creep * 100, true.adhesion_coefficient, "k:", label="truth (Polach 2005 dry)")
ax.set(xlabel="creep [%]", ylabel="CoA [-]")
ax.legend()
fig.tight_layout()
