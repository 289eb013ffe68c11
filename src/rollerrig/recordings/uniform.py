"""The rate of a uniform time base, and whether time stamps are one (rounded to the
resolution they were written with or not).

Apart from :mod:`rollerrig.recordings.timebase` because a :class:`~rollerrig.recordings.
recording.Recording` states its rate through it (and the time base module imports the
recording's).
"""

from __future__ import annotations

import numpy as np

from rollerrig._validation import ParameterError

__all__ = [
    "ROUNDED_GRID_LIMIT",
    "UNIFORM_STEP_TOLERANCE",
    "print_resolution",
    "rounded_grid",
    "uniform_sample_rate",
]

UNIFORM_STEP_TOLERANCE = 0.01
"""Largest deviation of a time step from the median step of a uniform time base [-]."""


def uniform_sample_rate(time) -> float:
    """Rate ``(n − 1) / (t[-1] − t[0])`` [Hz] of a uniform time base.

    The span, not the median step: time stamps written with few decimals (600 Hz as 0.00167,
    0.00166, ... s) have a median step off by the rounding (598.8 Hz, every frequency of a
    spectrum 0.2 % low); the span is off by one rounding over the whole recording.

    Parameters
    ----------
    time : ndarray, shape (n,)
        Sample times [s], strictly increasing, every step within 1 % of the median step, or
        a uniform grid rounded to the resolution the stamps were written with
        (:func:`rounded_grid`: 19.2 kHz written to whole µs).

    Returns
    -------
    float
        Sampling rate [Hz] (not rounded: see :func:`tidy_rate`).

    Raises
    ------
    ParameterError
        Fewer than 2 samples, a step that is not positive, or a non-uniform time base (naming
        the worst step and where it is).

    Examples
    --------
    >>> uniform_sample_rate(np.arange(5) / 250.0)
    250.0
    """
    time = np.asarray(time, dtype=float)
    steps = np.diff(time)
    if steps.size == 0 or not np.all(steps > 0):  # NaN compares false: refused here
        raise ParameterError("time must be strictly increasing with at least 2 samples [s]")
    step = float(np.median(steps))
    k = int(np.argmax(np.abs(steps - step)))
    if abs(steps[k] - step) > UNIFORM_STEP_TOLERANCE * step and not rounded_grid(time):
        raise ParameterError(
            f"a non-uniform time base (step {steps[k]:.6g} s at t = {time[k]:.6g} s against the "
            f"median {step:.6g} s; every step must be within 1 % of the median, or every stamp "
            "within half its printed resolution of one uniform grid)"
        )
    return (time.size - 1) / float(time[-1] - time[0])


ROUNDED_GRID_LIMIT = 0.05
"""Coarsest print resolution [share of a step] at which :func:`rounded_grid` still takes time
stamps for a rounded uniform grid: 1 µs at 19.2 kHz is 1.9 % of a step."""

_LARGEST_DECIMALS = 12  # a resolution below 1e-12 s is no printed one


def print_resolution(time) -> float:
    """The decimal resolution ``10^-k`` [s] the time stamps were written with (the largest of
    which every stamp is a whole multiple, to float round-off), or 0 where none down to
    1e-12 s. From the first 10 000 stamps.

    Examples
    --------
    >>> print_resolution(np.round(np.arange(5) / 19200.0, 6))
    1e-06
    >>> print_resolution(np.arange(5) / 3.0)
    0.0
    """
    t = np.asarray(time, dtype=float)[:10_000]
    t = t[np.isfinite(t)]
    if t.size < 2:
        return 0.0
    largest_step = float(np.max(np.abs(np.diff(t))))
    for k in range(_LARGEST_DECIMALS + 1):
        q = 10.0**-k
        if q > largest_step:  # no coarser than the steps: stamps near 0 are "multiples" of 1 s
            continue
        r = t / q
        # float round-off: a few ulp of the largest stamp, and 1e-3 of a quantum for stamps
        # made relative to a large origin (times of day: 7e-12 s at 13:00, 7e-6 of 1 µs)
        ulps = 64.0 * np.finfo(float).eps * float(np.max(np.abs(r)))
        if ulps > 0.1:  # the floats cannot show this resolution (epoch s at 10 µs), nor a finer
            return 0.0
        if float(np.max(np.abs(r - np.rint(r)))) <= 1e-3 + ulps:
            return q
    return 0.0


def rounded_grid(time) -> bool:
    """True when the time stamps are a uniform grid rounded to the resolution they were written
    with: every stamp within half that resolution of the least-squares line through them, the
    resolution at most :data:`ROUNDED_GRID_LIMIT` of a step.

    A 19.2 kHz clock written to whole µs steps by 52 and 53 µs, 1.9 % apart: not uniform by its
    steps, but each stamp lies within 0.5 µs of the 19 200 Hz grid. Jittered stamps (a logger's
    clock) stray from the line by more than their printed resolution and stay non-uniform.

    Examples
    --------
    >>> rounded_grid(np.round(np.arange(1000) / 19200.0, 6))
    True
    >>> rng = np.random.default_rng(0)
    >>> rounded_grid(np.round(np.arange(1000) / 250.0 + rng.normal(0, 1e-4, 1000), 6))
    False
    """
    t = np.asarray(time, dtype=float)
    n = t.size
    if n < 3 or not np.all(np.isfinite(t)):
        return False
    q = print_resolution(t)
    if q == 0.0:
        return False
    k = np.arange(n, dtype=float) - 0.5 * (n - 1)
    mean = float(np.mean(t))
    slope = float(np.dot(k, t - mean) / np.dot(k, k))
    if not slope > 0.0 or q > ROUNDED_GRID_LIMIT * slope:
        return False
    round_off = 2.0 * float(np.spacing(np.max(np.abs(t))))
    if round_off > 0.1 * q:  # the stamps' floats do not resolve their printed resolution
        return False
    deviation = float(np.max(np.abs(t - mean - slope * k)))
    # 1 % slack: a stamp exactly halfway rounds by q/2, and the fitted line is off by a little
    return bool(deviation <= 0.505 * q + round_off)
