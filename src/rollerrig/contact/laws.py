"""Creep laws by name, and friction parameter sets with their sources, loadable by name.

Laws (:data:`CREEP_LAWS`):

- ``"polach"``: Polach (2005), closed form (:func:`rollerrig.contact.polach_creep_force`);
- ``"fastsim"``: Kalker's FASTSIM (1982) (:func:`rollerrig.contact.fastsim.fastsim`);
- ``"modified-fastsim"``: FASTSIM with falling initial slope, k0, α_inf, β (Spiryagin, Polach &
  Cole 2013; as in CONTACT);
- ``"fastrip"``: FaStrip (Sichani, Enblom & Berg 2016) (:func:`rollerrig.contact.strip.fastrip`).

Every law takes the friction coefficient of Polach's exponential form (Polach 2005, eq. 8),
μ = μ0 [(1 - A) e^(-B|w|) + A], evaluated with the slip velocity w the caller gives, as
:func:`rollerrig.contact.polach_creep_force` does (for a creep curve at rolling speed v,
w = v·√(ξ² + η²): CONTACT's ``fastsim_params`` takes the same rigid slip for the modified
FASTSIM). One μ per case: the FASTSIM family here does not vary μ over the contact.

Parameter sets (:data:`FRICTION_PARAMETER_SETS`, :func:`parameter_set`) carry their source.

References
----------
.. [1] O. Polach, Wear 258 (2005) 992-1000.
.. [2] M. Spiryagin, O. Polach, C. Cole, Vehicle System Dynamics 51 (2013) 1765-1783.
.. [3] E.A.H. Vollebregt, *User guide for CONTACT*, section "Calculation of creep force
   curves" and example ``tractcurv.inp`` (Eurosprinter 127 001 measured by B. Engel, H.P.
   Beck, J. Alders, Elektrische Bahnen 96 (1998) 201-209).
"""

from __future__ import annotations

import difflib
from dataclasses import asdict, dataclass

import numpy as np

from rollerrig._validation import (
    ParameterError,
    require_broadcastable,
    require_finite,
    require_in_range,
    require_nonnegative,
    require_positive,
)
from rollerrig.contact.creep import (
    POLACH_DRY,
    POLACH_WET,
    PolachParameters,
    _friction_kernel,
    _polach_force_kernel,
)
from rollerrig.contact.curves import CreepCurve, _require_creep_values
from rollerrig.contact.fastsim import (
    FastsimGrid,
    Flexibilities,
    TangentialResult,
    fastsim,
)
from rollerrig.contact.hertz import combined_elastic_constants, hertz_contact
from rollerrig.contact.kalker import kalker_coefficients
from rollerrig.contact.strip import fastrip

__all__ = [
    "CREEP_LAWS",
    "EUROSPRINTER_COULOMB",
    "EUROSPRINTER_MODIFIED_FASTSIM",
    "FRICTION_PARAMETER_SETS",
    "FastsimParameters",
    "check_law",
    "creep_force",
    "default_parameter_sets",
    "law_creep_curve",
    "parameter_set",
]

CREEP_LAWS: tuple[str, ...] = ("polach", "fastsim", "modified-fastsim", "fastrip")
"""Names of the creep laws, as the ``--law`` option takes them."""


@dataclass(frozen=True)
class FastsimParameters:
    """Friction and slope-reduction parameters of the FASTSIM family.

    Parameters
    ----------
    static_friction : float
        μ0, friction coefficient at zero slip velocity [-].
    limit_ratio : float
        A = μ∞/μ0 [-], in (0, 1] (1: Coulomb friction).
    friction_decay : float
        B [s/m], >= 0.
    k0 : float
        Initial slope reduction k0 [-], 0 < k0 <= 1 (1: Kalker's FASTSIM).
    alpha_inf : float
        α_∞ = k_∞/k0 [-], in [0, 1] (1: no change with creepage).
    beta : float
        β [-], >= 0.
    name, source : str
        Label and bibliographic source.

    Examples
    --------
    >>> FastsimParameters(0.36, 0.38, 0.7, 0.54, 0.02, 0.62).k0
    0.54
    """

    static_friction: float
    limit_ratio: float
    friction_decay: float
    k0: float = 1.0
    alpha_inf: float = 1.0
    beta: float = 0.0
    name: str = "custom"
    source: str = ""

    def __post_init__(self) -> None:
        require_positive("static_friction (mu0)", self.static_friction, "-")
        require_in_range("limit_ratio (A)", self.limit_ratio, 0.0, 1.0, "-", high_inclusive=True)
        require_nonnegative("friction_decay (B)", self.friction_decay, "s/m")
        require_in_range("k0", self.k0, 0.0, 1.0, "-", high_inclusive=True)
        require_in_range(
            "alpha_inf", self.alpha_inf, 0.0, 1.0, "-", low_inclusive=True, high_inclusive=True
        )
        require_nonnegative("beta", self.beta, "-")

    def to_dict(self) -> dict:
        """Plain dictionary, for provenance records."""
        return asdict(self)


