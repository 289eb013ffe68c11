"""The rig's coupled twin with the dq V/f roller drive, at python level (scipy): :class:`DqTwin`.

The inverse-Γ machine (:mod:`rollerrig.drives.induction_dq`) fed by the open-loop V/f
controller (:mod:`rollerrig.drives.vf`), acting between the AM rotor (body 6) and stator
(body 7) of the rig's torsional chain, with the wheel-roller contact, the PMSM and the bearings
exactly as in the twin: the right-hand side calls :func:`rollerrig.rig.model.rig_rhs` with the
roller-drive torque slot set to the machine's air-gap torque (roller mode 1 with a lag, whose
state then *is* the torque; its own derivative is discarded). A model for studies, written so
that its parts port into the compiled twin.

State layout of :class:`DqTwin` (27): the twin's 20 states (``roller_drive_torque_state`` and
``speed_error_integral`` unused), then the machine's fluxes
(:data:`rollerrig.drives.induction_dq.STATE_NAMES`) and the controller's filters
(:data:`rollerrig.drives.vf.STATE_NAMES`). The frequency command is ω* = p v*(t)/r_r from the
twin's speed set point table (ramped beforehand, :func:`rollerrig.drives.vf.ramp_limited_command`).

Not integrated into the compiled twin: the fast backend's state layout
(:mod:`rollerrig.rig.model`) has no flux or controller states yet.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from rollerrig._validation import ParameterError, require_positive
from rollerrig.contact.creep import POLACH_PARAMETER_SETS
from rollerrig.drives import induction_dq as dq
from rollerrig.drives import vf
from rollerrig.rig import model as m
from rollerrig.rig.assemble import assemble, steady_free_rolling_state
from rollerrig.rig.dq_drive import (
    N_RIG,
    N_STATES,
    STATE_NAMES,
    X_CTRL,
    X_PSI,
    DqDrive,
    _drive_derivatives,
    _ramped_tables,
    default_dq_drive,
    drive_steady_state,
)
from rollerrig.rig.linear import CoupledMode, _operating_point_protocol, modes_of

__all__ = ["DqTwin"]


def _protocol(speed: float, load: float, friction: str, torque_time=None, torque=None):
    return _operating_point_protocol(
        speed,
        load,
        friction,
        torque_time,
        torque,
        name="dq-drive",
        description="steady free rolling / torque steps for the dq roller drive",
        source="rollerrig.rig.drive_dynamics",
    )


@dataclass
class DqTwin:
    """The rig's coupled twin with the dq V/f roller drive (python level).

    Build with :meth:`at` (an operating point or a torque protocol).

    Attributes
    ----------
    rig : RigParameters
        The rig.
    drive : DqDrive
        The roller drive.
    wheel : str
        Wheel drive, ``"pmsm"`` or ``"ideal_torque"``.
    params : ndarray
        The twin's parameter vector (roller slot carries the machine torque).
    tables : ndarray
        Input tables (speed set point ramped).
    speed, normal_load : float
        Operating point [m/s], [N].
    friction : str
        Polach set.
    """

    rig: object
    drive: DqDrive
    wheel: str
    params: np.ndarray = field(repr=False)
    tables: np.ndarray = field(repr=False)
    speed: float
    normal_load: float
    friction: str = "dry"
    _buf: np.ndarray = field(default=None, repr=False)

    @classmethod
    def at(
        cls,
        rig,
        speed: float,
        normal_load: float,
        drive: DqDrive | None = None,
        *,
        wheel: str = "pmsm",
        friction: str = "dry",
        torque_time: Sequence[float] | None = None,
        torque_request: Sequence[float] | None = None,
    ) -> DqTwin:
        """The coupled twin at a roller speed [m/s] and normal load [N].

        ``torque_time``/``torque_request`` give a wheel torque request [s], [N.m] (default
        none: free rolling). The friction set must be one of Polach's (``dry``, ``wet``).
        """
        v = require_positive("speed", speed, "m/s", single=True)
        load = require_positive("normal_load", normal_load, "N", single=True)
        if friction not in POLACH_PARAMETER_SETS:
            raise ParameterError(
                f"friction must be one of {sorted(POLACH_PARAMETER_SETS)}, got {friction!r}"
            )
        drive = drive or default_dq_drive(rig)
        drives = m.DriveConfig(wheel=wheel, roller="induction", roller_lag=1.0)
        inputs = assemble(rig, _protocol(v, load, friction, torque_time, torque_request), drives)
        p = inputs.segments[0].params.copy()
        p[m.P_RIPPLE_AMP] = 0.0
        p[m.P_ROLLER_MODE] = m.ROLLER_MODES["induction"]
        p[m.P_LAG_TAU] = 1.0  # the roller torque slot is a state: the machine's torque
        rr = p[m.P_RR]
        rate_v = drive.control.ramp_rate * 2.0 * np.pi * rr / drive.machine.pole_pairs
        tables = _ramped_tables(inputs.tables, rate_v)
        return cls(rig, drive, wheel, p, tables, v, load, friction, np.zeros(N_RIG))

    # --- right-hand side ---------------------------------------------------------------------
    def rhs(self, t: float, x: np.ndarray) -> np.ndarray:
        """dx/dt of the coupled model (27 states, :data:`STATE_NAMES`)."""
        p = self.params
        pm = self.drive.machine.as_array()
        pc = self.drive.control.as_array()
        psi, ctrl = x[X_PSI : X_PSI + 4], x[X_CTRL : X_CTRL + 3]
        xr = np.array(x[:N_RIG], dtype=float)
        xr[m.X_T_ROLLER] = dq.im_torque_kernel(psi[0], psi[1], psi[2], psi[3], pm[2], pm[4])
        dx = np.empty(N_STATES)
        dxr = self._buf if self._buf is not None else np.zeros(N_RIG)
        m.rig_rhs(t, xr, p, self.tables, dxr)
        dx[:N_RIG] = dxr
        dx[m.X_T_ROLLER] = 0.0
        dx[m.X_INT_SPEED] = 0.0
        v_set = m._interp(t, self.tables, m.TAB_SPEED_T, m.TAB_SPEED)
        omega_cmd = pm[4] * v_set / p[m.P_RR]
        rotor_speed = x[m.X_OMEGA + 5] - x[m.X_OMEGA + 6]
        d_psi, d_ctrl, _, _ = _drive_derivatives(
            self.drive, psi, ctrl, omega_cmd, rotor_speed, pm, pc
        )
        dx[X_PSI : X_PSI + 4] = d_psi
        dx[X_CTRL : X_CTRL + 3] = d_ctrl
        return dx

    def torques(self, x: np.ndarray, t: float = 0.0) -> dict[str, float]:
        """Roller-drive air-gap torque, T56 and the contact force at a state (SI)."""
        pm = self.drive.machine.as_array()
        xr = np.array(x[:N_RIG], dtype=float)
        psi = x[X_PSI : X_PSI + 4]
        xr[m.X_T_ROLLER] = dq.im_torque_kernel(psi[0], psi[1], psi[2], psi[3], pm[2], pm[4])
        terms = m.rig_terms(t, xr, self.params, self.tables)
        names = m.TERM_NAMES
        return {
            "roller_drive_torque": float(xr[m.X_T_ROLLER]),
            "t56": float(terms[names.index("t56")]),
            "contact_force": float(terms[names.index("contact_force")]),
        }

    # --- steady state -------------------------------------------------------------------------
    def steady_free_rolling(self) -> np.ndarray:
        """Steady free rolling with the dq drive: the state (27) the tests start from.

        The chain's state comes from :func:`rollerrig.rig.assemble.steady_free_rolling_state`
        with the roller held at the dq drive's steady speed (an ideal speed source there); the
        drive's speed is where it delivers the bearing losses
        (:func:`~rollerrig.rig.dq_drive.drive_steady_state`).
        """
        p_ideal = self.params.copy()
        p_ideal[m.P_ROLLER_MODE] = m.ROLLER_MODES["ideal_speed"]
        tables = self.tables.copy()
        rr = self.params[m.P_RR]
        omega_cmd = self.drive.electrical_omega_command(self.speed, rr)
        roller_speed = self.speed / rr
        x_rig = None
        for _ in range(3):  # the losses depend on the speed only through tanh(ω/ω_reg)
            tables[m.TAB_SPEED] = roller_speed * rr
            x_rig = steady_free_rolling_state(p_ideal, tables, friction_condition=self.friction)
            needed = float(x_rig[m.X_T_ROLLER])
            op = drive_steady_state(self.drive, omega_cmd, torque=needed)
            roller_speed = op.rotor_speed
        x = np.zeros(N_STATES)
        x[:N_RIG] = x_rig
        x[m.X_T_ROLLER] = 0.0
        x[X_PSI : X_PSI + 7] = op.state
        return x

    def active_states(self, x: np.ndarray | None = None) -> np.ndarray:
        """Indices of the states that move (unused twin and controller states dropped).

        With a state ``x`` (linearisation), the current filter is dropped when only the current
        limit uses it and the limit is inactive there: it then feeds nothing (a decoupled real
        pole −α_i).
        """
        control = self.drive.control
        drop = {m.X_T_ROLLER, m.X_INT_SPEED}
        if self.params[m.P_WHEEL_MODE] == 0.0:
            drop |= {m.X_ID, m.X_IQ, m.X_INT_D, m.X_INT_Q}
        used = set(control.active_states)
        if x is not None and not (control.ir_resistance > 0.0 or control.slip_gain > 0.0):
            i_f = np.hypot(x[X_CTRL], x[X_CTRL + 1])
            if not i_f > control.current_limit:
                used -= set(vf.STATE_NAMES[:2])
        drop |= {X_CTRL + k for k, n in enumerate(vf.STATE_NAMES) if n not in used}
        return np.array([k for k in range(N_STATES) if k not in drop])

    def linearise(self, x0: np.ndarray | None = None, step: float = 1e-7):
        """Jacobian A = ∂f/∂x on the active states at steady free rolling (central differences,
        ``h_k = step · max(|x0_k|, 1)``, as :func:`rollerrig.rig.linear.linearise_rhs`).

        Returns
        -------
        jacobian : ndarray
        names : tuple of str
        x0 : ndarray
        """
        x0 = self.steady_free_rolling() if x0 is None else np.asarray(x0, dtype=float)
        active = self.active_states(x0)
        jac = np.empty((active.size, active.size))
        for col, k in enumerate(active):
            h = step * max(abs(x0[k]), 1.0)
            xp, xm = x0.copy(), x0.copy()
            xp[k] += h
            xm[k] -= h
            jac[:, col] = (self.rhs(0.0, xp)[active] - self.rhs(0.0, xm)[active]) / (2.0 * h)
        return jac, tuple(STATE_NAMES[k] for k in active), x0

    def modes(self, damping_threshold: float = 0.3) -> tuple[CoupledMode, ...]:
        """Modes at steady free rolling (:func:`rollerrig.rig.linear.modes_of`)."""
        jac, names, _ = self.linearise()
        return modes_of(jac, names, self.rig, damping_threshold)

    def simulate(
        self,
        t_end: float,
        x0: np.ndarray | None = None,
        t_eval: np.ndarray | None = None,
        rtol: float = 1e-6,
        atol: float = 1e-8,
    ):
        """Integrate the coupled model (scipy Radau, finite-difference Jacobian on the active
        states); returns the ``solve_ivp`` solution (inactive states held)."""
        x0 = self.steady_free_rolling() if x0 is None else np.asarray(x0, dtype=float)
        active = self.active_states()
        full = x0.copy()

        def f(t, z):
            full[active] = z
            return self.rhs(t, full)[active]

        sol = solve_ivp(
            f, (0.0, float(t_end)), x0[active], method="Radau", t_eval=t_eval, rtol=rtol, atol=atol
        )
        if not sol.success:
            raise ParameterError(f"the coupled simulation failed: {sol.message}")
        y = np.repeat(x0[:, None], sol.t.size, axis=1)
        y[active] = sol.y
        sol.y_full = y
        return sol
