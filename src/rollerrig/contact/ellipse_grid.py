"""FASTSIM's discretisations of the unit contact ellipse, and the normal pressure on them.

Two discretisations (see :mod:`rollerrig.contact.fastsim`): Kalker-type strips of equal width,
each cut into equal elements between its own leading and trailing edge (``"strips"``), and
CONTACT's rectangular grid over the potential contact (``"contact"``), used to compare with
CONTACT at equal discretisation. A grid is normalised (x by a, y by b), so one grid serves every
ellipse. The pressure on it is Kalker's parabolic traction bound or the Hertzian one.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rollerrig._validation import ParameterError, require_in_range

__all__ = ["MIN_ELEMENTS", "FastsimGrid", "fastsim_grid"]

_BOUNDS = ("parabolic", "elliptic")


@dataclass(frozen=True)
class FastsimGrid:
    """A discretisation of the unit ellipse (x/a, y/b), reusable for every a, b.

    All arrays are normalised: x by a, y by b, areas by a·b. Rows are strips y = const; columns
    are processed from the leading edge (+x) to the trailing edge.

    Attributes
    ----------
    kind : str
        ``"strips"`` or ``"contact"``.
    x : ndarray, shape (ny, nx)
        Element centres x/a.
    y : ndarray, shape (ny,)
        Strip centres y/b.
    step : ndarray, shape (ny, nx)
        Step h/a from the previous evaluation point to this one.
    x_spin : ndarray, shape (ny, nx)
        Where the spin's rigid slip is evaluated for this step, x/a.
    area : ndarray, shape (ny, nx)
        Element area / (a b).
    inside : ndarray of bool, shape (ny, nx)
        Element in the contact.
    shape : ndarray, shape (ny, nx)
        1 - x²/a² - y²/b², clipped at 0, at the element centres.
    width : ndarray, shape (ny, nx)
        Element length along x / a.
    """

    kind: str
    x: np.ndarray
    y: np.ndarray
    step: np.ndarray
    x_spin: np.ndarray
    area: np.ndarray
    inside: np.ndarray
    shape: np.ndarray
    width: np.ndarray
    extent: tuple[float, float] = field(default=(1.0, 1.0))

    @property
    def size(self) -> tuple[int, int]:
        """(ny, nx)."""
        return self.x.shape


MIN_ELEMENTS = 5
"""Fewest elements of a FASTSIM grid across the ellipse along each axis [-] (on CONTACT's grid,
``MIN_ELEMENTS × scale`` over the potential contact): fewer do not resolve the tractions'
build-up along a strip nor the ellipse's outline. Measured 2026-12-02, before the pressures
were scaled to carry the load exactly (:func:`_pressure_shape`): the elliptic Hertz pressure
summed over the elements was then within 5 % of the load on Kalker's strips (2 % from 8) and
within 7.5 % on CONTACT's grid at scales 1-3, where one element had put 2.3 times the load
into the contact (a 1 x 1 CONTACT-type grid: 76 kN of force under μN = 25 kN); that error is
gone, the discretisation's of the tractions is not."""


def _element_count(name: str, value) -> int:
    """``value`` as a whole number of elements, at least :data:`MIN_ELEMENTS`."""
    count = require_in_range(
        name, value, MIN_ELEMENTS, np.inf, "-", low_inclusive=True, single=True
    )
    if count != int(count):
        raise ParameterError(f"{name} must be a whole number of elements [-], got {value!r}")
    return int(count)


