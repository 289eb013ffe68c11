"""Cross-sections of frame members: the sourced table of standard sections and their formulas.

A member's section is either a standard designation looked up in ``data/sections.csv`` or given
by its properties (:class:`SectionProperties` built by the frame file). Every value is SI inside.

The table (``rollerrig/frame/data/sections.csv``), one row per section, each with its source:

- **IPE and HEB** (hot-rolled I-sections): nominal dimensions of EN 10365:2017 and the section
  properties published in the ArcelorMittal *Sections and Merchant Bars* sales programme
  (four significant figures). Each row is checked against the exact geometry (two flanges, a
  web and four quarter-circle root fillets, :func:`i_section_properties`) in
  ``tests/frame/test_sections.py``.
- **SHS, RHS and CHS** (cold-formed structural hollow sections, EN 10219-2:2006): computed from
  the nominal dimensions with the standard's Annex B formulas and its corner radii for the
  calculation of properties (outer/inner radius 2t/t for t <= 6 mm, 2.5t/1.5t for
  6 < t <= 10 mm, 3t/2t above): :func:`rhs_properties`, :func:`chs_properties`.

The table's columns follow EN 1993-1-1: y-y is the strong axis (bending in the plane of the
web; the section's depth h lies along the web), z-z the weak axis. :class:`SectionProperties`
calls them ``strong`` and ``weak``; the frame analysis puts the depth along a member's local y
(its ``web`` direction), so that strong-axis bending is about local z.

Examples
--------
>>> s = standard_section("HEB 200")
>>> round(s.area * 1e4, 2), round(s.second_moment_strong * 1e8), round(s.depth * 1e3)
(78.08, 5696, 200)
>>> standard_section("he200b").name, standard_section("SHS 100x5").name
('HEB 200', 'SHS 100x100x5')
>>> round(rhs_properties(0.1, 0.1, 0.005).torsion_constant * 1e8, 1)  # [cm^4]
440.5
"""

from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass, replace
from functools import cache
from importlib import resources

__all__ = [
    "SHAPES",
    "SectionProperties",
    "canonical_designation",
    "chs_properties",
    "hollow_corner_radii",
    "i_section_properties",
    "rhs_properties",
    "section_table",
    "standard_section",
]

SHAPES = ("I", "RHS", "CHS", "general")
"""Section shapes: rolled I (IPE, HEB), rectangular or square hollow (RHS, SHS), circular hollow
(CHS), or a section given by its properties (``general``: stresses at a rectangular envelope of
depth x width)."""


@dataclass(frozen=True)
class SectionProperties:
    """Properties of a member's cross-section, SI units.

    The section's *depth* lies along the member's web direction (local y of the analysis), its
    *width* across it (local z). ``strong`` bending bends the member in the plane of the web
    (about local z), ``weak`` bending across it (about local y).

    Attributes
    ----------
    name : str
        Designation (``"HEB 200"``) or the frame file's section name.
    shape : str
        One of :data:`SHAPES`.
    area : float
        Cross-section area A [m^2].
    second_moment_strong : float
        Second moment of area about the strong axis, EN 1993 I_y [m^4].
    second_moment_weak : float
        Second moment of area about the weak axis, EN 1993 I_z [m^4].
    torsion_constant : float
        St Venant torsion constant I_t [m^4].
    depth : float
        Extent along the web direction, h [m] (CHS: the outside diameter).
    width : float
        Extent across it, b [m] (CHS: the outside diameter).
    torsion_modulus : float
        Torsional section modulus W_t [m^3]: the largest torsional shear stress is T / W_t.
    shear_area_strong : float
        Shear area for a shear force along the web direction, A_v [m^2] (EN 1993-1-1 6.2.6(3)).
    shear_area_weak : float
        Shear area for a shear force across it [m^2].
    source : str
        Where the values come from.
    """

    name: str
    shape: str
    area: float
    second_moment_strong: float
    second_moment_weak: float
    torsion_constant: float
    depth: float
    width: float
    torsion_modulus: float
    shear_area_strong: float
    shear_area_weak: float
    source: str = ""

    def renamed(self, name: str) -> SectionProperties:
        """The same section under another name."""
        return replace(self, name=name)

    @property
    def polar_moment(self) -> float:
        """Polar second moment I_y + I_z [m^4] (the rotary inertia of the section)."""
        return self.second_moment_strong + self.second_moment_weak


