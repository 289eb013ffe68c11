"""The torsional chain of the rig: mass, stiffness and damping matrices and its modes.

Seven bodies (Kayaalp, section 4.5.1, eqs. 4.1-4.12, re-derived in the sign convention of
CONTRIBUTING.md): 1 PMSM stator, 2 PMSM rotor, 3 wheel disc, 4 wheel tyre, 5 roller, 6 AM rotor,
7 AM stator; body 0 is ground. Spring-dampers carry ``T_ij = k_ij (θ_i − θ_j) + b_ij (ω_i − ω_j)``
with body i receiving ``−T_ij`` and body j ``+T_ij``::

    0 ─k01─ [-] ┆ [2] ─k23─ [3] ─k34─ [4] ╎ [5] ─k56─ [6] ┆ [7] ─k70─ 0

    1 PMSM stator ┆ 2 PMSM rotor (air gap, T12); 3 wheel disc, 4 wheel tyre ╎ 5 roller
    (contact, F_x); 6 AM rotor ┆ 7 AM stator (air gap, T67). Each spring has a damper b_ij.

There is no spring across 1-2 and 6-7 (the motor air gaps carry actuator torques) nor across 4-5
(the wheel-roller contact carries a creep force, which is dissipative). The free-vibration
equation is ``M θ̈ + C θ̇ + K θ = 0``; the linearised contact and motor characteristics at an
operating point enter as extra damping (:func:`contact_damping_matrix`, :func:`damper_matrix`).

With these elements the subchains {2, 3, 4} and {5, 6} are not tied to ground: K has two rigid
(zero-frequency) modes. The lightly damped roller-shaft mode J5-k56-J6 lies at
``(1/2π)·sqrt(k56 (J5 + J6) / (J5 J6)) ≈ 13.84 Hz`` for the default rig.

Examples
--------
>>> from rollerrig.rig.parameters import default_rig
>>> M, K, C = chain_matrices(default_rig())
>>> result = modal_analysis(M, K, C)
>>> [round(float(f), 2) for f in result.natural_frequencies]
[0.0, 0.0, 13.84, 19.02, 47.86, 64.97, 111.95]
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from rollerrig._validation import (
    ParameterError,
    require_finite,
    require_in_range,
    require_nonnegative,
    require_positive,
    require_whole,
)

__all__ = [
    "BODY_NAMES",
    "CHAIN_ELEMENTS",
    "ModalResult",
    "ModalRow",
    "assemble_chain",
    "chain_elements",
    "chain_matrices",
    "contact_damping_matrix",
    "damper_matrix",
    "format_modal_table",
    "modal_analysis",
    "modal_table",
]

#: Names of bodies 1..7 (index 0 of this tuple is body 1).
BODY_NAMES: tuple[str, ...] = (
    "pmsm_stator",
    "pmsm_rotor",
    "wheel_disc",
    "wheel_tyre",
    "roller",
    "am_rotor",
    "am_stator",
)

#: Spring-damper elements of the default topology: (body i, body j, name of the stiffness and
#: damping attribute in :class:`~rollerrig.rig.parameters.RigParameters`); 0 is ground.
CHAIN_ELEMENTS: tuple[tuple[int, int, str], ...] = (
    (0, 1, "pmsm_mount"),
    (2, 3, "wheel_shaft"),
    (3, 4, "wheel_rubber"),
    (5, 6, "roller_shaft"),
    (7, 0, "am_mount"),
)


# --------------------------------------------------------------------------------------------
# Kernel
# --------------------------------------------------------------------------------------------


def _assemble_chain_kernel(inertias, body_i, body_j, stiffness, damping):
    """M, K, C of a chain of lumped inertias joined by spring-dampers (no validation).

    Bodies are numbered 1..n (index ``b - 1`` in the matrices), 0 is ground. Element e between
    i and j adds ``k_e [[1, -1], [-1, 1]]`` on rows/columns (i, j), ground rows dropped.
    Plain loops and arithmetic only, so it also compiles under ``numba.njit``.
    """
    n = inertias.shape[0]
    M = np.zeros((n, n))
    K = np.zeros((n, n))
    C = np.zeros((n, n))
    for a in range(n):
        M[a, a] = inertias[a]
    for e in range(body_i.shape[0]):
        i = body_i[e] - 1
        j = body_j[e] - 1
        k = stiffness[e]
        b = damping[e]
        if i >= 0:
            K[i, i] += k
            C[i, i] += b
        if j >= 0:
            K[j, j] += k
            C[j, j] += b
        if i >= 0 and j >= 0:
            K[i, j] -= k
            K[j, i] -= k
            C[i, j] -= b
            C[j, i] -= b
    return M, K, C


# --------------------------------------------------------------------------------------------
# Assembly
# --------------------------------------------------------------------------------------------


def assemble_chain(
    inertias: Sequence[float] | np.ndarray,
    elements: Sequence[tuple[int, int, float, float]],
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mass, stiffness and damping matrices of any lumped torsional chain (or tree, or ring).

    Parameters
    ----------
    inertias : array_like, shape (n,)
        Moments of inertia of bodies 1..n [kg.m^2].
    elements : sequence of (i, j, k, b)
        Spring-dampers between body ``i`` and body ``j`` (0 = ground, 1..n = bodies), with
        torsional stiffness ``k`` [N.m/rad] and viscous damping ``b`` [N.m.s/rad]. The element
        torque is ``T_ij = k (θ_i − θ_j) + b (ω_i − ω_j)`` (CONTRIBUTING.md sign convention).

    Returns
    -------
    M, K, C : ndarray, shape (n, n)
        Diagonal mass matrix [kg.m^2], stiffness matrix [N.m/rad] and damping matrix
        [N.m.s/rad] of ``M θ̈ + C θ̇ + K θ = τ`` (Kayaalp eqs. 4.1-4.12 in matrix form).

    Raises
    ------
    ParameterError
        A non-positive inertia, a negative stiffness or damping, or a body index outside 0..n,
        or an element joining a body to itself.

    Examples
    --------
    >>> M, K, C = assemble_chain([1.0, 2.0], [(0, 1, 10.0, 0.0), (1, 2, 5.0, 0.1)])
    >>> K
    array([[15., -5.],
           [-5.,  5.]])
    """
    inertias = require_positive("inertias", inertias, "kg.m^2")
    if inertias.ndim != 1 or inertias.size == 0:
        raise ParameterError(f"inertias must be a non-empty 1-D array, got shape {inertias.shape}")
    n = inertias.size
    body_i, body_j, stiffness, damping = [], [], [], []
    for e, element in enumerate(elements):
        try:
            i, j, k, b = element
        except (TypeError, ValueError) as exc:
            raise ParameterError(f"elements[{e}] must be (i, j, k, b), got {element!r}") from exc
        for name, idx in (("i", i), ("j", j)):
            if isinstance(idx, bool) or not isinstance(idx, int | np.integer) or not 0 <= idx <= n:
                raise ParameterError(
                    f"elements[{e}] body {name} must be an integer in [0, {n}] (0 = ground), "
                    f"got {idx!r}"
                )
        if i == j:
            raise ParameterError(f"elements[{e}] joins body {i} to itself")
        require_nonnegative(f"elements[{e}] stiffness k", k, "N.m/rad")
        require_nonnegative(f"elements[{e}] damping b", b, "N.m.s/rad")
        body_i.append(int(i))
        body_j.append(int(j))
        stiffness.append(float(k))
        damping.append(float(b))
    return _assemble_chain_kernel(
        inertias,
        np.asarray(body_i, dtype=np.int64),
        np.asarray(body_j, dtype=np.int64),
        np.asarray(stiffness, dtype=float),
        np.asarray(damping, dtype=float),
    )


