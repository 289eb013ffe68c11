"""The filters a study tries: the seed's grid, the Savitzky-Golay tuning grid and their labels.

The seed (Kayaalp, sections 4.5.2.5-4.5.2.6) compares its filters on torque sampled at 250 Hz
(:data:`SEED_SAMPLE_RATE`) and gives the windows in samples at that rate; here they are scaled to
the rate a study runs at. Each candidate is a ``(method, params)`` pair for
:func:`rollerrig.signal.smoothing.smooth`.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from rollerrig._validation import ParameterError, require_positive
from rollerrig.signal._numeric import odd

__all__ = [
    "SEED_SAMPLE_RATE",
    "default_candidates",
    "filter_label",
    "savitzky_golay_candidates",
]

SEED_SAMPLE_RATE = 250.0
"""Sampling rate of the seed's torque recordings [Hz] (the default windows are given at it)."""


def filter_label(method: str, params: Mapping) -> str:
    """Short label of a candidate for tables and legends, e.g. ``"SG order 4 w111"``."""
    # A parameter left out shows as "?": the label also names a candidate whose parameters
    # are refused (rank_filters lists it with the reason).
    if method == "butterworth":
        kind = "zero-phase" if params.get("zero_phase", True) else "causal"
        cutoff = params.get("cutoff", "?")
        cutoff = f"{cutoff:g}" if isinstance(cutoff, int | float) else cutoff
        return f"Butterworth {params.get('order', 2)} @ {cutoff} Hz {kind}"
    if method == "savitzky_golay":
        return f"SG order {params.get('order', '?')} w{params.get('window', '?')}"
    names = {
        "moving_average": "MA",
        "gaussian": "Gaussian",
        "lowess": "LOWESS",
        "loess": "LOESS",
        "rlowess": "rLOWESS",
        "rloess": "rLOESS",
    }
    return f"{names.get(method, method)} w{params.get('window', '?')}"


def default_candidates(sample_rate: float = SEED_SAMPLE_RATE) -> list[tuple[str, dict]]:
    """The seed's filter grid (Kayaalp, sections 4.5.2.5-4.5.2.6), windows scaled to the rate.

    Butterworth orders 1-3 at 1.2 Hz, causal and zero-phase; moving average (11, 33, 65, 111,
    131), Gaussian (33, 65, 111, 131), LOWESS/LOESS (33, 65, 131), robust LOWESS/LOESS
    (33, 65, 131); Savitzky-Golay orders 2-7 × windows (33, 65, 111, 131). Windows are samples
    at 250 Hz, multiplied by ``sample_rate / 250`` (and made odd) at other rates.

    Parameters
    ----------
    sample_rate : float
        Sampling rate [Hz].

    Returns
    -------
    list of (str, dict)
        ``(method, params)`` pairs.

    Examples
    --------
    >>> len(default_candidates())
    51
    """
    fs = require_positive("sample_rate", sample_rate, "Hz", single=True)

    def w(k: int) -> int:
        return odd(k * fs / SEED_SAMPLE_RATE, 5)

    out: list[tuple[str, dict]] = []
    for zero_phase in (True, False):
        for order in (1, 2, 3):
            out.append(("butterworth", {"cutoff": 1.2, "order": order, "zero_phase": zero_phase}))
    out += [("moving_average", {"window": w(k)}) for k in (11, 33, 65, 111, 131)]
    out += [("gaussian", {"window": w(k)}) for k in (33, 65, 111, 131)]
    for method in ("lowess", "loess", "rlowess", "rloess"):
        out += [(method, {"window": w(k)}) for k in (33, 65, 131)]
    out += [
        ("savitzky_golay", {"window": w(k), "order": p})
        for p in range(2, 8)
        for k in (33, 65, 111, 131)
    ]
    return out


def savitzky_golay_candidates(
    sample_rate: float, orders: Iterable[int] = range(2, 8), windows: Iterable[int] | None = None
) -> list[tuple[str, dict]]:
    """The Savitzky-Golay tuning grid: every ``(order, window)`` with ``order < window``.

    Parameters
    ----------
    sample_rate : float
        Rate the filters run at [Hz].
    orders : iterable of int
        Polynomial orders.
    windows : iterable of int, optional
        Odd windows [samples at ``sample_rate``]; default 11, 21, ..., 201 at 250 Hz, scaled to
        ``sample_rate`` (0.04-0.8 s).

    Returns
    -------
    list of (str, dict)
        ``("savitzky_golay", {"window": w, "order": p})`` pairs.

    Examples
    --------
    >>> len(savitzky_golay_candidates(250.0)), savitzky_golay_candidates(250.0, [4], [5, 3])
    (120, [('savitzky_golay', {'window': 5, 'order': 4})])
    """
    fs = require_positive("sample_rate", sample_rate, "Hz", single=True)
    if windows is None:
        windows = sorted({odd(k * fs / SEED_SAMPLE_RATE, 5) for k in range(11, 202, 10)})
    candidates = [
        ("savitzky_golay", {"window": int(w), "order": int(p)})
        for p in orders
        for w in windows
        if int(p) < int(w)
    ]
    if not candidates:
        raise ParameterError("no (order, window) pair with order < window [samples]")
    return candidates
