"""Roller-to-track transfer of a creep–CoA curve measured on the rig, with its uncertainty band.

What transfers by contact mechanics, and what is carried over as measured
-------------------------------------------------------------------------
A curve measured on the roller is the product of two things:

* the **elastic part**, set by the geometry of the two bodies: the Hertz ellipse (a, b, a/b),
  Kalker's coefficients C11, C22, C23 at that a/b, the creep stiffness G·a·b·C11 and the shape
  of the saturation, which the creep law computes on the ellipse. On the rig's 0.452 m roller
  the ellipse is shorter in the rolling direction than on a tangent rail, and the creep
  stiffness lower (24 % on the bundled rig with the same crown);
* the **surface part**, set by the surfaces in contact: the reduction of the initial slope
  against Kalker's theory (Polach's k_A, k_S; the modified FASTSIM's k0, α∞, β), the friction
  level μ0 and its fall with slip velocity (A, B).

:func:`transfer_curve` fits the chosen law's surface parameters to the measured points *on the
roller's ellipse* (:func:`rollerrig.fit.fit_polach`,
:func:`rollerrig.fit.modified_fastsim.fit_modified_fastsim`), then carries the curve to the
rail's ellipse at the same normal load and rolling speed by the transfer factor F_rail/F_roller
at equal creepage, computed with the same surface parameters on both ellipses: by Polach's
closed form, or, for the modified FASTSIM, by the strip theory with the same slope reduction
(the modified FaStrip), whose saturation shape is closer to Kalker's exact theory (the factor
within 0.75 % of CONTACT's exact one, FASTSIM's 2.46 %: :data:`LAW_FACTOR_ERROR`).
Carrying the surface parameters over unchanged is an assumption (the surfaces, their
contamination and temperature are the rig's; a rail's roughness and third body differ) and is
stated in every output.

Creepage
--------
The rig's creep is referred to the roller's peripheral speed (Kayaalp eq. 4.21),
s = (ω_w r_w − ω_r r_r)/(ω_r r_r), with slip velocity w = ω_w r_w − ω_r r_r (eq. 4.22). Kalker's
creepage is referred to the mean rolling speed, ξ = w / ((ω_w r_w + ω_r r_r)/2). Hence

.. math:: \\xi = \\frac{2s}{2+s}, \\qquad s = \\frac{2\\xi}{2-\\xi}

(:func:`kalker_creepage`, :func:`rig_creep`); at 1 % they differ by 0.5 % of their value. On
track the rail takes the roller's place: s is referred to the vehicle speed V, ξ to the mean
of V and the wheel's circumferential speed, and w = s·V. The laws are evaluated in ξ; the
outputs give both, and the curves are compared at equal creepage and equal speed (so at equal
slip velocity).

Load dependence on the rig
--------------------------
With the swinging arm the contact's load changes along a test (N = (S + W_d)/(1 − σ(h/l)·CoA)).
Under Hertz scaling at a fixed a/b the laws depend on ξ and N only through ξ·N^(−1/3) (the
creep stiffness grows as N^(2/3)), so each point enters the fit at its own load and the
transfer is made at one load, by default the median contact load of the fitted points.

Uncertainty band (Monte Carlo, JCGM 101), and which construction
-----------------------------------------------------------------
Each draw takes (i) the law's surface parameters; (ii) the geometry: wheel and roller rolling
radii rectangular within the rig's stated tolerances (``sensors.wheel_radius_tolerance``,
``roller_radius_tolerance``), the transverse profile radii (wheel, roller, rail crown) normal
with a stated relative standard uncertainty; (iii) optionally a common relative systematic
error δ of the measured CoA. The geometry enters through the transfer factor,

.. math:: \\mathrm{CoA}_\\mathrm{track} = L(\\theta)\\,
          \\frac{f(\\theta, \\mathrm{track})}{f(\\theta, \\mathrm{roller})}\\,(1 + \\delta),

with f the law on the drawn ellipse and L the roller level, which depends on how well the fit
knows its parameters (:func:`rollerrig.analysis.transfer_band.choose_construction`; the
output's ``band["construction"]`` and ``["construction_why"]`` say which and why):

* ``"model"`` (identifiable fit, residuals without serial structure): L is the law at θ drawn
  from the fit's covariance (inflated by the AR(1) factor of its residuals, stated); a draw
  outside the bounds is drawn again, never clipped.
* ``"measured points"`` (not identifiable, or structured residuals: the law is not the data's):
  L is the measured curve itself, the law's curve plus its smoothed residuals, with the
  points' noise; θ ranges over Beale's 95 % region of parameters that fit the points about as
  well as the best, and enters only through the factor. Measured on CONTACT's exact roller
  curve (tests/analysis/test_transfer_coverage.py): the old clipped-covariance band covered
  CONTACT's rail curve at 4 of 11 creepages (Polach) and held its own central curve at only
  three quarters of the grid; this one covers 11 of 11 for both laws, within ±5-6 % of the
  curve. :mod:`rollerrig.analysis.transfer_band` gives the reasons.

The band is the 2.5-97.5 % interval of the draws at each creepage, widened to hold the central
curve (always inside its band) and then by the law's own error in the transfer factor against
Kalker's exact theory (:data:`LAW_FACTOR_ERROR`, measured with CONTACT) as a *bound*: the
edges times (1 ∓ e(ξ)), e scaled by the roller curve's rise. Not in the band: the difference
of the surfaces, E and ν (same steel on both sides).

References
----------
.. [1] B.T. Kayaalp, dissertation (University of Pardubice), eqs. 4.21-4.22.
.. [2] J.J. Kalker, *Three-Dimensional Elastic Bodies in Rolling Contact*, Kluwer (1990).
.. [3] O. Polach, Wear 258 (2005) 992-1000.
.. [4] M. Spiryagin, O. Polach, C. Cole, Vehicle System Dynamics 51 (2013) 1765-1783.
.. [5] JCGM 101:2008, Evaluation of measurement data - Propagation of distributions using a
   Monte Carlo method.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable

import numpy as np

from rollerrig._validation import ParameterError, require_positive
from rollerrig.analysis.measured_curve import (
    CSV_COLUMNS,
    MeasuredCurve,
    curve_from_analysis,
    read_analysis,
    read_curve_csv,
)
from rollerrig.analysis.transfer_band import (
    MODEL,
    choose_construction,
    measured_level,
    plausible_draws,
)
from rollerrig.analysis.transfer_geometry import (
    ContactGeometry,
    RailGeometry,
    hertz_ellipse,
    side_summary,
)
from rollerrig.analysis.transfer_law import (
    POLACH_NAMES,
    draws_within_bounds,
    factor_coa,
    law_bounds,
    law_coa,
    sse_on_points,
)
from rollerrig.analysis.transfer_result import TransferResult
from rollerrig.contact.fastsim import FastsimGrid, fastsim_grid
from rollerrig.contact.hertz import combined_elastic_constants
from rollerrig.contact.kinematics import kalker_creepage, rig_creep
from rollerrig.contact.laws import check_law

__all__ = [
    "CSV_COLUMNS",
    "LAW_FACTOR_ERROR",
    "LAW_FACTOR_ERROR_ONSET",
    "MIN_DRAWS",
    "TRANSFER_LAWS",
    "ContactGeometry",
    "MeasuredCurve",
    "RailGeometry",
    "TransferResult",
    "curve_from_analysis",
    "kalker_creepage",
    "read_analysis",
    "read_curve_csv",
    "rig_creep",
    "transfer_curve",
]

MIN_DRAWS = 50
"""Fewest Monte Carlo draws of a band [-]: its 2.5 % and 97.5 % quantiles need a few draws
beyond each (with 50, one on each side)."""

LAW_FACTOR_ERROR = {"polach": 0.0315, "modified-fastsim": 0.0080}
"""The largest relative error of each law's transfer factor F_rail/F_roller at equal creepage
against Kalker's exact theory [-], by law.

