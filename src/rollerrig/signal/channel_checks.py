"""A channel that never changes: one check and one message for the spectrum, the filter study
and the analysis (a disconnected sensor recorded as a constant)."""

from __future__ import annotations

import numpy as np

from rollerrig._validation import ParameterError

__all__ = ["check_varies", "constant_channel_message"]


def constant_channel_message(name: str, value: float, n: int, lacks: str) -> str:
    """The one text for a channel that never changes (spectrum, filter study, analysis).

    >>> constant_channel_message("channel 'torque'", 12.5, 3, "has no spectrum")
    "channel 'torque' is constant (12.5 in all 3 samples): it has no spectrum; check that the channel is connected and mapped"
    """  # noqa: E501
    return (
        f"{name} is constant ({value:g} in all {n} samples): it {lacks}; check that the channel "
        "is connected and mapped"
    )


def check_varies(values, name: str, lacks: str) -> None:
    """ParameterError (:func:`constant_channel_message`) when the finite ``values`` never
    change (beyond round-off, 1e-12 of their magnitude: a constant stays one after filters)."""
    x = np.asarray(values, dtype=float)
    finite = x[np.isfinite(x)]
    if finite.size < 2:
        return
    lo, hi = float(finite.min()), float(finite.max())
    if hi - lo <= 1e-12 * max(abs(lo), abs(hi)):
        raise ParameterError(constant_channel_message(name, float(finite[0]), x.size, lacks))
