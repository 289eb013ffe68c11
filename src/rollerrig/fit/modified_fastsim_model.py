"""The modified FASTSIM as the fit sees it: its parameters, their bounds, its CoA at many loads.

The law of :func:`rollerrig.fit.modified_fastsim.fit_modified_fastsim`: the modified FASTSIM
(Spiryagin, Polach & Cole 2013; :func:`rollerrig.contact.fastsim.fastsim` with ``k0, alpha_inf,
beta``) with Polach's slip-velocity-dependent friction, its six parameters in one vector θ =
(k0, α∞, β, μ0, A, B) and the bounds a fit searches them within.

Model. At each point i (creepage ξ_i in Kalker's definition, slip velocity w_i, contact load
N_i) the CoA is F_x/N of the modified FASTSIM on the Hertzian ellipse of the contact, with
μ(w) = μ0 [(1 − A) e^(−B|w|) + A] (Polach 2005, eq. 8). Under Hertz scaling (a, b ∝ N^(1/3) at
a fixed a/b) the simplified theory depends on ξ and N only through ξ·G a b C11/(μ N)
∝ ξ N^(−1/3), and so does Spiryagin's ε; each point is therefore evaluated on the ellipse of a
reference load N_ref (the median) at the equivalent creepage ξ_i (N_i/N_ref)^(−1/3), which is
exact for the law and lets one FASTSIM pass take every point.

References
----------
.. [1] M. Spiryagin, O. Polach, C. Cole, "Creep force modelling for rail traction vehicles
   based on the Fastsim algorithm", Vehicle System Dynamics 51 (2013) 1765-1783.
.. [2] O. Polach, Wear 258 (2005) 992-1000 (the friction law μ(w)).
"""

from __future__ import annotations

import numpy as np

from rollerrig._validation import require_finite, require_positive
from rollerrig.contact.creep import friction_kernel as _friction_kernel
from rollerrig.contact.fastsim import FastsimGrid, fastsim, fastsim_grid
from rollerrig.contact.laws import FastsimParameters

__all__ = [
    "MODIFIED_FASTSIM_PARAMETER_NAMES",
    "PARAMETER_LOWER",
    "PARAMETER_UPPER",
    "coa_kernel",
    "modified_fastsim_coa",
]

MODIFIED_FASTSIM_PARAMETER_NAMES = (
    "k0",
    "alpha_inf",
    "beta",
    "static_friction",
    "limit_ratio",
    "friction_decay",
)
"""Order of the parameters in a fit's ``stderr``, ``covariance`` and ``correlation``."""

PARAMETER_LOWER = np.array([1e-3, 0.0, 0.0, 1e-3, 1e-6, 0.0])
"""Lower bounds of the fit's search, in the order of :data:`MODIFIED_FASTSIM_PARAMETER_NAMES`
(the open bounds k0 > 0, μ0 > 0, A > 0 as small positive values) [units of each parameter]."""

PARAMETER_UPPER = np.array([1.0, 1.0, 1000.0, 1.0, 1.0, 10.0])
"""Upper bounds of the fit's search, in the order of :data:`MODIFIED_FASTSIM_PARAMETER_NAMES`
(μ0 <= 1 for dry steel on steel; B <= 10 s/m, published values 0.1-1 s/m) [units of each
parameter]."""


def _params(theta, name="fitted", source="fit_modified_fastsim") -> FastsimParameters:
    k0, al, be, mu0, a, b = (float(x) for x in theta)
    return FastsimParameters(mu0, a, b, k0=k0, alpha_inf=al, beta=be, name=name, source=source)


def _theta(p: FastsimParameters) -> np.ndarray:
    return np.array([p.k0, p.alpha_inf, p.beta, p.static_friction, p.limit_ratio, p.friction_decay])


def coa_kernel(xi_eq, w, n_ref, a, b, g, nu, theta, grid, mu_scale=1.0):
    """CoA of the modified FASTSIM at equivalent creepages (no validation of the data).

    ``xi_eq`` [-] the equivalent creepages on the ellipse a, b [m] of ``n_ref`` [N], ``w``
    [m/s] the slip velocities, ``g`` [Pa] and ``nu`` [-] the combined elastic constants,
    ``theta`` (k0, α∞, β, μ0, A, B), ``grid`` the discretisation
    (:class:`~rollerrig.contact.ellipse_grid.FastsimGrid`); ``mu_scale`` multiplies μ (the
    coverage check's sensitivity to μ).
    """
    k0, al, be, mu0, aa, bb = theta
    mu = mu_scale * _friction_kernel(w, mu0, aa, bb)
    r = fastsim(
        xi_eq,
        semi_axis_x=a,
        semi_axis_y=b,
        normal_load=n_ref,
        shear_modulus=g,
        poisson=nu,
        friction=mu,
        k0=k0,
        alpha_inf=al,
        beta=be,
        grid=grid,
    )
    return r.fx / n_ref


def modified_fastsim_coa(
    creep,
    slip_velocity,
    normal_load,
    semi_axis_x,
    semi_axis_y,
    shear_modulus,
    poisson,
    parameters: FastsimParameters,
    *,
    reference_load=None,
    grid: FastsimGrid | None = None,
):
    """CoA F_x/N of the modified FASTSIM at points of possibly different loads.

    .. math:: \\mathrm{CoA}_i = \\frac{F_x(\\xi_i (N_i/N_\\mathrm{ref})^{-1/3},\\, w_i;\\,
              a, b, N_\\mathrm{ref})}{N_\\mathrm{ref}}

    exact under Hertz scaling (see the module notes).

    Parameters
    ----------
    creep : array_like
        Creepage ξ [-] in Kalker's definition (referred to the mean rolling speed).
    slip_velocity : array_like
        w [m/s] (only |w| enters μ).
    normal_load : float or array_like
        N [N] per point.
    semi_axis_x, semi_axis_y : float
        Hertzian a, b [m] at ``reference_load``.
    shear_modulus : float
        Combined G [Pa].
    poisson : float
        Combined ν [-].
    parameters : FastsimParameters
        k0, α∞, β, μ0, A, B.
    reference_load : float, optional
        Load of the given semi-axes [N]; default the median of ``normal_load``.
    grid : FastsimGrid, optional
        Discretisation (default ``fastsim_grid(30, 30)``).

    Returns
    -------
    numpy.ndarray
        CoA [-], the shape of ``creep``.

    Examples
    --------
    >>> from rollerrig.contact.laws import EUROSPRINTER_MODIFIED_FASTSIM as P
    >>> c = modified_fastsim_coa([0.002, 0.02], [0.017, 0.17], 4300.0, 3.4e-3, 2.7e-3,
    ...                          8.08e10, 0.3, P)
    >>> [round(float(x), 3) for x in c]
    [0.267, 0.329]
    """
    s = require_finite("creep", creep, "-")
    w = np.broadcast_to(require_finite("slip_velocity", slip_velocity, "m/s"), s.shape)
    q = np.broadcast_to(require_positive("normal_load", normal_load, "N"), s.shape)
    n_ref = float(np.median(q)) if reference_load is None else float(reference_load)
    require_positive("reference_load", n_ref, "N")
    xi_eq = s * np.cbrt(n_ref / q)
    theta = _theta(parameters)
    g = fastsim_grid() if grid is None else grid
    out = coa_kernel(
        xi_eq.ravel(), w.ravel(), n_ref, semi_axis_x, semi_axis_y, shear_modulus, poisson,
        theta, g,
    )  # fmt: skip
    return out.reshape(s.shape)