# --------------------------------------------------------------------------------------------
# Formulas
# --------------------------------------------------------------------------------------------


def _spandrel(r: float) -> tuple[float, float, float]:
    """(area, centroid distance from each straight leg, own second moment about its centroid
    parallel to a leg) of the corner spandrel: an r x r square less a quarter circle of radius r
    centred at its far corner."""
    if r <= 0.0:
        return 0.0, 0.0, 0.0
    area = (1.0 - math.pi / 4.0) * r * r
    quarter = math.pi * r * r / 4.0
    cq = 4.0 * r / (3.0 * math.pi)  # quarter circle's centroid from its centre
    # About the leg (a straight side of the square through the spandrel's corner):
    first = r * r * r / 2.0 - quarter * (r - cq)
    quarter_about_leg = math.pi * r**4 / 16.0 - quarter * cq * cq + quarter * (r - cq) ** 2
    second = r**4 / 3.0 - quarter_about_leg
    e = first / area
    return area, e, second - area * e * e


def i_section_properties(h: float, b: float, tw: float, tf: float, r: float) -> dict[str, float]:
    """Exact area and second moments of a doubly symmetric rolled I-section with root fillets.

    Two flanges b x tf, a web tw between them, four quarter-circle root fillets of radius r
    (the spandrel between web and flange); parallel-axis theorem. Shear areas per
    EN 1993-1-1 6.2.6(3): ``A - 2 b tf + (tw + 2 r) tf`` along the web, ``2 b tf`` across it.

    Parameters
    ----------
    h, b, tw, tf, r : float
        Depth, flange width, web and flange thickness, root radius [m].

    Returns
    -------
    dict
        ``area`` [m^2], ``second_moment_strong``, ``second_moment_weak`` [m^4],
        ``shear_area_strong``, ``shear_area_weak`` [m^2].

    Examples
    --------
    >>> p = i_section_properties(0.2, 0.2, 0.009, 0.015, 0.018)  # HEB 200 (EN 10365)
    >>> round(p["area"] * 1e4, 2), round(p["second_moment_strong"] * 1e8)
    (78.08, 5696)
    """
    a_s, e, i_own = _spandrel(r)
    hw = h - 2.0 * tf
    area = 2.0 * b * tf + hw * tw + 4.0 * a_s
    y_f = h / 2.0 - tf - e
    z_f = tw / 2.0 + e
    i_strong = (b * h**3 - (b - tw) * hw**3) / 12.0 + 4.0 * (i_own + a_s * y_f**2)
    i_weak = (2.0 * tf * b**3 + hw * tw**3) / 12.0 + 4.0 * (i_own + a_s * z_f**2)
    return {
        "area": area,
        "second_moment_strong": i_strong,
        "second_moment_weak": i_weak,
        "shear_area_strong": area - 2.0 * b * tf + (tw + 2.0 * r) * tf,
        "shear_area_weak": 2.0 * b * tf,
    }


def hollow_corner_radii(t: float) -> tuple[float, float]:
    """Outer and inner corner radius (ro, ri) [m] of a cold-formed hollow section for the
    calculation of its properties (EN 10219-2:2006, Annex B): 2t/t for t <= 6 mm, 2.5t/1.5t for
    6 < t <= 10 mm, 3t/2t above.

    Examples
    --------
    >>> [round(x * 1e3, 3) for x in hollow_corner_radii(0.005)]
    [10.0, 5.0]
    """
    if t <= 6e-3 + 1e-12:
        return 2.0 * t, t
    if t <= 10e-3 + 1e-12:
        return 2.5 * t, 1.5 * t
    return 3.0 * t, 2.0 * t


def _rounded_rectangle(h: float, b: float, r: float) -> tuple[float, float, float]:
    """(area, I about the axis parallel to b, I about the axis parallel to h) of an h x b
    rectangle with four corners rounded to radius r."""
    a_s, e, i_own = _spandrel(r)
    area = h * b - 4.0 * a_s
    i_b = b * h**3 / 12.0 - 4.0 * (i_own + a_s * (h / 2.0 - e) ** 2)
    i_h = h * b**3 / 12.0 - 4.0 * (i_own + a_s * (b / 2.0 - e) ** 2)
    return area, i_b, i_h


