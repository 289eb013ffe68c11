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
:func:`rollerrig.fit.modified_fastsim.fit_modified_fastsim`), then evaluates the same law with
the same surface parameters on the rail's ellipse at the same normal load and rolling speed.
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

Uncertainty band (Monte Carlo, JCGM 101)
----------------------------------------
Each draw takes (i) the law's surface parameters from a normal distribution with the fit's
covariance, inflated by the AR(1) factor of its residual structure (stated), clipped to the
parameters' bounds; (ii) the geometry: wheel and roller rolling radii rectangular within the
rig's stated tolerances (``sensors.wheel_radius_tolerance``, ``roller_radius_tolerance``), the
transverse profile radii (wheel, roller, rail crown) normal with a stated relative standard
uncertainty; (iii) optionally a common relative systematic error of the measured CoA. The
measured curve is what it is: a draw's geometry enters through the transfer factor,

.. math:: \\mathrm{CoA}_\\mathrm{track} = \\mathrm{CoA}_\\mathrm{roller}(\\theta)\\,
          \\frac{f(\\theta, \\mathrm{track})}{f(\\theta, \\mathrm{roller})}\\,(1 + \\delta),

with f the law on the drawn ellipse. The band is the 2.5-97.5 % interval of the draws at each
creepage. Not in the band: the model error of the law (the fit's residual structure says how
large it is on the rig), the difference of the surfaces, E and ν (same steel on both sides).

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

import csv
import json
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from rollerrig._validation import ParameterError, require_finite, require_positive
from rollerrig.contact.creep import polach_force_kernel as _polach_force_kernel
from rollerrig.contact.fastsim import FastsimGrid, fastsim_grid
from rollerrig.contact.hertz import combined_elastic_constants, hertz_contact
from rollerrig.contact.kalker import kalker_coefficients
from rollerrig.contact.laws import check_law