def chain_elements(rig) -> list[tuple[int, int, float, float]]:
    """The (i, j, k, b) element list of the rig's seven-body chain, SI units.

    Parameters
    ----------
    rig : RigParameters
        Parameter set (see :func:`rollerrig.rig.parameters.default_rig`).

    Returns
    -------
    list of (int, int, float, float)
        ``(i, j, k [N.m/rad], b [N.m.s/rad])`` for k01, k23, k34, k56, k70 in that order.
    """
    return [
        (i, j, getattr(rig.stiffness, name), getattr(rig.damping, name))
        for i, j, name in CHAIN_ELEMENTS
    ]


def chain_matrices(rig) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M, K, C (7×7) of the rig's torsional chain, bodies 1..7 as rows 0..6.

    Kayaalp eqs. 4.1-4.12, re-derived in the CONTRIBUTING.md sign convention (eq. 4.7 uses J7,
    not J6). Actuator torques (air gaps 1-2 and 6-7), the contact force (4-5) and bearing
    losses are inputs, not elements.

    Parameters
    ----------
    rig : RigParameters
        Parameter set.

    Returns
    -------
    M : ndarray, shape (7, 7)
        ``diag(J1..J7)`` [kg.m^2].
    K : ndarray, shape (7, 7)
        Stiffness [N.m/rad].
    C : ndarray, shape (7, 7)
        Damping [N.m.s/rad].

    Examples
    --------
    >>> from rollerrig.rig.parameters import default_rig
    >>> M, K, C = chain_matrices(default_rig())
    >>> K[4:6, 4:6].tolist()
    [[43500.0, -43500.0], [-43500.0, 43500.0]]
    """
    inertias = [getattr(rig.inertia, name) for name in BODY_NAMES]
    return assemble_chain(inertias, chain_elements(rig))


MAX_BODIES = 1000
"""Most bodies of a chain :func:`damper_matrix` and :func:`contact_damping_matrix` build [-]: a
dense n×n matrix of a million bodies would take 7 TiB (the rig has 7)."""


def damper_matrix(n_bodies: int, i: int, j: int, damping: float) -> np.ndarray:
    """Damping matrix (n×n) of one extra linear damper between body i and body j (0 = ground).

    Use it for a linearised motor characteristic at an operating point: the induction motor's
    air-gap torque falls with rotor speed relative to the stator, ``c = −dT67/d(ω6 − ω7) > 0``
    between bodies 6 and 7.

    Parameters
    ----------
    n_bodies : int
        Number of bodies n.
    i, j : int
        Bodies joined (0 = ground, 1..n).
    damping : float
        Damping coefficient [N.m.s/rad], >= 0.

    Returns
    -------
    ndarray, shape (n, n)
        Damping matrix of the damper alone [N.m.s/rad]; add it to the chain's.

    Examples
    --------
    >>> damper_matrix(2, 0, 1, 3.0)
    array([[3., 0.],
           [0., 0.]])
    """
    n_bodies = require_whole("n_bodies", n_bodies, minimum=1, maximum=MAX_BODIES)
    _, _, C = assemble_chain(np.ones(n_bodies), [(i, j, 0.0, damping)])
    return C


def contact_damping_matrix(
    creep_force_slope: float,
    wheel_radius: float,
    roller_radius: float,
    n_bodies: int = 7,
    wheel_body: int = 4,
    roller_body: int = 5,
) -> np.ndarray:
    """Damping matrix of the linearised wheel-roller contact at an operating point.

    The contact force depends on the slip velocity ``w = ω4 r_w − ω5 r_r`` (Kayaalp eq. 4.22);
    it brakes the wheel (torque ``−r_w F_x``) and drives the roller (``+r_r F_x``). With
    ``d = dF_x/dw`` [N.s/m] at the operating point (roller speed held fixed),
    ``δτ = −d [[r_w², −r_w r_r], [−r_w r_r, r_r²]] δω`` on (wheel, roller): a damper with
    lever arms, symmetric and positive semidefinite for ``d >= 0`` (the rising branch of the
    creep curve), negative damping on the falling branch.

    Parameters
    ----------
    creep_force_slope : float
        ``dF_x/dw`` [N.s/m] (any sign).
    wheel_radius, roller_radius : float
        Rolling radii r_w, r_r [m].
    n_bodies : int, optional
        Size of the chain (7).
    wheel_body, roller_body : int, optional
        Body numbers of the wheel tyre (4) and the roller (5).

    Returns
    -------
    ndarray, shape (n, n)
        Contact damping [N.m.s/rad], nonzero only in the wheel and roller rows and columns.

    Examples
    --------
    >>> C = contact_damping_matrix(1000.0, 0.5, 0.25, n_bodies=2, wheel_body=1, roller_body=2)
    >>> C.tolist()
    [[250.0, -125.0], [-125.0, 62.5]]
    """
    slope = require_finite("creep_force_slope", creep_force_slope, "N.s/m", single=True)
    r_w = require_positive("wheel_radius", wheel_radius, "m", single=True)
    r_r = require_positive("roller_radius", roller_radius, "m", single=True)
    # 7.5 bodies, a body 4.5 or "a" had raised numpy's TypeError or IndexError; a million
    # bodies a MemoryError (7 TiB).
    n_bodies = require_whole("n_bodies", n_bodies, minimum=1, maximum=MAX_BODIES)
    wheel_body = require_whole("wheel_body", wheel_body, minimum=1, maximum=n_bodies)
    roller_body = require_whole("roller_body", roller_body, minimum=1, maximum=n_bodies)
    if wheel_body == roller_body:
        raise ParameterError("wheel_body and roller_body must differ")
    w, r = wheel_body - 1, roller_body - 1
    C = np.zeros((n_bodies, n_bodies))
    C[w, w] = slope * r_w * r_w
    C[r, r] = slope * r_r * r_r
    C[w, r] = C[r, w] = -slope * r_w * r_r
    return C


# --------------------------------------------------------------------------------------------
# Modal analysis
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ModalResult:
    """Modes of ``M θ̈ + C θ̇ + K θ = 0``, sorted by undamped natural frequency.

    Attributes
    ----------
    natural_frequencies : ndarray, shape (n,)
        Undamped natural frequencies [Hz] from ``K φ = ω² M φ``; exactly 0 for rigid modes.
    mode_shapes : ndarray, shape (n, n)
        Mass-normalised mode shapes as columns (``Φᵀ M Φ = I``) [rad per √(kg.m^2)]. Rigid
        modes are the indicator vectors of the floating subchains when these can be identified.
    rigid : ndarray of bool, shape (n,)
        True for rigid-body (zero-frequency) modes.
    poles : ndarray of complex, shape (2n,) or None
        Eigenvalues of the first-order (state-space) form [1/s], sorted by modulus, then by
        imaginary part; None when no damping was given.
    mode_poles : ndarray of complex, shape (n, 2) or None
        The two poles assigned to each undamped mode (by maximal modal assurance criterion of
        the displacement part of the state eigenvector).
    damped_frequencies : ndarray, shape (n,) or None
        Damped natural frequencies ``|Im λ| / 2π`` [Hz]; 0 for overdamped and rigid modes.
    damping_ratios : ndarray, shape (n,) or None
        ``ζ = −Re(λa + λb) / (2 √|λa λb|)`` [-]: ``−Re λ/|λ|`` for a complex pair, > 1 for an
        overdamped mode (two real poles); NaN for a mode whose poles include 0.
    """

    natural_frequencies: np.ndarray
    mode_shapes: np.ndarray
    rigid: np.ndarray
    poles: np.ndarray | None = None
    mode_poles: np.ndarray | None = None
    damped_frequencies: np.ndarray | None = None
    damping_ratios: np.ndarray | None = None

    @property
    def n_rigid(self) -> int:
        """Number of rigid-body modes [-]."""
        return int(np.count_nonzero(self.rigid))


def _is_spring_network(K: np.ndarray) -> bool:
    """True when K is a weighted graph Laplacian plus non-negative ground springs."""
    scale = max(float(np.max(np.abs(K))), np.finfo(float).tiny)
    off = K - np.diag(np.diag(K))
    return bool(np.all(off <= 1e-12 * scale) and np.all(K.sum(axis=1) >= -1e-9 * scale))


def _component_labels(adjacency: np.ndarray) -> np.ndarray:
    """Connected components of an undirected graph (symmetric boolean adjacency): one label
    per node, numbered in the order of each component's first node. A depth-first search:
    a chain has tens of bodies, and ``scipy.sparse.csgraph`` would cost every command that
    builds a rig 0.1-0.2 s of import for it."""
    n = adjacency.shape[0]
    labels = np.full(n, -1, dtype=np.int64)
    count = 0
    for start in range(n):
        if labels[start] >= 0:
            continue
        labels[start] = count
        stack = [start]
        while stack:
            for j in np.flatnonzero(adjacency[stack.pop()]):
                if labels[j] < 0:
                    labels[j] = count
                    stack.append(int(j))
        count += 1
    return labels


def _floating_components(K: np.ndarray) -> list[np.ndarray]:
    """Index sets of the subchains that no stiffness ties to ground (from K's pattern)."""
    n = K.shape[0]
    scale = max(float(np.max(np.abs(K))), np.finfo(float).tiny)
    adjacency = (np.abs(K) > 1e-12 * scale) & ~np.eye(n, dtype=bool)
    labels = _component_labels(adjacency | adjacency.T)
    grounded = K.sum(axis=1) > 1e-9 * scale  # row sum = stiffness to ground
    out = []
    for label in np.unique(labels):
        members = np.flatnonzero(labels == label)
        if not np.any(grounded[members]):
            out.append(members)
    return out


def _state_space_poles(M, K, C):
    """Eigenvalues and displacement parts of eigenvectors of ``[0 I; −K −C] z = λ [I 0; 0 M] z``.

    Solved as the standard eigenproblem of ``[0 I; −L⁻¹KL⁻ᵀ −L⁻¹CL⁻ᵀ]`` in the coordinates
    ``q = Lᵀθ`` (``M = LLᵀ``, Cholesky), displacements back as ``θ = L⁻ᵀq``: the same poles,
    but the pencil with ``M`` in it lost them to the QZ algorithm's scaling when inertias
    differ by many decades (one body of 1e20 kg.m^2 among bodies of 1-50 gave infinite
    eigenvalues for all the chain's elastic modes).
    """
    n = M.shape[0]
    inverse = _inverse_cholesky_factor(M)
    A = np.block(
        [[np.zeros((n, n)), np.eye(n)], [-inverse @ K @ inverse.T, -inverse @ C @ inverse.T]]
    )
    lam, vec = np.linalg.eig(A)
    return lam, inverse.T @ vec[:n, :]


def _inverse_cholesky_factor(M):
    """``L⁻¹`` of the Cholesky factor ``M = LLᵀ`` of a symmetric positive definite ``M``.

    numpy's linear algebra, not scipy's: the chain's matrices are a few bodies square, and
    ``import scipy.linalg`` (0.2 s, most of it scipy's array-API layer importing numpy.f2py)
    was a tenth of ``rollerrig simulate`` (issue 20).

    Raises
    ------
    numpy.linalg.LinAlgError
        ``M`` is not positive definite.
    """
    return np.linalg.inv(np.linalg.cholesky(M))


def _generalised_eigh(K, M):
    """Eigenvalues (ascending) and ``M``-normalised eigenvectors of ``K φ = λ M φ``.

    The Cholesky reduction that LAPACK's ``dsygv`` (``scipy.linalg.eigh(K, M)``) performs:
    ``L⁻¹ K L⁻ᵀ v = λ v`` with ``M = LLᵀ`` and ``φ = L⁻ᵀ v``, so that ``φᵀ M φ = I``.

    Raises
    ------
    numpy.linalg.LinAlgError
        ``M`` is not positive definite.
    """
    inverse = _inverse_cholesky_factor(M)
    reduced = inverse @ K @ inverse.T
    eigenvalues, vectors = np.linalg.eigh(0.5 * (reduced + reduced.T))
    return eigenvalues, inverse.T @ vectors


def _assign_poles(lam, x, modes, M, tol):
    """Give each undamped mode two poles, complex-conjugate pairs kept together, by MAC."""
    n = modes.shape[1]
    # units: a complex-conjugate pair (one representative) or one real pole
    units: list[list[int]] = []
    used = np.zeros(lam.size, dtype=bool)
    scale = max(float(np.max(np.abs(lam))), 1.0)
    for a in np.argsort(-np.abs(lam.imag)):
        if used[a]:
            continue
        used[a] = True
        if abs(lam[a].imag) > tol * scale:
            rest = np.flatnonzero(~used)
            b = rest[np.argmin(np.abs(lam[rest] - np.conj(lam[a])))]
            used[b] = True
            units.append([int(a), int(b)])
        else:
            units.append([int(a)])
    Mx = M @ x
    num = np.abs(modes.T @ Mx) ** 2  # (n modes, 2n poles)
    den = np.real(np.sum(np.conj(x) * Mx, axis=0))
    mac = num / np.where(den > 0, den, 1.0)
    capacity = np.full(n, 2)
    owner: list[list[int]] = [[] for _ in range(n)]
    candidates = sorted(
        ((mac[m, u[0]], ui, m) for ui, u in enumerate(units) for m in range(n)),
        key=lambda t: -t[0],
    )
    placed = np.zeros(len(units), dtype=bool)
    for _, ui, m in candidates:
        if not placed[ui] and capacity[m] >= len(units[ui]):
            owner[m].extend(units[ui])
            capacity[m] -= len(units[ui])
            placed[ui] = True
    # Rare leftovers (a conjugate pair facing two half-full modes): split them by MAC.
    for ui in np.flatnonzero(~placed):
        for p in units[ui]:
            m = max((m for m in range(n) if capacity[m] > 0), key=lambda m: mac[m, p])
            owner[m].append(p)
            capacity[m] -= 1
    return np.array([[lam[p] for p in owner[m]] for m in range(n)])


def modal_analysis(
    M: np.ndarray,
    K: np.ndarray,
    C: np.ndarray | None = None,
    extra_damping: np.ndarray | None = None,
    *,
    rigid_tolerance: float = 1e-12,
) -> ModalResult:
    """Undamped and (optionally) damped modes of a linear torsional chain.

    Undamped: the generalised symmetric eigenproblem ``K φ = ω² M φ`` (:func:`_generalised_eigh`),
    mass-normalised. Damped: the eigenvalues of the first-order form
    ``[0 I; −K −C] z = λ [I 0; 0 M] z`` with ``z = (θ, ω)``, so non-proportional damping is
    exact; the two poles of each mode give ``ω_n = √|λa λb|``, ``ζ = −Re(λa + λb)/(2 ω_n)`` and
    ``f_d = |Im(λa − λb)|/(4π)`` (for a complex pair: ``|λ|``, ``−Re λ/|λ|``, ``|Im λ|/2π``).

    Parameters
    ----------
    M : ndarray, shape (n, n)
        Mass (inertia) matrix [kg.m^2], symmetric positive definite.
    K : ndarray, shape (n, n)
        Stiffness matrix [N.m/rad], symmetric positive semidefinite.
    C : ndarray, shape (n, n), optional
        Damping matrix [N.m.s/rad]. None and no ``extra_damping``: undamped analysis only.
    extra_damping : ndarray, shape (n, n), optional
        Added to C [N.m.s/rad]: linearised contact (:func:`contact_damping_matrix`) and motor
        slip damping (:func:`damper_matrix`) at an operating point. May be non-symmetric.
    rigid_tolerance : float, optional
        When K is not a network of non-negative springs, a mode is rigid when
        ``ω² <= rigid_tolerance · max(ω²)`` [-]. For a spring network (any K from
        :func:`assemble_chain`) the rigid modes are counted exactly from the topology: one per
        subchain with no spring to ground.

    Returns
    -------
    ModalResult

    Raises
    ------
    ParameterError
        Matrices of the wrong shape, not finite, M not symmetric positive definite, or K not
        symmetric.

    Examples
    --------
    Two inertias on a shaft (free-free): one rigid mode and ``sqrt(k (J1 + J2)/(J1 J2))``.

    >>> import numpy as np
    >>> M, K, C = assemble_chain([1.0, 1.0], [(1, 2, 2.0, 0.0)])
    >>> r = modal_analysis(M, K)
    >>> r.rigid.tolist(), bool(np.isclose(r.natural_frequencies[1], 2.0 / (2 * np.pi)))
    ([True, False], True)
    """
    M = _square("M", M)
    n = M.shape[0]
    K = _square("K", K, n)
    # NaN had called no mode rigid, a negative tolerance none, silently.
    rigid_tolerance = require_in_range(
        "rigid_tolerance", rigid_tolerance, 0.0, 1.0, "-", low_inclusive=True, single=True
    )
    if not np.allclose(M, M.T, rtol=1e-12, atol=0.0):
        raise ParameterError("M [kg.m^2] must be symmetric")
    if not np.allclose(K, K.T, rtol=1e-12, atol=1e-12 * max(float(np.max(np.abs(K))), 1.0)):
        raise ParameterError("K [N.m/rad] must be symmetric")
    try:
        omega2, shapes = _generalised_eigh(K, M)
    except np.linalg.LinAlgError as exc:
        raise ParameterError("M [kg.m^2] must be positive definite") from exc
    top = max(float(np.max(np.abs(omega2))), np.finfo(float).tiny)
    if np.any(omega2 < -1e-9 * top):
        raise ParameterError("K [N.m/rad] must be positive semidefinite (negative ω² found)")
    components = _floating_components(K) if _is_spring_network(K) else None
    if components is not None:
        # A network of springs k >= 0: its null space is spanned exactly by the floating
        # subchains (a topological count, immune to the eigenvalue round-off), and the rigid
        # eigenvectors (arbitrarily mixed by eigh) are replaced by one mass-normalised
        # indicator vector per subchain: M-orthogonal, spanning the same null space.
        rigid = np.zeros(n, dtype=bool)
        rigid[: len(components)] = True  # eigh sorts ascending
        for col, members in enumerate(components):
            v = np.zeros(n)
            v[members] = 1.0
            shapes[:, col] = v / np.sqrt(v @ M @ v)
    else:
        rigid = omega2 <= rigid_tolerance * top
    omega2 = np.where(rigid, 0.0, omega2)
    frequencies = np.sqrt(omega2) / (2.0 * np.pi)

    if C is None and extra_damping is None:
        return ModalResult(frequencies, shapes, rigid)
    C_total = np.zeros((n, n)) if C is None else _square("C", C, n).copy()
    if extra_damping is not None:
        C_total = C_total + _square("extra_damping", extra_damping, n)
    lam, x = _state_space_poles(M, K, C_total)
    order = np.lexsort((lam.imag, np.abs(lam)))
    lam, x = lam[order], x[:, order]
    mode_poles = _assign_poles(lam, x, shapes, M, 1e-9)
    product = np.abs(mode_poles[:, 0] * mode_poles[:, 1])
    wn = np.sqrt(product)
    total = -np.real(mode_poles[:, 0] + mode_poles[:, 1])
    # A pole is zero (its mode's damping undefined) when it is tiny against its own mode's
    # undamped frequency, or within ten times the eigenvalues' rounding, eps max|λ|: a PMSM
    # stator of 1e-10, 1e-11, 3e-12, 1e-12, 1e-13 kg.m^2 on its mount (fast pole −b/J) gave
    # the mount's slow pole, −5 1/s, as −4.875, −6, −4, 0 and −128, errors of 0.6 to 0.5
    # eps max|λ|: the first is kept (ζ 1 % off), the others are flagged. Not against the
    # fastest pole alone, as before: then every other mode's damping was NaN beside it.
    pole_noise = 10.0 * np.finfo(float).eps * float(np.max(np.abs(lam)))
    smallest = np.min(np.abs(mode_poles), axis=1)
    has_zero = rigid | (smallest <= np.maximum(1e-9 * np.sqrt(omega2), pole_noise))
    with np.errstate(divide="ignore", invalid="ignore"):
        zeta = np.where(has_zero, np.nan, total / (2.0 * np.where(has_zero, 1.0, wn)))
        fd = np.abs(np.imag(mode_poles[:, 0] - mode_poles[:, 1])) / (4.0 * np.pi)
    fd = np.where(rigid, 0.0, fd)
    return ModalResult(frequencies, shapes, rigid, lam, mode_poles, fd, zeta)


def _square(name: str, value, n: int | None = None) -> np.ndarray:
    arr = require_finite(name, value)
    if arr.ndim != 2 or arr.shape[0] != arr.shape[1] or (n is not None and arr.shape[0] != n):
        want = f"({n}, {n})" if n is not None else "square"
        raise ParameterError(f"{name} must be a {want} matrix, got shape {arr.shape}")
    return arr


# --------------------------------------------------------------------------------------------
# Table
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ModalRow:
    """One mode of the chain, for printing (see :func:`format_modal_table`).

    Attributes
    ----------
    mode : int
        Mode number, 1-based, in order of undamped frequency.
    frequency : float
        Undamped natural frequency [Hz] (0 for a rigid mode).
    damped_frequency : float
        Damped natural frequency [Hz] (NaN without damping; 0 when overdamped or rigid).
    damping_ratio : float
        Damping ratio ζ [-] (NaN without damping or for a rigid mode).
    rigid : bool
        Rigid-body mode of a floating subchain.
    dominant_bodies : tuple of str
        Bodies holding at least ``threshold`` of the modal kinetic energy, largest first.
    kinetic_energy : dict
        Body name -> fraction of modal kinetic energy ``J_i φ_i²`` [-] (sums to 1).
    dominant_element : str
        Element with the largest share of modal strain energy (``""`` for a rigid mode).
    """

    mode: int
    frequency: float
    damped_frequency: float
    damping_ratio: float
    rigid: bool
    dominant_bodies: tuple[str, ...]
    kinetic_energy: dict[str, float] = field(default_factory=dict)
    dominant_element: str = ""


def modal_table(
    rig,
    *,
    extra_damping: np.ndarray | None = None,
    damped: bool = True,
    threshold: float = 0.1,
) -> list[ModalRow]:
    """Modes of the rig's torsional chain as printable rows.

    Parameters
    ----------
    rig : RigParameters
        Parameter set.
    extra_damping : ndarray, shape (7, 7), optional
        Linearised contact and motor damping at an operating point [N.m.s/rad].
    damped : bool, optional
        Include the chain's own damping C (default True).
    threshold : float, optional
        Kinetic-energy fraction above which a body counts as dominant [-], default 0.1.

    Returns
    -------
    list of ModalRow

    Examples
    --------
    >>> from rollerrig.rig.parameters import default_rig
    >>> rows = modal_table(default_rig())
    >>> row = rows[2]
    >>> round(row.frequency, 2), row.dominant_bodies, row.dominant_element
    (13.84, ('am_rotor', 'roller'), 'roller_shaft')
    """
    # NaN or a share above 1 had named no dominant body, a negative one every body, silently.
    threshold = require_in_range(
        "threshold", threshold, 0.0, 1.0, "-", low_inclusive=True, high_inclusive=True, single=True
    )
    M, K, C = chain_matrices(rig)
    result = modal_analysis(M, K, C if damped else None, extra_damping)
    elements = chain_elements(rig)
    masses = np.diag(M)
    rows = []
    for m in range(M.shape[0]):
        phi = result.mode_shapes[:, m]
        kinetic = masses * phi**2
        kinetic = kinetic / kinetic.sum()
        order = np.argsort(-kinetic)
        dominant = tuple(BODY_NAMES[b] for b in order if kinetic[b] >= threshold)
        element = ""
        if not result.rigid[m]:
            strain = []
            for i, j, k, _ in elements:
                ti = phi[i - 1] if i > 0 else 0.0
                tj = phi[j - 1] if j > 0 else 0.0
                strain.append(k * (ti - tj) ** 2)
            element = CHAIN_ELEMENTS[int(np.argmax(strain))][2]
        has_damping = result.damping_ratios is not None
        rows.append(
            ModalRow(
                mode=m + 1,
                frequency=float(result.natural_frequencies[m]),
                damped_frequency=float(result.damped_frequencies[m]) if has_damping else np.nan,
                damping_ratio=float(result.damping_ratios[m]) if has_damping else np.nan,
                rigid=bool(result.rigid[m]),
                dominant_bodies=dominant,
                kinetic_energy={BODY_NAMES[b]: float(kinetic[b]) for b in range(len(masses))},
                dominant_element=element,
            )
        )
    return rows


def format_modal_table(rows: Sequence[ModalRow]) -> str:
    """Plain-text table of :func:`modal_table` rows.

    Examples
    --------
    >>> from rollerrig.rig.parameters import default_rig
    >>> print(format_modal_table(modal_table(default_rig())).splitlines()[0])
    mode   f [Hz]  f_d [Hz]      zeta  element       dominant bodies
    """
    header = f"{'mode':>4} {'f [Hz]':>8} {'f_d [Hz]':>9} {'zeta':>9}  {'element':<13}"
    lines = [header + " dominant bodies"]
    unresolved = False
    for r in rows:
        if r.rigid:
            zeta = "rigid"
        elif np.isfinite(r.damping_ratio):
            zeta = f"{r.damping_ratio:9.4g}"
        elif np.isfinite(r.damped_frequency):  # damped, but this mode's poles unresolved
            zeta, unresolved = "n/a", True
        else:  # an undamped table (modal_table(damped=False)): no damping to give
            zeta = "-"
        damped = f"{r.damped_frequency:.2f}" if np.isfinite(r.damped_frequency) else "-"
        lines.append(
            f"{r.mode:>4} {r.frequency:>8.2f} {damped:>9} {zeta:>9}  "
            f"{r.dominant_element or '-':<13} {', '.join(r.dominant_bodies)}"
        )
    if unresolved:  # an elastic mode whose poles double precision did not resolve
        lines.append(
            "zeta n/a: the mode's two poles could not both be resolved in double precision (one "
            "of them many decades faster than the chain's other poles): check the inertia and "
            "mount of its dominant bodies"
        )
    return "\n".join(lines)
