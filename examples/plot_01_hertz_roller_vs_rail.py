"""
Hertz contact: a wheel on the roller versus on a rail
=====================================================

A roller rig replaces the rail by a roller of finite radius. The contact ellipse of the wheel on
the roller is shorter in the rolling direction than on a tangent rail, so the creep curve's
initial slope (G a b C11) differs: what a roller rig measures must be transferred to the track.
This example computes both contacts for the Pardubice rig's wheel and roller with the exact
Hertz theory (complete elliptic integrals), and the Polach creep curves on both.
"""

import matplotlib.pyplot as plt
import numpy as np

from rollerrig.contact import (
    POLACH_DRY,
    contact_versus_roller_radius,
    hertz_contact,
    polach_creep_curve,
)
from rollerrig.rig.parameters import default_rig

rig = default_rig()
g = rig.geometry
load = 10e3  # normal load [N]

roller = hertz_contact(
    load, g.wheel_radius_x, g.wheel_radius_y, g.roller_radius_x, g.roller_radius_y
)
# a tangent rail: infinite radius in the rolling direction, a 300 mm rail-head crown across
rail = hertz_contact(load, g.wheel_radius_x, g.wheel_radius_y, np.inf, 0.300)
for label, c in (("roller", roller), ("rail", rail)):
    print(
        f"{label:6s} a = {c.semi_axis_x * 1e3:.2f} mm, b = {c.semi_axis_y * 1e3:.2f} mm, "
        f"area = {c.area * 1e6:.1f} mm²"
    )

# %%
# The ellipse as the roller's radius grows towards a rail
# -------------------------------------------------------
radii = np.linspace(0.2, 3.0, 30)  # roller radius in the rolling plane [m]
comparison = contact_versus_roller_radius(
    radii, load, g.wheel_radius_x, g.wheel_radius_y, g.roller_radius_y
)
print(
    "area ratio at the Pardubice roller:",
    float(np.interp(g.roller_radius_x, radii, comparison.area_ratio)),
)
fig, ax = plt.subplots(figsize=(6, 3.5))
ax.plot(radii * 1e3, comparison.area_ratio, marker=".")
ax.axvline(g.roller_radius_x * 1e3, color="grey", ls=":", label="Pardubice roller")
ax.set(xlabel="roller radius [mm]", ylabel="area / area on rail [-]")
ax.legend()
fig.tight_layout()

# %%
# Creep curves on roller and rail (Polach, dry set of Polach 2005)
# ----------------------------------------------------------------
creep = np.linspace(0.0, 0.05, 400)
speed = 30 / 3.6  # [m/s]
on_roller = polach_creep_curve(
    creep,
    load,
    speed,
    g.wheel_radius_x,
    g.wheel_radius_y,
    g.roller_radius_x,
    g.roller_radius_y,
    POLACH_DRY,
)
on_rail = polach_creep_curve(
    creep, load, speed, g.wheel_radius_x, g.wheel_radius_y, 1e6, 0.300, POLACH_DRY
)
fig, ax = plt.subplots(figsize=(6, 3.5))
ax.plot(
    creep * 100,
    on_roller.adhesion_coefficient,
    label=f"roller r = {g.roller_radius_x * 1e3:.0f} mm",
)
ax.plot(creep * 100, on_rail.adhesion_coefficient, "--", label="tangent rail")
ax.set(xlabel="creep [%]", ylabel="CoA [-]", title="Polach dry, 10 kN, 30 km/h")
ax.legend()
fig.tight_layout()
for label, curve in (("roller", on_roller), ("rail", on_rail)):
    creep_at_peak, peak_coa = curve.peak
    print(f"peak on the {label}: CoA {peak_coa:.3f} at {creep_at_peak * 100:.2f} % creep")
