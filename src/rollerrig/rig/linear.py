"""The coupled twin linearised at steady free rolling: its damped modes and what moves in each.

The free-chain modal table (:func:`rollerrig.rig.chain.modal_table`) holds the seven inertias
and their spring-dampers only. In the running rig the wheel-roller contact (a creep force that
grows with the slip velocity: a damper with lever arms), the PMSM with its field-oriented current
control and the induction motor (its torque falls with rotor slip speed, through a first-order
response lag) are coupled to the chain. :func:`linearise_twin` linearises the full right-hand
side of the coupled model (:func:`rollerrig.rig.model.rig_rhs`, the same function the solvers
integrate) about steady free rolling (:func:`rollerrig.rig.assemble.steady_free_rolling_state`)
at a given roller speed and normal load:

    d(δx)/dt = A δx,   A = ∂f/∂x (x0)

by central differences, ``A[:, k] = (f(x0 + h_k e_k) − f(x0 − h_k e_k)) / (2 h_k)`` with
``h_k = step · max(|x0_k|, 1)`` (truncation error O(h²), round-off O(ε/h); the result is
compared with a second step ten times larger and the relative difference is kept). States the
chosen drives do not use (rows and columns of zeros) are dropped. The inverter torque ripple is
an input, not a dynamic, and is switched off for the linearisation.

:func:`coupled_modes` takes the eigenvalues λ of A. A complex pair is an oscillatory mode:
damped frequency ``f_d = |Im λ| / 2π``, natural frequency ``|λ| / 2π``, damping ratio
``ζ = −Re λ / |λ|``. A real eigenvalue is a non-oscillatory (first-order or overdamped) motion
with time constant ``τ = −1 / λ``; it cannot ring and never explains a spectral line. An
eigenvalue ``|λ| <= 1e-10 max|λ|`` is a rigid rotation of a subchain no spring ties to ground
(they come out at 1e-17 to 1e-16 of the fastest pole, the eigensolver's rounding; the slowest
physical poles of the bundled rigs are above 1e-5 of it).
Only oscillatory modes with ``ζ`` below a threshold (default 0.3: a resonance peak at least
about 5 dB above the static response) may label a spectral peak.

What moves: the participation factors ``p_ki = |w_ik v_ki|`` (``v`` right, ``w`` left
eigenvectors, ``W = V⁻¹``; Pérez-Arriaga et al. 1982), scale-free, summed per body (its angle
and speed) and per drive state group (PMSM currents and their PI integrals; the AM torque lag;
the servo's speed integral), normalised to 1; and the element of the chain with the largest
share of the modal strain energy ``k (θ_i − θ_j)²``.

Checks (tests/rig/test_linear.py): with the contact and the drives removed the eigenvalues are
those of :func:`rollerrig.rig.chain.modal_analysis` (to 1e-6); with the contact in and the AM
without lag they are those of the chain with :func:`~rollerrig.rig.chain.contact_damping_matrix`
(slope ``dF/dw = (kA + kS) G a b c11 / (2 √(v² + v_ε²))``, Polach's linear limit) and
:func:`~rollerrig.rig.chain.damper_matrix`; the roller-shaft pair against the two-inertia closed
form ``μ s² + b56 s + k56 = 0``, ``μ = J5 J6 / (J5 + J6)``.

References
----------
I. J. Pérez-Arriaga, G. C. Verghese, F. C. Schweppe, "Selective modal analysis with applications
to electric power systems", IEEE Trans. PAS-101 (1982) 3117-3125 (participation factors).
O. Polach, "Creep forces in simulations of traction vehicles running on adhesion limit", Wear 258
(2005) 992-1000 (the creep law and its linear limit).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.linalg

from rollerrig._validation import (
    ParameterError,
    did_you_mean,
    require_finite,
    require_in_range,
    require_positive,
)
from rollerrig.contact.creep import POLACH_PARAMETER_SETS, PolachParameters
from rollerrig.experiment.protocol import Protocol
from rollerrig.rig import model as m
from rollerrig.rig.assemble import assemble
from rollerrig.rig.chain import (
    BODY_NAMES,
    CHAIN_ELEMENTS,
    chain_elements,
    chain_matrices,
    modal_analysis,
)

__all__ = [
    "DEFAULT_DAMPING_THRESHOLD",
    "DEFAULT_NORMAL_LOAD",
    "CoupledMode",
    "CoupledModes",
    "LinearisedTwin",
    "coupled_modes",
    "format_coupled_modes",
    "linearise_rhs",
    "linearise_twin",
    "modes_of",
]

DEFAULT_NORMAL_LOAD = 4.3e3
"""Normal load used when a recording carries none [N]: the load of the seed's adhesion tests
(Kayaalp 4.5.1.6; the bundled protocols seed-30kmh-dry and seed-10kmh-wet)."""

DEFAULT_DAMPING_THRESHOLD = 0.3
"""Largest damping ratio of a mode that may explain a spectral line [-]."""

# |λ| / max|λ| below which an eigenvalue is a rigid rotation: a million times the rounding of
# the eigenvalues (1e-6 called a real 2 Hz mode rigid beside a contact pole of 1.35e7 1/s,
# heavy load at low speed on a soft motor mount)
_RIGID = 1e-10
_GROUPS: dict[str, str] = {
    **{f"theta{i + 1}": b for i, b in enumerate(BODY_NAMES)},
    **{f"omega{i + 1}": b for i, b in enumerate(BODY_NAMES)},
    "i_d": "pmsm_currents",
    "i_q": "pmsm_currents",
    "integral_d": "pmsm_currents",
    "integral_q": "pmsm_currents",
    "roller_drive_torque_state": "am_torque_lag",
    "speed_error_integral": "servo_speed_integral",
    "frame_displacement": "frame",
    "frame_velocity": "frame",
}


# --------------------------------------------------------------------------------------------
# Linearisation
# --------------------------------------------------------------------------------------------


def linearise_rhs(
    params: np.ndarray, tables: np.ndarray, state: np.ndarray, t: float = 0.0, step: float = 1e-7
) -> np.ndarray:
    """Jacobian ``∂f/∂x`` of :func:`rollerrig.rig.model.rig_rhs` by central differences.

    Parameters
    ----------
    params : ndarray, shape (N_PARAMS,)
        Parameter vector.
    tables : ndarray, shape (6, n)
        Input tables.
    state : ndarray, shape (N_STATES,)
        Operating point x0.
    t : float
        Time at which the inputs are read [s].
    step : float
        Relative step [-]: ``h_k = step · max(|x0_k|, 1)``.

    Returns
    -------
    ndarray, shape (N_STATES, N_STATES)
        ``A[i, k] = ∂f_i/∂x_k`` [1/s and mixed units].
    """
    x0 = np.asarray(state, dtype=float)
    n = x0.size
    jac = np.empty((n, n))
    plus, minus = np.empty(n), np.empty(n)
    for k in range(n):
        h = step * max(abs(x0[k]), 1.0)
        x = x0.copy()
        x[k] = x0[k] + h
        m.rig_rhs(t, x, params, tables, plus)
        x[k] = x0[k] - h
        m.rig_rhs(t, x, params, tables, minus)
        jac[:, k] = (plus - minus) / (2.0 * h)
    return jac


@dataclass(frozen=True)
class LinearisedTwin:
    """The coupled twin linearised about steady free rolling.

    Attributes
    ----------
    speed : float
        Roller surface speed set point [m/s].
    normal_load : float
        Normal load [N].
    drives : DriveConfig
        Drive models.
    friction : str
        Friction condition (Polach set) of the contact.
    state_names : tuple of str
        The active states (rows and columns of ``jacobian``).
    jacobian : ndarray, shape (n, n)
        ``A = ∂f/∂x`` on the active states.
    state : ndarray, shape (N_STATES,)
        Operating point x0 (all states).
    step_difference : float
        Largest difference between the Jacobians with steps ``step`` and ``10·step``, relative to
        the largest entry of each column [-] (the finite-difference check).
    params : ndarray
        Parameter vector used (ripple switched off).
    """

    speed: float
    normal_load: float
    drives: m.DriveConfig
    friction: str
    state_names: tuple[str, ...]
    jacobian: np.ndarray = field(repr=False)
    state: np.ndarray = field(repr=False)
    step_difference: float = 0.0
    params: np.ndarray = field(default=None, repr=False)


def _operating_point_protocol(
    speed: float,
    load: float,
    friction: str,
    torque_time=None,
    torque=None,
    *,
    name: str = "linearisation",
    description: str = "steady free rolling for the linearised twin",
    source: str = "rollerrig.rig.linear",
) -> Protocol:
    """Steady rolling at ``speed`` [rad/s] and ``load`` [N] with ``friction``, 1 s long, or
    with a wheel-torque table (``torque_time`` [s], ``torque`` [N m]) to its last instant."""
    return Protocol(
        name=name,
        description=description,
        source=source,
        duration=1.0 if torque_time is None else float(torque_time[-1]),
        torque_time=[0.0] if torque_time is None else list(torque_time),
        torque_request=[0.0] if torque is None else list(torque),
        speed_time=[0.0],
        roller_speed=[speed],
        load_time=[0.0],
        normal_load=[load],
        friction_time=[0.0],
        friction_condition=(friction,),
    )


def _active(jac: np.ndarray) -> np.ndarray:
    return np.flatnonzero(np.any(jac != 0.0, axis=0) | np.any(jac != 0.0, axis=1))


def _column_difference(a: np.ndarray, b: np.ndarray) -> float:
    scale = np.maximum(np.max(np.abs(a), axis=0), np.finfo(float).tiny)
    return float(np.max(np.abs(a - b) / scale))


def linearise_twin(
    rig,
    speed: float,
    normal_load: float,
    *,
    drives: m.DriveConfig | None = None,
    friction: str = "dry",
    friction_sets: Mapping[str, PolachParameters] | None = None,
    step: float = 1e-7,
) -> LinearisedTwin:
    """Linearise the coupled twin about steady free rolling at a speed and a normal load.

    The model inputs come from :func:`rollerrig.rig.assemble.assemble` (the same parameter
    vector and steady state the simulations start from) for a constant-speed, constant-load,
    zero-torque protocol.

    Parameters
    ----------
    rig : RigParameters
        Rig parameters.
    speed : float
        Roller surface speed [m/s], > 0.
    normal_load : float
        Normal load [N], > 0.
    drives : DriveConfig, optional
        Drive models (default: PMSM with FOC, induction motor V/f with the rig's lag).
    friction : str
        Friction condition, a key of ``friction_sets`` (default Polach 2005 dry).
    friction_sets : mapping, optional
        Polach parameter sets by name; default dry and wet of Polach (2005).
    step : float
        Relative finite-difference step [-].

    Returns
    -------
    LinearisedTwin

    Examples
    --------
    >>> from rollerrig.rig.parameters import default_rig
    >>> lin = linearise_twin(default_rig(), 30 / 3.6, 4.3e3)
    >>> len(lin.state_names), lin.step_difference < 1e-5
    (19, True)
    """
    v = require_positive("speed", speed, "m/s", single=True)
    load = require_positive("normal_load", normal_load, "N", single=True)
    # A step of 0, NaN or inf had given a Jacobian of NaN (0/0) with no error.
    step = require_in_range("step", step, 0.0, 1.0, "-", single=True)
    sets = dict(friction_sets or POLACH_PARAMETER_SETS)
    if friction not in sets:
        raise ParameterError(
            f"friction must be one of {sorted(sets)}, got {friction!r}"
            + did_you_mean(str(friction), sets)
        )
    drives = drives or m.DriveConfig()
    if drives.roller == "induction_dq":
        raise ParameterError(
            "the linearised twin covers the drives of the 22-state model; for the modes with "
            "the dq induction machine use rollerrig.rig.modes.twin_modes (any drive; rollerrig "
            "modes --roller-drive induction_dq)"
        )
    try:
        inputs = assemble(rig, _operating_point_protocol(v, load, friction), drives, sets)
    except ParameterError:
        raise
    except (ValueError, ArithmeticError) as exc:  # no steady state (root finding failed)
        raise ParameterError(
            f"no steady free rolling of the twin at {v:g} m/s and {load:g} N ({exc}); check the "
            "speed and the normal load"
        ) from exc
    params = inputs.segments[0].params.copy()
    params[m.P_RIPPLE_AMP] = 0.0
    x0 = inputs.initial_state
    jac = linearise_rhs(params, inputs.tables, x0, 0.0, step)
    check = linearise_rhs(params, inputs.tables, x0, 0.0, 10.0 * step)
    active = _active(jac)
    jac_a = jac[np.ix_(active, active)]
    return LinearisedTwin(
        speed=v,
        normal_load=load,
        drives=drives,
        friction=friction,
        state_names=tuple(m.STATE_NAMES[k] for k in active),
        jacobian=jac_a,
        state=x0,
        step_difference=_column_difference(jac_a, check[np.ix_(active, active)]),
        params=params,
    )


# --------------------------------------------------------------------------------------------
# Modes
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class CoupledMode:
    """One mode (eigenvalue) of the linearised twin.

    Attributes
    ----------
    eigenvalue : complex
        λ [1/s] (the one with Im λ > 0 of a complex pair).
    kind : str
        ``"oscillatory"`` (complex pair), ``"real"`` (no oscillation: first order or one pole of
        an overdamped pair) or ``"rigid"`` (λ = 0, rotation of a free subchain).
    frequency : float
        Damped frequency ``|Im λ| / 2π`` [Hz] (0 unless oscillatory).
    natural_frequency : float
        ``|λ| / 2π`` [Hz].
    damping_ratio : float or None
        ``−Re λ / |λ|`` [-] of an oscillatory mode; None for a real or rigid one.
    time_constant : float or None
        ``−1 / Re λ`` [s] (None for a rigid mode).
    participation : dict
        Body or drive-state group -> participation factor [-] (sums to 1).
    bodies : dict
        Body -> share of ``J_i |θ_i|²`` [-] (the kinetic-energy distribution; sums to 1).
    element : str
        Chain element that twists (largest strain energy), ``""`` for a rigid-body motion
        against a drive characteristic, a drive-state mode, or a rigid mode.
    can_ring : bool
        Oscillatory with ζ below the threshold: may explain a spectral line.
    """

    eigenvalue: complex
    kind: str
    frequency: float
    natural_frequency: float
    damping_ratio: float | None
    time_constant: float | None
    participation: dict[str, float]
    bodies: dict[str, float]
    element: str
    can_ring: bool

    @property
    def mechanical_participation(self) -> float:
        """Participation of the seven bodies' angles and speeds [-]."""
        return float(sum(v for k, v in self.participation.items() if k in BODY_NAMES))

    @property
    def drive_participation(self) -> dict[str, float]:
        """Participation of the drive-state groups [-]."""
        return {k: v for k, v in self.participation.items() if k not in BODY_NAMES}

    @property
    def what_moves(self) -> str:
        """The twisting element, the bodies holding >= 10 % of the motion and drive states
        participating >= 10 %, e.g. ``"roller_shaft: am_rotor 0.77, roller 0.23"``."""
        parts = []
        if self.mechanical_participation >= 0.1 and self.bodies:
            ranked = sorted(self.bodies.items(), key=lambda kv: -kv[1])
            shown = [f"{b} {v:.2f}" for b, v in ranked if v >= 0.1] or [
                f"{b} {v:.2f}" for b, v in ranked[:1]
            ]
            parts.append((f"{self.element}: " if self.element else "") + ", ".join(shown))
        drives = sorted(self.drive_participation.items(), key=lambda kv: -kv[1])
        shown = [f"{g} {v:.2f}" for g, v in drives if v >= 0.1]
        if shown:
            parts.append(("drive: " if parts else "") + ", ".join(shown))
        return "; ".join(parts)

    @property
    def label(self) -> str:
        """Label for a spectral peak, e.g. ``"rig mode 13.78 Hz, ζ 0.0039 (roller_shaft: ...)"``."""
        zeta = "" if self.damping_ratio is None else f", ζ {self.damping_ratio:.2g}"
        return f"rig mode {self.frequency:.2f} Hz{zeta} ({self.what_moves})"

    def as_row(self) -> dict[str, Any]:
        """JSON-ready row (finite numbers or None, units in the keys)."""
        return {
            "kind": self.kind,
            "frequency [Hz]": self.frequency,
            "natural_frequency [Hz]": self.natural_frequency,
            "damping_ratio [-]": self.damping_ratio,
            "time_constant [s]": self.time_constant,
            "eigenvalue_real [1/s]": float(self.eigenvalue.real),
            "eigenvalue_imag [1/s]": float(self.eigenvalue.imag),
            "can_ring": self.can_ring,
            "element": self.element or None,
            "what_moves": self.what_moves,
            "bodies": dict(self.bodies),
            "participation": dict(self.participation),
        }


@dataclass(frozen=True)
class CoupledModes:
    """Modes of the linearised twin at an operating point.

    Attributes
    ----------
    speed : float
        Roller surface speed [m/s].
    normal_load : float
        Normal load [N].
    load_source : str
        Where the load came from (e.g. ``"normal_load channel"``, ``"default 4.3 kN"``).
    drives : DriveConfig
        Drive models.
    friction : str
        Friction condition of the contact.
    damping_threshold : float
        ζ below which an oscillatory mode can ring [-].
    modes : tuple of CoupledMode
        Oscillatory modes by frequency, then real modes by time constant, then rigid ones.
    step_difference : float
        Finite-difference check of the Jacobian [-] (:class:`LinearisedTwin`).
    """

    speed: float
    normal_load: float
    load_source: str
    drives: m.DriveConfig
    friction: str
    damping_threshold: float
    modes: tuple[CoupledMode, ...]
    step_difference: float = 0.0

    @property
    def ringing(self) -> tuple[CoupledMode, ...]:
        """The modes that may explain a spectral line (oscillatory, ζ below the threshold)."""
        return tuple(md for md in self.modes if md.can_ring)

    def operating_point(self) -> dict[str, Any]:
        """The operating point, JSON-ready."""
        return {
            "roller_speed [m/s]": self.speed,
            "roller_speed [km/h]": self.speed * 3.6,
            "normal_load [N]": self.normal_load,
            "normal_load_source": self.load_source,
            "wheel_drive": self.drives.wheel,
            "roller_drive": self.drives.roller,
            "roller_lag [s]": self.drives.roller_lag,
            "friction": self.friction,
        }

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready summary: operating point, threshold, one row per mode."""
        return {
            "operating_point": self.operating_point(),
            "damping_threshold [-]": self.damping_threshold,
            "finite_difference_check [-]": self.step_difference,
            "modes": [md.as_row() for md in self.modes],
        }


def _participation(vectors: np.ndarray) -> np.ndarray:
    """Participation factors |w_ik v_ki| (rows: states, columns: modes), normalised per mode."""
    try:
        left = np.linalg.inv(vectors)
        p = np.abs(left.T * vectors)
    except np.linalg.LinAlgError:  # defective: fall back to the right eigenvectors alone
        p = np.abs(vectors) ** 2
    total = p.sum(axis=0)
    return p / np.where(total > 0.0, total, 1.0)


def _energies(vector: np.ndarray, names: tuple[str, ...], inertias, elements):
    """Kinetic shares ``J_i |θ_i|²`` over the bodies and the strain energy of each element."""
    theta = np.zeros(7, dtype=complex)
    for k, name in enumerate(names):
        if name.startswith("theta"):
            theta[int(name[5:]) - 1] = vector[k]
    kinetic = inertias * np.abs(theta) ** 2
    strain = []
    for i, j, k, _ in elements:
        ti = theta[i - 1] if i > 0 else 0.0
        tj = theta[j - 1] if j > 0 else 0.0
        strain.append(k * abs(ti - tj) ** 2)
    return kinetic, np.asarray(strain)


def _require_resolvable(lam, vec, names, scale, rig) -> None:
    """Refuse a spectrum whose fastest pole hides the chain's modes.

    An eigenvalue ``|λ| <= 1e-10 max|λ|`` counts as rigid (module docstring). When the fastest
    pole is so fast that this bound exceeds the slowest elastic mode of the free chain, that
    mode could not be told from a rigid rotation (a stator of 1e-12 kg.m^2 on its mount: a
    pole at −1e17 1/s, whose rounding alone, about 20 1/s, is as large as the chain's slow
    poles). The error names the pole and what moves in it, so that the parameter can be found.
    """
    M, K, _ = chain_matrices(rig)
    free = modal_analysis(M, K)  # undamped: the frequencies alone
    elastic = free.natural_frequencies[~free.rigid].tolist()
    if not elastic or _RIGID * scale < 2.0 * np.pi * min(elastic):
        return
    fastest = int(np.argmax(np.abs(lam)))
    share = np.abs(vec[:, fastest]) / max(float(np.max(np.abs(vec[:, fastest]))), 1e-300)
    moves = ", ".join(names[i] for i in np.argsort(-share)[:2])
    raise ParameterError(
        f"the linearised twin has a pole at {abs(lam[fastest]):.3g} 1/s (time constant "
        f"{1.0 / abs(lam[fastest]):.3g} s; states {moves}), so fast beside the chain's slowest "
        f"elastic mode ({min(elastic):.3g} Hz) that the eigenvalues' rounding (about "
        f"{np.finfo(float).eps * abs(lam[fastest]):.2g} 1/s) could not tell the slow modes from "
        "rigid rotations: check the rig's inertias, stiffnesses and dampings of those states' "
        "bodies (an inertia far below the others, or a very stiff or heavily damped mount)"
    )


def modes_of(
    jacobian: np.ndarray,
    state_names,
    rig,
    damping_threshold: float = DEFAULT_DAMPING_THRESHOLD,
) -> tuple[CoupledMode, ...]:
    """Modes of ``d(δx)/dt = A δx`` with what moves in each: bodies and drive states.

    Bodies: shares of ``J_i |θ_i|²`` of the right eigenvector (the kinetic-energy distribution,
    since ``ω_i = λ θ_i``). Drive states: participation factors (module docstring). The chain
    element with the largest strain energy is named when the mode's strain energy is at least
    a fifth of its kinetic energy ``|λ|² Σ J_i |θ_i|²`` (a twisting mode, not a rigid-body
    motion against a drive characteristic).

    Parameters
    ----------
    jacobian : ndarray, shape (n, n)
        A on the states ``state_names``.
    state_names : sequence of str
        Names from :data:`rollerrig.rig.model.STATE_NAMES`.
    rig : RigParameters
        For the inertias and chain elements.
    damping_threshold : float
        ζ below which an oscillatory mode can ring [-].

    Returns
    -------
    tuple of CoupledMode
        Oscillatory modes by frequency, then real ones by time constant, then rigid ones.
    """
    jacobian = require_finite("jacobian", jacobian)
    names = tuple(state_names)
    if jacobian.ndim != 2 or jacobian.shape[0] != jacobian.shape[1]:
        raise ParameterError(f"jacobian must be a square matrix, got shape {jacobian.shape}")
    if len(names) != jacobian.shape[0]:
        raise ParameterError(
            f"state_names must name each of the jacobian's {jacobian.shape[0]} states, got "
            f"{len(names)} names"
        )
    damping_threshold = check_damping_threshold(damping_threshold)
    lam, vec = scipy.linalg.eig(jacobian)
    scale = max(float(np.max(np.abs(lam))), np.finfo(float).tiny)
    _require_resolvable(lam, vec, names, scale, rig)
    part = _participation(vec)
    groups = list(dict.fromkeys(_GROUPS.get(n, n) for n in names))
    group_of = np.array([groups.index(_GROUPS.get(n, n)) for n in names])
    elements = chain_elements(rig)
    inertias = np.array([getattr(rig.inertia, b) for b in BODY_NAMES])
    out = []
    for k, value in enumerate(lam):
        if value.imag < 0.0 and abs(value.imag) > 1e-12 * scale:
            continue  # the conjugate's twin
        share = np.bincount(group_of, weights=part[:, k], minlength=len(groups))
        participation = {g: float(s) for g, s in zip(groups, share, strict=True) if s > 0.0}
        kinetic, strain = _energies(vec[:, k], names, inertias, elements)
        total = float(kinetic.sum())
        bodies = {
            b: float(e / total) for b, e in zip(BODY_NAMES, kinetic, strict=True) if total > 0
        }
        magnitude = abs(value)
        element = ""
        if strain.size and float(strain.max()) >= 0.2 * magnitude**2 * total:
            element = CHAIN_ELEMENTS[int(np.argmax(strain))][2]
        if magnitude <= _RIGID * scale:
            kind, fd, zeta, tau, element = "rigid", 0.0, None, None, ""
        elif abs(value.imag) <= 1e-12 * scale:
            kind, fd, zeta, tau = "real", 0.0, None, float(-1.0 / value.real)
        else:
            kind = "oscillatory"
            fd = float(abs(value.imag) / (2.0 * np.pi))
            zeta = float(-value.real / magnitude)
            tau = float(-1.0 / value.real) if value.real != 0.0 else None
        out.append(
            CoupledMode(
                eigenvalue=complex(value.real, abs(value.imag)),
                kind=kind,
                frequency=fd,
                natural_frequency=float(magnitude / (2.0 * np.pi)),
                damping_ratio=zeta,
                time_constant=tau,
                participation=participation,
                bodies=bodies,
                element=element,
                can_ring=kind == "oscillatory" and zeta < damping_threshold,
            )
        )
    rank = {"oscillatory": 0, "real": 1, "rigid": 2}
    out.sort(key=lambda md: (rank[md.kind], md.frequency, md.time_constant or 0.0))
    return tuple(out)


def check_damping_threshold(damping_threshold: float) -> float:
    """``damping_threshold`` [-] as a float, or a ParameterError when it is not in (0, 1)."""
    return require_in_range("damping_threshold", damping_threshold, 0.0, 1.0, "-", single=True)


def coupled_modes(
    rig,
    speed: float,
    normal_load: float,
    *,
    drives: m.DriveConfig | None = None,
    friction: str = "dry",
    damping_threshold: float = DEFAULT_DAMPING_THRESHOLD,
    load_source: str = "given",
) -> CoupledModes:
    """Damped modes of the coupled, linearised twin at a roller speed and a normal load.

    Parameters
    ----------
    rig, speed, normal_load, drives, friction
        Rig parameters, roller surface speed [m/s] (> 0), normal load [N] (> 0), drive models
        and friction condition (Polach set name), as in :func:`linearise_twin`.
    damping_threshold : float
        ζ below which an oscillatory mode may explain a spectral line [-], in (0, 1).
    load_source : str
        Where the load came from, stated in every output.

    Returns
    -------
    CoupledModes

    Examples
    --------
    >>> from rollerrig.rig.parameters import default_rig
    >>> cm = coupled_modes(default_rig(), 30 / 3.6, 4.3e3)
    >>> [round(md.frequency, 1) for md in cm.ringing]
    [0.8, 13.8, 110.8]
    """
    check_damping_threshold(damping_threshold)
    lin = linearise_twin(rig, speed, normal_load, drives=drives, friction=friction)
    return CoupledModes(
        speed=lin.speed,
        normal_load=lin.normal_load,
        load_source=str(load_source),
        drives=lin.drives,
        friction=lin.friction,
        damping_threshold=float(damping_threshold),
        modes=modes_of(lin.jacobian, lin.state_names, rig, float(damping_threshold)),
        step_difference=lin.step_difference,
    )


def _lag_text(modes: CoupledModes) -> str:
    """What sets the roller drive's dynamics, for the table's header."""
    if modes.drives.roller == "induction_dq":
        return "the rig's [roller_drive_vf] settings; no lag"
    lag = modes.drives.roller_lag
    return f"lag {'rig value' if lag is None else f'{lag:g} s'}"


def format_coupled_modes(modes: CoupledModes) -> str:
    """Plain-text table of the coupled modes (frequency, ζ, time constant, what moves).

    Examples
    --------
    >>> from rollerrig.rig.parameters import default_rig
    >>> text = format_coupled_modes(coupled_modes(default_rig(), 30 / 3.6, 4.3e3))
    >>> text.splitlines()[3].split()[:4]
    ['mode', 'f_d', '[Hz]', 'zeta']
    """
    op = modes.operating_point()
    lines = [
        f"Coupled twin linearised at steady free rolling: {op['roller_speed [km/h]']:.1f} km/h, "
        f"N = {modes.normal_load / 1e3:.3g} kN ({modes.load_source}), {modes.friction} contact,",
        f"wheel drive {modes.drives.wheel}, roller drive {modes.drives.roller} "
        f"({_lag_text(modes)})",
        f"can ring: oscillatory with zeta < {modes.damping_threshold:g}; real and rigid modes "
        "never explain a spectral line",
        f"{'mode':>4} {'f_d [Hz]':>9} {'zeta':>8} {'tau [s]':>9}  {'ring':<4}  what moves "
        "(kinetic share; drive-state participation)",
    ]
    for i, md in enumerate(modes.modes, start=1):
        zeta = "-" if md.damping_ratio is None else f"{md.damping_ratio:.3g}"
        tau = "-" if md.time_constant is None else f"{md.time_constant:.3g}"
        kind = {"real": "real pole", "rigid": "rigid"}.get(md.kind, "")
        fd = f"{md.frequency:9.2f}" if md.kind == "oscillatory" else f"{kind:>9}"
        lines.append(
            f"{i:>4} {fd} {zeta:>8} {tau:>9}  {'yes' if md.can_ring else 'no':<4}  {md.what_moves}"
        )
    return "\n".join(lines)
