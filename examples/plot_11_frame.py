"""
The rig frame: static and modal FE
==================================

Does the frame's flexibility matter for the measurement? The bundled Pardubice frame (every
dimension a stated assumption, sections from a sourced HEB/IPE/RHS table) is analysed with
PyNiteFEA under the test load (20 kN normal, 2 kN traction): deflection, stresses at the strain
gauges, the first modes, and the stiffness and modal mass seen from the contact, which the twin
takes as one degree of freedom (``DriveConfig(frame="flexible")``).
"""

from rollerrig.frame import analyze_frame, contact_dof, default_frame
from rollerrig.report.frame import deformed_shape_figure, mode_shape_figure

frame = default_frame()
result = analyze_frame(frame, 20e3, 2e3, n_modes=4)
print("first frequencies [Hz]:", [round(float(f), 1) for f in result.frequencies])
dof = contact_dof(result)
print(
    f"longitudinal stiffness at the contact {dof.stiffness:.3g} N/m, "
    f"modal mass {dof.modal_mass:.0f} kg"
)

# %%
fig = deformed_shape_figure(result)

# %%
fig = mode_shape_figure(result, modes=2)
