"""The rig's coupled model with the dq induction machine under open-loop V/f as roller drive.

A second compiled model beside :mod:`rollerrig.rig.model` (roller drive ``"induction_dq"``), so
that the default twin keeps its 22 states: the state here is the rig's 22
(:data:`rollerrig.rig.model.STATE_NAMES`; ``roller_drive_torque_state`` and
``speed_error_integral`` unused, held at 0), then the machine's four flux linkages
(:data:`rollerrig.drives.induction_dq.STATE_NAMES`, in the controller frame rotating at ω_s)
and the V/f controller's three filter states (:data:`rollerrig.drives.vf.STATE_NAMES`).

The right-hand side wraps :func:`rollerrig.rig.model.rig_rhs` exactly as
:meth:`rollerrig.rig.dq_twin.DqTwin.rhs` does: the roller-drive torque slot
(``X_T_ROLLER``, read as a lagged torque state in roller mode 4) is set to the machine's air-gap
torque, and the machine and controller (:func:`rollerrig.drives.vf.vf_control_kernel`,
:func:`rollerrig.drives.induction_dq.im_flux_derivatives_kernel`) are driven by the frequency
command ω* = p v*(t)/r_r from the speed set-point table (ramped beforehand by the drive's ramp
rate, :func:`rollerrig.drives.vf.ramp_limited_command`) and the rotor speed ω6 − ω7.

Parameter vector: the rig's :data:`rollerrig.rig.model.N_PARAMS`, then the machine's five
(:meth:`rollerrig.drives.induction_dq.InverseGammaMachine.as_array`: R_s, R_R, L_σ, L_M, p) and
the controller's thirteen (:meth:`rollerrig.drives.vf.VfControl.as_array`).
"""

from __future__ import annotations

import numpy as np

from rollerrig.drives import induction_dq as _dq
from rollerrig.drives import vf as _vf
from rollerrig.drives.induction_dq import im_flux_derivatives_kernel, im_torque_kernel
from rollerrig.drives.vf import vf_control_kernel
from rollerrig.rig import model as m
from rollerrig.rig.model import _interp, rig_rhs

__all__ = [
    "N_DQ_PARAMS",
    "N_DQ_STATES",
    "P_MACHINE",
    "P_VF",
    "STATE_NAMES",
    "X_CTRL",
    "X_PSI",
    "air_gap_torque",
    "rig_dq_rhs",
]

N_RIG = m.N_STATES
X_PSI = N_RIG  # ψ_s d, q, ψ_R d, q [Wb] at 22..25
X_CTRL = N_RIG + 4  # filtered current d, q [A], filtered slip [rad/s] at 26..28
N_DQ_STATES = N_RIG + 7
STATE_NAMES = (*m.STATE_NAMES, *_dq.STATE_NAMES, *_vf.STATE_NAMES)

P_MACHINE = m.N_PARAMS  # R_s, R_R [ohm], L_σ, L_M [H], p [-]
P_VF = P_MACHINE + 5  # the 13 settings of VfControl.as_array()
N_DQ_PARAMS = P_VF + 13

ROLLER_MODE_DQ = 4.0
"""``P_ROLLER_MODE`` of this model: the roller-drive torque slot is an external state (the
rig's ``rig_terms`` reads it as a lagged torque, with ``P_LAG_TAU`` = 1)."""


def air_gap_torque(x, p):
    """The machine's air-gap torque [N.m] at the state ``x`` (motoring positive)."""
    return im_torque_kernel(
        x[X_PSI], x[X_PSI + 1], x[X_PSI + 2], x[X_PSI + 3], p[P_MACHINE + 2], p[P_MACHINE + 4]
    )


def rig_dq_rhs(t, x, p, tables, dx):
    """Right-hand side of the rig with the dq V/f roller drive, written into ``dx`` in place.

    Parameters
    ----------
    t : float
        Time [s].
    x : ndarray, shape (N_DQ_STATES,)
        State (:data:`STATE_NAMES`).
    p : ndarray, shape (N_DQ_PARAMS,)
        The rig's parameters, then the machine's and the controller's.
    tables : ndarray, shape (6, n)
        Piecewise-linear inputs (speed set point ramped by the drive).
    dx : ndarray, shape (N_DQ_STATES,)
        Output: time derivative of the state.
    """
    psi_s_d = x[X_PSI]
    psi_s_q = x[X_PSI + 1]
    psi_r_d = x[X_PSI + 2]
    psi_r_q = x[X_PSI + 3]
    l_sigma = p[P_MACHINE + 2]
    pole_pairs = p[P_MACHINE + 4]
    xr = x[:N_RIG].copy()
    xr[m.X_T_ROLLER] = im_torque_kernel(psi_s_d, psi_s_q, psi_r_d, psi_r_q, l_sigma, pole_pairs)
    rig_rhs(t, xr, p, tables, dx[:N_RIG])
    dx[m.X_T_ROLLER] = 0.0
    dx[m.X_INT_SPEED] = 0.0

    v_set = _interp(t, tables, m.TAB_SPEED_T, m.TAB_SPEED)
    omega_cmd = pole_pairs * v_set / p[m.P_RR]
    rotor_speed = x[m.X_OMEGA + 5] - x[m.X_OMEGA + 6]
    i_s_d = (psi_s_d - psi_r_d) / l_sigma
    i_s_q = (psi_s_q - psi_r_q) / l_sigma
    u_d, u_q, omega_s, d_if_d, d_if_q, d_slip = vf_control_kernel(
        omega_cmd,
        i_s_d,
        i_s_q,
        x[X_CTRL],
        x[X_CTRL + 1],
        x[X_CTRL + 2],
        p[P_VF],
        p[P_VF + 1],
        p[P_VF + 2],
        p[P_VF + 3],
        p[P_VF + 4],
        p[P_VF + 5],
        p[P_VF + 6],
        p[P_VF + 7],
        p[P_VF + 8],
        p[P_VF + 9],
        p[P_VF + 10],
        p[P_VF + 11],
        p[P_VF + 12],
    )
    d0, d1, d2, d3 = im_flux_derivatives_kernel(
        psi_s_d,
        psi_s_q,
        psi_r_d,
        psi_r_q,
        u_d,
        u_q,
        omega_s,
        pole_pairs * rotor_speed,
        p[P_MACHINE],
        p[P_MACHINE + 1],
        l_sigma,
        p[P_MACHINE + 3],
    )
    dx[X_PSI] = d0
    dx[X_PSI + 1] = d1
    dx[X_PSI + 2] = d2
    dx[X_PSI + 3] = d3
    dx[X_CTRL] = d_if_d
    dx[X_CTRL + 1] = d_if_q
    dx[X_CTRL + 2] = d_slip


def rig_dq_params(rig_params: np.ndarray, machine, control) -> np.ndarray:
    """The parameter vector of this model: the rig's (roller mode 4, unit lag slot), the
    machine's and the controller's."""
    p = np.empty(N_DQ_PARAMS)
    p[:P_MACHINE] = rig_params[:P_MACHINE]
    p[m.P_ROLLER_MODE] = ROLLER_MODE_DQ
    p[m.P_LAG_TAU] = 1.0  # the roller torque slot is a state: the machine's torque
    p[P_MACHINE:P_VF] = machine.as_array()
    p[P_VF:] = control.as_array()
    return p
