"""What a creep law of the simplified theory returns: total forces and traction fields.

:func:`rollerrig.contact.fastsim.fastsim` and :func:`rollerrig.contact.strip.fastrip` return a
:class:`TangentialResult`, with the surface tractions (:class:`TractionField`) when asked for.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rollerrig.contact.flexibilities import Flexibilities

__all__ = ["TangentialResult", "TractionField"]


@dataclass(frozen=True)
class TractionField:
    """Surface tractions of each case on the grid (for plots of adhesion and slip zones).

    Attributes
    ----------
    x, y : ndarray, shape (ny, nx)
        Element centres [m] (x along rolling, leading edge at +x).
    px, py : ndarray, shape (n_cases, ny, nx)
        Tangential tractions [Pa], with the package's sign (that of the creepage).
    bound : ndarray, shape (n_cases, ny, nx)
        Traction bound μ p_n [Pa].
    state : ndarray of int8, shape (n_cases, ny, nx)
        0 outside the contact, 1 adhesion, 2 slip.
    """

    x: np.ndarray
    y: np.ndarray
    px: np.ndarray
    py: np.ndarray
    bound: np.ndarray
    state: np.ndarray

    @property
    def slip_fraction(self) -> np.ndarray:
        """Fraction of the contact's elements in slip, per case [-]."""
        inside = self.state > 0
        return (self.state == 2).sum(axis=(1, 2)) / np.maximum(inside.sum(axis=(1, 2)), 1)


@dataclass(frozen=True)
class TangentialResult:
    """Total tangential forces of a creep law for one or more cases.

    Attributes
    ----------
    fx, fy : ndarray, shape (n_cases,)
        Creep forces [N] (sign of the creepage).
    mz : ndarray, shape (n_cases,)
        Spin moment ∫(x p_y - y p_x) dA [N m].
    friction : ndarray, shape (n_cases,)
        μ used in each case [-].
    k_eff : ndarray, shape (n_cases,)
        Slope reduction factor k (1 for Kalker's FASTSIM) [-].
    flexibilities : Flexibilities
        L1, L2, L3 [m³/N] used (before division by k).
    tractions : TractionField or None
        Only when asked for.
    """

    fx: np.ndarray
    fy: np.ndarray
    mz: np.ndarray
    friction: np.ndarray
    k_eff: np.ndarray
    flexibilities: Flexibilities
    tractions: TractionField | None = None
