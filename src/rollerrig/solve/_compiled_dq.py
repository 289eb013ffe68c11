"""numba-compiled rig model with the dq V/f roller drive (:mod:`rollerrig.rig.model_dq`).

Imported only when the roller drive ``"induction_dq"`` is used, so that the default twin
neither binds nor compiles it. :data:`RIG_DQ` is ROS34PW2 bound to :func:`rig_dq_rhs`, cached
on disk like :data:`rollerrig.solve._compiled.RIG`.
"""

from __future__ import annotations

from numba.extending import register_jitable

from rollerrig.drives import induction_dq as _dq
from rollerrig.drives import vf as _vf
from rollerrig.rig import model_dq as _model_dq
from rollerrig.solve import _cache, ros34pw
from rollerrig.solve import _compiled as _rig  # registers the rig's kernels

_KERNELS = (
    _dq.im_torque_kernel,
    _dq.im_flux_derivatives_kernel,
    _vf.vf_voltage_kernel,
    _vf.vf_control_kernel,
    _rig._model.rig_rhs,
    _model_dq.air_gap_torque,
)
for _fn in _KERNELS:
    register_jitable(_fn)

rig_dq_rhs = _cache.njit(_model_dq.rig_dq_rhs, error_model="numpy")  # as _compiled.rig_rhs
"""Compiled :func:`rollerrig.rig.model_dq.rig_dq_rhs`."""

rig_terms_series = _rig.rig_terms_series

RIG_DQ = ros34pw.bind(rig_dq_rhs, name="rig_dq")
"""ROS34PW2 bound to :data:`rig_dq_rhs` (:class:`~rollerrig.solve._wdriver.Driver`), cached."""
