"""The geometry of a roller-to-track transfer: the rig's wheel and roller, the rail, and the
Hertz ellipse with Kalker's coefficients on either side.

:class:`ContactGeometry` holds the rig's bodies with the stated uncertainty of their radii,
:class:`RailGeometry` the rail the curve is transferred to (tangent or curved), and
:func:`hertz_ellipse` the elastic part on one side (:mod:`rollerrig.analysis.transfer`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rollerrig._validation import ParameterError, require_positive
from rollerrig.contact.hertz import hertz_contact
from rollerrig.contact.kalker import kalker_coefficients

__all__ = ["ContactGeometry", "HertzEllipse", "RailGeometry", "hertz_ellipse", "side_summary"]


@dataclass(frozen=True)
class ContactGeometry:
    """The rig's wheel and roller, their material, and the geometry's stated uncertainty.

    Parameters
    ----------
    wheel_radius_x, wheel_radius_y : float
        Wheel rolling radius and transverse profile radius [m].
    roller_radius_x, roller_radius_y : float
        Roller rolling radius and transverse profile radius [m].
    youngs_modulus : float
        E of both bodies [Pa].
    poisson : float
        ν of both bodies [-].
    wheel_radius_tolerance, roller_radius_tolerance : float
        Half-widths of the rectangular tolerance of the rolling radii [m].
    profile_radius_uncertainty : float
        Relative standard uncertainty of every transverse profile radius [-] (normal); a
        stated assumption (worn profiles differ from the nominal).

    Examples
    --------
    >>> ContactGeometry(0.348, 0.291, 0.452, 1.89).roller_radius_x
    0.452
    """

    wheel_radius_x: float
    wheel_radius_y: float
    roller_radius_x: float
    roller_radius_y: float
    youngs_modulus: float = 210e9
    poisson: float = 0.3
    wheel_radius_tolerance: float = 0.0
    roller_radius_tolerance: float = 0.0
    profile_radius_uncertainty: float = 0.05

    def __post_init__(self) -> None:
        for name in ("wheel_radius_x", "wheel_radius_y", "roller_radius_x", "roller_radius_y"):
            require_positive(name, getattr(self, name), "m")
        require_positive("youngs_modulus", self.youngs_modulus, "Pa")
        for name in ("wheel_radius_tolerance", "roller_radius_tolerance"):
            v = float(getattr(self, name))
            if not (math.isfinite(v) and v >= 0):
                raise ParameterError(f"{name} must be finite and >= 0 [m], got {v!r}")
        u = float(self.profile_radius_uncertainty)
        if not (math.isfinite(u) and 0 <= u < 0.5):
            raise ParameterError(f"profile_radius_uncertainty must lie in [0, 0.5) [-], got {u!r}")

    @classmethod
    def from_rig(cls, rig, profile_radius_uncertainty: float = 0.05) -> ContactGeometry:
        """From a :class:`~rollerrig.rig.parameters.RigParameters` (its geometry, material and
        the rolling radii's tolerances of its ``[sensors]`` table)."""
        g, m, s = rig.geometry, rig.material, rig.sensors
        return cls(
            g.wheel_radius_x,
            g.wheel_radius_y,
            g.roller_radius_x,
            g.roller_radius_y,
            m.youngs_modulus,
            m.poisson,
            s.wheel_radius_tolerance,
            s.roller_radius_tolerance,
            profile_radius_uncertainty,
        )

    def to_dict(self) -> dict:
        """SI, units in the keys."""
        return {
            "wheel_radius_x [m]": self.wheel_radius_x,
            "wheel_radius_y [m]": self.wheel_radius_y,
            "roller_radius_x [m]": self.roller_radius_x,
            "roller_radius_y [m]": self.roller_radius_y,
            "youngs_modulus [Pa]": self.youngs_modulus,
            "poisson [-]": self.poisson,
            "wheel_radius_tolerance [m] (half-width, rectangular)": self.wheel_radius_tolerance,
            "roller_radius_tolerance [m] (half-width, rectangular)": self.roller_radius_tolerance,
            "profile_radius_uncertainty [-] (relative, standard)": (
                self.profile_radius_uncertainty
            ),
        }


@dataclass(frozen=True)
class RailGeometry:
    """The rail the curve is transferred to.

    Parameters
    ----------
    crown_radius : float, optional
        Transverse radius of the rail head [m]; default None: the roller's transverse radius
        (the same crown: the transfer then isolates the roller's curvature).
    curve_radius : float
        Radius of the track's curve [m]; ``inf`` (default) for tangent track.
    contact_angle : float
        Angle of the contact normal from the vertical [rad]. On curved track the running
        surface's normal curvature along the rail is sin(γ)/R (a surface of revolution about
        the curve's axis): zero on the crown (γ = 0), tiny on the gauge corner.
    crown_radius_uncertainty : float, optional
        Relative standard uncertainty of ``crown_radius`` [-]; default the geometry's
        ``profile_radius_uncertainty``.

    Notes
    -----
    Curved track is taken only through that normal curvature (treated as convex; the gauge
    corner of the high rail is concave by the same amount, of order r_w·sin γ/R against the
    wheel's curvature, i.e. below 0.2 % for R > 100 m). The lateral creepage and spin of
    curving are not part of a longitudinal creep curve and are not modelled.

    Examples
    --------
    >>> RailGeometry().longitudinal_radius
    inf
    >>> round(RailGeometry(0.3, 200.0, 0.5).longitudinal_radius, 1)
    417.2
    """

    crown_radius: float | None = None
    curve_radius: float = math.inf
    contact_angle: float = 0.0
    crown_radius_uncertainty: float | None = None

    def __post_init__(self) -> None:
        if self.crown_radius is not None:
            require_positive("crown_radius", self.crown_radius, "m")
        r = float(self.curve_radius)
        if math.isnan(r) or r <= 0:
            raise ParameterError(f"curve_radius must be > 0 [m] (inf: tangent), got {r!r}")
        g = float(self.contact_angle)
        if not (math.isfinite(g) and abs(g) < math.pi / 2):
            raise ParameterError(f"contact_angle must lie in (-pi/2, pi/2) [rad], got {g!r}")
        u = self.crown_radius_uncertainty
        if u is not None and not (math.isfinite(u) and 0 <= u < 0.5):
            raise ParameterError(f"crown_radius_uncertainty must lie in [0, 0.5) [-], got {u!r}")

    @property
    def longitudinal_radius(self) -> float:
        """Radius of the running surface along the rail in the contact's normal plane [m]."""
        s = abs(math.sin(self.contact_angle))
        if math.isinf(self.curve_radius) or s == 0.0:
            return math.inf
        return self.curve_radius / s

    def describe(self, roller_radius_y: float) -> str:
        """One line: tangent or curved, and the crown."""
        crown = (
            f"crown radius {roller_radius_y * 1e3:.0f} mm (the roller's: same crown)"
            if self.crown_radius is None
            else f"crown radius {self.crown_radius * 1e3:.0f} mm"
        )
        if math.isinf(self.longitudinal_radius):
            kind = (
                "tangent rail"
                if math.isinf(self.curve_radius)
                else (f"curve R = {self.curve_radius:g} m on the crown (no longitudinal curvature)")
            )
        else:
            kind = (
                f"curve R = {self.curve_radius:g} m, contact angle "
                f"{math.degrees(self.contact_angle):.1f} deg (rail radius along the rolling "
                f"direction {self.longitudinal_radius:.4g} m)"
            )
        return f"{kind}, {crown}"


@dataclass(frozen=True)
class HertzEllipse:
    """A Hertz ellipse and Kalker's coefficients at its a/b: semi-axes a, b [m], C11, C22,
    C23 [-], area [m²], peak pressure p0 [Pa]."""

    a: float
    b: float
    c11: float
    c22: float
    c23: float
    area: float
    p0: float

    @property
    def a_over_b(self) -> float:
        return self.a / self.b


def hertz_ellipse(load, rx_wheel, ry_wheel, rx_other, ry_other, e, nu_combined, nu):
    """The Hertz ellipse of the wheel on the other body at ``load`` [N] (radii [m], E [Pa],
    ν and the combined ν [-]), with Kalker's coefficients at its a/b."""
    c = hertz_contact(load, rx_wheel, ry_wheel, rx_other, ry_other, youngs_modulus=e, poisson=nu)
    a, b = float(c.semi_axis_x), float(c.semi_axis_y)
    k = kalker_coefficients(a / b, nu_combined)
    return HertzEllipse(
        a, b, float(k.c11), float(k.c22), float(k.c23), float(c.area), float(c.peak_pressure)
    )


def side_summary(ell: HertzEllipse, g: float) -> dict:
    """JSON-ready: the elastic part on one side (semi-axes, a/b, C_ij, creep stiffness with
    shear modulus ``g`` [Pa]); units in the keys."""
    return {
        "semi_axis_x [m]": ell.a,
        "semi_axis_y [m]": ell.b,
        "a_over_b [-]": ell.a_over_b,
        "area [m^2]": ell.area,
        "peak_pressure [Pa]": ell.p0,
        "C11 [-]": ell.c11,
        "C22 [-]": ell.c22,
        "C23 [-]": ell.c23,
        "creep_stiffness G a b C11 [N]": g * ell.a * ell.b * ell.c11,
    }
