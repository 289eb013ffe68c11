"""Cut an adhesion test into its phases; ascending and descending branches; hysteresis.

An adhesion test (Kayaalp, sections 4.1.4 and 4.2.1) is free rolling, then cycles of a torque
ramp, a hold at the level, a release (sudden) or ramp down (slow), and a rest. The phases are
found from the torque request if the recording has it, else from the measured roller-shaft
torque (low-pass filtered), by levels relative to each cycle:

- a cycle is a run of samples where the level exceeds the idle baseline by more than
  ``active_fraction`` of the test's peak, lasting at least ``min_cycle_duration``;
- its ramp starts where a line fitted to the rising level between 20 % and 60 % of the cycle's
  maximum meets the baseline (robust to noise, exact for a linear request);
- the hold is the span where the level stays within ``hold_band`` of the cycle's maximum;
- the fall ends where the level has come back to within ``rest_fraction`` of the drop above the
  baseline; a fall shorter than ``release_max_duration`` is a "release", a longer one a
  "ramp_down";
- idle time before the first cycle is "free_rolling", after a cycle "rest".

From the measured torque the phases follow the roller shaft, not the request: after a sudden
release the shaft torque T56 lags the request by the induction motor's response lag and the
shaft mode (about 0.35 s on the default rig at 30 km/h), so "release" lasts that long.

Branches and hysteresis: within a cycle the ascending branch of the creep-CoA curve runs from the
ramp start to the maximum creep, the descending branch from the maximum creep until the creep is
back within ``return_fraction`` of its rise (or the next cycle starts). :func:`hysteresis` puts
both branches on a common creep grid over the creep range they share and reports

- ``area`` = ∫ (μ_asc(s) − μ_desc(s)) ds over that range [-] (signed: negative when the
  descending branch lies above the ascending one), ``abs_area`` = ∫ |μ_asc − μ_desc| ds [-];
- ``max_difference`` = max |μ_asc − μ_desc| at equal creep [-] and the creep where it occurs.

A memoryless contact law (the twin's true CoA against the true creep at constant speed) has
none; the rig's CoA = T56/(r_r N) shows a loop because T56 includes the roller's inertia torque
(on the seed test it stays near 0.45 for ~0.3 s after the release while the true CoA falls to
0.15). At 250 Hz the descent of the creep after a sudden release (~0.05 s) has only a dozen
samples: simulate or record faster to resolve the descending branch.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy import signal

from rollerrig._validation import (
    ParameterError,
    require_broadcastable,
    require_finite,
    require_in_range,
    require_increasing,
    require_nonnegative,
    require_positive,
    require_whole,
)
from rollerrig.recordings.recording import Recording, RecordingError
from rollerrig.recordings.validate import true_runs

__all__ = [
    "PHASE_NAMES",
    "Branches",
    "Hysteresis",
    "Phase",
    "adhesion_branches",
    "hysteresis",
    "quiet_phase",
    "segment_test",
    "true_runs",
]

PHASE_NAMES = ("free_rolling", "ramp_up", "hold", "release", "ramp_down", "rest")
"""Names a :class:`Phase` can carry."""


class Phase(NamedTuple):
    """One phase of a test.

    Attributes
    ----------
    name : str
        One of :data:`PHASE_NAMES`.
    start, end : float
        Start and end time [s].
    cycle : int
        Index of the torque cycle the phase belongs to (0, 1, ...); -1 for free rolling.
        A rest belongs to the cycle it follows.
    """

    name: str
    start: float
    end: float
    cycle: int

    @property
    def duration(self) -> float:
        """end − start [s]."""
        return self.end - self.start


class Branches(NamedTuple):
    """Sample indices of the ascending and descending branches of one cycle."""

    cycle: int
    ascending: np.ndarray
    descending: np.ndarray


class Hysteresis(NamedTuple):
    """Hysteresis between the ascending and descending branches (see the module docstring).

    Attributes
    ----------
    area : float
        ∫ (μ_asc − μ_desc) ds over the common creep range [-].
    abs_area : float
        ∫ |μ_asc − μ_desc| ds [-].
    max_difference : float
        max |μ_asc − μ_desc| on the grid [-].
    creep_at_max_difference : float
        Creep where it occurs [-].
    creep_grid : ndarray
        The common creep grid [-].
    ascending, descending : ndarray
        Each branch's CoA on the grid [-].
    """

    area: float
    abs_area: float
    max_difference: float
    creep_at_max_difference: float
    creep_grid: np.ndarray
    ascending: np.ndarray
    descending: np.ndarray


def segment_test(
    recording: Recording,
    *,
    source: str | None = None,
    active_fraction: float | None = None,
    hold_band: float | None = None,
    rest_fraction: float = 0.1,
    release_max_duration: float = 1.0,
    min_cycle_duration: float = 0.3,
    smoothing_cutoff: float | None = 5.0,
) -> list[Phase]:
    """Phases of an adhesion test, from the torque request or the measured torque.

    Parameters
    ----------
    recording : Recording
        Needs ``torque_request`` or ``torque``.
    source : {"torque_request", "torque"}, optional
        Channel to segment; default the request if recorded, else the measured torque.
    active_fraction : float, optional
        Level above the baseline, relative to the test's peak, that makes a cycle [-], in
        (0, 1); default 0.05 for the request, 0.25 for the measured torque (above the ~15 %
        oscillation of T56 after a sudden release on the default rig).
    hold_band : float, optional
        Relative band below a cycle's maximum that counts as hold [-], in [0, 1); default
        0.002 for the request, 0.05 for the measured torque.
    rest_fraction : float
        The fall ends when the level is back within this fraction of the drop [-], in [0, 1).
    release_max_duration : float
        Longest fall still called a release [s]; longer falls are "ramp_down".
    min_cycle_duration : float
        Shortest run above the activity threshold that counts as a cycle [s].
    smoothing_cutoff : float or None
        Cut-off of the zero-phase low-pass (Butterworth, order 2) applied to the measured
        torque [Hz]; ``None`` for none. Never applied to the request.

    Returns
    -------
    list of Phase
        Consecutive phases covering the recording from its first to its last sample.

    Examples
    --------
    >>> t = np.arange(0, 10, 0.01)
    >>> req = np.interp(t, [0, 2, 5, 5.5, 5.52, 10], [0, 0, 600, 600, 0, 0])
    >>> rec = Recording(t, {"torque_request": req}, {"torque_request": "N.m"})
    >>> [(p.name, round(p.start, 2)) for p in segment_test(rec)]
    [('free_rolling', 0.0), ('ramp_up', 2.0), ('hold', 5.0), ('release', 5.5), ('rest', 5.52)]
    """
    if source is None:
        source = "torque_request" if "torque_request" in recording else "torque"
    if source not in ("torque_request", "torque"):
        raise ParameterError(f"source must be 'torque_request' or 'torque', got {source!r}")
    recording.require(source)
    is_request = source == "torque_request"
    if active_fraction is None:
        active_fraction = 0.05 if is_request else 0.25
    if hold_band is None:
        hold_band = 0.002 if is_request else 0.05
    # A NaN sample, or setting, compared false everywhere: the test's cycles had vanished.
    active_fraction = require_in_range(
        "active_fraction", active_fraction, 0.0, 1.0, "1", single=True
    )
    hold_band = require_in_range(
        "hold_band", hold_band, 0.0, 1.0, "1", low_inclusive=True, single=True
    )
    rest_fraction = require_in_range(
        "rest_fraction", rest_fraction, 0.0, 1.0, "1", low_inclusive=True, single=True
    )
    require_positive("release_max_duration", release_max_duration, "s")
    require_nonnegative("min_cycle_duration", min_cycle_duration, "s")
    t = recording.time
    u = require_finite(f"channel {source!r}", recording[source], "N.m")
    if not is_request and smoothing_cutoff is not None:
        fs = recording.sample_rate
        require_positive("smoothing_cutoff", smoothing_cutoff, "Hz")
        if smoothing_cutoff >= 0.5 * fs:
            raise ParameterError(
                f"smoothing_cutoff must be below Nyquist ({0.5 * fs:g} Hz), got {smoothing_cutoff}"
            )
        sos = signal.butter(2, smoothing_cutoff, fs=fs, output="sos")
        # scipy's default edge padding (3 x the filter's order) needs longer records; a short
        # one is padded by what it has, and is then judged by the tests below like any other.
        padlen = min(3 * (2 * len(sos) + 1), u.size - 1)
        u = signal.sosfiltfilt(sos, u, padlen=padlen)
    sign = 1.0 if u[np.argmax(np.abs(u))] >= 0 else -1.0
    level = sign * u
    peak = float(np.max(level))
    idle = np.abs(level) < active_fraction * max(peak, 1e-300)
    baseline = float(np.median(level[idle])) if np.any(idle) else 0.0
    span = peak - baseline
    if not span > 0:
        return [Phase("free_rolling", float(t[0]), float(t[-1]), -1)]

    active = (level - baseline) > active_fraction * span
    runs = [(i, j) for i, j in true_runs(active) if t[j] - t[i] >= min_cycle_duration]

    phases: list[Phase] = []
    cursor = float(t[0])
    for cycle, (i, j) in enumerate(runs):
        seg = level[i : j + 1]
        k_max = i + int(np.argmax(seg))
        m = float(level[k_max])
        drop = m - baseline
        # Ramp start: line through the rising part between 20 % and 60 % of the rise.
        lo_i = int(np.searchsorted(t, cursor))
        rising = np.arange(lo_i, k_max + 1)
        rel = (level[rising] - baseline) / drop
        sel = rising[(rel >= 0.2) & (rel <= 0.6)]
        if sel.size >= 2 and np.ptp(t[sel]) > 0:
            slope, icpt = np.polyfit(t[sel], level[sel], 1)
            start = (baseline - icpt) / slope if slope > 0 else float(t[i])
        else:
            start = float(t[max(i - 1, lo_i)])
        start = float(np.clip(start, cursor, t[i]))
        # Hold: within hold_band of the cycle's maximum.
        near = np.flatnonzero(level[i : j + 1] >= m - hold_band * drop) + i
        hold_start, hold_end = float(t[near[0]]), float(t[near[-1]])
        # End of the fall: back within rest_fraction of the drop.
        after = np.flatnonzero(level[near[-1] :] - baseline <= rest_fraction * drop)
        next_start = runs[cycle + 1][0] if cycle + 1 < len(runs) else t.size - 1
        k_end = near[-1] + int(after[0]) if after.size else next_start
        k_end = min(k_end, next_start)
        fall_end = float(t[k_end])
        fall = "release" if fall_end - hold_end <= release_max_duration else "ramp_down"

        phases.append(Phase("free_rolling" if cycle == 0 else "rest", cursor, start, cycle - 1))
        phases.append(Phase("ramp_up", start, hold_start, cycle))
        phases.append(Phase("hold", hold_start, hold_end, cycle))
        phases.append(Phase(fall, hold_end, fall_end, cycle))
        cursor = fall_end
    phases.append(
        Phase("free_rolling" if not runs else "rest", cursor, float(t[-1]), len(runs) - 1)
    )
    return [p for p in phases if p.end > p.start]


def adhesion_branches(
    time,
    creep,
    phases: list[Phase],
    return_fraction: float = 0.05,
) -> list[Branches]:
    """Ascending and descending branches of the creep-CoA curve, per cycle.

    Parameters
    ----------
    time : array_like, shape (n,)
        Sample times [s], finite and strictly increasing.
    creep : array_like, shape (n,)
        Creep [-] (true, or derived from the encoders; smooth it first if it is noisy).
    phases : list of Phase
        From :func:`segment_test`.
    return_fraction : float
        The descending branch ends when the creep is back within this fraction of its rise
        above the creep at the ramp start [-].

    Returns
    -------
    list of Branches
        Index arrays into ``time``: ascending from the ramp start to the maximum creep
        (inclusive), descending from the maximum creep to the return (inclusive).
    """
    # Found by binary search: unsorted time had given branches of the wrong samples, silently;
    # a repeated instant is no sample of a recording (Recording refuses it too).
    t = require_increasing("time", time, "s")
    s = np.asarray(creep, dtype=float)
    if t.shape != s.shape:
        raise RecordingError(f"time {t.shape} and creep {s.shape} differ in shape")
    out = []
    cycles = sorted({p.cycle for p in phases if p.name == "ramp_up"})
    for c in cycles:
        mine = [p for p in phases if p.cycle == c and p.name != "rest"]
        start = min(p.start for p in mine)
        fall_end = max(p.end for p in mine)
        nxt = [p.start for p in phases if p.name == "ramp_up" and p.cycle == c + 1]
        limit = nxt[0] if nxt else t[-1]
        i0 = int(np.searchsorted(t, start))
        i1 = int(np.searchsorted(t, fall_end, side="right"))
        k_peak = i0 + int(np.nanargmax(np.abs(s[i0:i1])))
        sign = 1.0 if s[k_peak] >= 0 else -1.0
        s0 = sign * s[i0]
        rise = sign * s[k_peak] - s0
        i_lim = int(np.searchsorted(t, limit, side="right"))
        back = np.flatnonzero(sign * s[k_peak:i_lim] - s0 <= return_fraction * rise)
        k_end = k_peak + int(back[0]) if back.size else i_lim - 1
        out.append(Branches(c, np.arange(i0, k_peak + 1), np.arange(k_peak, k_end + 1)))
    return out


def _on_grid(creep: np.ndarray, coa: np.ndarray, grid: np.ndarray) -> np.ndarray:
    """Bin-average a branch around the grid points, then interpolate the bin means.

    Each bin (half-way between grid points) gives the mean creep and mean CoA of its samples;
    these points, in creep order, are interpolated linearly at the grid (exact for a branch
    that is linear within a bin, and averages noise where a bin holds several samples).
    """
    half = 0.5 * (grid[1] - grid[0])
    edges = np.concatenate([[grid[0] - half], 0.5 * (grid[1:] + grid[:-1]), [grid[-1] + half]])
    inside = (creep >= edges[0]) & (creep <= edges[-1])
    creep, coa = creep[inside], coa[inside]
    idx = np.clip(np.searchsorted(edges, creep, side="right") - 1, 0, grid.size - 1)
    counts = np.bincount(idx, minlength=grid.size)
    filled = counts > 0
    mean_s = np.bincount(idx, weights=creep, minlength=grid.size)[filled] / counts[filled]
    mean_mu = np.bincount(idx, weights=coa, minlength=grid.size)[filled] / counts[filled]
    return np.interp(grid, mean_s, mean_mu)


def hysteresis(creep_ascending, coa_ascending, creep_descending, coa_descending, grid_points=101):
    """Hysteresis between the ascending and descending branches of a creep-CoA curve.

    Both branches are put on a common grid of ``grid_points`` creep values spanning the range
    both cover (bin means around each grid point, interpolated linearly between bins);
    ``area`` = ∫ (μ_asc − μ_desc) ds (trapezoid rule), ``abs_area`` = ∫ |μ_asc − μ_desc| ds,
    ``max_difference`` = max |μ_asc − μ_desc| on the grid.

    Parameters
    ----------
    creep_ascending, coa_ascending : array_like
        Ascending branch: creep [-] and CoA [-].
    creep_descending, coa_descending : array_like
        Descending branch: creep [-] and CoA [-].
    grid_points : int
        Number of grid points [-], >= 2.

    Returns
    -------
    Hysteresis

    Examples
    --------
    Two parallel lines 0.1 apart over creep 0..0.02:

    >>> s = np.linspace(0, 0.02, 50)
    >>> h = hysteresis(s, 10 * s, s, 10 * s + 0.1)
    >>> round(h.area, 6), round(h.max_difference, 6)
    (-0.002, 0.1)
    """
    # A grid step needs 2 points; a million is far finer than any measured branch.
    points = require_whole("grid_points", grid_points, minimum=2, maximum=1_000_000)
    sa, ma = require_broadcastable(creep_ascending=creep_ascending, coa_ascending=coa_ascending)
    sd, md = require_broadcastable(creep_descending=creep_descending, coa_descending=coa_descending)
    keep_a, keep_d = np.isfinite(sa) & np.isfinite(ma), np.isfinite(sd) & np.isfinite(md)
    sa, ma, sd, md = sa[keep_a], ma[keep_a], sd[keep_d], md[keep_d]
    if sa.size < 2 or sd.size < 2:
        raise RecordingError("each branch needs at least 2 finite samples")
    lo = max(sa.min(), sd.min())
    hi = min(sa.max(), sd.max())
    if not hi > lo:
        raise RecordingError(
            f"the branches share no creep range (ascending {sa.min():.4g}..{sa.max():.4g}, "
            f"descending {sd.min():.4g}..{sd.max():.4g})"
        )
    grid = np.linspace(lo, hi, points)
    asc = _on_grid(sa, ma, grid)
    desc = _on_grid(sd, md, grid)
    diff = asc - desc
    k = int(np.argmax(np.abs(diff)))
    return Hysteresis(
        area=float(np.trapezoid(diff, grid)),
        abs_area=float(np.trapezoid(np.abs(diff), grid)),
        max_difference=float(np.abs(diff[k])),
        creep_at_max_difference=float(grid[k]),
        creep_grid=grid,
        ascending=asc,
        descending=desc,
    )


def quiet_phase(phases: list[Phase]) -> tuple[float, float] | None:
    """The longest phase without torque activity (free rolling or rest) [s], for spectra."""
    quiet = [ph for ph in phases if ph.name in ("free_rolling", "rest")]
    if not quiet:
        return None
    best = max(quiet, key=lambda ph: ph.end - ph.start)
    return best.start, best.end