Measured against CONTACT (Vollebregt; exact theory, steady rolling, Coulomb friction mu 0.33,
grid-extrapolated from 32 x 32 and 64 x 64 elements) on the bundled rig at 10 kN: the wheel on
the 0.452 m roller (a/b 0.847) and on a tangent rail with the roller's crown (a/b 1.239)
(tests/contact/data/cntc_exact_rig.json, tests/contact/test_cntc.py). Polach's closed form
misses by up to 3.14 % at xi = 2e-3, in the transition to full sliding. With the modified
FASTSIM the factor is taken from the strip theory with the fitted parameters (the modified
FaStrip, :func:`~rollerrig.analysis.transfer_law.factor_coa`): FaStrip's factor is within
0.75 % at every creepage (FASTSIM's own, 2.46 %, missed the 2 % target); all agree within
0.1 % at small creepage. The band of :func:`transfer_curve` includes this error
(``law_error=True``); on other geometries it is an assumption that it is no larger, and with a
slope reduction (k0, alpha_inf, beta) there is no exact reference: the strip theory's
saturation shape is assumed to carry it as well as Coulomb friction."""

LAW_FACTOR_ERROR_ONSET = 0.3
"""Fraction of the roller curve's peak CoA below which the law's factor error is scaled down
linearly to zero [-]: at small creepage every law's factor is the ratio of the creep
stiffnesses G a b C11 (measured within 0.1 % of the exact theory)."""

TRANSFER_LAWS = ("polach", "modified-fastsim")
"""Laws a transfer can use: those with parameters for the measured slope reduction."""


# --------------------------------------------------------------------------------------------
# The transfer
# --------------------------------------------------------------------------------------------


def _peak(xi, curves):
    k = np.argmax(curves, axis=-1)
    return xi[k], np.take_along_axis(curves, k[..., None], axis=-1)[..., 0]


def _stated_systematic(measured: MeasuredCurve) -> float | None:
    """The median relative standard uncertainty u/CoA of the points above half the largest
    CoA [-], capped below 0.5; None without finite values."""
    coa = np.asarray(measured.coa, float)
    u = np.asarray(measured.coa_uncertainty, float)
    high = coa >= 0.5 * np.max(coa)
    rel = u[high] / coa[high]
    rel = rel[np.isfinite(rel)]
    if rel.size == 0:
        return None
    return float(min(np.median(rel), 0.49))


def transfer_curve(
    measured: MeasuredCurve,
    geometry: ContactGeometry,
    rail: RailGeometry | None = None,
    law: str = "modified-fastsim",
    *,
    normal_load: float | None = None,
    rolling_speed: float | None = None,
    draws: int = 400,
    seed: int = 0,
    coa_systematic: float | None = None,
    inflate_for_structure: bool = True,
    points: int = 161,
    grid: FastsimGrid | None = None,
    fit_options: dict | None = None,
    law_error: bool = True,
    progress: Callable[[str], None] | None = None,
) -> TransferResult:
    """Predict the creep–CoA curve on the rail from one measured on the rig's roller.

    The chosen law's surface parameters are fitted to the measured points on the roller's
    Hertz ellipse and evaluated, unchanged, on the rail's ellipse at the same load and speed
    (module notes). The band is a Monte Carlo propagation of the parameters and of the
    geometry's stated uncertainty, on the law's curve where the fit determines its parameters
    and on the measured points where it does not (``result.band["construction"]``, with the
    reason); its central curve is always inside it.

    Parameters
    ----------
    measured : MeasuredCurve
        From :func:`read_analysis` or :func:`read_curve_csv`.
    geometry : ContactGeometry
        The rig's wheel and roller (:meth:`ContactGeometry.from_rig`).
    rail : RailGeometry, optional
        Default: tangent rail with the roller's crown radius.
    law : {"polach", "modified-fastsim"}
        The creep law (:data:`TRANSFER_LAWS`).
    normal_load : float, optional
        N [N] of the transfer; default the median contact load of the points.
    rolling_speed : float, optional
        V [m/s]; default the median roller speed of the points.
    draws : int
        Monte Carlo draws (>= 50).
    seed : int
        Seed of the draws (>= 0).
    coa_systematic : float, optional
        Relative standard uncertainty of the measured CoA common to all points [-] (a
        systematic error of the rig: load, torque class, arm). A number enters each draw as a
        common factor (1 + δ). Default: where the points carry their standard uncertainty
        (an analysis's), the median of u/CoA over the points above half the largest CoA,
        taken as common to all points (conservative: part of it is random); else none, noted.
    inflate_for_structure : bool
        Inflate the fit's covariance by the square of its residuals' AR(1) factor.
    points : int
        Creepages of the output grid: ξ_max·1e-4, then evenly from ξ_max/200 to the largest
        measured ξ_max.
    grid : FastsimGrid, optional
        FASTSIM discretisation (default ``fastsim_grid(30, 30)``).
    fit_options : dict, optional
        Passed to the fit (e.g. ``{"profile": False}`` for the modified FASTSIM).
    law_error : bool
        Include the law's own error in the transfer factor (:data:`LAW_FACTOR_ERROR`, measured
        against Kalker's exact theory) in the band, as a bound: the band's edges times
        1 ∓ e(ξ), e(ξ) the law's error scaled by the roller curve's rise (zero at ξ → 0, full
        from :data:`LAW_FACTOR_ERROR_ONSET` of its peak on). A largest error measured at one
        geometry is not a distribution, so it is not drawn.
    progress : callable, optional
        Told what is being done, as text: the fit, the plausible set, the draws and the
        peaks (the command line's progress; a few seconds to tens of seconds in all).

    Returns
    -------
    TransferResult

    Raises
    ------
    ParameterError
        A law without slope-reduction parameters (``fastsim``, ``fastrip``), an unknown law,
        a non-physical input.

    Examples
    --------
    A curve on the bundled rig's roller, to the tangent rail with the same crown: the
    factor at small creepage is the ratio of the creep stiffnesses G a b C11.

    >>> import warnings
    >>> from rollerrig.contact.creep import POLACH_DRY
    >>> s = np.linspace(0.0005, 0.06, 60)
    >>> y = 0.5 * np.tanh(s / 0.01)
    >>> m = MeasuredCurve(s, y, s * 8.33, np.full(60, 4300.0), np.full(60, 8.33))
    >>> geo = ContactGeometry(0.348, 0.291, 0.452, 1.89)
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     r = transfer_curve(m, geo, RailGeometry(), "polach", draws=50)
    >>> round(r.stiffness_ratio, 3)
    1.321
    """
    check_law(law)
    if law not in TRANSFER_LAWS:
        raise ParameterError(
            f"law {law!r} has no parameter for the measured reduction of the initial slope, so "
            "a measured curve cannot be fitted with it; use 'modified-fastsim' (FASTSIM with "
            "k0, alpha_inf, beta; k0 = alpha_inf = 1 is Kalker's FASTSIM) or 'polach'"
        )
    rail = RailGeometry() if rail is None else rail
    draws = int(draws)
    if draws < MIN_DRAWS:
        raise ParameterError(f"draws must be at least {MIN_DRAWS}, got {draws}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ParameterError(f"seed must be an integer >= 0 (numpy's generators), got {seed!r}")
    if int(points) < 10:
        raise ParameterError(f"points must be at least 10, got {points}")
    if coa_systematic is not None and not (
        math.isfinite(coa_systematic) and 0 <= coa_systematic < 0.5
    ):
        raise ParameterError(f"coa_systematic must lie in [0, 0.5) [-], got {coa_systematic!r}")
    grid = fastsim_grid() if grid is None else grid
    geo = geometry
    notes = list(measured.notes)
    if coa_systematic is None and measured.coa_uncertainty is not None:
        coa_systematic = _stated_systematic(measured)
        if coa_systematic is not None:
            notes.append(
                f"the measured CoA's stated uncertainty enters the band as a common relative "
                f"error u = {coa_systematic:.3g} (the median u/CoA of the points above half the "
                "largest CoA, taken as common to all points: conservative)"
            )
    xi_pts = measured.creepage
    y = np.asarray(measured.coa, float)
    w_pts = np.asarray(measured.slip_velocity, float)
    q_pts = np.asarray(measured.normal_load, float)
    n_ref = float(np.median(q_pts)) if normal_load is None else float(normal_load)
    v_ref = float(np.median(measured.rolling_speed)) if rolling_speed is None else rolling_speed
    v_is = "as given" if rolling_speed is not None else (
        "the median roller speed of the points fitted"
    )  # fmt: skip
    require_positive("normal_load", n_ref, "N")
    require_positive("rolling_speed", v_ref, "m/s")
    elastic_c = combined_elastic_constants(geo.youngs_modulus, geo.poisson, geo.youngs_modulus,
                                           geo.poisson)  # fmt: skip
    g, nu = float(elastic_c.shear_modulus), float(elastic_c.poisson)
    crown = geo.roller_radius_y if rail.crown_radius is None else rail.crown_radius
    rail_rx = rail.longitudinal_radius

    def ellipses(wx, wy, rx, ry, crown_r):
        roll = hertz_ellipse(n_ref, wx, wy, rx, ry, geo.youngs_modulus, nu, geo.poisson)
        track = hertz_ellipse(n_ref, wx, wy, rail_rx, crown_r, geo.youngs_modulus, nu, geo.poisson)
        return roll, track

    roller_e, track_e = ellipses(
        geo.wheel_radius_x, geo.wheel_radius_y, geo.roller_radius_x, geo.roller_radius_y, crown
    )

    say = progress if progress is not None else (lambda text: None)

    # ---- the fit on the roller's ellipse (each point at its own load) ---------------------
    say(f"fitting {law} to {len(xi_pts)} points on the roller")
    options = dict(fit_options or {})
    caught_messages = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if law == "polach":
            from rollerrig.fit.polach import fit_polach

            k_ref = g * roller_e.a * roller_e.b * roller_e.c11
            stiffness = k_ref * np.cbrt((q_pts / n_ref) ** 2)
            fit = fit_polach(xi_pts, y, q_pts, stiffness, slip_velocity=w_pts, **options)
            theta = np.array(fit.parameters.as_tuple())
            names = POLACH_NAMES
        else:
            from rollerrig.fit.modified_fastsim import (
                MODIFIED_FASTSIM_PARAMETER_NAMES,
                fit_modified_fastsim,
            )

            fit = fit_modified_fastsim(
                xi_pts, y, q_pts, roller_e.a, roller_e.b, g, nu, slip_velocity=w_pts,
                reference_load=n_ref, grid=grid, **options,
            )  # fmt: skip
            p = fit.parameters
            theta = np.array(
                [p.k0, p.alpha_inf, p.beta, p.static_friction, p.limit_ratio, p.friction_decay]
            )
            names = MODIFIED_FASTSIM_PARAMETER_NAMES
        caught_messages = list(dict.fromkeys(str(m.message) for m in caught))
    notes.extend(f"fit ({law}) on the roller: {m}" for m in caught_messages)

    # ---- the output grid --------------------------------------------------------------------
    xi_max = float(np.max(xi_pts))
    # One point at 1e-4 of the range (the small-creepage limit), then an even grid.
    xi = np.concatenate([[xi_max * 1e-4], np.linspace(xi_max / 200.0, xi_max, int(points) - 1)])
    s = rig_creep(xi)
    w = s * v_ref

    def law_on(theta_, ell):
        return law_coa(law, theta_, xi, w, n_ref, ell, g, nu, grid)

    def factor_of(theta_, roller_ell, track_ell):
        on = [factor_coa(law, theta_, xi, w, n_ref, e, g, nu) for e in (track_ell, roller_ell)]
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(on[1] != 0.0, on[0] / on[1], 1.0)

    roller = law_on(theta, roller_e)
    factor = factor_of(theta, roller_e, track_e)
    track = roller * factor  # the law's roller curve carried over by the factor

    # ---- Monte Carlo ------------------------------------------------------------------------
    rng = np.random.default_rng(seed)
    construction, why = choose_construction(fit)
    cov = np.array(fit.covariance, float)
    cov = np.where(np.isfinite(cov), cov, 0.0)
    structure = fit.residual_structure
    inflation = 1.0
    if inflate_for_structure and structure is not None and structure.structured:
        inflation = (
            float(structure.stderr_inflation) if np.isfinite(structure.stderr_inflation) else 1.0
        )
    cov = cov * inflation**2
    lower, upper, feasible = law_bounds(law)
    sse, fitted_pts = sse_on_points(law, xi_pts, y, w_pts, q_pts, n_ref, roller_e, g, nu, grid,
                                     theta)  # fmt: skip
    plausible = None
    if construction == MODEL:
        thetas = draws_within_bounds(theta, cov, lower, upper, feasible, draws, rng)
        level, level_u = roller, np.zeros_like(xi)
    else:
        say("the parameter sets the data cannot tell apart")
        thetas, plausible = plausible_draws(
            theta, np.array(fit.covariance, float), sse, lower, upper, draws, rng, feasible
        )
        level, level_u, noise_sigma, nodes = measured_level(xi_pts, y, fitted_pts, xi, roller)
        plausible.update(noise_sigma=noise_sigma, nodes=nodes)
    n_draws = draws
    pick = np.arange(n_draws) % len(thetas)
    up = geo.profile_radius_uncertainty
    uc = up if rail.crown_radius_uncertainty is None else rail.crown_radius_uncertainty
    wx = geo.wheel_radius_x + geo.wheel_radius_tolerance * rng.uniform(-1, 1, n_draws)
    rx = geo.roller_radius_x + geo.roller_radius_tolerance * rng.uniform(-1, 1, n_draws)
    wy = geo.wheel_radius_y * np.clip(1 + up * rng.standard_normal(n_draws), 0.2, None)
    ry = geo.roller_radius_y * np.clip(1 + up * rng.standard_normal(n_draws), 0.2, None)
    if rail.crown_radius is None:
        cr = ry  # the same crown as the roller's, by definition of the comparison
    else:
        cr = rail.crown_radius * np.clip(1 + uc * rng.standard_normal(n_draws), 0.2, None)
    delta = (
        np.zeros(n_draws) if not coa_systematic else coa_systematic * rng.standard_normal(n_draws)
    )
    z_level = rng.standard_normal(n_draws)
    # The law's error in the factor, a bound: nil where the factor is the stiffness ratio
    # (small creepage), up to LAW_FACTOR_ERROR once the curve has left its linear part.
    rise = np.clip(roller / np.max(roller) / LAW_FACTOR_ERROR_ONSET, 0.0, 1.0)
    law_half_width = LAW_FACTOR_ERROR[law] * rise if law_error else np.zeros_like(xi)
    roller_d = np.empty((n_draws, xi.size))
    track_d = np.empty((n_draws, xi.size))
    law_roller_d = np.empty((n_draws, xi.size))
    law_track_d = np.empty((n_draws, xi.size))
    factor_d = np.empty((n_draws, xi.size))
    ratio_k = np.empty(n_draws)
    say(f"{n_draws} draws of the geometry and the parameters")
    for i in range(n_draws):
        r_e, t_e = ellipses(wx[i], wy[i], rx[i], ry[i], cr[i])
        th = thetas[pick[i]]
        f_i = factor_of(th, r_e, t_e)
        if construction == MODEL:
            base = law_on(th, roller_e)
        else:  # the law's own curves place the peaks (below); the model's draws do not need them
            base = level + level_u * z_level[i]
            law_roller_d[i] = law_on(th, r_e)
            law_track_d[i] = law_roller_d[i] * f_i
        factor_d[i] = f_i
        roller_d[i] = base * (1 + delta[i])
        track_d[i] = base * f_i * (1 + delta[i])
        ratio_k[i] = (t_e.a * t_e.b * t_e.c11) / (r_e.a * r_e.b * r_e.c11)
    lo, hi = 2.5, 97.5
    law_roller, law_track = roller, track
    if construction != MODEL:
        roller = level
        track = level * factor

    def band(x, central, bound=None):
        low, high = np.percentile(x, lo, axis=0), np.percentile(x, hi, axis=0)
        low, high = np.minimum(low, central), np.maximum(high, central)
        if bound is not None:
            low, high = low * (1.0 - bound), high * (1.0 + bound)
        return low, high

    roller_lo, roller_hi = band(roller_d, roller)
    track_lo, track_hi = band(track_d, track, law_half_width)
    factor_lo, factor_hi = band(factor_d, factor, law_half_width)

    # ---- peaks -------------------------------------------------------------------------------
    say("the peaks and their intervals")
    # Where the curve is the law's (model), its peak and the draws' give the interval. Where
    # it is the measured level, a noisy flat top cannot place the peak: the creepage is the
    # law's (fitted shape; interval from the plausible set's), the CoA the level's there.
    peaks = {}
    sides = (
        ("roller", roller, roller_d, law_roller, law_roller_d),
        ("track", track, track_d, law_track, law_track_d),
    )
    for name, curve, d, law_curve, law_d in sides:
        if construction == MODEL:
            k0 = int(np.argmax(curve))
            xd, cd = _peak(xi, d)
        else:
            k0 = int(np.argmax(law_curve))
            xd, _ = _peak(xi, law_d)
            cd = np.take_along_axis(d, np.argmax(law_d, axis=1)[:, None], axis=1)[:, 0]
        x0, c0 = float(xi[k0]), float(curve[k0])
        interior = bool(k0 < xi.size - 1)
        # The curve written (the CSV's, the figure's): where the law's shape places the peak,
        # the measured level can still have its own largest value elsewhere.
        km = int(np.argmax(curve))
        maximum = {
            "creepage [-]": float(xi[km]),
            "coa [-]": float(curve[km]),
            "inside_measured_range": bool(km < xi.size - 1),
        }
        if not interior:  # a bound: the peak CoA is at least the curve's largest
            c0 = max(c0, maximum["coa [-]"])
        x95 = [float(np.percentile(xd, lo)), float(np.percentile(xd, hi))]
        c95 = [float(np.percentile(cd, lo)), float(np.percentile(cd, hi))]
        peaks[name] = {
            "creepage [-]": x0,
            "creep [-]": float(rig_creep(x0)),
            "coa [-]": c0,
            "creepage_95 [-]": [min(x95[0], x0), max(x95[1], x0)],
            "coa_95 [-]": [min(c95[0], c0), max(c95[1], c0)],
            "inside_measured_range": interior,
            "curve_maximum": maximum,
        }
        if construction != MODEL:
            peaks[name]["located_by"] = (
                "the law's fitted shape (the measured level's flat top cannot place it); the "
                "CoA is the measured level's there"
            )
        if not interior:
            shape = "the law's fitted shape" if construction != MODEL else "the curve"
            peaks[name]["note"] = (
                f"{shape} still rises at the largest measured creepage: the peak is not "
                "inside the measured range; creepage [-] is the largest creepage and coa [-] "
                "the curve's largest CoA, both lower bounds"
                + (
                    f" (the curve written, the measured level, has its largest CoA, "
                    f"{maximum['coa [-]']:.4g}, inside the range at xi = "
                    f"{maximum['creepage [-]']:.4g}: curve_maximum)"
                    if maximum["inside_measured_range"]
                    else ""
                )
            )
    peaks["creepage_ratio roller/track [-]"] = (
        peaks["roller"]["creepage [-]"] / peaks["track"]["creepage [-]"]
    )

    # ---- what is what ------------------------------------------------------------------------
    k_roll = g * roller_e.a * roller_e.b * roller_e.c11
    k_track = g * track_e.a * track_e.b * track_e.c11
    elastic = {
        "what": "Hertz ellipse (exact), Kalker's C11, C22, C23 at its a/b (Kalker 1990 Table "
        "E.3), creep stiffness G a b C11, and the saturation shape of the law (for the "
        "modified FASTSIM, of the strip theory with its parameters), computed on both "
        "geometries at the same load",
        "combined_shear_modulus [Pa]": g,
        "combined_poisson [-]": nu,
        "roller": side_summary(roller_e, g),
        "track": side_summary(track_e, g),
        "ratio_track_over_roller": {
            "semi_axis_x": track_e.a / roller_e.a,
            "semi_axis_y": track_e.b / roller_e.b,
            "area": track_e.area / roller_e.area,
            "C11": track_e.c11 / roller_e.c11,
            "creep_stiffness": k_track / k_roll,
            "creep_stiffness_95": [
                float(np.percentile(ratio_k, lo)),
                float(np.percentile(ratio_k, hi)),
            ],
        },
    }
    values = dict(zip(names, theta.tolist(), strict=True))
    surface = {
        "what": (
            "Polach's kA, kS (reduction of the initial slope) and mu0, A, B (friction level and "
            "its fall with slip velocity)"
            if law == "polach"
            else "the modified FASTSIM's k0, alpha_inf, beta (reduction of the initial slope) "
            "and mu0, A, B (friction level and its fall with slip velocity)"
        ),
        "parameters": values,
        "stderr": {k: (float(v) if np.isfinite(v) else None) for k, v in fit.stderr.items()},
        "identifiable": bool(fit.identifiable),
        "assumption": "carried over from the roller to the rail unchanged: the rail's surface, "
        "third body and temperature are taken to be the rig's",
    }
    assumptions = [
        "The surface parameters fitted on the roller (" + ", ".join(names) + ") hold on the "
        "rail unchanged: what the roller's and the rail's surfaces differ in is not in the "
        "prediction nor in its band.",
        f"Same normal load ({n_ref:.0f} N) and rolling speed (V = {v_ref * 3.6:.3g} km/h, "
        f"{v_is}) on roller and rail; the curves are compared at equal creepage, hence equal "
        "slip velocity.",
        "Same steel on both sides (E, nu of the rig file); Hertz half-space contact, "
        "longitudinal creepage only (no lateral creepage or spin).",
        f"Rail: {rail.describe(geo.roller_radius_y)}.",
        f"The prediction spans the measured creepage (xi up to {xi_max:.4g}); beyond it the "
        "surface parameters would be extrapolated.",
        (
            f"The law's own error in the transfer factor, up to {LAW_FACTOR_ERROR[law]:.2%} "
            "against Kalker's exact theory (CONTACT) on the bundled rig's roller and a tangent "
            "rail, is in the band (a bound on its edges); on other geometries it is assumed to "
            "be no larger."
            if law_error
            else f"The law's own error in the transfer factor (up to {LAW_FACTOR_ERROR[law]:.2%} "
            "against Kalker's exact theory on the bundled rig) is not in the band."
        ),
    ]
    if construction == MODEL:
        parameter_input = {
            "name": f"{law} surface parameters",
            "distribution": "multivariate normal, the fit's covariance"
            + (
                f" x {inflation:.3g}^2 (AR(1) factor of the structured residuals)"
                if inflation > 1
                else ""
            )
            + "; draws outside the parameters' bounds drawn again (never clipped)",
        }
        level_text = "the law's curve fitted on the roller (each draw: the law at its parameters)"
    else:
        parameter_input = {
            "name": f"{law} surface parameters (through the transfer factor only)",
            "distribution": "the plausible set: Beale's 95 % region S(theta) <= "
            f"{plausible['sse_limit']:.3g} (S(theta_fit) = {plausible['sse_fit']:.3g}, on "
            f"{plausible['points']} points), sampled from the fit's covariance at scale "
            f"{plausible['scale']:g} (acceptance {plausible['acceptance']:.2f}); "
            f"{len(thetas)} parameter sets, the fit's among them",
        }
        level_text = (
            "the measured points: the law's curve plus its residuals smoothed by a cubic "
            f"smoothing spline on {plausible['nodes']} nodes (smoothing by generalised "
            "cross-validation); its random scatter from the points' noise u = "
            f"{plausible['noise_sigma']:.3g} (CoA, pseudo-residuals) through the spline, normal"
        )
    method = {
        "method": "Monte Carlo propagation of distributions (JCGM 101); 95 % probabilistically "
        "symmetric interval (2.5-97.5 % quantiles) at each creepage, widened to hold the "
        "central curve and by the law's error bound",
        "construction": construction,
        "construction_why": why,
        "roller_level": level_text,
        "draws": draws,
        "seed": int(seed),
        "inputs": [
            parameter_input,
            {
                "name": "wheel and roller rolling radii",
                "distribution": f"rectangular, half-widths {geo.wheel_radius_tolerance:g} m and "
                f"{geo.roller_radius_tolerance:g} m (the rig's stated tolerances)",
            },
            {
                "name": "transverse profile radii (wheel, roller"
                + (", rail crown = roller's" if rail.crown_radius is None else ", rail crown")
                + ")",
                "distribution": f"normal, relative standard uncertainty {up:g}"
                + ("" if rail.crown_radius is None else f" (crown {uc:g})")
                + " (a stated assumption)",
            },
        ],
        "geometry_enters": "through the transfer factor f(track)/f(roller): the measured curve "
        "on the roller is what it is",
        "not_included": [
            "differences between the rig's and the rail's surfaces",
            "E and nu (same steel on both sides)",
        ],
        "covariance_inflation [-]": inflation,
    }
    if construction == MODEL:
        method["not_included"].insert(
            0, "the law's error in fitting the measured points (see the fit's residual structure)"
        )
    else:
        method["plausible_set"] = {
            "sse_fit [CoA2]": plausible["sse_fit"],
            "sse_limit [CoA2]": plausible["sse_limit"],
            "points": plausible["points"],
            "scale [-]": plausible["scale"],
            "acceptance [-]": plausible["acceptance"],
            "parameter_sets": len(thetas),
            "noise_sigma [-]": plausible["noise_sigma"],
            "spline_nodes": plausible["nodes"],
        }
    if law_error:
        method["inputs"].append(
            {
                "name": f"the law's error in the transfer factor ({law})",
                "distribution": f"a bound, not drawn: the band's edges times 1 -/+ "
                f"{LAW_FACTOR_ERROR[law]:g} (the largest error measured against CONTACT's "
                f"exact theory), scaled by the roller curve's rise to "
                f"{LAW_FACTOR_ERROR_ONSET:g} of its peak",
            }
        )
    else:
        method["not_included"].append("the law's error in the transfer factor")
    if coa_systematic:
        method["inputs"].append(
            {
                "name": "systematic error of the measured CoA",
                "distribution": f"normal, common factor 1 + delta, u(delta) = {coa_systematic:g}",
            }
        )
    else:
        method["not_included"].append(
            "the systematic uncertainty of the measured CoA (rig load, torque class, arm): "
            "give coa_systematic to include it"
        )
    notes.append(f"band construction: {construction} ({why})")
    if construction != MODEL:
        notes.append(
            "the rail curve is the measured roller level times the law's transfer factor: the "
            "law's fit on the roller is used only for the ratio of the two ellipses"
        )
    return TransferResult(
        law=law,
        creepage=xi,
        creep=s,
        slip_velocity=w,
        roller=roller,
        roller_low=roller_lo,
        roller_high=roller_hi,
        track=track,
        track_low=track_lo,
        track_high=track_hi,
        factor=factor,
        factor_low=factor_lo,
        factor_high=factor_hi,
        normal_load=n_ref,
        rolling_speed=float(v_ref),
        geometry=geo,
        rail=rail,
        elastic=elastic,
        surface=surface,
        fit=fit,
        peaks=peaks,
        band=method,
        assumptions=assumptions,
        notes=notes,
        measured=measured,
        rolling_speed_is=v_is,
    )
