"""The frame's modes: its zero-energy modes (a mechanism) and its natural modes.

Both are eigenproblems of PyNite's matrices of the free DOFs, solved sparse (shift-invert
Lanczos, ARPACK) and, below ``_DENSE_BELOW`` rows, dense (LAPACK). A mechanism (too few
supports, or a part that can move without straining any member) is found by
:func:`check_stability` and named as a :class:`~rollerrig.frame.errors.FrameFileError`, with
the node and the DOF that move most in it: PyNite itself only looks at zero diagonal terms and
prints them. The natural frequencies and mass-normalised mode shapes come from the stiffness
and consistent mass matrices, with the rotary inertia of each section about its member's axis
corrected (``_modes``).
"""

from __future__ import annotations

import numpy as np

from rollerrig.frame.errors import FrameFileError
from rollerrig.frame.femodel import _Mesh, build_model
from rollerrig.frame.structure import DOF_NAMES, Frame

__all__ = ["check_stability"]

_DOF_WORDS = {
    "x": "move in x",
    "y": "move in y",
    "z": "move in z",
    "rx": "rotate about x",
    "ry": "rotate about y",
    "rz": "rotate about z",
}


def check_stability(mesh: _Mesh, *, tolerance: float = 1e-9) -> None:
    """Raise :class:`~rollerrig.frame.errors.FrameFileError` when the supported frame is a
    mechanism.

    The stiffness matrix of the free DOFs is scaled to a unit diagonal; an eigenvalue below
    ``tolerance`` is a zero-energy mode (a mechanism: too few supports, or a part that can move
    without straining any member). The error names the node and the DOF that move most in it.
    The smallest eigenvalue is found sparse (shift-invert Lanczos about a small negative shift,
    where the scaled matrix minus the shift is positive definite), so that the check costs about
    what a static solution does; a tiny matrix is solved dense.
    """
    from Pynite import Analysis

    model, frame = mesh.model, mesh.frame
    if not model.load_combos:
        model.add_load_combo("stiffness", {"stiffness": 1.0})
    Analysis._prepare_model(model)
    combo = next(iter(model.load_combos))
    k = model.Ke(combo, check_stability=False, sparse=True).tocsr()
    free = np.asarray(_free_dofs(model), dtype=int)
    if not free.size:
        return
    kff = k[free][:, free]
    diag = kff.diagonal().copy()
    zero = np.flatnonzero(diag <= 1e-12 * max(float(diag.max()), 1.0))
    if zero.size:
        _mechanism(frame, model, int(free[zero[0]]), "with no stiffness at all")
    scale = scipy_sparse().diags(1.0 / np.sqrt(diag))
    s = (scale @ kff @ scale).tocsc()
    value, vector = _lowest_mode(s, tolerance)
    if value < tolerance:
        _mechanism(
            frame,
            model,
            int(free[int(np.argmax(np.abs(vector)))]),
            "without straining any member (a zero-energy mode)",
        )


def scipy_sparse():
    """:mod:`scipy.sparse` (imported when first needed)."""
    import scipy.sparse

    return scipy.sparse


_DENSE_BELOW = 200
"""Matrices with fewer rows than this are solved dense (ARPACK needs k < n and gains nothing)."""


def _lowest_mode(s, tolerance: float) -> tuple[float, np.ndarray]:
    """The smallest eigenvalue of a symmetric positive semi-definite sparse matrix with a unit
    diagonal, and its eigenvector; the shift ``-tolerance`` makes a zero-energy mode stand out
    (inverted, it is a billion times any mode above 1)."""
    if s.shape[0] < _DENSE_BELOW:
        values, vectors = np.linalg.eigh(s.toarray())
        return float(values[0]), vectors[:, 0]
    from scipy.sparse.linalg import eigsh

    # The eigenvalues lie in [0, n]; about a small negative shift the nearest is the smallest.
    values, vectors = eigsh(s, k=1, sigma=-tolerance, which="LM")
    return float(values[0]), vectors[:, 0]


def _free_dofs(model) -> list[int]:
    """Global indices of the DOFs no support holds (PyNite's numbering: node ID * 6 + DOF)."""
    free = []
    for node in model.nodes.values():
        held = (
            node.support_DX,
            node.support_DY,
            node.support_DZ,
            node.support_RX,
            node.support_RY,
            node.support_RZ,
        )
        free += [node.ID * 6 + d for d in range(6) if not held[d]]
    return free


def _frame_node(name: str) -> str:
    """The frame's name of a FE node: an element's inner node is named after its member."""
    return name.split("~")[0]


