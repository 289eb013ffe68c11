"""Order maps: peak frequency versus speed with the order lines overlaid (Campbell-like).

A speed-proportional source is a straight line through the origin, ``f = k p ω_r / 2π`` (roller
side) or ``f = k p (ω_w/ω_r) ω_r / 2π`` (wheel side); a speed-independent line is horizontal.
Peaks that sit on a line share its source (Kayaalp, section 4.5.2.4).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from rollerrig._validation import require_finite, require_positive, require_whole
from rollerrig.signal.attribution import _TWO_PI, _entry, _label, _peak_values

__all__ = ["OrderLine", "OrderMap", "order_map"]


@dataclass(frozen=True)
class OrderLine:
    """A speed-proportional (or fixed) line of an order map.

    Attributes
    ----------
    source : str
        Source kind (:data:`SOURCE_KINDS`).
    order : int
        Harmonic number (0 for a speed-independent line).
    label : str
        Legend label, e.g. ``"AM electrical ×2"``.
    frequency : ndarray
        Frequency of the line [Hz] on :attr:`OrderMap.speed_grid`.
    """

    source: str
    order: int
    label: str
    frequency: np.ndarray


@dataclass(frozen=True)
class OrderMap:
    """Peak frequency versus roller speed with the order lines overlaid.

    Attributes
    ----------
    speed : ndarray
        Roller angular speed of each peak's recording [rad/s].
    frequency : ndarray
        Peak frequencies [Hz].
    power : ndarray
        Peak powers (NaN when unknown).
    source : ndarray of str
        Source kind of each peak's best attribution ("" when the entry carried none).
    recording : ndarray of int
        Index of each peak's entry.
    speed_grid : ndarray
        Roller speeds the lines are drawn on [rad/s].
    lines : tuple of OrderLine
        AM electrical harmonics, roller orders, and (when the wheel-to-roller speed ratio is
        known) wheel orders and the PMSM electrical frequency, plus the speed-independent lines.
    wheel_to_roller : float or None
        Median ω_w / ω_r of the entries (about r_roller / r_wheel = 1.30 on Kayaalp's rig).
    """

    speed: np.ndarray
    frequency: np.ndarray
    power: np.ndarray
    source: np.ndarray
    recording: np.ndarray
    speed_grid: np.ndarray
    lines: tuple[OrderLine, ...]
    wheel_to_roller: float | None


def order_map(
    entries,
    am_harmonics: Sequence[int] = (1, 2, 3),
    roller_orders: Sequence[int] = (1, 2, 3, 4),
    wheel_orders: Sequence[int] = (1,),
    pmsm_harmonics: Sequence[int] = (1,),
    speed_independent=(),
    am_pole_pairs: int = 5,
    pmsm_pole_pairs: int = 22,
    wheel_to_roller: float | None = None,
    n_grid: int = 101,
) -> OrderMap:
    """Data for a plot of peak frequency versus speed with the order lines overlaid.

    A speed-proportional source is a straight line through the origin,
    ``f = k p ω_r / 2π`` (roller side) or ``f = k p (ω_w/ω_r) ω_r / 2π`` (wheel side); a
    speed-independent line is horizontal. Peaks that sit on a line share its source.

    Parameters
    ----------
    entries : sequence
        One per recording: an :class:`ExplainedSpectrum`, or ``(roller_speed, peaks)`` or
        ``(roller_speed, wheel_speed, peaks)`` with speeds [rad/s] and peaks as
        :class:`SpectralPeak` or frequencies [Hz].
    am_harmonics, roller_orders, wheel_orders, pmsm_harmonics : sequence of int
        Harmonic numbers of the lines drawn.
    speed_independent : array_like of float
        Horizontal lines [Hz].
    am_pole_pairs, pmsm_pole_pairs : int
        Pole pairs.
    wheel_to_roller : float, optional
        ω_w / ω_r for the wheel-side lines; default the median over entries with a wheel speed
        (no wheel-side lines when none has one).
    n_grid : int
        Points of the speed grid, from 0 to 1.1 times the largest speed.

    Returns
    -------
    OrderMap

    Examples
    --------
    >>> m = order_map([(3.07, [2.45]), (18.44, [14.67, 1.333])], speed_independent=[1.333])
    >>> m.frequency.tolist(), [line.label for line in m.lines][:2]
    ([2.45, 14.67, 1.333], ['AM electrical ×1', 'AM electrical ×2'])
    """
    harmonics = {
        name: tuple(require_whole(f"{name}[{j}]", k, minimum=1) for j, k in enumerate(orders))
        for name, orders in (
            ("am_harmonics", am_harmonics),
            ("roller_orders", roller_orders),
            ("wheel_orders", wheel_orders),
            ("pmsm_harmonics", pmsm_harmonics),
        )
    }
    am_pole_pairs = require_whole("am_pole_pairs", am_pole_pairs, minimum=1)
    pmsm_pole_pairs = require_whole("pmsm_pole_pairs", pmsm_pole_pairs, minimum=1)
    # A line needs two points; a million is far more than a plot resolves.
    n_grid = require_whole("n_grid", n_grid, minimum=2, maximum=1_000_000, unit="points")
    if wheel_to_roller is not None:
        wheel_to_roller = require_positive("wheel_to_roller", wheel_to_roller, single=True)
    speed, freq, power, source, rec = [], [], [], [], []
    ratios = []
    for i, item in enumerate(entries):
        roller, wheel, peaks, _ = _entry(item)
        if wheel is not None and roller:  # a recording at rest tells no speed ratio
            ratios.append(abs(wheel) / abs(roller))
        if hasattr(item, "rows") and hasattr(item, "spectrum"):  # an ExplainedSpectrum
            kinds = [r.source for r in item.rows]
        else:
            kinds = [""] * len(peaks)
        f, pw, _ = _peak_values(peaks) if peaks else (np.array([]), np.array([]), None)
        if pw is None:  # bare frequencies: power unknown
            pw = np.full(f.shape, np.nan)
        speed += [0.0 if roller is None else abs(roller)] * f.size  # None: at rest
        freq += f.tolist()
        power += pw.tolist()
        source += kinds
        rec += [i] * f.size
    speed_arr = np.array(speed, dtype=float)
    ratio = wheel_to_roller
    if ratio is None and ratios:
        ratio = float(np.median(ratios))
    top = 1.1 * float(speed_arr.max()) if speed_arr.size else 1.0
    grid = np.linspace(0.0, top, n_grid)
    fr = grid / _TWO_PI
    lines = [
        OrderLine("am_electrical", k, f"AM electrical ×{k}", k * am_pole_pairs * fr)
        for k in harmonics["am_harmonics"]
    ]
    lines += [
        OrderLine("roller_order", k, f"roller order ×{k}", k * fr)
        for k in harmonics["roller_orders"]
    ]
    if ratio is not None:
        fw = ratio * fr
        lines += [
            OrderLine("pmsm_electrical", k, f"PMSM electrical ×{k}", k * pmsm_pole_pairs * fw)
            for k in harmonics["pmsm_harmonics"]
        ]
        lines += [
            OrderLine("wheel_order", k, f"wheel order ×{k}", k * fw)
            for k in harmonics["wheel_orders"]
        ]
    for fc in np.atleast_1d(require_finite("speed_independent", speed_independent, "Hz")):
        lines.append(
            OrderLine(
                "speed_independent",
                0,
                _label("speed_independent", 0, fc),
                np.full(grid.shape, float(fc)),
            )
        )
    return OrderMap(
        speed_arr,
        np.array(freq, dtype=float),
        np.array(power, dtype=float),
        np.array(source, dtype=object),
        np.array(rec, dtype=int),
        grid,
        tuple(lines),
        ratio,
    )