EUROSPRINTER_COULOMB = FastsimParameters(
    static_friction=0.33,
    limit_ratio=1.0,
    friction_decay=0.0,
    name="eurosprinter-coulomb",
    source=(
        "CONTACT user guide, 'Calculation of creep force curves', example tractcurv.inp, "
        "series 1 (exact theory) and 3 (original FASTSIM): Coulomb friction mu = 0.33, "
        "Eurosprinter 127 001 (Engel, Beck & Alders 1998), 106.7 kN/wheel, V = 10 m/s"
    ),
)
"""Kalker's theories with Coulomb friction μ = 0.33, CONTACT's first Eurosprinter curve."""

EUROSPRINTER_MODIFIED_FASTSIM = FastsimParameters(
    static_friction=0.36,
    limit_ratio=0.38,
    friction_decay=0.7,
    k0=0.54,
    alpha_inf=0.02,
    beta=0.62,
    name="eurosprinter-modified-fastsim",
    source=(
        "Spiryagin, Polach & Cole (2013), VSD 51, as run in CONTACT's tractcurv.inp series 4 "
        "(k0 = 0.54, alpha_inf = 0.02, beta = 0.62; the user guide's text prints beta = 0.64); "
        "friction mu0 = 0.36, A = 0.38, B = 0.7 s/m (guide: FKIN 0.1368, FEXP1 0.2232, "
        "SABSH1 990 mm/s); fitted to the Eurosprinter 127 001 measurements of Engel, Beck & "
        "Alders (1998), 106.7 kN/wheel, V = 10 m/s"
    ),
)
"""Modified FASTSIM set of the Eurosprinter curve (Spiryagin et al. 2013, via CONTACT)."""

FRICTION_PARAMETER_SETS: dict[str, PolachParameters | FastsimParameters] = {
    "polach-dry": POLACH_DRY,
    "polach-wet": POLACH_WET,
    EUROSPRINTER_COULOMB.name: EUROSPRINTER_COULOMB,
    EUROSPRINTER_MODIFIED_FASTSIM.name: EUROSPRINTER_MODIFIED_FASTSIM,
}
"""Every named friction parameter set, by name (the Polach sets are the package's own)."""


def _did_you_mean(kind: str, name: str, known) -> ParameterError:
    close = difflib.get_close_matches(name, list(known), n=1, cutoff=0.5)
    hint = f"; did you mean {close[0]!r}?" if close else ""
    return ParameterError(f"unknown {kind} {name!r}{hint} (known: {', '.join(known)})")


def parameter_set(name: str) -> PolachParameters | FastsimParameters:
    """A friction parameter set by name.

    Parameters
    ----------
    name : str
        One of :data:`FRICTION_PARAMETER_SETS`.

    Returns
    -------
    PolachParameters or FastsimParameters

    Raises
    ------
    ParameterError
        For an unknown name, with the closest known name and the list of names.

    Examples
    --------
    >>> parameter_set("eurosprinter-modified-fastsim").beta
    0.62
    """
    if not isinstance(name, str):  # None had been a bare TypeError, a list an unhashable one
        raise ParameterError(
            f"name must be the name of a friction parameter set (a str), got {name!r} (known: "
            f"{', '.join(FRICTION_PARAMETER_SETS)})"
        )
    try:
        return FRICTION_PARAMETER_SETS[name]
    except KeyError:
        raise _did_you_mean("friction parameter set", name, FRICTION_PARAMETER_SETS) from None


def check_law(law: str) -> str:
    """Return ``law`` if it names a creep law, else raise with a did-you-mean.

    Examples
    --------
    >>> check_law("fastsim")
    'fastsim'
    """
    if not isinstance(law, str):
        raise ParameterError(
            f"law must be the name of a creep law (a str), got {law!r} (known: "
            f"{', '.join(CREEP_LAWS)})"
        )
    if law not in CREEP_LAWS:
        raise _did_you_mean("creep law", law, CREEP_LAWS)
    return law