__all__ = [
    "CSV_COLUMNS",
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

LAW_FACTOR_ERROR = (
    "on the rig's roller and a tangent rail with its crown (a/b of the ellipses 0.37 and "
    "0.33, Coulomb friction), the factor F_rail/F_roller of Polach's law differs from the "
    "strip theory's (FaStrip, within 0.003 of mu N of CONTACT's exact theory) by under 0.2 % "
    "at small creepage and by up to 3.6 % in the transition to full sliding (mu 0.33), "
    "FASTSIM's by up to 3.4 %."
)
"""The measured shape error of the transfer factor by law (tests/contact/test_transfer.py)."""

TRANSFER_LAWS = ("polach", "modified-fastsim")
"""Laws a transfer can use: those with parameters for the measured slope reduction."""

CSV_COLUMNS = {
    "creep": ("required", {"-": 1.0, "1": 1.0, "%": 0.01}),
    "coa": ("required", {"-": 1.0, "1": 1.0}),
    "slip_velocity": ("optional", {"m/s": 1.0}),
    "normal_load": ("optional", {"N": 1.0, "kN": 1e3}),
    "rolling_speed": ("optional", {"m/s": 1.0, "km/h": 1 / 3.6}),
    "coa_uncertainty": ("optional", {"-": 1.0, "1": 1.0}),
}
"""Columns of a creep-curve CSV, ``name [unit]``: whether required, and the units accepted
(with the factor to SI). ``creep`` is the rig's (Kayaalp eq. 4.21) unless stated otherwise;
``rolling_speed`` the roller's peripheral speed; ``coa_uncertainty`` a standard uncertainty."""

_MIN_POINTS = 10


def kalker_creepage(creep):
    """Kalker's creepage ξ (mean rolling speed) from the rig's creep s (roller speed).

    .. math:: \\xi = \\frac{w}{(v_w + v_r)/2} = \\frac{2s}{2+s}, \\quad s = \\frac{w}{v_r}

    Parameters
    ----------
    creep : array_like
        s [-] (Kayaalp eq. 4.21), s > −2.

    Returns
    -------
    numpy.ndarray
        ξ [-].

    Examples
    --------
    >>> float(kalker_creepage(0.02))
    0.019801980198019802
    >>> float(rig_creep(kalker_creepage(0.02)))
    0.02
    """
    s = require_finite("creep", creep, "-")
    if np.any(s <= -2.0):
        raise ParameterError("creep s must be above -2 (the wheel would turn backwards)")
    return 2.0 * s / (2.0 + s)


def rig_creep(creepage):
    """The rig's creep s (roller speed, Kayaalp eq. 4.21) from Kalker's creepage ξ.

    .. math:: s = \\frac{2\\xi}{2-\\xi}

    Parameters
    ----------
    creepage : array_like
        ξ [-], |ξ| < 2.

    Returns
    -------
    numpy.ndarray
        s [-].

    Examples
    --------
    >>> round(float(rig_creep(0.1)), 6)
    0.105263
    """
    xi = require_finite("creepage", creepage, "-")
    if np.any(np.abs(xi) >= 2.0):
        raise ParameterError("Kalker's creepage must lie in (-2, 2)")
    return 2.0 * xi / (2.0 - xi)


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
class MeasuredCurve:
    """Creep–CoA points measured on the rig.

    Attributes
    ----------
    creep : ndarray
        The rig's creep s [-] (Kayaalp eq. 4.21, referred to the roller speed).
    coa : ndarray
        CoA F/N [-] on the contact's load.
    slip_velocity : ndarray
        w [m/s].
    normal_load : ndarray
        Contact load N at each point [N].
    rolling_speed : ndarray
        Roller peripheral speed at each point [m/s].
    coa_uncertainty : ndarray or None
        Standard uncertainty of each CoA [-].
    source : str
        Where the points came from.
    notes : tuple of str
        What the reader found or assumed.
    analysis_fit : dict or None
        The analysis's own Polach fit (from its JSON), for comparison.
    rig_sha256 : str or None
        The rig the analysis was made with.
    """

    creep: np.ndarray
    coa: np.ndarray
    slip_velocity: np.ndarray
    normal_load: np.ndarray
    rolling_speed: np.ndarray
    coa_uncertainty: np.ndarray | None = None
    source: str = ""
    notes: tuple[str, ...] = ()
    analysis_fit: dict | None = None
    rig_sha256: str | None = None

    @property
    def creepage(self) -> np.ndarray:
        """Kalker's creepage ξ [-] of the points."""
        return kalker_creepage(self.creep)


# --------------------------------------------------------------------------------------------
# Readers
# --------------------------------------------------------------------------------------------


def _analysis_paths(path: Path) -> tuple[Path, Path]:
    name = path.name
    for suffix in ("-analysis.json", "-analysis.nc"):
        if name.endswith(suffix):
            stem = name[: -len(suffix)]
            return path.with_name(f"{stem}-analysis.json"), path.with_name(f"{stem}-analysis.nc")
    raise ParameterError(
        f"{path}: not an analysis of `rollerrig analyze` (expected <name>-analysis.json or "
        "<name>-analysis.nc beside each other)"
    )


_ANALYSIS_CHANNELS = (
    "creep_smoothed",
    "coa_corrected",
    "slip_velocity_smoothed",
    "normal_load",
    "roller_speed",
)


def read_analysis(path, rig=None) -> MeasuredCurve:
    """The ascending-branch creep–CoA points of a ``rollerrig analyze`` result.

    Reads ``<name>-analysis.json`` (the phases, the Polach fit, the rig's hash) and
    ``<name>-analysis.nc`` (the channels) beside it, and takes the points the analysis's fits
    took: the ascending branches of every cycle
    (:func:`rollerrig.measure.segmentation.adhesion_branches` on the smoothed creep), creep
    above 1e-4 and corrected CoA above 0.01; the CoA corrected for the rig's dynamics, on the
    contact's load N = (S + W_d)/(1 − σ(h/l)·CoA) (the swinging arm, the rig's ``[arm]``).

    Parameters
    ----------
    path : str or path-like
        ``<name>-analysis.json`` or ``<name>-analysis.nc``.
    rig : RigParameters, optional
        The rig the analysis was made with (default the bundled rig); a different hash from
        the analysis's is noted.

    Returns
    -------
    MeasuredCurve

    Raises
    ------
    ParameterError
        A missing or unreadable file, a missing channel or phase list, too few points.
    """
    import xarray as xr

    from rollerrig.measure.segmentation import Phase
    from rollerrig.output import rig_sha256
    from rollerrig.rig.parameters import default_rig

    json_path, nc_path = _analysis_paths(Path(path))
    for p in (json_path, nc_path):
        if not p.is_file():
            raise ParameterError(f"{p}: missing; `rollerrig analyze` writes both files")
    try:
        summary = json.loads(json_path.read_text())
    except (OSError, ValueError) as exc:
        raise ParameterError(f"{json_path}: not readable as JSON ({exc})") from None
    if not isinstance(summary, dict) or not isinstance(summary.get("phases"), list):
        raise ParameterError(f"{json_path}: no 'phases' list: not an analysis summary")
    try:
        phases = [
            Phase(str(p["name"]), float(p["start [s]"]), float(p["end [s]"]), int(p["cycle"]))
            for p in summary["phases"]
        ]
    except (KeyError, TypeError, ValueError) as exc:
        raise ParameterError(f"{json_path}: a phase lacks name/start/end/cycle ({exc})") from None
    try:
        ds = xr.load_dataset(nc_path, engine="h5netcdf")
    except Exception as exc:  # any reader fault: one message naming the file
        raise ParameterError(f"{nc_path}: not readable as NetCDF ({type(exc).__name__})") from None
    missing = [c for c in _ANALYSIS_CHANNELS if c not in ds]
    if missing:
        raise ParameterError(f"{nc_path}: channels {missing} missing (an analysis has them)")
    rig = default_rig() if rig is None else rig
    notes = []
    analysed_with = (summary.get("provenance") or {}).get("rig") or {}
    if analysed_with.get("sha256") and analysed_with["sha256"] != rig_sha256(rig):
        notes.append(
            f"the analysis was made with rig {analysed_with.get('name')!r} "
            f"(sha256 {str(analysed_with['sha256'])[:12]}...), not the rig given here "
            f"({rig.meta.name!r}, {rig_sha256(rig)[:12]}...): pass the analysis's rig with --rig"
        )
    u = None
    if "coa_corrected_standard_uncertainty" in ds:
        u = np.asarray(ds["coa_corrected_standard_uncertainty"].values, float)
    channels = {name: np.asarray(ds[name].values, float) for name in _ANALYSIS_CHANNELS}
    return _curve_from_channels(
        np.asarray(ds["time"].values, float),
        channels,
        u,
        phases,
        rig,
        source=str(json_path),
        notes=notes,
        fit=summary.get("polach_fit_corrected_coa"),
        sha=analysed_with.get("sha256"),
        where=str(nc_path),
    )


def curve_from_analysis(result, rig=None) -> MeasuredCurve:
    """The ascending-branch creep–CoA points of an analysis in memory
    (:func:`rollerrig.analysis.adhesion.analyze_test`'s result), as :func:`read_analysis`
    takes them from its files.

    Parameters
    ----------
    result : TestAnalysis
        The analysis.
    rig : RigParameters, optional
        The rig it was made with (its ``[arm]`` puts the CoA on the contact's load); default
        the bundled rig.

    Returns
    -------
    MeasuredCurve

    Raises
    ------
    ParameterError
        Too few points or a missing channel.
    """
    from rollerrig.rig.parameters import default_rig

    rig = default_rig() if rig is None else rig
    rec = result.recording
    missing = [c for c in _ANALYSIS_CHANNELS if c not in rec]
    if missing:
        raise ParameterError(f"the analysis has no channels {missing}")
    channels = {name: np.asarray(rec[name], float) for name in _ANALYSIS_CHANNELS}
    u = None
    budget = getattr(result, "coa_uncertainty", None)
    if budget is not None:
        unc = budget.uncertainty
        u = np.interp(rec.time, unc.time, np.asarray(unc.u, float))
    fit = result.summary().get("polach_fit_corrected_coa") if hasattr(result, "summary") else None
    return _curve_from_channels(
        np.asarray(rec.time, float),
        channels,
        u,
        list(result.phases),
        rig,
        source="the analysis",
        notes=[],
        fit=fit,
        sha=getattr(result, "rig_sha256", None),
        where="the analysis",
    )


def _curve_from_channels(t, ch, u, phases, rig, *, source, notes, fit, sha, where):
    """The points the analysis's fits took (ascending branches, creep > 1e-4, CoA > 0.01) on
    the contact's load of the rig's arm."""
    from rollerrig.measure.segmentation import adhesion_branches

    creep = ch["creep_smoothed"]
    coa = ch["coa_corrected"]
    branches = adhesion_branches(t, creep, phases)
    points = np.array([], dtype=int)
    if branches:
        points = np.concatenate([br.ascending for br in branches])
        points = points[(creep[points] > 1e-4) & (coa[points] > 0.01)]
    points = points[np.isfinite(creep[points]) & np.isfinite(coa[points])]
    if points.size < _MIN_POINTS:
        raise ParameterError(
            f"{where}: {points.size} ascending-branch points with creep > 1e-4 and CoA > 0.01"
            f", {_MIN_POINTS} needed"
        )
    spring = ch["normal_load"][points]
    arm = rig.arm
    load = (spring + arm.dead_weight) / (1.0 - arm.transfer_ratio * coa[points])
    speed = ch["roller_speed"][points] * rig.geometry.roller_radius_x
    if u is not None:
        u = u[points]
        if not np.all(np.isfinite(u)):
            u = None
    if isinstance(fit, dict) and fit.get("points") not in (None, points.size):
        notes.append(
            f"the analysis's Polach fit used {fit.get('points')} points, {points.size} read here"
        )
    notes.append(
        f"{points.size} ascending-branch points of {len(branches)} cycle(s): corrected CoA on the"
        f" contact's load (swinging arm h/l = {arm.transfer_ratio:.3g}, W_d = "
        f"{arm.dead_weight:g} N), smoothed creep (Kayaalp eq. 4.21) and slip velocity"
    )
    return MeasuredCurve(
        creep=creep[points],
        coa=coa[points],
        slip_velocity=ch["slip_velocity_smoothed"][points],
        normal_load=load,
        rolling_speed=speed,
        coa_uncertainty=u,
        source=source,
        notes=tuple(notes),
        analysis_fit=fit if isinstance(fit, dict) else None,
        rig_sha256=sha,
    )


def _parse_header(cell: str, path) -> tuple[str, str | None]:
    text = cell.strip()
    if text.endswith("]") and "[" in text:
        name, unit = text[:-1].split("[", 1)
        return name.strip().lower(), unit.strip()
    return text.lower(), None


def read_curve_csv(
    path,
    *,
    creepage: str = "roller",
    normal_load: float | None = None,
    rolling_speed: float | None = None,
) -> MeasuredCurve:
    """Creep–CoA points from a CSV with named columns and units (:data:`CSV_COLUMNS`).

    The header names each column as ``name [unit]``: ``creep [-]`` or ``creep [%]`` and
    ``coa [-]`` are required; ``slip_velocity [m/s]``, ``normal_load [N]`` (or ``[kN]``),
    ``rolling_speed [m/s]`` (or ``[km/h]``) and ``coa_uncertainty [-]`` are optional, the load
    and speed then given as arguments. Other columns are ignored. The rows are points of one
    traction curve (creep ≥ 0), sorted by creep.

    Parameters
    ----------
    path : str or path-like
        The CSV (comma-separated, one header row; lines starting with ``#`` are skipped).
    creepage : {"roller", "mean"}
        What ``creep`` is referred to: the roller speed (the rig's, Kayaalp eq. 4.21) or the
        mean rolling speed (Kalker's ξ; converted to the rig's with :func:`rig_creep`).
    normal_load : float, optional
        N [N] of every point, when the file has no ``normal_load`` column.
    rolling_speed : float, optional
        Roller speed [m/s] of every point, when the file has no ``rolling_speed`` column.

    Returns
    -------
    MeasuredCurve

    Raises
    ------
    ParameterError
        Naming the file, the column and the row: a missing column or unit, an unknown unit, a
        cell that is not a number, NaN or inf, creep that decreases or is negative, a CoA
        beyond ±2, a non-positive load or speed, fewer than 10 points.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "c.csv"
    >>> rows = ["creep [%],coa [-]"] + [f"{0.2 * i},{0.04 * i}" for i in range(1, 12)]
    >>> _ = p.write_text("\\n".join(rows))
    >>> c = read_curve_csv(p, normal_load=4300.0, rolling_speed=8.33)
    >>> round(float(c.creep[-1]), 6), bool(np.isclose(c.slip_velocity[0], 0.002 * 8.33))
    (0.022, True)
    """
    path = Path(path)
    if creepage not in ("roller", "mean"):
        raise ParameterError(f"creepage must be 'roller' or 'mean', got {creepage!r}")
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise ParameterError(f"{path}: not readable as a text CSV ({exc})") from None
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise ParameterError(f"{path}: empty (a header row 'creep [-],coa [-]' and points needed)")
    try:
        rows = list(csv.reader(lines))
    except csv.Error as exc:
        raise ParameterError(f"{path}: not a CSV ({exc})") from None
    header = [_parse_header(c, path) for c in rows[0]]
    names = [h[0] for h in header]
    index: dict[str, tuple[int, float]] = {}
    for i, (name, unit) in enumerate(header):
        if name not in CSV_COLUMNS:
            continue
        if name in index:
            raise ParameterError(f"{path}: column {name!r} appears twice")
        units = CSV_COLUMNS[name][1]
        if unit is None:
            raise ParameterError(
                f"{path}: column {name!r} has no unit: write '{name} [{next(iter(units))}]' "
                f"(units accepted: {', '.join(units)})"
            )
        if unit not in units:
            raise ParameterError(
                f"{path}: column '{name} [{unit}]': unit {unit!r} not accepted for {name} "
                f"(accepted: {', '.join(units)})"
            )
        index[name] = (i, units[unit])
    required = [n for n, (kind, _) in CSV_COLUMNS.items() if kind == "required"]
    lacking = [n for n in required if n not in index]
    if lacking:
        raise ParameterError(
            f"{path}: required column(s) {lacking} missing (found: {names}); the header needs "
            "'creep [-]' (or [%]) and 'coa [-]'"
        )
    data: dict[str, list[float]] = {n: [] for n in index}
    for r, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise ParameterError(f"{path}, row {r}: {len(row)} cells, the header has {len(header)}")
        for name, (i, factor) in index.items():
            try:
                value = float(row[i])
            except ValueError:
                raise ParameterError(
                    f"{path}, row {r}, column {name!r}: {row[i]!r} is not a number"
                ) from None
            if not math.isfinite(value):
                raise ParameterError(f"{path}, row {r}, column {name!r}: {row[i]!r} (not finite)")
            data[name].append(value * factor)
    arrays = {n: np.asarray(v, float) for n, v in data.items()}
    n = arrays["creep"].size
    if n < _MIN_POINTS:
        raise ParameterError(f"{path}: {n} points, at least {_MIN_POINTS} needed")
    s = arrays["creep"]
    if np.any(s < 0):
        r = int(np.flatnonzero(s < 0)[0]) + 2
        raise ParameterError(
            f"{path}, row {r}: negative creep; give one traction curve with creep >= 0 (mirror a "
            "braking curve: creep and CoA both negated)"
        )
    if np.any(np.diff(s) < 0):
        r = int(np.flatnonzero(np.diff(s) < 0)[0]) + 3
        raise ParameterError(
            f"{path}, row {r}: creep decreases (non-monotonic): the rows must be points of one "
            "ascending curve sorted by creep (a descending branch or a second test does not "
            "belong in the same file)"
        )
    if s[-1] >= 1.0:
        raise ParameterError(
            f"{path}: creep reaches {s[-1]:g} [-], 100 % or more: is it in per cent? label the "
            "column 'creep [%]'"
        )
    if creepage == "mean":
        s = rig_creep(s)
    y = arrays["coa"]
    if np.any(np.abs(y) > 2.0):
        r = int(np.flatnonzero(np.abs(y) > 2.0)[0]) + 2
        raise ParameterError(f"{path}, row {r}: CoA {y[r - 2]:g} beyond +-2: not a CoA [-]")
    if np.count_nonzero(s > 0) < _MIN_POINTS:
        raise ParameterError(f"{path}: fewer than {_MIN_POINTS} points with creep > 0")

    def per_point(name, given, unit, option):
        if name in arrays:
            if given is not None:
                raise ParameterError(f"{path}: the file has a {name} column; do not give {option}")
            v = arrays[name]
        elif given is None:
            raise ParameterError(
                f"{path}: no '{name} [{unit}]' column: give {option} for every point"
            )
        else:
            v = np.full(n, float(given))
        if np.any(v <= 0):
            raise ParameterError(f"{path}: {name} must be > 0 [{unit}]")
        return v

    q = per_point("normal_load", normal_load, "N", "the normal load")
    v = per_point("rolling_speed", rolling_speed, "m/s", "the rolling speed")
    w = arrays.get("slip_velocity", s * v)
    u = arrays.get("coa_uncertainty")
    if u is not None and np.any(u < 0):
        raise ParameterError(f"{path}: coa_uncertainty must be >= 0 [-]")
    notes = [
        f"{n} points from {path.name}; creep referred to the "
        + ("roller speed (Kayaalp eq. 4.21)" if creepage == "roller" else "mean rolling speed "
           "(Kalker), converted to the rig's: s = 2 xi/(2 - xi)")
    ]  # fmt: skip
    if "slip_velocity" not in arrays:
        notes.append("slip velocity w = s v (no slip_velocity column)")
    return MeasuredCurve(s, y, np.asarray(w, float), q, v, u, str(path), tuple(notes))


# --------------------------------------------------------------------------------------------
# The law on an ellipse
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Ellipse:
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


def _ellipse(load, rx_wheel, ry_wheel, rx_other, ry_other, e, nu_combined, nu):
    c = hertz_contact(load, rx_wheel, ry_wheel, rx_other, ry_other, youngs_modulus=e, poisson=nu)
    a, b = float(c.semi_axis_x), float(c.semi_axis_y)
    k = kalker_coefficients(a / b, nu_combined)
    return _Ellipse(
        a, b, float(k.c11), float(k.c22), float(k.c23), float(c.area), float(c.peak_pressure)
    )


def _law_coa(law, theta, xi, w, load, ell: _Ellipse, g, nu, grid):
    """CoA of the law with surface parameters ``theta`` on ellipse ``ell`` at one load."""
    if law == "polach":
        mu0, aa, bb, ka, ks = theta
        k = g * ell.a * ell.b * ell.c11
        return _polach_force_kernel(xi, w, load, k, mu0, aa, bb, ka, ks) / load
    from rollerrig.fit.modified_fastsim import coa_kernel as _coa_kernel

    return _coa_kernel(xi, w, load, ell.a, ell.b, g, nu, np.asarray(theta), grid)


_POLACH_NAMES = ("static_friction", "limit_ratio", "friction_decay", "k_adhesion", "k_slip")
_POLACH_LOWER = np.array([1e-3, 1e-6, 0.0, 1e-6, 1e-6])
_POLACH_UPPER = np.array([2.0, 1.0, 50.0, 1.0, 1.0])  # draws only: clip to physical range


def _clip_draws(law, draws):
    if law == "polach":
        out = np.clip(draws, _POLACH_LOWER, _POLACH_UPPER)
        out[:, 4] = np.minimum(out[:, 4], out[:, 3])
        return out
    from rollerrig.fit.modified_fastsim import PARAMETER_LOWER as _LOWER
    from rollerrig.fit.modified_fastsim import PARAMETER_UPPER as _UPPER

    return np.clip(draws, _LOWER, _UPPER)


# --------------------------------------------------------------------------------------------
# The result
# --------------------------------------------------------------------------------------------


@dataclass
class TransferResult:
    """What :func:`transfer_curve` predicts, with the band and every stated assumption.

    Attributes
    ----------
    law : str
        The creep law.
    creepage : ndarray
        Kalker's ξ of the output grid [-].
    creep : ndarray
        The same creepage referred to the roller (rig) or rail (track) speed, s [-].
    slip_velocity : ndarray
        w = s·V [m/s].
    roller, roller_low, roller_high : ndarray
        The fitted curve on the roller and its 95 % band [-].
    track, track_low, track_high : ndarray
        The predicted curve on the rail and its 95 % band [-].
    factor, factor_low, factor_high : ndarray
        F_track/F_roller at equal creepage and its 95 % band [-].
    normal_load, rolling_speed : float
        N [N] and V [m/s] of both curves.
    geometry : ContactGeometry
    rail : RailGeometry
    elastic : dict
        The elastic part on each side (semi-axes, a/b, C_ij, creep stiffness), and ratios.
    surface : dict
        The surface parameters carried over, with standard errors.
    fit : PolachFit or ModifiedFastsimFit
    peaks : dict
        Peak creepage and CoA on each side with their 95 % intervals.
    band : dict
        How the band was made: method, draws, inputs, what is not in it.
    assumptions, notes : list of str
    measured : MeasuredCurve
    """

    law: str
    creepage: np.ndarray
    creep: np.ndarray
    slip_velocity: np.ndarray
    roller: np.ndarray
    roller_low: np.ndarray
    roller_high: np.ndarray
    track: np.ndarray
    track_low: np.ndarray
    track_high: np.ndarray
    factor: np.ndarray
    factor_low: np.ndarray
    factor_high: np.ndarray
    normal_load: float
    rolling_speed: float
    geometry: ContactGeometry
    rail: RailGeometry
    elastic: dict
    surface: dict
    fit: object
    peaks: dict
    band: dict
    assumptions: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    measured: MeasuredCurve | None = None

    @property
    def stiffness_ratio(self) -> float:
        """G·a·b·C11 on the rail over that on the roller [-] (the factor at ξ → 0)."""
        return self.elastic["ratio_track_over_roller"]["creep_stiffness"]

    def factor_at(self, creepage: float) -> float:
        """F_track/F_roller at Kalker creepage ``creepage`` [-] (linear interpolation)."""
        return float(np.interp(creepage, self.creepage, self.factor))

    def columns(self) -> dict:
        """The curves as columns for :func:`rollerrig.output.write_table` (name -> values,
        unit, long name)."""
        ref = "roller (rig) or rail (track) speed, Kayaalp eq. 4.21"
        return {
            "creepage_kalker": (self.creepage, "1", "creepage referred to the mean rolling speed"),
            "creep": (self.creep, "1", f"creep referred to the {ref}"),
            "slip_velocity": (self.slip_velocity, "m/s", "slip velocity w = s V"),
            "coa_roller": (self.roller, "1", f"CoA on the roller, {self.law} fitted"),
            "coa_roller_low95": (self.roller_low, "1", "2.5 % quantile of the roller CoA"),
            "coa_roller_high95": (self.roller_high, "1", "97.5 % quantile of the roller CoA"),
            "coa_track": (self.track, "1", "CoA predicted on the rail"),
            "coa_track_low95": (self.track_low, "1", "2.5 % quantile of the rail CoA"),
            "coa_track_high95": (self.track_high, "1", "97.5 % quantile of the rail CoA"),
            "factor": (self.factor, "1", "F_track / F_roller at equal creepage"),
            "factor_low95": (self.factor_low, "1", "2.5 % quantile of the factor"),
            "factor_high95": (self.factor_high, "1", "97.5 % quantile of the factor"),
        }

    def summary(self) -> dict:
        """JSON-ready: conditions, the elastic part, the surface part, factors, peaks, band,
        assumptions, the fit; units in the keys."""
        xi = self.creepage
        probes = [x for x in (0.001, 0.002, 0.005, 0.01, 0.02, 0.05) if x <= xi[-1]]
        fit = self.fit
        fit_summary = fit.summary() if hasattr(fit, "summary") else _polach_fit_summary(fit)
        return {
            "law": self.law,
            "source": None if self.measured is None else self.measured.source,
            "creepage": {
                "rig": "s = (omega_w r_w - omega_r r_r)/(omega_r r_r), referred to the roller "
                "speed (Kayaalp eq. 4.21); on track referred to the rail (vehicle) speed V",
                "kalker": "xi = w / ((v_wheel + v_roller)/2), referred to the mean rolling speed "
                "(Kalker); the laws are evaluated in xi",
                "conversion": "xi = 2 s/(2 + s), s = 2 xi/(2 - xi); w = s V",
                "compared_at": "equal creepage and equal speed, hence equal slip velocity",
            },
            "conditions": {
                "normal_load [N]": self.normal_load,
                "rolling_speed [m/s]": self.rolling_speed,
                "rail": self.rail.describe(self.geometry.roller_radius_y),
            },
            "geometry": self.geometry.to_dict(),
            "transferred_by_contact_mechanics": self.elastic,
            "carried_over_as_measured": self.surface,
            "transfer_factor": {
                "small_creepage (= creep stiffness ratio) [-]": self.stiffness_ratio,
                "at_creepage [-]": {f"{x:g}": self.factor_at(x) for x in probes},
                "at_roller_peak [-]": self.factor_at(self.peaks["roller"]["creepage [-]"]),
                "largest_creepage [-]": float(xi[-1]),
                "factor_at_largest_creepage [-]": float(self.factor[-1]),
            },
            "peaks": self.peaks,
            "band": self.band,
            "assumptions": self.assumptions,
            "notes": self.notes,
            "fit": fit_summary,
            "analysis_polach_fit": None if self.measured is None else self.measured.analysis_fit,
        }


def _polach_fit_summary(fit) -> dict:
    stderr = {k: (float(v) if np.isfinite(v) else None) for k, v in fit.stderr.items()}
    p = fit.parameters
    out = {
        "law": "polach",
        "parameters": {
            "mu0 [-]": p.static_friction,
            "A [-]": p.limit_ratio,
            "B [s/m]": p.friction_decay,
            "kA [-]": p.k_adhesion,
            "kS [-]": p.k_slip,
        },
        "stderr": stderr,
        "rmse [-]": float(fit.rmse),
        "dof": int(fit.dof),
        "points": int(fit.creep.size),
        "identifiable": bool(fit.identifiable),
        "at_bound": list(fit.at_bound),
        "residual_structure": None
        if fit.residual_structure is None
        else fit.residual_structure.as_dict(),
        "slip_velocity_coverage": None if fit.coverage is None else fit.coverage.as_dict(),
    }
    if any(v is None for v in stderr.values()):
        out["stderr_null_because"] = "J^T J singular: not determined by the data"
    return out


# --------------------------------------------------------------------------------------------
# The transfer
# --------------------------------------------------------------------------------------------


def _side_dict(ell: _Ellipse, g: float) -> dict:
    return {
        "semi_axis_x [m]": ell.a,
        "semi_axis_y [m]": ell.b,
        "a_over_b [-]": ell.a_over_b,
        "area [m2]": ell.area,
        "peak_pressure [Pa]": ell.p0,
        "C11 [-]": ell.c11,
        "C22 [-]": ell.c22,
        "C23 [-]": ell.c23,
        "creep_stiffness G a b C11 [N]": g * ell.a * ell.b * ell.c11,
    }


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
) -> TransferResult:
    """Predict the creep–CoA curve on the rail from one measured on the rig's roller.

    The chosen law's surface parameters are fitted to the measured points on the roller's
    Hertz ellipse and evaluated, unchanged, on the rail's ellipse at the same load and speed
    (module notes); the band is a Monte Carlo propagation of the fit's covariance and of the
    geometry's stated uncertainty.

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
        Seed of the draws.
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
    if draws < 50:
        raise ParameterError(f"draws must be at least 50, got {draws}")
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
    require_positive("normal_load", n_ref, "N")
    require_positive("rolling_speed", v_ref, "m/s")
    elastic_c = combined_elastic_constants(geo.youngs_modulus, geo.poisson, geo.youngs_modulus,
                                           geo.poisson)  # fmt: skip
    g, nu = float(elastic_c.shear_modulus), float(elastic_c.poisson)
    crown = geo.roller_radius_y if rail.crown_radius is None else rail.crown_radius
    rail_rx = rail.longitudinal_radius

    def ellipses(wx, wy, rx, ry, crown_r):
        roll = _ellipse(n_ref, wx, wy, rx, ry, geo.youngs_modulus, nu, geo.poisson)
        track = _ellipse(n_ref, wx, wy, rail_rx, crown_r, geo.youngs_modulus, nu, geo.poisson)
        return roll, track

    roller_e, track_e = ellipses(
        geo.wheel_radius_x, geo.wheel_radius_y, geo.roller_radius_x, geo.roller_radius_y, crown
    )

    # ---- the fit on the roller's ellipse (each point at its own load) ---------------------
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
            names = _POLACH_NAMES
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
        return _law_coa(law, theta_, xi, w, n_ref, ell, g, nu, grid)

    roller = law_on(theta, roller_e)
    track = law_on(theta, track_e)
    factor = track / roller

    # ---- Monte Carlo ------------------------------------------------------------------------
    rng = np.random.default_rng(seed)
    cov = np.array(fit.covariance, float)
    cov = np.where(np.isfinite(cov), cov, 0.0)
    structure = fit.residual_structure
    inflation = 1.0
    if inflate_for_structure and structure is not None and structure.structured:
        inflation = (
            float(structure.stderr_inflation) if np.isfinite(structure.stderr_inflation) else 1.0
        )
    cov = cov * inflation**2
    cov = 0.5 * (cov + cov.T)
    evals, evecs = np.linalg.eigh(cov)
    root = evecs * np.sqrt(np.clip(evals, 0.0, None))
    thetas = _clip_draws(law, theta + rng.standard_normal((draws, theta.size)) @ root.T)
    up = geo.profile_radius_uncertainty
    uc = up if rail.crown_radius_uncertainty is None else rail.crown_radius_uncertainty
    wx = geo.wheel_radius_x + geo.wheel_radius_tolerance * rng.uniform(-1, 1, draws)
    rx = geo.roller_radius_x + geo.roller_radius_tolerance * rng.uniform(-1, 1, draws)
    wy = geo.wheel_radius_y * np.clip(1 + up * rng.standard_normal(draws), 0.2, None)
    ry = geo.roller_radius_y * np.clip(1 + up * rng.standard_normal(draws), 0.2, None)
    if rail.crown_radius is None:
        cr = ry  # the same crown as the roller's, by definition of the comparison
    else:
        cr = rail.crown_radius * np.clip(1 + uc * rng.standard_normal(draws), 0.2, None)
    delta = np.zeros(draws) if not coa_systematic else coa_systematic * rng.standard_normal(draws)
    roller_d = np.empty((draws, xi.size))
    track_d = np.empty((draws, xi.size))
    ratio_k = np.empty(draws)
    for i in range(draws):
        r_e, t_e = ellipses(wx[i], wy[i], rx[i], ry[i], cr[i])
        base = law_on(thetas[i], roller_e)
        f_i = law_on(thetas[i], t_e) / law_on(thetas[i], r_e)
        roller_d[i] = base * (1 + delta[i])
        track_d[i] = base * f_i * (1 + delta[i])
        ratio_k[i] = (t_e.a * t_e.b * t_e.c11) / (r_e.a * r_e.b * r_e.c11)
    factor_d = track_d / roller_d
    lo, hi = 2.5, 97.5

    def band(x):
        return np.percentile(x, lo, axis=0), np.percentile(x, hi, axis=0)

    roller_lo, roller_hi = band(roller_d)
    track_lo, track_hi = band(track_d)
    factor_lo, factor_hi = band(factor_d)

    # ---- peaks -------------------------------------------------------------------------------
    peaks = {}
    for name, curve, d in (("roller", roller, roller_d), ("track", track, track_d)):
        x0, c0 = _peak(xi, curve[None])
        xd, cd = _peak(xi, d)
        interior = bool(np.argmax(curve) < xi.size - 1)
        peaks[name] = {
            "creepage [-]": float(x0[0]),
            "creep [-]": float(rig_creep(x0[0])),
            "coa [-]": float(c0[0]),
            "creepage_95 [-]": [float(np.percentile(xd, lo)), float(np.percentile(xd, hi))],
            "coa_95 [-]": [float(np.percentile(cd, lo)), float(np.percentile(cd, hi))],
            "inside_measured_range": interior,
        }
        if not interior:
            peaks[name]["note"] = (
                "the curve still rises at the largest measured creepage: the peak is not "
                "inside the measured range"
            )
    peaks["creepage_ratio roller/track [-]"] = (
        peaks["roller"]["creepage [-]"] / peaks["track"]["creepage [-]"]
    )

    # ---- what is what ------------------------------------------------------------------------
    k_roll = g * roller_e.a * roller_e.b * roller_e.c11
    k_track = g * track_e.a * track_e.b * track_e.c11
    elastic = {
        "what": "Hertz ellipse (exact), Kalker's C11, C22, C23 at its a/b (Kalker 1990 Table "
        "E.3), creep stiffness G a b C11, and the saturation shape of the law, computed on "
        "both geometries at the same load",
        "combined_shear_modulus [Pa]": g,
        "combined_poisson [-]": nu,
        "roller": _side_dict(roller_e, g),
        "track": _side_dict(track_e, g),
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
        f"Same normal load ({n_ref:.0f} N) and rolling speed ({v_ref:.3g} m/s) on both; the "
        "curves are compared at equal creepage, hence equal slip velocity.",
        "Same steel on both sides (E, nu of the rig file); Hertz half-space contact, "
        "longitudinal creepage only (no lateral creepage or spin).",
        f"Rail: {rail.describe(geo.roller_radius_y)}.",
        f"The prediction spans the measured creepage (xi up to {xi_max:.4g}); beyond it the "
        "surface parameters would be extrapolated.",
        f"The law's own shape error in the transfer factor is not in the band: {LAW_FACTOR_ERROR}",
    ]
    method = {
        "method": "Monte Carlo propagation of distributions (JCGM 101); 95 % probabilistically "
        "symmetric interval (2.5-97.5 % quantiles) at each creepage",
        "draws": draws,
        "seed": int(seed),
        "inputs": [
            {
                "name": f"{law} surface parameters",
                "distribution": "multivariate normal, the fit's covariance"
                + (
                    f" x {inflation:.3g}^2 (AR(1) factor of the structured residuals)"
                    if inflation > 1
                    else ""
                )
                + ", clipped to the parameters' bounds",
            },
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
            "the law's model error (see the fit's residual structure)",
            "differences between the rig's and the rail's surfaces",
            "E and nu (same steel on both sides)",
        ],
        "covariance_inflation [-]": inflation,
    }
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
    if not fit.identifiable:
        notes.append(
            "the fit is not fully identifiable from these data (see the fit's notes): its "
            "covariance, hence the band, describes the scatter about this one solution; the "
            "transfer factor itself depends little on the surface parameters"
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
    )
