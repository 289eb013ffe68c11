"""The frame reduced to one longitudinal degree of freedom at the wheel-roller contact.

The traction pattern is the statically equivalent set of forces that a unit traction force at
the wheel-roller contact puts on the frame. Its work-conjugate displacement
``q = Σ f_i · u_i`` is the relative longitudinal displacement of wheel and roller at the
contact, so the frame's longitudinal stiffness at the contact is ``k = 1 / (fᵀ K⁻¹ f)`` and a
mode's participation at the contact is ``q_r = fᵀ φ_r`` (:func:`contact_dof`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.frame.errors import FrameFileError
from rollerrig.frame.results import FrameResult
from rollerrig.frame.structure import Frame

__all__ = [
    "ContactDof",
    "check_contact",
    "contact_dof",
    "contact_shares",
    "dominant_is_established",
]


@dataclass(frozen=True)
class ContactDof:
    """The frame reduced to one longitudinal degree of freedom at the wheel-roller contact.

    The coordinate is the relative longitudinal displacement of wheel and roller at the contact
    (work-conjugate to the traction force). For the twin: a spring ``stiffness`` in series with
    the contact; to give it the dominant mode's frequency, a mass ``equivalent_mass`` on it
    (``stiffness / (2π f)²``). ``modal_mass`` and ``modal_stiffness`` are that mode's alone,
    referred to the contact coordinate (``q_r = 1``); ``participation`` is the mode's share of
    the static flexibility (1 when the mode carries all of it).

    Attributes
    ----------
    stiffness : float
        Static longitudinal stiffness at the contact, 1 / (fᵀ K⁻¹ f) [N/m].
    mode : int
        Index (0-based) of the mode that contributes most to the contact flexibility.
    frequency : float
        Its natural frequency [Hz].
    modal_mass : float
        m_r / q_r², its modal mass referred to the contact coordinate [kg].
    modal_stiffness : float
        (2π f)² × modal_mass [N/m].
    participation : float
        (q_r² / ω_r²) / (fᵀ K⁻¹ f) [-].
    equivalent_mass : float
        stiffness / (2π f)² [kg].
    """

    stiffness: float
    mode: int
    frequency: float
    modal_mass: float
    modal_stiffness: float
    participation: float
    equivalent_mass: float

    def to_dict(self) -> dict[str, float]:
        """SI values keyed with their units, for JSON."""
        return {
            "stiffness [N/m]": self.stiffness,
            "mode": self.mode + 1,
            "frequency [Hz]": self.frequency,
            "modal_mass [kg]": self.modal_mass,
            "modal_stiffness [N/m]": self.modal_stiffness,
            "participation [-]": self.participation,
            "equivalent_mass [kg]": self.equivalent_mass,
        }


def check_contact(frame: Frame) -> None:
    """Raise :class:`~rollerrig.frame.errors.FrameFileError` when the load points put no
    force on the frame under traction: the contact coordinate of :func:`contact_dof` is then
    undefined (checked before an analysis that would end there)."""
    if not any(any(lp.traction) for lp in frame.load_points.values()):
        raise FrameFileError(
            frame.origin,
            [
                "load_points: every load point's traction is [0, 0, 0], so the frame has no "
                "stiffness at the contact; give the force a unit traction force puts on the "
                "frame (traction = [x, y, z]) at the load points"
            ],
        )


def contact_shares(
    frequencies: np.ndarray, participation: np.ndarray, flexibility: float
) -> np.ndarray:
    """Each mode's share of the contact's static flexibility, ``(q_r² / ω_r²) / (fᵀ K⁻¹ f)``.

    Over every mode of the FE model the shares sum to 1 (the modal expansion of ``K⁻¹``), so
    ``1 - sum(shares)`` bounds the share of any mode not computed.

    Parameters
    ----------
    frequencies : ndarray
        Natural frequencies [Hz].
    participation : ndarray
        Contact coordinates of the mass-normalised modes, q_r = fᵀ φ_r [m/sqrt(kg)].
    flexibility : float
        The contact's static flexibility fᵀ K⁻¹ f [m/N].

    Returns
    -------
    ndarray
        The shares [-].
    """
    omega = 2.0 * np.pi * np.asarray(frequencies, dtype=float)
    return np.asarray(participation, dtype=float) ** 2 / omega**2 / flexibility


def dominant_is_established(shares: np.ndarray) -> bool:
    """Whether the largest of the computed modes' ``shares`` (:func:`contact_shares`) is the
    largest of all: no mode left out can carry more than the flexibility they leave
    unaccounted for."""
    if not len(shares):
        return False
    unaccounted = 1.0 - float(np.sum(shares))
    # 1e-9: the shares of a complete set sum to 1 only to rounding.
    return float(np.max(shares)) >= unaccounted - 1e-9


def contact_dof(result: FrameResult) -> ContactDof:
    """The frame's longitudinal stiffness and the dominant mode's mass at the contact.

    The mode chosen is the one with the largest share ``q_r² / ω_r²`` of the contact's static
    flexibility (the first longitudinal mode seen from the contact). It is chosen only when the
    modes of ``result`` establish it: its share at least the flexibility they leave unaccounted
    for, which a mode not computed might carry (:func:`~rollerrig.frame.analyze_frame` computes
    modes until they do).

    Raises
    ------
    FrameFileError
        The frame's load points put no force on it under traction (no contact coordinate).
    ParameterError
        No mode computed moves the contact, or the modes computed do not establish which
        dominates it (a mode above them may carry more of the flexibility).

    Examples
    --------
    >>> from rollerrig.frame import analyze_frame, default_frame
    >>> dof = contact_dof(analyze_frame(default_frame(), n_modes=6))
    >>> dof.stiffness > 1e7 and 0 < dof.participation <= 1.0 + 1e-9
    True
    """
    check_contact(result.frame)
    omega = 2.0 * np.pi * result.frequencies
    share = contact_shares(
        result.frequencies, result.contact_participation, result.contact_flexibility
    )
    r = int(np.argmax(share))
    q = float(result.contact_participation[r])
    if not share[r] > 0.0:
        raise ParameterError(
            f"none of the {len(omega)} modes computed moves the contact; compute more modes "
            "(n_modes)"
        )
    if not dominant_is_established(share):
        raise ParameterError(
            f"the contact's dominant mode is not established: the {len(omega)} modes computed "
            f"carry {np.sum(share):.1%} of the contact's flexibility, the largest of them "
            f"(mode {r + 1}, {result.frequencies[r]:.2f} Hz) {share[r]:.1%}, and a mode above "
            "them may carry more; compute more modes (n_modes)"
        )
    modal_mass = 1.0 / (q * q)  # shapes are mass-normalised: m_r = 1
    k = result.longitudinal_stiffness_at_contact
    return ContactDof(
        stiffness=k,
        mode=r,
        frequency=float(result.frequencies[r]),
        modal_mass=modal_mass,
        modal_stiffness=float(omega[r] ** 2 * modal_mass),
        participation=float(share[r]),
        equivalent_mass=float(k / omega[r] ** 2),
    )
