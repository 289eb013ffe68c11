"""The first-order lag the dq V/f drive amounts to in the rig: :func:`fit_lag_in_rig`.

The twin's Thevenin drive with a response lag τ (:class:`rollerrig.rig.model.DriveConfig`
``roller_lag``) fitted to the response of the coupled twin with the dq drive
(:class:`rollerrig.rig.dq_twin.DqTwin`) to a wheel-torque step, to compare with Kayaalp's
c_lp = 2.75; the lag of the machine alone at a held speed is
:func:`rollerrig.rig.dq_drive.fit_lag_at_held_speed`.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

from rollerrig.drives.induction import clp_from_lag_time_constant
from rollerrig.rig import model as m
from rollerrig.rig.assemble import assemble
from rollerrig.rig.dq_drive import DqDrive, LagFit, default_dq_drive
from rollerrig.rig.dq_twin import DqTwin, _protocol

__all__ = ["fit_lag_in_rig"]


def fit_lag_in_rig(
    rig,
    speed: float,
    normal_load: float,
    torque_step: float = 300.0,
    drive: DqDrive | None = None,
    *,
    t_step: float = 0.2,
    rise: float = 0.02,
    duration: float = 2.5,
    friction: str = "dry",
    bounds: tuple[float, float] = (1e-3, 1.0),
    signal: str = "roller_drive_torque",
) -> LagFit:
    """Fit the twin's Thevenin + lag drive to the dq drive's response to a wheel-torque step.

    Both twins (ideal-torque wheel drive, as Kayaalp 4.5.1.8 did) start from steady free rolling
    at ``speed`` [m/s] and ``normal_load`` [N]; the wheel torque request rises by
    ``torque_step`` [N.m] in ``rise`` [s] at ``t_step`` [s]. τ of the Thevenin drive
    (:data:`rollerrig.rig.model.DriveConfig` ``roller_lag``) minimises the RMS difference of
    ``signal`` (``"roller_drive_torque"`` or ``"t56"``) over the run.
    """
    drive = drive or default_dq_drive(rig)
    tt = [0.0, t_step, t_step + rise, duration]
    tq = [0.0, 0.0, torque_step, torque_step]
    t = np.linspace(0.0, duration, int(duration * 400) + 1)
    twin = DqTwin.at(
        rig,
        speed,
        normal_load,
        drive,
        wheel="ideal_torque",
        friction=friction,
        torque_time=tt,
        torque_request=tq,
    )
    sol = twin.simulate(duration, t_eval=t)
    dq_sig = np.array([twin.torques(sol.y_full[:, k], tk)[signal] for k, tk in enumerate(t)])

    proto = _protocol(speed, normal_load, friction, tt, tq)

    def lag_response(tau):
        drives = m.DriveConfig(wheel="ideal_torque", roller="induction", roller_lag=tau)
        inputs = assemble(rig, proto, drives)
        p = inputs.segments[0].params.copy()
        p[m.P_RIPPLE_AMP] = 0.0
        buf = np.zeros(m.N_STATES)
        keep = np.array(
            [
                k
                for k in range(m.N_STATES)
                if k not in (m.X_ID, m.X_IQ, m.X_INT_D, m.X_INT_Q, m.X_INT_SPEED)
            ]
        )
        full = inputs.initial_state.copy()

        def f(tk, z):
            full[keep] = z
            m.rig_rhs(tk, full, p, inputs.tables, buf)
            return buf[keep].copy()

        # max_step: without it scipy's Radau can stall in Newton failures after a long step
        # (4177 Jacobians, 28 s at τ = 0.04 s with R_s = 0.085 ohm); with it 0.5 s at every τ
        s = solve_ivp(
            f,
            (0.0, duration),
            full[keep],
            method="Radau",
            t_eval=t,
            rtol=1e-6,
            atol=1e-8,
            max_step=0.02,
        )
        y = np.repeat(inputs.initial_state[:, None], t.size, axis=1)
        y[keep] = s.y
        idx = m.TERM_NAMES.index(
            "roller_drive_torque" if signal == "roller_drive_torque" else "t56"
        )
        return np.array([m.rig_terms(tk, y[:, k], p, inputs.tables)[idx] for k, tk in enumerate(t)])

    responses: dict[float, np.ndarray] = {}  # the optimum's response is one of those tried

    def cost(log_tau):
        responses[log_tau] = lag_response(np.exp(log_tau))
        return float(np.sqrt(np.mean((responses[log_tau] - dq_sig) ** 2)))

    best = minimize_scalar(
        cost,
        bounds=(np.log(bounds[0]), np.log(bounds[1])),
        method="bounded",
        options={"xatol": 1e-3},
    )
    tau = float(np.exp(best.x))
    return LagFit(
        time_constant=tau,
        clp=float(clp_from_lag_time_constant(tau)),
        rms_error=float(best.fun),
        peak_response=float(np.max(np.abs(dq_sig - dq_sig[0]))),
        t=t,
        dq_torque=dq_sig,
        lag_torque=responses[best.x] if best.x in responses else lag_response(tau),
    )
