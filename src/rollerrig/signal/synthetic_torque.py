"""A synthetic roller-shaft torque shaped like the seed's, with its truth and its segments.

The filter study's tests, doctests and benchmarks need a torque record whose noise-free truth and
steady/transient parts are known: :func:`seed_like_torque` builds one after Kayaalp, sections
4.5.2.4-4.5.2.6 (ramp, adhesion peak, release within 20 ms, damped oscillation, ramp down), with
the induction-motor ripple and white noise added.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rollerrig._validation import require_positive
from rollerrig.signal.filter_candidates import SEED_SAMPLE_RATE
from rollerrig.signal.steady_transient import Segmentation

__all__ = ["SyntheticTorque", "seed_like_torque"]


@dataclass(frozen=True)
class SyntheticTorque:
    """A synthetic roller-shaft torque record with known truth.

    Attributes
    ----------
    time : ndarray
        Sample times [s].
    raw : ndarray
        Measured-like torque [N·m]: truth + motor ripple + noise.
    truth : ndarray
        Noise-free torque [N·m].
    torque_request : ndarray
        Piecewise torque request [N·m].
    segmentation : Segmentation
        Steady and transient parts by construction.
    sample_rate : float
        Sampling rate [Hz].
    """

    time: np.ndarray
    raw: np.ndarray
    truth: np.ndarray
    torque_request: np.ndarray
    segmentation: Segmentation
    sample_rate: float


def seed_like_torque(
    sample_rate: float = SEED_SAMPLE_RATE,
    duration: float = 20.0,
    electrical_frequency: float = 14.7,
    ripple: tuple[float, ...] = (15.0, 6.0),
    noise: float = 5.0,
    seed: int = 0,
) -> SyntheticTorque:
    """A torque record shaped like the seed's (Kayaalp, sections 4.5.2.4-4.5.2.6).

    Layout over 20 s (scaled to ``duration``): steady 100 N·m; ramp 4-9.6 s to 320 N·m, then a
    sharper rise to a 400 N·m adhesion peak at 10 s; release to 220 N·m within 20 ms; damped
    oscillation after it (3 Hz, 60 N·m, 0.35 s decay); steady; ramp down 14-16 s to 100 N·m;
    steady. Added: induction-motor ripple at ``electrical_frequency`` (14.7 Hz at 30 km/h
    = 5 × the roller rotation frequency) and its harmonics with amplitudes ``ripple`` [N·m], and
    white noise of standard deviation ``noise`` [N·m].

    Parameters
    ----------
    sample_rate : float
        Sampling rate [Hz].
    duration : float
        Record length [s].
    electrical_frequency : float
        Ripple fundamental [Hz].
    ripple : tuple of float
        Amplitudes of the fundamental and its harmonics [N·m].
    noise : float
        White-noise standard deviation [N·m].
    seed : int
        Random seed.

    Returns
    -------
    SyntheticTorque
        The record.

    Examples
    --------
    >>> sig = seed_like_torque()
    >>> sig.raw.shape, round(float(sig.truth.max()))
    ((5000,), 400)
    """
    fs = require_positive("sample_rate", sample_rate, "Hz", single=True)
    dur = require_positive("duration", duration, "s", single=True)
    n = round(dur * fs)
    t = np.arange(n) / fs
    c = dur / 20.0
    t_up, t_knee, t_peak, t_rel = 4.0 * c, 9.6 * c, 10.0 * c, 0.02
    t_hold, t_down = 14.0 * c, 16.0 * c
    base, knee, peak, after = 100.0, 320.0, 400.0, 220.0
    u = np.clip((t - t_up) / (t_knee - t_up), 0.0, 1.0)
    q = np.clip((t - t_knee) / (t_peak - t_knee), 0.0, 1.0)
    rise = base + (knee - base) * u + (peak - knee) * (1.0 - (1.0 - q) ** 2)
    v = np.clip((t - t_peak) / t_rel, 0.0, 1.0)
    drop = peak + (after - peak) * 0.5 * (1 - np.cos(np.pi * v))
    td = np.maximum(t - t_peak - t_rel, 0.0)
    osc = 60.0 * np.exp(-td / 0.35) * np.sin(2 * np.pi * 3.0 * td)
    w = np.clip((t - t_hold) / (t_down - t_hold), 0.0, 1.0)
    down = after + (base - after) * w
    truth = np.where(t < t_peak, rise, np.where(t < t_hold, drop + osc, down))
    ramp = np.clip((t - t_up) / (t_peak - t_up), 0.0, 1.0)
    request = np.where(
        t < t_peak, base + (peak + 20.0 - base) * ramp, np.where(t < t_hold, after, down)
    )
    rng = np.random.default_rng(seed)
    disturbance = noise * rng.standard_normal(n)
    for k, amp in enumerate(ripple, start=1):
        disturbance += amp * np.sin(
            2 * np.pi * k * electrical_frequency * t + rng.uniform(0, 2 * np.pi)
        )
    raw = truth + disturbance

    def idx(a: float, b: float) -> tuple[int, int]:
        return round(a * fs), round(b * fs)

    seg = Segmentation.from_ranges(
        n,
        steady=[
            idx(0.5 * c, t_up - 0.5 * c),
            idx(t_peak + 2.0 * c, t_hold - 0.5 * c),
            idx(t_down + 0.5 * c, dur - 0.5 * c),
        ],
        transient=[
            idx(t_up - 0.25 * c, t_peak + 1.5 * c),
            idx(t_hold - 0.25 * c, t_down + 0.25 * c),
        ],
    )
    return SyntheticTorque(t, raw, truth, request, seg, fs)
