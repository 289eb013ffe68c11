"""numba-compiled versions of the rig model, built from the very same Python source.

The physics kernels are plain functions (they run on numpy for the baseline and the tests);
``register_jitable`` lets numba compile them wherever compiled code calls them, so no kernel
exists twice. :data:`RIG` is ROS34PW2 bound to the compiled model (:func:`rig_rhs`), the driver
of the fast backend. Everything here is cached on disk (:mod:`rollerrig.solve._cache`): a process
loads the machine code instead of compiling it, unless the package's compiled sources changed.
Importing this module costs nothing until a compiled function is first called.
"""

from __future__ import annotations

import types

from numba.extending import register_jitable

from rollerrig.contact import creep as _creep
from rollerrig.contact import kinematics as _kinematics
from rollerrig.drives import induction as _induction
from rollerrig.drives import pmsm as _pmsm
from rollerrig.drives import servo as _servo
from rollerrig.rig import model as _model
from rollerrig.solve import _cache, ros34pw

_KERNELS = (
    _creep._friction_kernel,
    _creep._adhesion_gradient_kernel,
    _creep._polach_force_kernel,
    _creep._polach_force_at_friction_kernel,
    _creep._polach_shape_derivatives,
    _creep._polach_shape_kernel,
    _kinematics._creep_kernel,
    _pmsm.pmsm_current_derivatives,
    _pmsm.pmsm_torque,
    _pmsm.pmsm_current_reference,
    _pmsm.pmsm_foc_voltages,
    _induction.induction_torque,
    _induction.vf_voltage,
    _induction.vf_supply_frequency,
    _induction.linear_induction_torque,
    _induction.lag_derivative,
    _servo.servo_speed_torque,
    _model._piece,
    _model._interp,
    _model._interp_slope,
    _model.segment_tables,
    _model.roller_setpoint_at,
    _model.lowest_speed_setpoint,
    _model.speed_setpoint_bounds,
    _model._bearing_torques,
    _model._creep_stiffness_at,
    _model._table_ratio,
    _model._law_ratio,
    _model._law_ratio_curvature,
    _model._gradient_scale,
    _model._force_and_slope,
    _model._arm_step_down,
    _model._contact_load_and_force,
    _model._open_loop_roller_torque,
    _model.rig_terms,
)
# Compiled without reference counting (_nrt=False): the kernels allocate nothing, and with it
# each call that passed the parameter array took and gave back a reference (atomic operations):
# a fifth to a quarter of the right-hand side's time (perf, 2026-11-30), the arm's Newton loop
# calling the creep law up to four times a call.
# rig_terms is inlined into rig_rhs by numba (its IR), not called: as a call it passed three
# arrays and returned its 23 terms through memory, 40 ns of the right-hand side's 224
# (2026-11-30; the default solve 21.1 -> 19.9 ms, for 2-3 s more CPU of a cold compile). The
# law's kernel with its several exits is left to LLVM: numba's inliner warns about such
# functions' variables, for no measurable gain.
_INLINED = (_model.rig_terms,)
for _fn in _KERNELS:
    register_jitable(_nrt=False, inline="always" if _fn in _INLINED else "never")(_fn)
# The output series calls rig_terms out of line, through a copy of it: inlined there too, its
# body compiled a third time on a cold start (3.9 s against 0.9, numba's compile events).
_rig_terms_call = register_jitable(_nrt=False)(
    types.FunctionType(_model.rig_terms.__code__, vars(_model), "rig_terms")
)

# numpy's error model: a division by zero gives inf or NaN (which the drivers report as a
# non-finite state) instead of a zero check before every division, which cost 22-37 % of the
# right-hand side (issue 20). No division of the model divides by zero on a valid rig.
rig_rhs = _cache.njit(_model.rig_rhs, error_model="numpy", _nrt=False)
"""Compiled :func:`rollerrig.rig.model.rig_rhs`."""


@_cache.njit(error_model="numpy")  # as rig_rhs, whose compiled kernels it then shares
def rig_terms_series(t, x, p, tables, out):
    """Evaluate :func:`rollerrig.rig.model.rig_terms` at every sample: ``out[k, :]`` for
    ``t[k]``, ``x[k, :]``.

    The kernel registered above, as :func:`rig_rhs` calls it: a dispatcher of its own would
    compile the same code a second time on a first run (2-2.7 s, numba's compile events).
    """
    for k in range(t.shape[0]):
        terms = _rig_terms_call(t[k], x[k], p, tables)
        for j in range(len(terms)):
            out[k, j] = terms[j]


@_cache.njit(error_model="numpy")
def rig_rates_series(t, x, p, tables, out):
    """Evaluate :func:`rig_rhs` at every sample: ``out[k, :] = f(t[k], x[k, :])``.

    The accelerations of the truth channels come from here, the equations of motion at the
    output instants, not from differences of interpolated speeds (issue 20, point 4).
    """
    for k in range(t.shape[0]):
        rig_rhs(t[k], x[k], p, tables, out[k])


RIG = ros34pw.bind(rig_rhs, name="rig")
"""ROS34PW2 bound to :data:`rig_rhs` (:class:`~rollerrig.solve._wdriver.Driver`), cached."""