def default_parameter_sets(law: str) -> dict[str, PolachParameters | FastsimParameters]:
    """The sets a law is shown with by default: Polach's dry/wet, or the Eurosprinter set.

    ``fastsim`` and ``fastrip`` take μ0, A, B of Polach's dry and wet sets (k_A, k_S are
    Polach's own and are not used); ``modified-fastsim`` needs k0, α_∞, β and takes
    :data:`EUROSPRINTER_MODIFIED_FASTSIM`.

    Examples
    --------
    >>> list(default_parameter_sets("modified-fastsim"))
    ['eurosprinter-modified-fastsim']
    """
    check_law(law)
    if law == "modified-fastsim":
        return {EUROSPRINTER_MODIFIED_FASTSIM.name: EUROSPRINTER_MODIFIED_FASTSIM}
    return {"dry": POLACH_DRY, "wet": POLACH_WET}


def _check_pair(law, parameters):
    if law == "polach" and not isinstance(parameters, PolachParameters):
        raise ParameterError(
            f"law 'polach' needs Polach's k_A, k_S: set {parameters.name!r} has none "
            "(use 'polach-dry' or 'polach-wet')"
        )
    if law == "modified-fastsim" and not isinstance(parameters, FastsimParameters):
        raise ParameterError(
            f"law 'modified-fastsim' needs k0, alpha_inf, beta: set {parameters.name!r} has "
            "none (use 'eurosprinter-modified-fastsim' or a FastsimParameters)"
        )


def creep_force(
    law: str,
    long_creep,
    slip_velocity,
    normal_load,
    semi_axis_x,
    semi_axis_y,
    shear_modulus,
    poisson,
    parameters: PolachParameters | FastsimParameters = POLACH_DRY,
    *,
    lat_creep=0.0,
    spin=0.0,
    grid: FastsimGrid | None = None,
    tractions: bool = False,
) -> TangentialResult:
    """Creep forces by the named law, with μ(w) of Polach's exponential form.

    .. math:: \\mu = \\mu_0\\left[(1-A)e^{-B|w|} + A\\right]  \\quad\\text{(Polach 2005, eq. 8)}

    Parameters
    ----------
    law : str
        One of :data:`CREEP_LAWS`.
    long_creep : array_like
        ξ [-].
    slip_velocity : array_like
        w [m/s], broadcast with the creepages (only |w| enters μ).
    normal_load : float
        N [N].
    semi_axis_x, semi_axis_y : float
        Hertzian a (rolling direction), b [m].
    shear_modulus : float
        Combined G [Pa].
    poisson : float
        Combined ν [-].
    parameters : PolachParameters or FastsimParameters
        Friction (and law) parameters; ``fastsim``/``fastrip`` use only μ0, A, B.
    lat_creep : array_like
        η [-] (FASTSIM family only).
    spin : array_like
        φ [1/m] (FASTSIM family only).
    grid : FastsimGrid, optional
        Discretisation of the FASTSIM family.
    tractions : bool
        Return the traction distributions (FASTSIM family).

    Returns
    -------
    TangentialResult
        For ``polach``: F_x only (F_y = M_z = 0, no tractions).

    Raises
    ------
    ParameterError
        Unknown law (did-you-mean), a set that lacks the law's parameters, Polach with lateral
        creepage or spin, a non-physical value, or creepages and ``slip_velocity`` whose shapes
        do not broadcast together (naming them).

    Examples
    --------
    >>> r = creep_force("fastsim", 0.01, 0.083, 4300.0, 3.4e-3, 2.7e-3, 8.08e10, 0.3)
    >>> round(float(r.fx[0] / 4300.0), 3)
    0.534
    """
    check_law(law)
    _check_pair(law, parameters)
    xi = require_finite("long_creep", long_creep, "-")
    w = require_finite("slip_velocity", slip_velocity, "m/s")
    eta = require_finite("lat_creep", lat_creep, "-")
    phi = require_finite("spin", spin, "1/m")
    xi, w, eta, phi = (
        v.ravel()
        for v in require_broadcastable(long_creep=xi, slip_velocity=w, lat_creep=eta, spin=phi)
    )
    p = parameters
    mu = _friction_kernel(w, p.static_friction, p.limit_ratio, p.friction_decay)
    common = dict(
        semi_axis_x=semi_axis_x,
        semi_axis_y=semi_axis_y,
        normal_load=normal_load,
        shear_modulus=shear_modulus,
        poisson=poisson,
        friction=mu,
        grid=grid,
        tractions=tractions,
    )
    if law == "polach":
        if np.any(eta) or np.any(phi):
            raise ParameterError(
                "law 'polach' is longitudinal only here: lat_creep and spin must be 0 "
                "(use a FASTSIM-family law)"
            )
        a = require_positive("semi_axis_x", semi_axis_x, "m", single=True)
        b = require_positive("semi_axis_y", semi_axis_y, "m", single=True)
        g = require_positive("shear_modulus", shear_modulus, "Pa", single=True)
        q = require_positive("normal_load", normal_load, "N", single=True)
        c11 = float(kalker_coefficients(a / b, poisson).c11)
        fx = _polach_force_kernel(xi, w, q, g * a * b * c11, *parameters.as_tuple())
        zero = np.zeros_like(fx)
        return TangentialResult(
            fx, zero, zero, mu, np.ones_like(fx), Flexibilities(zero, zero, zero)
        )
    if law == "fastrip":
        return fastrip(xi, eta, phi, **common)
    if law == "modified-fastsim":
        return fastsim(xi, eta, phi, k0=p.k0, alpha_inf=p.alpha_inf, beta=p.beta, **common)
    return fastsim(xi, eta, phi, **common)


