"""
A Polach fit on a measured creep curve read from a CSV file
===========================================================

Creep–CoA points, as a lab has them from a test or digitises them from a published figure, are
fitted with Polach's creep law: μ0, A, B, k_A and k_S with their standard errors, the
correlations, and the checks that say whether the points determine them.

**Where the data come from.** ``eurosprinter_engel1998.csv`` (beside this example in the
repository's ``examples/`` folder) holds 168 measured points of the Siemens Eurosprinter
127 001 locomotive (one wheel, 106.7 kN, traction on tangent track at 36 km/h), published
by Engel, Beck & Alders (Elektrische Bahnen 96, 1998, 201-209) and shown in two figures of the
user guide of Vollebregt's CONTACT. They were digitised from those figures' pixels by
``tools/digitise_eurosprinter.py``: axes and ticks located, the cyan markers isolated by colour
and their centres found by template matching; to within 0.04 % creepage and 0.005 in F_x/F_n
below 5 % creepage, 0.2 % and 0.004 above (half a marker width; the file's header says more).
The creepage is Kalker's ξ, which the reader is told (``creepage="mean"``).

The contact is CONTACT's for this case: a 625 mm wheel on a rail, Hertz a/b = 0.5, G = 82 GPa,
ν = 0.28. One speed and much scatter: the fit's checks then say which parameters such a curve
cannot determine (a ``PolachFitWarning``). Replace the file by your own; the fit and its checks
are the same.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from scipy import optimize, stats

from rollerrig.analysis.measured_curve import read_curve_csv
from rollerrig.contact import POLACH_DRY
from rollerrig.contact.creep import PolachParameters
from rollerrig.contact.hertz import hertz_contact
from rollerrig.contact.kalker import kalker_coefficients
from rollerrig.contact.laws import EUROSPRINTER_COULOMB, EUROSPRINTER_MODIFIED_FASTSIM
from rollerrig.fit import fit_polach, polach_coa
from rollerrig.fit.modified_fastsim import modified_fastsim_coa

csv = Path("eurosprinter_engel1998.csv")
if not csv.exists():  # run from the repository's root
    csv = Path("examples") / csv

# %%
# Read the points and build the contact
# -------------------------------------
# The file has the load, the speed and the slip velocity (w = ξ·10 m/s) as columns.
points = read_curve_csv(csv, creepage="mean")
xi, coa, w = points.creepage, points.coa, points.slip_velocity
load = float(points.normal_load[0])  # [N]
nu, shear = 0.28, 82e9  # [-], [Pa]
youngs = 2 * shear * (1 + nu)


def semi_axes(crown):
    """Hertz a, b [m] of the 625 mm wheel on a rail of crown radius ``crown`` [m]."""
    h = hertz_contact(load, 0.625, np.inf, np.inf, crown, youngs, nu)
    return float(h.semi_axis_x), float(h.semi_axis_y)


crown = optimize.brentq(lambda r: semi_axes(r)[0] / semi_axes(r)[1] - 0.5, 0.7, 10.0)
a, b = semi_axes(crown)
stiffness = shear * a * b * float(kalker_coefficients(a / b, nu).c11)  # G a b C11 [N]
print(f"{xi.size} points; rail crown {crown:.3f} m: a = {a * 1e3:.2f} mm, b = {b * 1e3:.2f} mm")

# %%
# Fit and the checks
# ------------------
fit = fit_polach(xi, coa, load, stiffness, slip_velocity=w)
print(fit.parameters)
print("standard errors:", {k: round(float(v), 3) for k, v in fit.stderr.items()})
print("identifiable:", fit.identifiable, "| RMSE:", round(float(fit.rmse), 4))
print(fit.coverage.describe())
print(fit.residual_structure.describe())

# %%
# The published sets on the same points
# -------------------------------------
# Polach's dry set (Polach 2005) is a general-purpose set for dry rail; the modified FASTSIM
# set of Spiryagin, Polach & Cole (2013) was fitted to this very curve, and CONTACT runs it in
# its example; Kalker's theory with Coulomb friction μ = 0.33 is CONTACT's first curve.
contact = (load, a, b, shear, nu)
published = {
    "modified FASTSIM, Spiryagin et al. 2013": lambda x, v: modified_fastsim_coa(
        x, v, *contact, EUROSPRINTER_MODIFIED_FASTSIM
    ),
    "FASTSIM, Coulomb μ = 0.33": lambda x, v: modified_fastsim_coa(
        x, v, *contact, EUROSPRINTER_COULOMB
    ),
    "Polach 2005, dry": lambda x, v: polach_coa(x, v, load, stiffness, POLACH_DRY),
}
for label, law in published.items():
    rmse = np.sqrt(np.mean((law(xi, w) - coa) ** 2))
    print(f"RMSE of {label}: {rmse:.4f}")

# %%
# The fitted curve's 95 % band
# ----------------------------
# From the fit's covariance by the delta method: narrow where the points are many, although the
# parameters one by one are poorly determined (their errors are strongly correlated).
s = np.linspace(1e-4, 0.25, 400)
theta = np.array(fit.parameters.as_tuple())


def curve(t):
    return polach_coa(s, 10.0 * s, load, stiffness, PolachParameters(*t))


jac = np.empty((s.size, theta.size))
for j in range(theta.size):
    h = 1e-6 * max(abs(theta[j]), 1e-3)
    up, dn = theta.copy(), theta.copy()
    up[j], dn[j] = theta[j] + h, theta[j] - h
    jac[:, j] = (curve(up) - curve(dn)) / (2 * h)
half = stats.t.ppf(0.975, fit.dof) * np.sqrt(np.einsum("ij,jk,ik->i", jac, fit.covariance, jac))

# %%
# The points, the fit and the published sets
# ------------------------------------------
# As CONTACT's two figures: up to 5 % and up to 25 % creepage. Below the first point (0.38 %)
# nothing holds the initial slope (k_A): the band opens there.
fitted = curve(theta)
fig, axes = plt.subplots(1, 2, figsize=(9, 4), sharey=True)
for ax, xmax in zip(axes, (5, 25), strict=True):
    ax.plot(xi * 100, coa, "*", ms=5, color="tab:cyan", label="Engel et al. 1998 (digitised)")
    ax.fill_between(s * 100, fitted - half, fitted + half, color="tab:blue", alpha=0.25, lw=0,
                    label="fit's 95 % band")  # fmt: skip
    ax.plot(s * 100, fitted, color="tab:blue", label=f"Polach fit (RMSE {fit.rmse:.3f})")
    for (label, law), style in zip(published.items(), ("-", "--", ":"), strict=True):
        ax.plot(s * 100, law(s, 10.0 * s), style, color="0.3", lw=1.2, label=label)
    ax.set(xlabel="longitudinal creepage ξ [%]", xlim=(0, xmax), ylim=(0, 0.5))
axes[0].set_ylabel("traction coefficient F_x/F_n [-]")
axes[1].legend(fontsize=7.5, loc="upper right")
fig.tight_layout()
