"""The model a Polach fit fits: Polach's CoA and the creep stiffness of the rig's contact.

Polach's creep law with slip-velocity-dependent friction (Polach 2005; Kayaalp eqs. 4.19-4.20),
evaluated by the same kernel as the twin (:func:`rollerrig.contact.creep.polach_force_kernel`):

.. math::
    \\mathrm{CoA}(s, w) = \\frac{2\\mu}{\\pi}\\left(\\frac{k_A\\varepsilon}{1+(k_A\\varepsilon)^2}
        + \\arctan(k_S\\varepsilon)\\right),\\quad
    \\varepsilon = \\frac{\\pi}{4}\\frac{G a b c_{11}}{Q\\mu}s,\\quad
    \\mu = \\mu_0\\left[(1-A)e^{-B|w|} + A\\right]

with the creep stiffness G a b c11 [N] of the contact at each point's load (Hertz and Kalker;
:func:`creep_stiffness_for_rig`).

References
----------
.. [1] O. Polach, "Creep forces in simulations of traction vehicles running on adhesion limit",
   Wear 258 (2005) 992-1000.
.. [2] B.T. Kayaalp, dissertation (University of Pardubice), eqs. 4.19-4.20.
"""

from __future__ import annotations

import numpy as np

from rollerrig._validation import require_finite, require_positive
from rollerrig.contact.creep import POLACH_DRY, PolachParameters  # noqa: F401 (the examples)
from rollerrig.contact.creep import polach_force_kernel as _polach_force_kernel

__all__ = ["PARAMETER_NAMES", "creep_stiffness_for_rig", "polach_coa"]

PARAMETER_NAMES = ("static_friction", "limit_ratio", "friction_decay", "k_adhesion", "k_slip")
"""Order of the parameters in a fit's ``stderr``, ``covariance`` and ``correlation``."""


def polach_coa(creep, slip_velocity, normal_load, creep_stiffness, parameters: PolachParameters):
    """Polach's CoA F/Q at given creep, slip velocity, load and creep stiffness.

    Parameters
    ----------
    creep : array_like
        s [-].
    slip_velocity : array_like
        w [m/s].
    normal_load : array_like
        Q [N].
    creep_stiffness : array_like
        G a b c11 [N] at that load.
    parameters : PolachParameters

    Returns
    -------
    numpy.ndarray
        CoA [-].

    Examples
    --------
    >>> round(float(polach_coa(0.01, 0.0833, 4300.0, 1.13e6, POLACH_DRY)), 3)
    0.421
    """
    q = require_positive("normal_load", normal_load, "N")
    return (
        _polach_force_kernel(
            require_finite("creep", creep, "-"),
            require_finite("slip_velocity", slip_velocity, "m/s"),
            q,
            require_positive("creep_stiffness", creep_stiffness, "N"),
            *parameters.as_tuple(),
        )
        / q
    )


def creep_stiffness_for_rig(normal_load, rig=None):
    """Kalker's creep stiffness G a b c11 [N] of the rig's wheel-roller contact at a load.

    Exact Hertz contact of the rig's geometry and material at the load, Kalker's c11 at its a/b
    and ν, and the combined shear modulus, as :func:`rollerrig.contact.curves.polach_creep_curve`
    and the twin compute them.

    Parameters
    ----------
    normal_load : float or array_like
        Q [N], > 0.
    rig : RigParameters or mapping, optional
        The rig (default: the bundled default rig); a ``{section: {key: value}}`` mapping in SI
        (e.g. ``json.loads(ds.attrs["provenance"])["rig_parameters"]``) also works.

    Returns
    -------
    numpy.ndarray
        G a b c11 [N].

    Examples
    --------
    >>> round(float(creep_stiffness_for_rig(4300.0)) / 1e6, 4)
    1.1295
    """
    from rollerrig.contact.hertz import combined_elastic_constants, hertz_contact
    from rollerrig.contact.kalker import kalker_coefficients
    from rollerrig.rig.parameters import default_rig

    if rig is None:
        rig = default_rig()
    d = rig.to_dict() if hasattr(rig, "to_dict") else rig
    g, mat = d["geometry"], d["material"]
    q = require_positive("normal_load", normal_load, "N")
    out = np.empty(q.shape)
    # Every distinct load at once (Hertz and Kalker broadcast): a twin's load channel has a
    # value per sample, and one scalar contact per load took 2.4 ms (17 s for a 7.5 s test).
    unique, inverse = np.unique(q, return_inverse=True)
    contact = hertz_contact(
        unique,
        g["wheel_radius_x"],
        g["wheel_radius_y"],
        g["roller_radius_x"],
        g["roller_radius_y"],
        youngs_modulus=mat["youngs_modulus"],
        poisson=mat["poisson"],
    )
    E, nu = mat["youngs_modulus"], mat["poisson"]
    elastic = combined_elastic_constants(E, nu, E, nu)
    c11 = kalker_coefficients(contact.a_over_b, float(elastic.poisson)).c11
    values = float(elastic.shear_modulus) * np.asarray(contact.semi_axis_x, dtype=float)
    values = values * np.asarray(contact.semi_axis_y, dtype=float) * np.asarray(c11, dtype=float)
    out.reshape(-1)[:] = values.reshape(-1)[inverse.reshape(-1)]
    return out