def fastsim_grid(
    nx: int = 30, ny: int = 30, kind: str = "strips", scale: float = 1.1
) -> FastsimGrid:
    """A FASTSIM discretisation of the unit ellipse.

    Parameters
    ----------
    nx, ny : int
        Elements per strip (``"strips"``) or grid columns (``"contact"``: CONTACT's MX), and
        strips (MY); whole numbers, at least :data:`MIN_ELEMENTS` (times ``scale`` on the
        contact grid).
    kind : {"strips", "contact"}
        Kalker-type strips (each strip cut into ``nx`` equal elements, default), or CONTACT's
        rectangular potential-contact grid (for comparison at equal discretisation).
    scale : float
        Potential contact half-size / semi-axis for ``"contact"`` (CONTACT's SCALE) [-], at
        least 1 (the potential contact holds the ellipse).

    Returns
    -------
    FastsimGrid

    Examples
    --------
    >>> fastsim_grid(20, 10).size
    (10, 20)
    """
    nx = _element_count("nx", nx)
    ny = _element_count("ny", ny)
    if kind == "strips":
        y = -1.0 + (np.arange(ny) + 0.5) * 2.0 / ny
        half = np.sqrt(1.0 - y * y)  # strip half-length / a
        h = 2.0 * half / nx
        i = np.arange(nx)
        x = half[:, None] - (i[None, :] + 0.5) * h[:, None]
        step = np.broadcast_to(h[:, None], (ny, nx)).copy()
        width = step.copy()
        step[:, 0] = 0.5 * h
        x_spin = x + 0.5 * step
        area = h[:, None] * (2.0 / ny) * np.ones((1, nx))
        inside = np.ones((ny, nx), dtype=bool)
        extent = (1.0, 1.0)
    elif kind == "contact":
        # A potential contact smaller than the ellipse cuts it off (30 N of a 25 kN force).
        s = require_in_range("scale", scale, 1.0, np.inf, "-", low_inclusive=True, single=True)
        if min(nx, ny) < MIN_ELEMENTS * s:  # elements across the ellipse, not the grid
            raise ParameterError(
                f"nx and ny must be at least {MIN_ELEMENTS} x scale = {MIN_ELEMENTS * s:g} on "
                f"the contact grid ({MIN_ELEMENTS} elements across the ellipse) [-], got "
                f"{nx} x {ny}"
            )
        dx, dy = 2.0 * s / nx, 2.0 * s / ny
        xc = -s + (np.arange(nx) + 0.5) * dx
        y = -s + (np.arange(ny) + 0.5) * dy
        x = np.broadcast_to(xc[::-1][None, :], (ny, nx)).copy()  # leading edge (+x) first
        step = np.full((ny, nx), dx)
        width = step.copy()
        x_spin = x + dx / 6.0  # CONTACT set_tang_rhs: offset dq * facphi, facphi = 1/6
        area = np.full((ny, nx), dx * dy)
        inside = (1.0 - x * x - (y * y)[:, None]) > 0.0
        extent = (s, s)
    else:
        raise ParameterError(f"kind must be one of 'strips', 'contact', got {kind!r}")
    shape = np.maximum(0.0, 1.0 - x * x - (y * y)[:, None])
    return FastsimGrid(kind, x, y, step, x_spin, area, inside, shape, width, extent)


def _pressure_shape(grid: FastsimGrid, bound: str, a: float, b: float) -> np.ndarray:
    """Normal pressure per newton of load, p_n/N [1/m²], at the element centres: the
    parabolic (FASTSIM's) or elliptic (Hertz's) shape, scaled so that the elements carry
    the load exactly (Σ p_n ΔA = N).

    The closed-form constants, 2/(π a b) and 3/(2 π a b), integrate to 1 over the ellipse, but
    the grid's sum of them did not: on the default 30 x 30 strips it was 1 + 6.5e-4 (+2.4e-3
    for the elliptic shape, +1.5e-2 on 10 x 10), so a fully sliding contact carried more than
    μN (3 302.1 N at μN = 3 300 N; a review, 2026-12-03).
    """
    shape = grid.shape if bound == "parabolic" else np.sqrt(grid.shape)
    return shape / (float(np.sum(shape * grid.area)) * a * b)


def _equivalent_ellipse(grid: FastsimGrid, inside: np.ndarray, a: float, b: float):
    """CONTACT's equivalent ellipse of a gridded contact (Kik-Piotrowski: area and a/b kept)."""
    area = float(np.sum(grid.area[inside])) * a * b
    cols = np.flatnonzero(inside.any(axis=0))
    rows = np.flatnonzero(inside.any(axis=1))
    length = float(grid.step[0, 0]) * a * (cols.max() - cols.min() + 1)
    width = (2.0 * grid.extent[1] / grid.size[0]) * b * (rows.max() - rows.min() + 1)
    r = np.sqrt(area / np.pi)
    return r * np.sqrt(length / width), r * np.sqrt(width / length)


def _checked_grid(grid) -> FastsimGrid:
    """``grid``, or the default grid for None; anything else refused (an int had reached a
    bare AttributeError deep inside the kernel)."""
    if grid is None:
        return fastsim_grid()
    if not isinstance(grid, FastsimGrid):
        raise ParameterError(
            "grid must be a FastsimGrid (see fastsim_grid) or None, got a value of type "
            f"{type(grid).__name__}"
        )
    return grid