def law_creep_curve(
    law: str,
    creep,
    normal_load,
    rolling_speed,
    wheel_radius_x,
    wheel_radius_y,
    roller_radius_x,
    roller_radius_y,
    parameters: PolachParameters | FastsimParameters = POLACH_DRY,
    youngs_modulus=210e9,
    poisson=0.3,
    grid: FastsimGrid | None = None,
) -> CreepCurve:
    """Creep-adhesion curve of a wheel on a roller (or tangent rail) by the named law.

    The counterpart of :func:`rollerrig.contact.polach_creep_curve` for every law: exact Hertz,
    Kalker's C11 at the contact's a/b, slip velocity w = s·v, μ(w) of Polach's form.

    Parameters
    ----------
    law : str
        One of :data:`CREEP_LAWS`.
    creep : array_like
        Longitudinal creep s = w/v [-], w the slip velocity and v ``rolling_speed``, taken
        as the law's creepage as Polach refers it (to the vehicle speed, for which the
        roller's surface speed stands on the rig; Kayaalp eq. 4.21). Kalker's and CONTACT's
        creepage is referred to the mean rolling speed, ξ = 2s/(2 + s)
        (:func:`~rollerrig.contact.kinematics.kalker_creepage`): at 1 % the two differ by
        0.5 % of their value; compare a curve with CONTACT's at equal ξ.
    normal_load : float
        Q [N].
    rolling_speed : float
        v [m/s].
    wheel_radius_x, wheel_radius_y, roller_radius_x, roller_radius_y : float
        Radii [m] (``np.inf`` roller radius: tangent rail).
    parameters : PolachParameters or FastsimParameters
        Friction (and law) parameters.
    youngs_modulus : float
        E [Pa] of both bodies.
    poisson : float
        ν [-] of both bodies.
    grid : FastsimGrid, optional
        FASTSIM-family discretisation.

    Returns
    -------
    CreepCurve
        ``parameters`` holds the set used.

    Examples
    --------
    >>> c = law_creep_curve("fastsim", np.linspace(0, 0.05, 101), 10e3, 30 / 3.6,
    ...                     0.348, 0.291, 0.452, 1.890)
    >>> round(c.peak[1], 2)
    0.54
    """
    check_law(law)
    s = _require_creep_values(creep)
    q = require_positive("normal_load", normal_load, "N", single=True)
    v = require_positive("rolling_speed", rolling_speed, "m/s", single=True)
    contact = hertz_contact(
        q,
        wheel_radius_x,
        wheel_radius_y,
        roller_radius_x,
        roller_radius_y,
        youngs_modulus=youngs_modulus,
        poisson=poisson,
    )
    elastic = combined_elastic_constants(youngs_modulus, poisson, youngs_modulus, poisson)
    g, nu = float(elastic.shear_modulus), float(elastic.poisson)
    a, b = float(contact.semi_axis_x), float(contact.semi_axis_y)
    c11 = float(kalker_coefficients(a / b, nu).c11)
    w = np.abs(s) * v
    result = creep_force(law, s, w, q, a, b, g, nu, parameters, grid=grid)
    return CreepCurve(
        creep=s,
        slip_velocity=w,
        adhesion_coefficient=result.fx.reshape(s.shape) / q,
        contact=contact,
        c11=c11,
        creep_stiffness=g * a * b * c11,
        normal_load=q,
        rolling_speed=v,
        parameters=parameters,
    )
