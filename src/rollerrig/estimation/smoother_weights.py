"""The steady-state smoother as a linear filter on the torque, angle and bearing-loss samples
(:func:`smoother_weights`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.estimation.estimator_parameters import _MAX_SETTLING, _positive
from rollerrig.estimation.smoother import (
    RollerChain,
    _smoother_backward,
    _smoother_design,
    _smoother_forward,
    _smoother_noises,
)

__all__ = ["SmootherWeights", "smoother_weights"]


@dataclass(frozen=True)
class SmootherWeights:
    """The steady-state smoother as a linear filter: the contact torque at sample k is
    Σ_j torque[j] T56_{k−j} + angle[j] θ_{k−j} + bearing[j] R05_{k−j}, j over ``lags``.

    Attributes
    ----------
    lags : numpy.ndarray
        j [samples] (negative: later samples).
    torque : numpy.ndarray
        Weights of the torque samples [N.m/N.m].
    angle : numpy.ndarray
        Weights of the encoder angle samples θ = counts·2π/CPR [N.m/rad] (they sum to zero).
    bearing : numpy.ndarray
        Weights of the bearing-loss samples [N.m/N.m].
    """

    lags: np.ndarray
    torque: np.ndarray
    angle: np.ndarray
    bearing: np.ndarray

    def noise_variance(self, torque_sd: float, counts_per_rev: float) -> float:
        """Variance of the estimate from white torque noise and uniform quantisation [N².m²].

        Parameters
        ----------
        torque_sd : float
            Standard deviation of the torque sensor's white noise [N.m].
        counts_per_rev : float
            Encoder counts per revolution [-] (quantisation variance (2π/CPR)²/12).
        """
        q = 2.0 * math.pi / counts_per_rev
        return float(torque_sd**2 * np.sum(self.torque**2) + q * q / 12.0 * np.sum(self.angle**2))


def smoother_weights(
    sample_rate: float,
    *,
    counts_per_rev: float,
    roller_inertia: float,
    torque_noise: float | None = None,
    process_noise: float | None = None,
    model: str = "random_walk",
    chain: RollerChain | None = None,
    drive_noise: float | None = None,
    lines: bool = False,
    tolerance: float = 1e-9,
) -> SmootherWeights:
    """The weights of the steady-state smoother of :func:`smooth_contact_torque` (away from the
    ends of a recording, and without the order lines' fit, itself a linear projection).

    Parameters
    ----------
    sample_rate, counts_per_rev, roller_inertia, torque_noise, process_noise, model, chain,
    drive_noise
        As :func:`smooth_contact_torque`.
    lines : bool
        Take the default torque noise of a chain smoother that fits order lines.
    tolerance : float
        The weights are cut where the filters' slowest pole has decayed to this [-].

    Returns
    -------
    SmootherWeights

    Examples
    --------
    The weights keep a constant torque and read J5·α5 off a parabola of the angle
    (Σ_j w_j j² h²/2 = J5), and the encoder's quantisation with 1 N.m of torque noise leaves
    about 5 N.m of noise on the roller alone:

    >>> w = smoother_weights(250.0, counts_per_rev=10000, roller_inertia=45.0)
    >>> round(float(w.torque.sum()), 6), round(float(np.sum(w.angle * w.lags**2) / 2 / 250**2), 3)
    (1.0, 45.0)
    >>> round(w.noise_variance(1.0, 10000) ** 0.5, 1)
    4.9
    """
    fs = _positive("sample_rate", sample_rate, "Hz")
    cpr = _positive("counts_per_rev", counts_per_rev, "1")
    inertia = _positive("roller_inertia", roller_inertia, "kg.m^2")
    tol = _positive("tolerance", tolerance, "1")
    model, q, sigma_t, q_drive = _smoother_noises(
        model, chain, torque_noise, process_noise, drive_noise, lines
    )
    if q_drive == "ml":
        raise ParameterError(
            "smoother_weights needs a drive_noise value [N^2.m^2/s]: 'ml' is fitted to a "
            "recording (take ContactEstimate.drive_noise of smooth_contact_torque)"
        )
    sd = _smoother_design(model, fs, inertia, cpr, q, sigma_t, chain, q_drive)
    slowest = float(np.max(np.abs(np.linalg.eigvals(sd.Phi))))
    half = int(min(math.ceil(math.log(min(tol, 0.5)) / math.log(slowest)), _MAX_SETTLING))
    size = 2 * half + 1
    zero, nz = np.zeros(size), sd.F.shape[0]

    def response(dth, y_torque, u):
        Z = _smoother_forward(sd, dth, y_torque, u, np.zeros(nz), exact=False)
        Zs = _smoother_backward(sd, Z, dth, u, exact=False)
        return Zs[::-1, sd.i_d] * sd.scale[sd.i_d]  # output k − j for the impulse at j = half

    impulse = np.zeros(size)
    impulse[half] = 1.0
    steps = np.zeros(size)
    steps[half], steps[half + 1] = 1.0, -1.0  # Δθ of θ_j = δ_j,half
    angle = response(steps, zero, zero)
    bearing = response(zero, zero, impulse)
    torque = bearing if chain is None else response(zero, impulse, zero)
    return SmootherWeights(np.arange(half, -half - 1, -1), torque, angle, bearing)
