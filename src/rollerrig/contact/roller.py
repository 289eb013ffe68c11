"""Roller versus tangent rail: how the roller's longitudinal curvature changes the Hertz contact.

On a roller rig the rail is a roller of finite radius R_rx in the rolling plane, where a tangent
rail is flat (R_rx = ∞). The extra curvature raises A = ½(1/R_wx + 1/R_rx), shortens the contact
ellipse in the rolling direction and shrinks the contact area. This module is a thin vectorised
layer over :func:`rollerrig.contact.hertz.hertz_contact` for the study of the seed's section 2.5
(Kayaalp, §2.5, Fig. 12-13): wheel 350 mm, lateral radii 300 mm (wheel) and 400 mm (roller),
20 kN, E = 210 GPa, ν = 0.3, roller radius swept from 350 mm to infinity.

References
----------
.. [1] Kayaalp, "Accuracy improvement of measurements by analyzing dynamic response of a tram
   wheel roller-rig", dissertation, Univ. Pardubice, §2.5.
.. [2] K. L. Johnson, *Contact Mechanics*, Cambridge University Press (1985), §4.2.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rollerrig.contact.hertz import hertz_contact

__all__ = [
    "RollerRailComparison",
    "area_ratio_to_tangent_rail",
    "contact_versus_roller_radius",
]


@dataclass(frozen=True)
class RollerRailComparison:
    """Contact on rollers of several radii and on the tangent rail (R_rx = ∞) for reference.

    Attributes
    ----------
    roller_radius_x : ndarray
        Roller radii R_rx in the rolling plane [m] (``np.inf`` is the tangent rail).
    semi_axis_x, semi_axis_y : ndarray
        Semi-axes a (rolling direction) and b (lateral) on each roller [m].
    area : ndarray
        Contact area π a b on each roller [m²].
    tangent_semi_axis_x, tangent_semi_axis_y : float
        Semi-axes on the tangent rail [m].
    tangent_area : float
        Contact area on the tangent rail [m²].
    """

    roller_radius_x: np.ndarray
    semi_axis_x: np.ndarray
    semi_axis_y: np.ndarray
    area: np.ndarray
    tangent_semi_axis_x: float
    tangent_semi_axis_y: float
    tangent_area: float

    @property
    def area_ratio(self) -> np.ndarray:
        """Area on the roller divided by the area on the tangent rail [-] (≤ 1)."""
        return self.area / self.tangent_area

    @property
    def relative_area_difference(self) -> np.ndarray:
        """(tangent area - roller area) / tangent area [-], the seed's "difference" (§2.5)."""
        return 1.0 - self.area / self.tangent_area


def contact_versus_roller_radius(
    roller_radii_x,
    normal_load=20e3,
    wheel_radius_x=0.35,
    wheel_radius_y=0.30,
    roller_radius_y=0.40,
    youngs_modulus=210e9,
    poisson=0.3,
) -> RollerRailComparison:
    """Hertz contact on rollers of radii ``roller_radii_x`` and on the tangent rail.

    Each case is :func:`~rollerrig.contact.hertz.hertz_contact` with
    A = ½(1/R_wx + 1/R_rx), B = ½(1/R_wy + 1/R_ry); the tangent rail has R_rx = ∞. Both bodies
    share E and ν. Defaults are the seed's section 2.5 study (Kayaalp, §2.5).

    Parameters
    ----------
    roller_radii_x : array_like
        Roller radii in the rolling plane R_rx [m], > 0 (``np.inf`` allowed).
    normal_load : float, optional
        Normal load Q [N], > 0. Default 20e3 (Kayaalp, §2.5).
    wheel_radius_x : float, optional
        Wheel rolling radius R_wx [m]. Default 0.35.
    wheel_radius_y : float, optional
        Wheel transverse profile radius R_wy [m]. Default 0.30.
    roller_radius_y : float, optional
        Roller (rail head) transverse profile radius R_ry [m]. Default 0.40.
    youngs_modulus : float, optional
        Young's modulus of both bodies [Pa]. Default 210e9.
    poisson : float, optional
        Poisson ratio of both bodies [-], in [0, 0.5]. Default 0.3.

    Returns
    -------
    RollerRailComparison
        Semi-axes and area per roller radius, with the tangent-rail reference.

    Raises
    ------
    ParameterError
        As :func:`~rollerrig.contact.hertz.hertz_contact`, naming the offending parameter.

    Examples
    --------
    The seed's §2.5 numbers: tangent rail 31.12 mm², roller of 10 m 30.81 mm² (exact Hertz).

    >>> c = contact_versus_roller_radius([0.35, 10.0])
    >>> round(float(c.tangent_area) * 1e6, 2), round(float(c.area[1]) * 1e6, 2)
    (31.12, 30.81)
    """
    radii = np.asarray(roller_radii_x, dtype=float)
    # One call for the rollers and the tangent rail (the last entry, R_rx = ∞).
    both = hertz_contact(
        normal_load,
        wheel_radius_x,
        wheel_radius_y,
        np.append(radii, np.inf),
        roller_radius_y,
        youngs_modulus=youngs_modulus,
        poisson=poisson,
    )
    a, b, area = (np.asarray(v) for v in (both.semi_axis_x, both.semi_axis_y, both.area))
    return RollerRailComparison(
        roller_radius_x=radii,
        semi_axis_x=a[:-1].reshape(radii.shape),
        semi_axis_y=b[:-1].reshape(radii.shape),
        area=area[:-1].reshape(radii.shape),
        tangent_semi_axis_x=float(a[-1]),
        tangent_semi_axis_y=float(b[-1]),
        tangent_area=float(area[-1]),
    )


def area_ratio_to_tangent_rail(roller_radii_x, **geometry):
    """Contact area on a roller of radius R_rx divided by the area on the tangent rail [-].

    The ratio lies in (0, 1] and tends to 1 as R_rx → ∞ (Kayaalp, §2.5, Fig. 13).

    Parameters
    ----------
    roller_radii_x : array_like
        Roller radii in the rolling plane R_rx [m], > 0 (``np.inf`` allowed).
    **geometry
        ``normal_load`` [N], ``wheel_radius_x``, ``wheel_radius_y``, ``roller_radius_y`` [m],
        ``youngs_modulus`` [Pa], ``poisson`` [-]: as in :func:`contact_versus_roller_radius`
        (the same defaults, the seed's §2.5 study).

    Returns
    -------
    float or ndarray
        A_roller / A_tangent [-], shaped like ``roller_radii_x``.

    Examples
    --------
    >>> round(float(area_ratio_to_tangent_rail(10.0)), 4)
    0.9899
    """
    ratio = contact_versus_roller_radius(roller_radii_x, **geometry).area_ratio
    return ratio[()] if ratio.ndim == 0 else ratio
