"""The coupled model of the roller rig: 7-inertia torsional chain, wheel-roller contact, drives.

Bodies (Kayaalp Fig. 32, eqs. 4.1-4.14, re-derived with one sign convention, see
CONTRIBUTING.md): 1 PMSM stator, 2 PMSM rotor, 3 wheel disc, 4 wheel tyre, 5 roller, 6 AM rotor,
7 AM stator; ground is body 0. With T_ij = k_ij(θ_i − θ_j) + b_ij(ω_i − ω_j):

    J1 α1 = T01 − T_p                 (PMSM stator: mount reaction, air-gap reaction)
    J2 α2 = T_p − T23                 (PMSM rotor)
    J3 α3 = T23 − T34 − R03           (wheel disc, bearing loss)
    J4 α4 = T34 − F_x r_w             (wheel tyre, contact)
    J5 α5 = F_x r_r − T56 − R05       (roller, contact, bearing loss)
    J6 α6 = T56 + T_a                 (AM rotor; T_a < 0 when the AM brakes)
    J7 α7 = −T_a − T70                (AM stator)
    m_f ẍ_f = F_x − k_f x_f − c_f ẋ_f  (frame at the contact; with DriveConfig(frame="flexible"))

Corrections to the seed: eq. 4.7 divides by J6 where J7 belongs; the text swaps T12/T67 (T_p is
the PMSM air-gap torque between bodies 1-2, T_a the AM's between 6-7); R03 and R05 (eqs.
4.13-4.14) are forces and are multiplied here by a bearing radius; bearing friction is smoothed
with tanh(ω/ω_reg) so that standstill is finite.

The torque sensor sits on the roller shaft and measures T56; the rig reports
CoA_measured = T56 / (r_r S) with S the air spring's force, while the contact carries
N = S + W_d + σ (h/l) F_x (the swinging arm) and the true contact force satisfies
F_x r_r = T56 + J5 α5 + R05.

Everything in this module that the solvers call (:func:`rig_terms`, :func:`rig_rhs`) is written
with plain arithmetic and numpy ufuncs on scalars, so the very same source runs as a Python
function (the baseline) and compiles under numba (the fast backend). Both are pure functions
of their arguments for parameters as assembled; a solver's private copy with ``P_ARM_START``
set carries the arm loop's root from call to call in that slot (a first guess: the result is
the same to round-off) and the creep stiffness of the last load in ``P_MEMO_LOAD`` and
``P_MEMO_STIFFNESS`` (the same value), and flags in ``P_VOLTAGE_LIMITED`` where the PMSM's
controller met its voltage limit (which a sweep's solver reads: the slot ``P_ARM_START``
marks a solver's copy for both).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from rollerrig.contact.creep import friction_kernel as _friction_kernel
from rollerrig.contact.creep import polach_shape_derivatives as _polach_shape_derivatives
from rollerrig.contact.kinematics import creep_kernel as _creep_kernel
from rollerrig.drives.induction import (
    induction_torque,
    lag_derivative,
    linear_induction_torque,
    vf_supply_frequency,
    vf_voltage,
)
from rollerrig.drives.pmsm import (
    pmsm_current_derivatives,
    pmsm_current_reference,
    pmsm_foc_voltages,
    pmsm_torque,
)
from rollerrig.drives.servo import servo_speed_torque

__all__ = [
    "N_PARAMS",
    "N_STATES",
    "STATE_NAMES",
    "TERM_NAMES",
    "DriveConfig",
    "rig_rhs",
    "rig_terms",
]

# ---------------------------------------------------------------------------------------------
# State layout
# ---------------------------------------------------------------------------------------------
X_THETA = 0  # θ1..θ7 [rad] at 0..6
X_OMEGA = 7  # ω1..ω7 [rad/s] at 7..13
X_ID, X_IQ, X_INT_D, X_INT_Q = 14, 15, 16, 17  # PMSM currents [A], PI integrals [A.s]
X_T_ROLLER = 18  # lagged roller-drive air-gap torque [N.m]
X_INT_SPEED = 19  # servo speed-error integral [rad]
X_FRAME_X, X_FRAME_V = 20, 21  # frame displacement at the contact [m], its velocity [m/s]
N_STATES = 22

STATE_NAMES = (
    *(f"theta{i}" for i in range(1, 8)),
    *(f"omega{i}" for i in range(1, 8)),
    "i_d",
    "i_q",
    "integral_d",
    "integral_q",
    "roller_drive_torque_state",
    "speed_error_integral",
    "frame_displacement",
    "frame_velocity",
)

# ---------------------------------------------------------------------------------------------
# Parameter vector layout (flat float64, so that numba sees one array)
# ---------------------------------------------------------------------------------------------
P_J = 0  # J1..J7 at 0..6 [kg.m^2]
P_K01, P_K23, P_K34, P_K56, P_K70 = 7, 8, 9, 10, 11  # [N.m/rad]
P_B01, P_B23, P_B34, P_B56, P_B70 = 12, 13, 14, 15, 16  # [N.m.s/rad]
P_RW, P_RR = 17, 18  # rolling radii [m]
P_CREEP_STIFF_REF, P_LOAD_REF = 19, 20  # G a b C11 at the reference load [N], that load [N]
P_MU0, P_A, P_B, P_KA, P_KS = 21, 22, 23, 24, 25  # Polach parameters of the current segment
P_VREG = 26  # creep regularisation speed [m/s]
P_BEAR_W, P_BEAR_R = 27, 28  # f_g × bearing radius, wheel and roller [m]
P_W_ROLLER = 29  # roller subsystem weight W_r [N]
P_OMEGA_REG = 30  # bearing-friction regularisation speed [rad/s]
P_WHEEL_MODE = 31  # 0 ideal torque source, 1 PMSM with FOC
P_PP, P_RS, P_LD, P_LQ, P_FLUX = 32, 33, 34, 35, 36
P_KP, P_KI, P_VMAX, P_IMAX = 37, 38, 39, 40
P_RIPPLE_AMP, P_RIPPLE_FREQ = 41, 42  # optional inverter torque ripple [N.m], [Hz]
P_ROLLER_MODE = 43  # 0 ideal speed, 1 AM Thevenin V/f, 2 AM linear, 3 servo, 4 AM dq (model_dq)
P_AM_PP, P_AM_V, P_AM_RTH, P_AM_XTH, P_AM_R2, P_AM_X2, P_AM_FRATED = 44, 45, 46, 47, 48, 49, 50
P_AM_SLOPE = 51  # linear torque-slip slope [N.m.s/rad]
P_LAG_TAU = 52  # roller-drive response lag τ [s]; 0 means none
P_SERVO_KP, P_SERVO_KI, P_SERVO_TLIM = 53, 54, 55
P_FRAME_MODE = 56  # 0 rigid frame, 1 one longitudinal degree of freedom at the contact
P_FRAME_K, P_FRAME_M, P_FRAME_C = 57, 58, 59  # [N/m], [kg], [N.s/m]
P_ARM_RATIO, P_ARM_WEIGHT = 60, 61  # swinging arm: σ h/l [-], dead weight W_d [N]
P_LAW = 62  # creep law (LAW_CODES): 0 Polach's closed form, else the table below
P_K0, P_ALPHA_INF, P_BETA = 63, 64, 65  # modified FASTSIM's slope reduction (1, 1, 0: none)
P_TAB_STEP, P_TAB_INV = 66, 67  # node spacing h of the creep table in ε = G a b C11 ξ/(μN), 1/h
N_TAB = 513  # nodes of the creep table (rollerrig.contact.table.TABLE_NODES)
P_TAB_F = 68  # F/(μN) at the nodes [-], N_TAB values
P_TAB_DF = P_TAB_F + N_TAB  # d(F/(μN))/dε at the nodes [-], N_TAB values
# The arm's load loop's first iterate w [-] (_contact_load_and_force). 0, as assembled: it
# starts from w = 1 (N = B) and the parameters are read only. A solver sets it to 1 in its own
# copy of the parameters: the loop then starts from the root of the call before (the next
# stage of a step is a small move) and leaves its root here, which took the arm's loop from
# 2.1 to 1.3 law evaluations a call and the default solve from 20.2 to 17.6 ms (2026-11-30).
P_ARM_START = P_TAB_DF + N_TAB
# With P_ARM_START positive, the last load B [N] whose creep stiffness was computed and that
# stiffness [N]: constant through a hold, and its cube root had been 8 % of a solve's samples.
P_MEMO_LOAD, P_MEMO_STIFFNESS = P_ARM_START + 1, P_ARM_START + 2
# With P_ARM_START positive, set to 1 where the PMSM's controller met its voltage limit: its
# current loops are then not the linear loops a sweep's ETDRK4 takes exactly
# (rollerrig.solve.fast.CURRENT_BLOCKS), and the solver integrates that segment otherwise.
P_VOLTAGE_LIMITED = P_MEMO_STIFFNESS + 1
N_PARAMS = P_VOLTAGE_LIMITED + 1


def start_solver_copy(params):
    """Turn parameter vectors (``params[..., :N_PARAMS]``, a solver's own copy) into a solver's:
    the arm's loop starts from w = 1 and carries its root, no load's creep stiffness kept yet.
    Written in place; a segment handed from one solver to another starts afresh with it."""
    params[..., P_ARM_START] = 1.0
    params[..., P_MEMO_LOAD] = np.nan
    params[..., P_VOLTAGE_LIMITED] = 0.0


WHEEL_MODES = {"ideal_torque": 0.0, "pmsm": 1.0}
ROLLER_MODES = {
    "ideal_speed": 0.0,
    "induction": 1.0,
    "induction_linear": 2.0,
    "servo": 3.0,
    "induction_dq": 4.0,
}
FRAME_MODES = {"rigid": 0.0, "flexible": 1.0}
LAW_CODES = {"polach": 0.0, "fastsim": 1.0, "modified-fastsim": 2.0, "fastrip": 3.0}
"""Creep laws of the twin (:data:`rollerrig.contact.CREEP_LAWS`) -> ``p[P_LAW]``."""

# Table rows (piecewise-linear inputs, padded by repeating the last breakpoint)
TAB_TORQUE_T, TAB_TORQUE, TAB_SPEED_T, TAB_SPEED, TAB_LOAD_T, TAB_LOAD = 0, 1, 2, 3, 4, 5
N_TABLE_ROWS = 6

TERM_NAMES = (
    "torque_request",
    "roller_speed_setpoint",
    "air_spring_force",
    "normal_load",
    "creep",
    "slip_velocity",
    "friction",
    "contact_force",
    "pmsm_torque",
    "roller_drive_torque",
    "roller_drive_torque_target",
    "t01",
    "t23",
    "t34",
    "t56",
    "t70",
    "bearing_torque_wheel",
    "bearing_torque_roller",
    "v_d",
    "v_q",
    "pmsm_integral_rate_d",
    "pmsm_integral_rate_q",
    "speed_integral_rate",
)


# Positions in the tuple of rig_terms of the terms rig_rhs uses (compile-time constants).
_T_FORCE = TERM_NAMES.index("contact_force")
_T_PMSM = TERM_NAMES.index("pmsm_torque")
_T_ROLLER = TERM_NAMES.index("roller_drive_torque")
_T_TARGET = TERM_NAMES.index("roller_drive_torque_target")
_T_01, _T_23, _T_34, _T_56, _T_70 = (
    TERM_NAMES.index(n) for n in ("t01", "t23", "t34", "t56", "t70")
)
_T_BEAR_W = TERM_NAMES.index("bearing_torque_wheel")
_T_BEAR_R = TERM_NAMES.index("bearing_torque_roller")
_T_VD, _T_VQ = TERM_NAMES.index("v_d"), TERM_NAMES.index("v_q")
_T_DINT_D = TERM_NAMES.index("pmsm_integral_rate_d")
_T_DINT_Q = TERM_NAMES.index("pmsm_integral_rate_q")
_T_DINT_SPEED = TERM_NAMES.index("speed_integral_rate")


@dataclass(frozen=True)
class DriveConfig:
    """Which drive models the simulation uses.

    Parameters
    ----------
    wheel : {"pmsm", "ideal_torque"}
        PMSM dq model with field-oriented PI current control and voltage limit, or an ideal
        torque source delivering the request exactly.
    roller : {"induction", "induction_linear", "ideal_speed", "servo", "induction_dq"}
        Induction motor under open-loop V/f (Thevenin circuit, Kayaalp eq. 4.28), its linear
        torque-slip fit (Kayaalp Fig. 45), an ideal speed source, a speed-controlled
        servo/PMSM roller drive (the seed's proposed fix), or the induction machine as a
        dynamic dq model (stator and rotor fluxes) under open-loop V/f control
        (:mod:`rollerrig.rig.model_dq`, a second compiled model with 29 states).
    roller_lag : float or None
        Roller-drive response lag τ [s]. ``None`` takes the rig's value (from c_lp, eq. 4.29);
        0 means no lag. Not used by ``"induction_dq"`` (its dynamics are the machine's).
    frame : {"rigid", "flexible"}
        The rig frame: rigid (the seed's model), or one longitudinal degree of freedom at the
        contact with the rig's ``[frame]`` stiffness, mass and damping (Kayaalp 4.3.1's
        hypothesis, :class:`rollerrig.rig.sections.FrameParameters`).
    law : {"polach", "fastsim", "modified-fastsim", "fastrip"}
        The creep law of the contact force (:data:`rollerrig.contact.CREEP_LAWS`): Polach's
        closed form (Kayaalp eq. 4.16), or a law of the FASTSIM family from its table in
        ε = G a b C11 ξ/(μN) (:mod:`rollerrig.contact.table`), with μ(w) of Polach's form.
        ``"modified-fastsim"`` takes k0, α_∞, β from a friction set that has them
        (:class:`rollerrig.contact.FastsimParameters`), else the Eurosprinter set's.
    """

    wheel: Literal["pmsm", "ideal_torque"] = "pmsm"
    roller: Literal["induction", "induction_linear", "ideal_speed", "servo", "induction_dq"] = (
        "induction"
    )
    roller_lag: float | None = None
    frame: Literal["rigid", "flexible"] = "rigid"
    law: Literal["polach", "fastsim", "modified-fastsim", "fastrip"] = "polach"

    def __post_init__(self) -> None:
        from rollerrig._validation import ParameterError, did_you_mean, require_nonnegative

        for what, value, known in (
            ("wheel drive", self.wheel, WHEEL_MODES),
            ("roller drive", self.roller, ROLLER_MODES),
            ("frame", self.frame, FRAME_MODES),
            ("creep law", self.law, LAW_CODES),
        ):
            # A name that is not text (a list, a number) is named as such: ``in`` on a dict
            # had raised a bare "unhashable type" TypeError for a list.
            if not isinstance(value, str) or value not in known:
                raise ParameterError(
                    f"{what} must be one of {list(known)}, got {value!r}"
                    + (did_you_mean(value, known) if isinstance(value, str) else "")
                )
        if self.roller_lag is not None:
            # True is not a lag of 1 s, nor "0.1" one of 0.1 s.
            if isinstance(self.roller_lag, bool | np.bool_ | str | bytes):
                raise ParameterError(
                    f"roller_lag must be a number [s] or None, got {self.roller_lag!r}"
                )
            lag = require_nonnegative("roller_lag", self.roller_lag, "s", single=True)
            object.__setattr__(self, "roller_lag", lag)


def _bearing_torques(load, omega_wheel, omega_roller, p):
    """Bearing friction torques of wheel and roller [N.m]: f_g·N·r_b, smoothed at standstill.

    Kayaalp eqs. 4.13-4.14 (forces R03 = N f_g, R05 = (W_r + N) f_g) times the bearing radius,
    with ``tanh(ω/ω_reg)`` in place of the sign.
    """
    bearing_w = p[P_BEAR_W] * load * np.tanh(omega_wheel / p[P_OMEGA_REG])
    bearing_r = p[P_BEAR_R] * (p[P_W_ROLLER] + load) * np.tanh(omega_roller / p[P_OMEGA_REG])
    return bearing_w, bearing_r


def _creep_stiffness_at(load, p):
    """Kalker's creep stiffness G a b C11 [N] at the normal load ``load`` [N].

    Hertz semi-axes scale with N^(1/3) at fixed a/b, so G a b C11 scales with N^(2/3) from its
    value at the reference load.
    """
    ratio = load / p[P_LOAD_REF]
    return p[P_CREEP_STIFF_REF] * np.cbrt(ratio * ratio)  # cbrt: a third of the cost of pow


_ARM_NEWTON_STEPS = 30
"""Most steps of the normal-load loop (:func:`_contact_load_and_force`); from its first
guess (N = S + W_d) Newton's method converges to round-off in 3-5 steps (|κ μ| <= 1), in up
to 12 (measured on 60 000 random cases to |κ μ| = 2.5) where the transfer nears self-locking
(κ μ F/(μN) near 1 and above: a very large load, a step that would cross w = 0 replaced by
:func:`_arm_step_down`; 20 000 random cases of the property test, vanishing loads included,
all within it); Halley's steps (Polach's law) take fewer."""


def _table_ratio(e, p):
    """F/(μN) [-] of the tabulated law at ε = ``e`` >= 0 and its derivative d(F/(μN))/dε [-].

    Cubic Hermite interpolation between the nodes ``p[P_TAB_F:]``, ``p[P_TAB_DF:]`` spaced
    ``p[P_TAB_STEP]`` (:mod:`rollerrig.contact.table`); saturated (constant) beyond the last.
    """
    h = p[P_TAB_STEP]
    u = e * p[P_TAB_INV]
    if u != u:  # NaN creep: let it show as NaN
        return u, u
    if u >= N_TAB - 1:
        return p[P_TAB_F + N_TAB - 1], 0.0
    i = int(u)
    t = u - i
    y0 = p[P_TAB_F + i]
    y1 = p[P_TAB_F + i + 1]
    s0 = p[P_TAB_DF + i] * h
    s1 = p[P_TAB_DF + i + 1] * h
    t2 = t * t
    t3 = t2 * t
    value = (2.0 * t3 - 3.0 * t2 + 1.0) * y0 + (t3 - 2.0 * t2 + t) * s0
    value = value + (3.0 * t2 - 2.0 * t3) * y1 + (t3 - t2) * s1
    slope = (
        6.0 * (t2 - t) * (y0 - y1) + (3.0 * t2 - 4.0 * t + 1.0) * s0 + (3.0 * t2 - 2.0 * t) * s1
    ) * p[P_TAB_INV]
    return value, slope


def _law_ratio(eps, p):
    """F_x/(μN) [-] of the creep law at the adhesion gradient ``eps`` [-], and its derivative
    d(F_x/(μN))/dε [-].

    Polach (``p[P_LAW]`` = 0): (2/π) h(ε) with ε = (π/4) C ξ/(μN)
    (:func:`rollerrig.contact.creep.polach_shape_kernel`, Kayaalp eq. 4.20). A tabulated law:
    sgn(ε) f(k(|ε|)|ε|) with ε = C ξ/(μN), where k is the modified FASTSIM's slope reduction
    k0 (α_∞ + (1 − α_∞)/(1 + β ε_s)), ε_s = (π/4) k0 |ε|
    (:func:`rollerrig.contact.fastsim.slope_reduction`; ``p[P_LAW]`` = 2 only, k = 1 for
    FASTSIM and FaStrip), and the derivative f' (k + |ε| dk/d|ε|). C = G a b C11 at the load.
    """
    ratio, dratio, _ = _law_ratio_curvature(eps, p)
    return ratio, dratio


def _law_ratio_curvature(eps, p):
    """:func:`_law_ratio` and, for Polach's law (``p[P_LAW]`` = 0), the second derivative
    d²(F_x/(μN))/dε² [-] (:func:`rollerrig.contact.creep.polach_shape_derivatives`); 0 for a
    tabulated law, whose arm loop takes Newton's steps (:func:`_contact_load_and_force`)."""
    if p[P_LAW] == 0.0:
        shape, slope, curvature = _polach_shape_derivatives(eps, p[P_KA], p[P_KS])
        return (2.0 / np.pi) * shape, (2.0 / np.pi) * slope, (2.0 / np.pi) * curvature
    e = abs(eps)
    if p[P_LAW] == 2.0:  # the modified FASTSIM: f at k ε
        k0 = p[P_K0]
        alpha = p[P_ALPHA_INF]
        beta = p[P_BETA]
        denom = 1.0 + beta * 0.25 * np.pi * k0 * e
        k = k0 * (alpha + (1.0 - alpha) / denom)
        dk = -k0 * (1.0 - alpha) * beta * 0.25 * np.pi * k0 / (denom * denom)
        ratio, dratio = _table_ratio(k * e, p)
        dratio = dratio * (k + e * dk)
    else:
        ratio, dratio = _table_ratio(e, p)
    return (ratio if eps >= 0.0 else -ratio), dratio, 0.0


def _gradient_scale(p):
    """ε/(C ξ/(μN)) of the creep law [-]: π/4 for Polach's (his eq. 4), 1 for a table's."""
    return 0.25 * np.pi if p[P_LAW] == 0.0 else 1.0


def _force_and_slope(creep, load, friction, p):
    """The creep law's force F_x [N] at the normal load ``load`` [N] and dF_x/dN [-].

    F = μN r(ε) with r the law's ratio (:func:`_law_ratio`): Polach's (``p[P_LAW]`` = 0,
    Kayaalp eq. 4.16) or a table. ε ∝ C(N)/N ∝ N^(-1/3) (the creep stiffness scales with
    N^(2/3)), so dF/dN = F/N − μ ε r'(ε)/3.
    """
    q_mu = load * friction
    if q_mu <= 0.0:
        return 0.0, 0.0
    eps = _gradient_scale(p) * _creep_stiffness_at(load, p) * creep / q_mu
    ratio, dratio = _law_ratio(eps, p)
    force = q_mu * ratio
    return force, force / load - friction * eps * dratio * (1.0 / 3.0)


def _contact_load_and_force(air_spring, creep, friction, p):
    """Normal load N [N] and creep force F_x [N] at the contact, with the arm's load transfer.

    The swinging arm makes the normal load depend on the creep force it produces (moments about
    the arm's pivot; :class:`rollerrig.rig.sections.ArmParameters`):

        N = B + κ F_x(N),    B = S + W_d,    κ = σ h / l,

    where F_x(N) = μ N r(ε) is the creep law's force (Polach's, Kayaalp eq. 4.16, by default;
    :func:`_law_ratio`) with μN and the creep stiffness at N. The algebraic loop is solved, not
    lagged. Since ε ∝ N^(-1/3), in ``w = (B/N)^(1/3)`` the gradient is ``ε = ε_B w`` and the
    equation (divided by N) reads

        g(w) = 1 − κ μ r(ε_B w) − w³ = 0,    g'(w) = −κ μ ε_B r'(ε_B w) − 3 w²,

    solved from w = 1 (N = B) by Halley's method for Polach's law, whose second derivative is
    rational (no further arctan; 2.1 law evaluations a call on the default experiment's
    trajectory against Newton's 3.0), and by Newton's for a tabulated law. Where
    ``p[P_ARM_START]`` is positive (a solver's own copy of the parameters) the loop starts
    from that w instead and writes its root there: successive calls of a solver are close
    in state, and the default experiment then takes 1.3 law evaluations a call (the root is
    the same to the loop's tolerance from any start; a value that is not a usable start, 0,
    NaN or above 1e6, starts from w = 1). There the creep stiffness at B is also kept with B
    (``P_MEMO_LOAD``, ``P_MEMO_STIFFNESS``): through a hold B does not change, and its cube
    root had been 8 % of the default solve's samples, on the loop's critical path (17.7 ->
    15.6 ms). Halley's step
    ``s = −2 g g'/(2 g'² − g g'')`` is taken where its denominator exceeds ``g'²`` (a step at
    most twice Newton's), Newton's elsewhere. No cube root inside the loop (one for ε_B). The
    loop stops after a step below ``tol w`` (Halley 3e-5, Newton 1e-6/3: the error left is
    about s³ or s², round-off either way), so that the right-hand side is a smooth function of
    the state for the solvers' forward-difference Jacobians; the force then follows the last
    step to the order of the method (F = μ B r(ε_B w)/w³, r expanded about the last
    iterate). For B > 0 a root always exists (g(0) = 1, g → −∞): where the transfer nears
    self-locking (κ μ r near 1 or above) it is a very large load. The loop keeps a bracket of
    the root (the largest iterate with g > 0, the smallest with g <= 0): a step that leaves it,
    where a creep curve falling past its peak makes g non-monotonic and the steps would cycle
    about a stationary point of g, is replaced by the bracket's midpoint, or, with no iterate
    below the root yet (a step that would cross w = 0, N → ∞), by a step toward a bound below
    the root (:func:`_arm_step_down`). B = 0 gives no load and no force.
    """
    base = air_spring + p[P_ARM_WEIGHT]
    if base < 0.0:
        base = 0.0
    q_mu = base * friction
    if q_mu <= 0.0:
        return base, 0.0
    carry = p[P_ARM_START]
    if carry > 0.0 and base == p[P_MEMO_LOAD]:
        stiffness = p[P_MEMO_STIFFNESS]
    else:
        stiffness = _creep_stiffness_at(base, p)
        if carry > 0.0:
            p[P_MEMO_LOAD] = base
            p[P_MEMO_STIFFNESS] = stiffness
    eps_base = _gradient_scale(p) * stiffness * creep / q_mu
    if p[P_ARM_RATIO] == 0.0:
        return base, q_mu * _law_ratio_curvature(eps_base, p)[0]
    w = carry if 0.0 < carry < 1e6 else 1.0
    ratio, dratio, curvature = _law_ratio_curvature(eps_base * w, p)
    kappa_mu = p[P_ARM_RATIO] * friction
    halley = p[P_LAW] == 0.0
    lo = 0.0  # g(lo) > 0: g(0) = 1
    hi = np.inf  # g(hi) < 0 once an iterate has shown it
    for _ in range(_ARM_NEWTON_STEPS):
        w3 = w * w * w
        g = 1.0 - kappa_mu * ratio - w3
        if g > 0.0:
            lo = max(lo, w)
        else:
            hi = min(hi, w)
        dg = kappa_mu * eps_base * dratio + 3.0 * w * w  # −g'(w)
        step = g / dg
        tol = 1e-6 / 3.0  # Newton's: the error left is about step², round-off
        if halley:
            d2g = kappa_mu * eps_base * eps_base * curvature + 6.0 * w  # −g''(w)
            denom = 2.0 * dg * dg + g * d2g  # 2 g'² − g g''
            if denom > dg * dg:
                step = 2.0 * g * dg / denom
                tol = 3e-5  # Halley's: the error left is about step³
        new = w + step
        if abs(step) <= tol * w and new > 0.0:
            # F = μ B r(ε_B w)/w³ with r about the last iterate (round-off once converged).
            de = eps_base * step
            r = ratio + de * (dratio + 0.5 * de * curvature)
            if carry > 0.0:
                p[P_ARM_START] = new
            return base / (new * new * new), q_mu * r / (new * new * new)
        if not (lo < new < hi):  # out of the bracket (or NaN): g is not monotonic between
            if lo > 0.0 and hi < np.inf:
                new = 0.5 * (lo + hi)
            elif lo == 0.0:  # the root lies in (0, min(w, hi)): toward a bound below it
                new = _arm_step_down(min(w, hi), kappa_mu, eps_base, p)
            else:  # the root lies above lo
                new = 2.0 * lo
        w = new
        ratio, dratio, curvature = _law_ratio_curvature(eps_base * w, p)
    w3 = w * w * w
    return base / w3, q_mu * ratio / w3


def _arm_step_down(w, kappa_mu, eps_base, p):
    """The next iterate [-] of the arm's loop (:func:`_contact_load_and_force`) where Newton's
    step would cross w = 0: the geometric mean of ``w`` and a w below the root.

    Below ``w_lo = 1/(2 |κ μ ε_B| r'(0))`` g stays positive (|r(ε)| <= r'(0) |ε| for the
    concave creep laws, so κ μ r <= 1/2 there, and w³ < 1/2 where Newton crossed, which takes
    |κ μ r| near 1 and so w_lo < 0.8), so the root lies in (w_lo, w): halving the gap
    on a log scale reaches it in a few steps even where it sits at w ~ 1e-40 (a load of
    1e-125 N under a self-locking transfer, κ μ >= 1, where halving w took 130 steps).
    Halving ``w`` where no such bound is known.
    """
    slope0 = _law_ratio(0.0, p)[1]
    lower = 0.5 / (abs(kappa_mu * eps_base) * slope0)
    if 0.0 < lower < w:
        return np.sqrt(lower * w)
    return 0.5 * w


def _open_loop_roller_torque(rotor_speed, omega_ref, p):
    """Air-gap torque of the open-loop roller drive [N.m] (roller modes 1 and 2).

    Mode 1: the induction motor's Thevenin torque (Kayaalp eq. 4.28) under the V/f law for the
    set speed ``omega_ref`` [rad/s]; mode 2: its linear torque-slip fit (Kayaalp Fig. 45).
    ``rotor_speed`` is the rotor speed relative to the stator [rad/s]; motoring positive.
    """
    if p[P_ROLLER_MODE] == 1.0:
        f_supply = vf_supply_frequency(omega_ref, p[P_AM_PP])
        voltage = vf_voltage(f_supply, p[P_AM_V], p[P_AM_FRATED], 0.0)
        return induction_torque(
            rotor_speed,
            f_supply,
            voltage,
            p[P_AM_RTH],
            p[P_AM_XTH],
            p[P_AM_R2],
            p[P_AM_X2],
            p[P_AM_FRATED],
            p[P_AM_PP],
        )
    return linear_induction_torque(rotor_speed, omega_ref, p[P_AM_SLOPE])


def rig_terms(t, x, p, tables):
    """Every torque, force and contact quantity of the rig at one instant.

    Returns a tuple ordered as :data:`TERM_NAMES` (SI units). Pure scalar arithmetic: compiled by
    numba for the fast backend, evaluated as Python for the baseline. It writes only to
    ``p[P_ARM_START]``, ``p[P_MEMO_LOAD]`` and ``p[P_MEMO_STIFFNESS]``, and only where the
    first is positive (a solver's copy of the parameters: :func:`_contact_load_and_force`), and
    there ``p[P_VOLTAGE_LIMITED]`` where the PMSM's controller meets its voltage limit.
    """
    torque_request = _interp(t, tables, TAB_TORQUE_T, TAB_TORQUE)
    speed_setpoint = _interp(t, tables, TAB_SPEED_T, TAB_SPEED)
    air_spring = _interp(t, tables, TAB_LOAD_T, TAB_LOAD)

    th1, th2, th3, th4, th5, th6, th7 = x[0], x[1], x[2], x[3], x[4], x[5], x[6]
    w1, w2, w3, w4, w5, w6, w7 = x[7], x[8], x[9], x[10], x[11], x[12], x[13]

    # Shafts and mounts (T_ij = k (θi − θj) + b (ωi − ωj); ground is at rest).
    t01 = p[P_K01] * (0.0 - th1) + p[P_B01] * (0.0 - w1)
    t23 = p[P_K23] * (th2 - th3) + p[P_B23] * (w2 - w3)
    t34 = p[P_K34] * (th3 - th4) + p[P_B34] * (w3 - w4)
    t56 = p[P_K56] * (th5 - th6) + p[P_B56] * (w5 - w6)
    t70 = p[P_K70] * (th7 - 0.0) + p[P_B70] * (w7 - 0.0)

    # Contact: Polach's creep force with the creep stiffness at the present load. With a
    # flexible frame the roller's contact point moves with the frame at x[X_FRAME_V] relative
    # to the wheel's: the slip is ω4 r_w − (ω5 r_r + v_f) (the state is 0 for a rigid frame).
    # The normal load is the air spring's force plus the arm's transfer of the creep force.
    v_frame = x[X_FRAME_V] if p[P_FRAME_MODE] != 0.0 else 0.0  # rigid: not a degree of freedom
    w5_contact = w5 + v_frame / p[P_RR]
    creep, slip_velocity = _creep_kernel(w4, w5_contact, p[P_RW], p[P_RR], p[P_VREG])
    friction = _friction_kernel(slip_velocity, p[P_MU0], p[P_A], p[P_B])
    load, force = _contact_load_and_force(air_spring, creep, friction, p)

    bearing_w, bearing_r = _bearing_torques(load, w3, w5, p)

    # Wheel drive: PMSM with field-oriented current control, or an ideal torque source.
    v_d = 0.0
    v_q = 0.0
    dint_d = 0.0
    dint_q = 0.0
    if p[P_WHEEL_MODE] == 0.0:
        t_pmsm = torque_request
    else:
        t_pmsm = pmsm_torque(x[X_ID], x[X_IQ], p[P_PP], p[P_FLUX], p[P_LD], p[P_LQ])
        i_d_ref, i_q_ref = pmsm_current_reference(torque_request, p[P_PP], p[P_FLUX], p[P_IMAX])
        v_d, v_q, dint_d, dint_q = pmsm_foc_voltages(
            x[X_ID],
            x[X_IQ],
            i_d_ref,
            i_q_ref,
            x[X_INT_D],
            x[X_INT_Q],
            w2 - w1,
            p[P_PP],
            p[P_LD],
            p[P_LQ],
            p[P_FLUX],
            p[P_KP],
            p[P_KI],
            p[P_VMAX],
        )
        # At the limit the voltages are scaled onto it: |v| = V_max up to rounding.
        if p[P_ARM_START] > 0.0 and v_d * v_d + v_q * v_q >= (1.0 - 1e-9) * p[P_VMAX] ** 2:
            p[P_VOLTAGE_LIMITED] = 1.0
    if p[P_RIPPLE_AMP] != 0.0:
        t_pmsm = t_pmsm + p[P_RIPPLE_AMP] * np.sin(2.0 * np.pi * p[P_RIPPLE_FREQ] * t)

    # Roller drive: the air-gap torque acts between rotor (6) and stator (7).
    omega_ref = speed_setpoint / p[P_RR]  # direct drive: AM rotor speed = roller speed
    rotor_speed = w6 - w7  # relative to the stator
    mode = p[P_ROLLER_MODE]
    dint_speed = 0.0
    if mode == 1.0 or mode == 2.0:
        target = _open_loop_roller_torque(rotor_speed, omega_ref, p)
    elif mode == 3.0:
        target, dint_speed = servo_speed_torque(
            rotor_speed, omega_ref, x[X_INT_SPEED], p[P_SERVO_KP], p[P_SERVO_KI], p[P_SERVO_TLIM]
        )
    else:
        # Ideal speed source: exactly the torque that keeps the rotor on the set point.
        accel_ref = _interp_slope(t, tables, TAB_SPEED_T, TAB_SPEED) / p[P_RR]
        target = p[P_J + 5] * accel_ref - t56
    if mode == 0.0 or p[P_LAG_TAU] == 0.0:
        t_roller = target
    else:
        t_roller = x[X_T_ROLLER]

    return (
        torque_request,
        speed_setpoint,
        air_spring,
        load,
        creep,
        slip_velocity,
        friction,
        force,
        t_pmsm,
        t_roller,
        target,
        t01,
        t23,
        t34,
        t56,
        t70,
        bearing_w,
        bearing_r,
        v_d,
        v_q,
        dint_d,
        dint_q,
        dint_speed,
    )


def rig_rhs(t, x, p, tables, dx):
    """Right-hand side of the coupled rig model, written into ``dx`` in place.

    Parameters
    ----------
    t : float
        Time [s].
    x : ndarray, shape (N_STATES,)
        State (see :data:`STATE_NAMES`).
    p : ndarray, shape (N_PARAMS,)
        Flat parameter vector (see the ``P_*`` indices).
    tables : ndarray, shape (6, n)
        Piecewise-linear inputs: torque request, roller speed set point, air-spring force.
    dx : ndarray, shape (N_STATES,)
        Output: time derivative of the state.
    """
    terms = rig_terms(t, x, p, tables)
    force = terms[_T_FORCE]
    t_pmsm = terms[_T_PMSM]
    t_roller = terms[_T_ROLLER]
    target = terms[_T_TARGET]
    t01, t23, t34, t56, t70 = terms[_T_01], terms[_T_23], terms[_T_34], terms[_T_56], terms[_T_70]
    bearing_w = terms[_T_BEAR_W]
    bearing_r = terms[_T_BEAR_R]

    for i in range(7):
        dx[X_THETA + i] = x[X_OMEGA + i]
    dx[X_OMEGA + 0] = (t01 - t_pmsm) / p[P_J + 0]
    dx[X_OMEGA + 1] = (t_pmsm - t23) / p[P_J + 1]
    dx[X_OMEGA + 2] = (t23 - t34 - bearing_w) / p[P_J + 2]
    dx[X_OMEGA + 3] = (t34 - force * p[P_RW]) / p[P_J + 3]
    dx[X_OMEGA + 4] = (force * p[P_RR] - t56 - bearing_r) / p[P_J + 4]
    dx[X_OMEGA + 5] = (t56 + t_roller) / p[P_J + 5]
    dx[X_OMEGA + 6] = (-t_roller - t70) / p[P_J + 6]

    if p[P_WHEEL_MODE] != 0.0:
        did, diq = pmsm_current_derivatives(
            x[X_ID],
            x[X_IQ],
            terms[_T_VD],
            terms[_T_VQ],
            x[X_OMEGA + 1] - x[X_OMEGA],
            p[P_PP],
            p[P_RS],
            p[P_LD],
            p[P_LQ],
            p[P_FLUX],
        )
    else:
        did = 0.0
        diq = 0.0
    dx[X_ID] = did
    dx[X_IQ] = diq
    dx[X_INT_D] = terms[_T_DINT_D]
    dx[X_INT_Q] = terms[_T_DINT_Q]
    if p[P_ROLLER_MODE] != 0.0 and p[P_LAG_TAU] != 0.0:
        dx[X_T_ROLLER] = lag_derivative(target, x[X_T_ROLLER], p[P_LAG_TAU])
    else:
        dx[X_T_ROLLER] = 0.0
    dx[X_INT_SPEED] = terms[_T_DINT_SPEED]
    if p[P_FRAME_MODE] != 0.0:
        # m_f ẍ_f = F_x − k_f x_f − c_f ẋ_f: the contact force pushes the roller's bearings.
        dx[X_FRAME_X] = x[X_FRAME_V]
        dx[X_FRAME_V] = (force - p[P_FRAME_K] * x[X_FRAME_X] - p[P_FRAME_C] * x[X_FRAME_V]) / p[
            P_FRAME_M
        ]
    else:
        dx[X_FRAME_X] = 0.0
        dx[X_FRAME_V] = 0.0


def _piece(tables, row_t, t):
    """``(lo, hi)``, consecutive, with ``tables[row_t, lo] <= t < tables[row_t, hi]``, by
    bisection, for ``t`` within the breakpoints' span ``[tables[row_t, 0],
    tables[row_t, -1])``."""
    lo = 0
    hi = tables.shape[1] - 1
    while hi - lo > 1:  # invariant: tables[row_t, lo] <= t < tables[row_t, hi]
        mid = (lo + hi) >> 1
        if tables[row_t, mid] <= t:
            lo = mid
        else:
            hi = mid
    return lo, hi


def _interp(t, tables, row_t, row_y):
    """``np.interp(t, tables[row_t], tables[row_y])`` for a scalar ``t``: the piecewise-linear
    input at ``t``.

    The same value as numpy's (right-continuous at a repeated breakpoint, the end values held
    outside), found by bisection. Compiled, it costs about 4 ns a call where numba's
    ``np.interp`` on a scalar costs about 70 ns (it builds arrays): three calls were half of
    the right-hand side's time. The rows are indexed in place, not sliced (no array view made
    per call).
    """
    n = tables.shape[1]
    if t < tables[row_t, 0]:
        return tables[row_y, 0]
    if t >= tables[row_t, n - 1]:
        return tables[row_y, n - 1]
    lo, hi = _piece(tables, row_t, t)
    t_lo = tables[row_t, lo]
    y_lo = tables[row_y, lo]
    return y_lo + (tables[row_y, hi] - y_lo) * ((t - t_lo) / (tables[row_t, hi] - t_lo))


SEGMENT_NODES = 2
"""Nodes of a segment's table (:func:`segment_tables`); an assembled input table has at least
:data:`MIN_TABLE_NODES` (:func:`_interp_slope` tells the two apart by their width)."""

MIN_TABLE_NODES = 3
"""Fewest nodes of an assembled input table (the last point repeated where it has fewer)."""


def stack_table_rows(rows):
    """The input tables from breakpoint rows of unequal length: each row padded by repeating
    its last point, to the longest row's length and at least :data:`MIN_TABLE_NODES` (a
    two-node table is a segment's line to :func:`_interp_slope`). Plain numpy, not compiled.
    """
    n = max(MIN_TABLE_NODES, *(len(r) for r in rows))
    out = np.empty((len(rows), n))
    for i, r in enumerate(rows):
        out[i, : len(r)] = r
        out[i, len(r) :] = r[-1]
    return out


def segment_tables(tables, t0, t1, out):
    """Each input's line over the segment ``[t0, t1]``, as a two-node table, into ``out``.

    ``out`` (rows of ``tables``, :data:`SEGMENT_NODES`) gets, for each pair of rows (times,
    values), the two breakpoints of the piece of the piecewise-linear input that holds the
    segment's middle (or, outside the breakpoints, the held end value), so that
    :func:`_interp` and :func:`_interp_slope` on ``out`` give the very values they give on
    ``tables`` anywhere inside the segment, with no bisection (three a right-hand side, 5 % of
    its cost on the default experiment's 14-node tables). At ``t1`` itself they give the
    limits from inside the segment, value and slope (:func:`_interp_slope` takes a two-node
    table as closed at its end), where the whole table gives the next piece's: a step's last
    stage is taken at ``t1`` and belongs to the segment (the ideal speed source's
    acceleration had been 0 there, its rotor losing a sixth of a step's speed change at the
    end of every ramp, 2026-11-30). A third node on the piece's line did the same at 5 %
    more of the default solve (a bisection step in each look-up).

    Returns False, and leaves ``out`` unusable, where an input has a breakpoint strictly
    inside the segment (the protocol's segments end at every breakpoint; an input ramped
    after the segments were cut may not): the segment then needs ``tables`` itself.
    """
    n = tables.shape[1]
    middle = 0.5 * (t0 + t1)
    for r in range(0, tables.shape[0], 2):
        if middle < tables[r, 0] or middle >= tables[r, n - 1]:
            if middle < tables[r, 0]:
                if t1 > tables[r, 0]:
                    return False
                value = tables[r + 1, 0]
            else:
                if t0 < tables[r, n - 1]:
                    return False
                value = tables[r + 1, n - 1]
            out[r, 0] = t0 - 1.0
            out[r, 1] = t1 + 1.0
            out[r + 1, 0] = value
            out[r + 1, 1] = value
            continue
        lo, hi = _piece(tables, r, middle)
        if t0 < tables[r, lo] or t1 > tables[r, hi]:
            return False
        out[r, 0] = tables[r, lo]
        out[r, 1] = tables[r, hi]
        out[r + 1, 0] = tables[r + 1, lo]
        out[r + 1, 1] = tables[r + 1, hi]
    return True


def roller_setpoint_at(t, tables):
    """The roller's speed set point [m/s] at ``t`` [s] (the input tables' ramp)."""
    return _interp(t, tables, TAB_SPEED_T, TAB_SPEED)


def lowest_speed_setpoint(tables, t0, t1):
    """The lowest magnitude [m/s] of the roller's speed set point over ``[t0, t1]``: at the
    segment's ends and at the breakpoints inside it (the input is piecewise linear)."""
    return speed_setpoint_bounds(tables, t0, t1)[0]


def speed_setpoint_bounds(tables, t0, t1):
    """The lowest and the highest magnitude [m/s] of the roller's speed set point over
    ``[t0, t1]``, at the segment's ends and the breakpoints inside it (the input is piecewise
    linear; the set point is never negative)."""
    v0 = abs(roller_setpoint_at(t0, tables))
    v1 = abs(roller_setpoint_at(t1, tables))
    lo = min(v0, v1)
    hi = max(v0, v1)
    # Only the breakpoints inside, found by bisection: a replayed recording's table has a node
    # per sample and thousands of segments, and every segment asks (fast._stops).
    j = np.searchsorted(tables[TAB_SPEED_T], t0, side="right")
    while j < tables.shape[1] and tables[TAB_SPEED_T, j] < t1:
        v = abs(tables[TAB_SPEED, j])
        lo = min(lo, v)
        hi = max(hi, v)
        j += 1
    return lo, hi


def _interp_slope(t, tables, row_t, row_y):
    """Slope of the piecewise-linear input ``(tables[row_t], tables[row_y])`` at ``t``
    (right-continuous; 0 outside); a two-node table (a segment's line, :func:`segment_tables`)
    is closed at its end, where the segment's last stage is taken."""
    if tables.shape[1] == SEGMENT_NODES:
        t_lo = tables[row_t, 0]
        t_hi = tables[row_t, 1]
        if t_lo <= t <= t_hi and t_hi > t_lo:
            return (tables[row_y, 1] - tables[row_y, 0]) / (t_hi - t_lo)
        return 0.0
    if not tables[row_t, 0] <= t < tables[row_t, tables.shape[1] - 1]:
        return 0.0
    lo, hi = _piece(tables, row_t, t)
    return (tables[row_y, hi] - tables[row_y, lo]) / (tables[row_t, hi] - tables[row_t, lo])