def _mechanism(frame: Frame, model, index: int, why: str) -> None:
    node = next(n for n in model.nodes.values() if n.ID == index // 6)
    dof = DOF_NAMES[index % 6]
    where = (
        f"node {node.name!r}"
        if "~" not in node.name
        else f"member {_frame_node(node.name)!r} (between its ends)"
    )
    raise FrameFileError(
        frame.origin,
        [
            f"supports: the frame is a mechanism: {where} can {_DOF_WORDS[dof]} ({dof}) {why}; "
            "add supports (e.g. fix the column feet) or members that hold it"
        ],
    )


def _modes(frame: Frame, elements_per_member: int, n_modes: int):
    """(frequencies [Hz], mass-normalised shapes (n_modes, n_nodes, 6), model mass [kg]).

    Stiffness and consistent mass matrices are PyNite's (members' own mass through a
    self-weight case with gravity 1, lumped masses as nodal loads), with one correction: PyNite
    takes the torsion constant J for the rotary inertia of a section about the member's axis,
    where the polar moment I_p = I_y + I_z belongs (HEB 200: J = 59 cm^4, I_p = 7699 cm^4); the
    missing ``ρ L (I_p - J) / 6 [[2, 1], [1, 2]]`` is added on each element's twist DOFs. The
    generalised eigenproblem of the free DOFs is solved sparse (shift-invert Lanczos,
    ``scipy.sparse.linalg.eigsh``, about a shift of -1 (rad/s)^2, below every frequency, so that
    the nearest eigenvalues are the lowest); a small one dense (``scipy.linalg.eigh``).
    """
    import scipy.linalg
    from Pynite import Analysis
    from scipy.sparse.linalg import eigsh

    sparse = scipy_sparse()
    mesh = build_model(frame, elements_per_member=elements_per_member, masses=True)
    model = mesh.model
    Analysis._prepare_model(model)
    k = model.Ke("mass", check_stability=False, sparse=True).tocsr()
    m = model.M("mass", "Z", 1.0, sparse=True).tocoo()
    rows, cols, data = [m.row], [m.col], [m.data]
    block = np.arange(3)
    for member, elements in mesh.elements.items():
        mb = frame.members[member]
        s, rho = frame.sections[mb.section], frame.materials[mb.material].density
        for el, s0, s1 in elements:
            e = model.members[el]
            extra = rho * (s1 - s0) * (s.polar_moment - s.torsion_constant) / 6.0
            axis = e.T()[0, :3]
            i, j = e.i_node.ID * 6 + 3, e.j_node.ID * 6 + 3
            for a, b, w in ((i, i, 2.0), (j, j, 2.0), (i, j, 1.0), (j, i, 1.0)):
                rows.append(np.repeat(a + block, 3))
                cols.append(np.tile(b + block, 3))
                data.append((w * extra * np.outer(axis, axis)).ravel())
    m = sparse.coo_matrix(
        (np.concatenate(data), (np.concatenate(rows), np.concatenate(cols))), shape=m.shape
    ).tocsr()
    order = np.concatenate([np.arange(6) + model.nodes[n].ID * 6 for n in mesh.nodes])
    held = np.concatenate(
        [np.asarray(frame.supports.get(n, (False,) * 6), dtype=bool) for n in mesh.nodes]
    )
    free = order[~held]
    n = max(1, min(int(n_modes), free.size))
    kff, mff = k[free][:, free], m[free][:, free]
    if free.size < _DENSE_BELOW or n >= free.size - 1:
        values, vectors = scipy.linalg.eigh(
            kff.toarray(), mff.toarray(), subset_by_index=[0, n - 1]
        )
    else:
        values, vectors = eigsh(kff.tocsc(), k=n, M=mff.tocsc(), sigma=-1.0, which="LM")
        ranked = np.argsort(values)
        values, vectors = values[ranked], vectors[:, ranked]
        vectors = vectors / np.sqrt(np.einsum("ij,ij->j", vectors, mff @ vectors))
    shapes = []
    for v in vectors.T:
        phi = np.zeros(order.size)
        phi[~held] = v  # normalised: vᵀ M v = 1 [kg]
        big = int(np.argmax(np.abs(phi)))
        shapes.append(np.sign(phi[big]) * phi.reshape(-1, 6))  # largest component positive
    total = frame.total_mass()
    frequencies = np.sqrt(np.clip(values, 0.0, None)) / (2.0 * np.pi)
    return frequencies, np.asarray(shapes), float(total)
