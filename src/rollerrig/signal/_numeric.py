"""Small numeric helpers shared by the signal modules (one place for each rule).

* :func:`odd` -- a window length in samples made odd (the filter study's windows);
* :func:`finite_or_none` -- a number for JSON and tables: None where it is not finite;
* :func:`power_of_two_scale` -- an exact rescaling that keeps squares and sums inside the float
  range;
* :func:`tidy_rate` -- a rate computed from float time stamps, rounded to 10 significant digits;
* :func:`uniform_sample_rate` -- the rate of a uniform time base, or an error naming the step
  that breaks it;
* :func:`check_samples` -- a streamed chunk checked for non-finite and absurd values, the error
  naming the sample.
"""

from __future__ import annotations

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.recordings.uniform import uniform_sample_rate
from rollerrig.signal.channel_checks import check_varies, constant_channel_message

__all__ = [
    "check_samples",
    "check_varies",
    "constant_channel_message",
    "finite_or_none",
    "odd",
    "power_of_two_scale",
    "tidy_rate",
    "uniform_sample_rate",
]


def odd(n: float, minimum: int = 3) -> int:
    """``n`` rounded, at least ``minimum``, and made odd by adding one [samples].

    Examples
    --------
    >>> odd(110.6), odd(4), odd(1.0, 1)
    (111, 5, 1)
    """
    k = max(round(n), minimum)
    return k if k % 2 else k + 1


def finite_or_none(value) -> float | None:
    """A float, or None for None, NaN and inf (JSON has no NaN; the caller says why).

    Examples
    --------
    >>> finite_or_none(2), finite_or_none(float("nan")), finite_or_none(None)
    (2.0, None, None)
    """
    if value is None:
        return None
    value = float(value)
    return value if np.isfinite(value) else None


def power_of_two_scale(peak: float) -> float:
    """A power of two ``s`` with ``s·peak`` in [0.5, 1) (1 for a zero peak) [1/unit].

    Multiplying by a power of two is exact in floating point, so a signal scaled by it keeps every
    digit while its squares and sums can neither overflow nor underflow.

    Examples
    --------
    >>> power_of_two_scale(400.0), power_of_two_scale(0.0)
    (0.001953125, 1.0)
    """
    peak = float(peak)
    return 1.0 if peak == 0.0 else float(np.ldexp(1.0, -int(np.frexp(peak)[1])))


def tidy_rate(rate: float) -> float:
    """A rate [Hz] rounded to 10 significant digits (19200.000000001 from float stamps: 19200).

    Examples
    --------
    >>> tidy_rate(1.0 / (1.0 / 19200.0))
    19200.0
    """
    return float(f"{float(rate):.10g}")


def check_samples(values, start: int, limit: float, why: str, name: str = "the signal") -> None:
    """Refuse a chunk holding a non-finite value or one beyond ``limit``, naming the sample.

    Parameters
    ----------
    values : ndarray, shape (m,) or (m, channels)
        Samples along axis 0 [any unit].
    start : int
        Index of ``values[0]`` in the whole signal [samples].
    limit : float
        Largest magnitude accepted [unit of ``values``].
    why : str
        What goes wrong beyond ``limit`` (stated in the error).
    name : str
        The signal in the error (e.g. ``"channel 'torque'"``).

    Raises
    ------
    ParameterError
        ``"<name> has a non-finite value (nan) at sample 12345; ..."`` or ``"<name> reaches
        1e+120 at sample 7, beyond 1e+100: <why>; ..."``.

    Examples
    --------
    >>> check_samples(np.array([1.0, 2.0]), 0, 1e100, "no sensor reads that")
    >>> check_samples(np.array([1.0, np.inf]), 10, 1e100, "why", "torque")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    rollerrig._validation.ParameterError: torque has a non-finite value (inf) at sample 11; ...
    """
    values = np.asarray(values)
    if values.size == 0 or float(np.max(np.abs(values))) <= limit:  # NaN compares False
        return
    rows = values.reshape(values.shape[0], -1)
    bad = ~np.isfinite(rows)
    if bad.any():
        i = int(np.argmax(bad.any(axis=1)))
        raise ParameterError(
            f"{name} has a non-finite value ({rows[i][bad[i]][0]}) at sample {start + i}; fill "
            "or cut the gap first (e.g. --lenient)"
        )
    i = int(np.argmax((np.abs(rows) > limit).any(axis=1)))
    value = rows[i][int(np.argmax(np.abs(rows[i])))]
    raise ParameterError(
        f"{name} reaches {value:.3g} at sample {start + i}, beyond {limit:.0e}: {why}; check the "
        "channel's unit and scale in the channel map"
    )
