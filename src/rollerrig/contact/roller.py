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

from rollerrig._validation import ParameterError, require_broadcastable, require_number
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
        Roller radii R_rx in the rolling plane [m] (``np.inf`` is the tangent rail), one per
        case: the roller radii broadcast against the geometry's arrays.
    semi_axis_x, semi_axis_y : ndarray
        Semi-axes a (rolling direction) and b (lateral) on each roller [m], shaped like
        ``roller_radius_x``.
    area : ndarray
        Contact area π a b on each roller [m²], shaped like ``roller_radius_x``.
    tangent_semi_axis_x, tangent_semi_axis_y : float or ndarray
        Semi-axes on the tangent rail [m]: a float where the geometry (load, wheel, roller
        profile, material) is one, else one per case, shaped like ``roller_radius_x``.
    tangent_area : float or ndarray
        Contact area on the tangent rail [m²], as the tangent semi-axes.
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
    normal_load : array_like, optional
        Normal load Q [N], > 0. Default 20e3 (Kayaalp, §2.5).
    wheel_radius_x : array_like, optional
        Wheel rolling radius R_wx [m]. Default 0.35.
    wheel_radius_y : array_like, optional
        Wheel transverse profile radius R_wy [m]. Default 0.30.
    roller_radius_y : array_like, optional
        Roller (rail head) transverse profile radius R_ry [m]. Default 0.40.
    youngs_modulus : array_like, optional
        Young's modulus of both bodies [Pa]. Default 210e9.
    poisson : array_like, optional
        Poisson ratio of both bodies [-], in [0, 0.5]. Default 0.3.

    All arguments broadcast together; the cases are their broadcast shape.

    Returns
    -------
    RollerRailComparison
        Semi-axes and area per case, with the tangent-rail reference (one per case where the
        geometry is given as arrays).

    Raises
    ------
    ParameterError
        If a roller radius is not > 0 (NaN, 0, negative: a concave roller is no roller rig),
        if arguments have shapes that do not broadcast together (naming them and their shapes),
        and as :func:`~rollerrig.contact.hertz.hertz_contact`, naming the offending parameter.

    Examples
    --------
    The seed's §2.5 numbers: tangent rail 31.12 mm², roller of 10 m 30.81 mm² (exact Hertz).

    >>> c = contact_versus_roller_radius([0.35, 10.0])
    >>> round(float(c.tangent_area) * 1e6, 2), round(float(c.area[1]) * 1e6, 2)
    (31.12, 30.81)

    Two loads, one roller each: a tangent-rail reference per load.

    >>> c = contact_versus_roller_radius([0.35, 10.0], normal_load=[1e4, 2e4])
    >>> c.area.shape, c.tangent_area.shape
    ((2,), (2,))
    """
    radii = _require_roller_radii(roller_radii_x)
    geometry = dict(
        normal_load=normal_load,
        wheel_radius_x=wheel_radius_x,
        wheel_radius_y=wheel_radius_y,
        roller_radius_y=roller_radius_y,
        youngs_modulus=youngs_modulus,
        poisson=poisson,
    )
    # The shapes first, under the caller's names (the tangent rail's R_rx = ∞ had been appended
    # to the radii, and an error named an array one longer than the caller's); the values are
    # hertz_contact's to check.
    cases = np.broadcast_shapes(
        *(a.shape for a in require_broadcastable(roller_radii_x=radii, **geometry))
    )
    g = geometry
    kw = dict(youngs_modulus=g["youngs_modulus"], poisson=g["poisson"])
    fixed = (g["normal_load"], g["wheel_radius_x"], g["wheel_radius_y"])
    roller = hertz_contact(*fixed, radii, g["roller_radius_y"], **kw)
    tangent = hertz_contact(*fixed, np.inf, g["roller_radius_y"], **kw)

    def per_case(v):
        return np.broadcast_to(np.asarray(v, dtype=float), cases).copy()

    def reference(v):
        v = np.asarray(v, dtype=float)
        return float(v) if v.ndim == 0 else per_case(v)

    return RollerRailComparison(
        roller_radius_x=per_case(radii),
        semi_axis_x=per_case(roller.semi_axis_x),
        semi_axis_y=per_case(roller.semi_axis_y),
        area=per_case(roller.area),
        tangent_semi_axis_x=reference(tangent.semi_axis_x),
        tangent_semi_axis_y=reference(tangent.semi_axis_y),
        tangent_area=reference(tangent.area),
    )


def _require_roller_radii(value) -> np.ndarray:
    """Roller radii [m] as a float array: each > 0, ``np.inf`` allowed (the tangent rail).

    :func:`~rollerrig.contact.hertz.hertz_contact` takes a negative radius as a concave body
    (a wheel inside a drum), so a radius of -1 m had given an area ratio of 1.130, outside the
    (0, 1] these functions promise.
    """
    radii = require_number("roller_radii_x", value, "m")
    bad = ~(radii > 0.0)  # NaN too
    if np.any(bad):
        got = f"{float(radii):g}" if radii.ndim == 0 else np.array2string(radii[bad][:6])
        raise ParameterError(
            f"roller_radii_x must be > 0 [m] (np.inf for the tangent rail), got {got}"
        )
    return radii


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
        A_roller / A_tangent [-], shaped like the cases (``roller_radii_x`` broadcast against
        the geometry's arrays).

    Raises
    ------
    ParameterError
        As :func:`contact_versus_roller_radius` (a roller radius not > 0 among them).

    Examples
    --------
    >>> round(float(area_ratio_to_tangent_rail(10.0)), 4)
    0.9899
    """
    ratio = contact_versus_roller_radius(roller_radii_x, **geometry).area_ratio
    return ratio[()] if ratio.ndim == 0 else ratio
