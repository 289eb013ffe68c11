"""The order lines of the torque channel (cos/sin of an order of the roller's or the wheel's
rotation), their amplitudes by maximum likelihood on the forward filter's innovations, constant
within blocks of :data:`LINE_BLOCK`: removed before the chain smoother runs
(:func:`rollerrig.estimation.smoother.smooth_contact_torque`).
"""

from __future__ import annotations

import math

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.estimation.smoother_model import _Smoother
from rollerrig.estimation.smoother_passes import _innovations

__all__ = ["LINE_BLOCK"]


LINE_BLOCK = 60.0
"""Length of the blocks in which the order lines of the torque are fitted [s]: their amplitude
and phase are taken as constant within a block."""


def _order_lines(sd: _Smoother, dth, torque, u, angles_orders, fs):
    """Lines cos/sin(order·angle) of the torque channel, their amplitudes by maximum
    likelihood: constant within blocks of :data:`LINE_BLOCK` (as states without process noise
    in the measurement), estimated by weighted least squares on the forward filter's
    innovations, which are linear in the amplitudes (e(a) = e(0) − Σ a_j ψ_j, ψ_j the
    innovations of the line j alone). The samples of the filter's transient are left out."""
    n = torque.size
    cols = [
        f(order * angle)
        for angle, orders in angles_orders
        for order in orders
        for f in (np.cos, np.sin)
    ]
    zero = np.zeros(n)
    W = np.linalg.cholesky(np.linalg.inv(sd.H @ sd.P_prior @ sd.H.T + np.eye(2)))
    e0 = _innovations(sd, dth, torque, u) @ W
    psi = np.array([_innovations(sd, zero, x, zero) @ W for x in cols])  # (m, n − 1, 2)
    block = max(round(LINE_BLOCK * fs), 1)
    starts = list(range(0, n, block))
    if len(starts) > 1 and n - starts[-1] < block // 2:
        starts.pop()  # a short last block joins the one before
    fit = np.zeros(n)
    skip = sd.gains.shape[0] + 1
    for b, lo in enumerate(starts):
        hi = starts[b + 1] if b + 1 < len(starts) else n
        rows = slice(max(lo, skip) - 1, hi - 1)  # innovations of samples lo..hi−1
        if rows.stop - rows.start <= len(cols):
            continue  # too short a block to tell the lines apart
        A = psi[:, rows].reshape(len(cols), -1).T
        coef, *_ = np.linalg.lstsq(A, e0[rows].reshape(-1), rcond=None)
        for a, x in zip(coef, cols, strict=True):
            fit[lo:hi] += a * x[lo:hi]
    return fit


def _orders(name: str, orders) -> tuple[float, ...]:
    try:
        values = tuple(float(o) for o in orders)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be numbers (orders of the rotation) [-]") from None
    for o in values:
        if not (math.isfinite(o) and o > 0.0):
            raise ParameterError(f"{name} must be finite and > 0 [-], got {o!r}")
    return values