def rhs_properties(h: float, b: float, t: float, name: str = "") -> SectionProperties:
    """A cold-formed rectangular (or square) hollow section, EN 10219-2:2006 Annex B.

    Area and second moments are exact for the rounded outer and inner outlines (corner radii of
    :func:`hollow_corner_radii`); the torsion constant and modulus are the standard's:
    ``I_t = t^3 p/3 + 2 K A_p``, ``W_t = I_t / (t + K/t)`` with ``r_c = (ro + ri)/2``,
    ``p = 2[(b - t) + (h - t)] - 2 r_c (4 - π)``, ``A_p = (b - t)(h - t) - r_c^2 (4 - π)``,
    ``K = 2 A_p t / p``. Shear area along the depth ``A h / (b + h)`` (EN 1993-1-1 6.2.6(3)).

    Parameters
    ----------
    h, b, t : float
        Depth (along the web direction), width and wall thickness [m].
    name : str
        Designation.
    """
    ro, ri = hollow_corner_radii(t)
    a_o, ib_o, ih_o = _rounded_rectangle(h, b, ro)
    a_i, ib_i, ih_i = _rounded_rectangle(h - 2.0 * t, b - 2.0 * t, ri)
    area = a_o - a_i
    rc = (ro + ri) / 2.0
    p = 2.0 * ((b - t) + (h - t)) - 2.0 * rc * (4.0 - math.pi)
    a_p = (b - t) * (h - t) - rc * rc * (4.0 - math.pi)
    k = 2.0 * a_p * t / p
    it = t**3 * p / 3.0 + 2.0 * k * a_p
    return SectionProperties(
        name=name,
        shape="RHS",
        area=area,
        second_moment_strong=ib_o - ib_i,
        second_moment_weak=ih_o - ih_i,
        torsion_constant=it,
        depth=h,
        width=b,
        torsion_modulus=it / (t + k / t),
        shear_area_strong=area * h / (b + h),
        shear_area_weak=area * b / (b + h),
        source="EN 10219-2:2006 Annex B formulas from the nominal dimensions",
    )


def chs_properties(d: float, t: float, name: str = "") -> SectionProperties:
    """A circular hollow section (EN 10219-2 / EN 10210-2 Annex B: exact for a ring).

    ``A = π (D² - d²)/4``, ``I = π (D⁴ - d⁴)/64``, ``I_t = 2 I``; the largest torsional shear
    stress is ``T (D/2) / I_t``, so ``W_t = 4 I / D``; shear area ``2 A / π``
    (EN 1993-1-1 6.2.6(3)(g)).

    Examples
    --------
    >>> round(chs_properties(0.1683, 0.0063).area * 1e4, 2)  # CHS 168.3 x 6.3 [cm^2]
    32.06
    """
    di = d - 2.0 * t
    area = math.pi * (d * d - di * di) / 4.0
    i = math.pi * (d**4 - di**4) / 64.0
    return SectionProperties(
        name=name,
        shape="CHS",
        area=area,
        second_moment_strong=i,
        second_moment_weak=i,
        torsion_constant=2.0 * i,
        depth=d,
        width=d,
        torsion_modulus=2.0 * i / (d / 2.0),
        shear_area_strong=2.0 * area / math.pi,
        shear_area_weak=2.0 * area / math.pi,
        source="EN 10219-2:2006 Annex B formulas from the nominal dimensions",
    )


# --------------------------------------------------------------------------------------------
# The table
# --------------------------------------------------------------------------------------------

_DIMS = r"(\d+(?:\.\d+)?)"
_PATTERNS = (
    (re.compile(r"^(IPE|HEB)(\d+)$"), lambda m: f"{m[1]} {m[2]}"),
    (re.compile(r"^HE(\d+)B$"), lambda m: f"HEB {m[1]}"),
    (re.compile(rf"^SHS{_DIMS}X{_DIMS}X{_DIMS}$"), lambda m: f"SHS {m[1]}x{m[2]}x{m[3]}"),
    (re.compile(rf"^SHS{_DIMS}X{_DIMS}$"), lambda m: f"SHS {m[1]}x{m[1]}x{m[2]}"),
    (re.compile(rf"^RHS{_DIMS}X{_DIMS}X{_DIMS}$"), lambda m: f"RHS {m[1]}x{m[2]}x{m[3]}"),
    (re.compile(rf"^CHS{_DIMS}X{_DIMS}$"), lambda m: f"CHS {m[1]}x{m[2]}"),
)


def canonical_designation(text: str) -> str | None:
    """The table's spelling of a designation, or None if it is not of a known form.

    Case, spaces and the multiplication sign do not matter; ``HE 200 B`` is ``HEB 200`` and
    ``SHS 100x5`` is ``SHS 100x100x5``.

    Examples
    --------
    >>> canonical_designation("he 200 b"), canonical_designation("RHS 200 × 100 × 8")
    ('HEB 200', 'RHS 200x100x8')
    >>> canonical_designation("W8x31") is None
    True
    """
    key = re.sub(r"\s+", "", str(text)).upper().replace("×", "X").replace("*", "X")
    for pattern, form in _PATTERNS:
        m = pattern.match(key)
        if m:
            return form(m)
    return None


@dataclass(frozen=True)
class _Row:
    designation: str
    shape: str
    values: dict[str, float]
    source: str


@cache
def _rows() -> dict[str, _Row]:
    text = resources.files("rollerrig.frame").joinpath("data/sections.csv").read_text("utf-8")
    lines = [line for line in text.splitlines() if line and not line.startswith("#")]
    out = {}
    for rec in csv.DictReader(lines):
        values = {
            k: float(v) for k, v in rec.items() if k not in ("designation", "shape", "source") and v
        }
        out[rec["designation"]] = _Row(rec["designation"], rec["shape"], values, rec["source"])
    return out


def section_table() -> list[str]:
    """The designations of the bundled table, in table order.

    Examples
    --------
    >>> "IPE 200" in section_table() and "CHS 168.3x6.3" in section_table()
    True
    """
    return list(_rows())


def _nearest(name: str | None, rows) -> list[str]:
    """The three sections of the same family closest in size to ``name`` (first dimension)."""
    if name is None:
        return []
    family, _, size = name.partition(" ")
    try:
        wanted = float(size.split("x")[0])
    except ValueError:
        return []
    same = [n for n in rows if n.split(" ")[0] == family]
    return sorted(same, key=lambda n: abs(float(n.split(" ")[1].split("x")[0]) - wanted))[:3]


def standard_section(designation: str) -> SectionProperties:
    """The properties of a standard section of the bundled table (SI units).

    Raises
    ------
    KeyError
        The designation is not in the table (the message names the closest ones).
    """
    import difflib

    name = canonical_designation(designation)
    rows = _rows()
    if name is None or name not in rows:
        close = _nearest(name, rows) or difflib.get_close_matches(
            name or str(designation).upper(), list(rows), n=3
        )
        hint = f"; closest: {', '.join(close)}" if close else ""
        raise KeyError(f"{designation!r} is not in the section table{hint}")
    row = rows[name]
    v = row.values
    mm, cm2, cm4 = 1e-3, 1e-4, 1e-8
    if row.shape == "I":
        h, b, tw, tf, r = (v[k] * mm for k in ("h_mm", "b_mm", "tw_mm", "tf_mm", "r_mm"))
        geometry = i_section_properties(h, b, tw, tf, r)
        it = v["It_cm4"] * cm4
        return SectionProperties(
            name=name,
            shape="I",
            area=v["A_cm2"] * cm2,
            second_moment_strong=v["Iy_cm4"] * cm4,
            second_moment_weak=v["Iz_cm4"] * cm4,
            torsion_constant=it,
            depth=h,
            width=b,
            torsion_modulus=it / max(tw, tf),
            shear_area_strong=geometry["shear_area_strong"],
            shear_area_weak=geometry["shear_area_weak"],
            source=row.source,
        )
    if row.shape == "CHS":
        out = chs_properties(v["h_mm"] * mm, v["t_mm"] * mm, name)
    else:
        out = rhs_properties(v["h_mm"] * mm, v["b_mm"] * mm, v["t_mm"] * mm, name)
    # The tabulated (rounded) values are what the table states; the formulas give the rest.
    return replace(
        out,
        area=v["A_cm2"] * cm2,
        second_moment_strong=v["Iy_cm4"] * cm4,
        second_moment_weak=v["Iz_cm4"] * cm4,
        torsion_constant=v["It_cm4"] * cm4,
        source=row.source,
    )
