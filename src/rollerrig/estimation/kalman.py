"""The causal Kalman filter of the contact torque: online, one sample at a time
(:class:`ContactObserver`), or over a whole recording (:func:`estimate_contact_torque`).

Its parts: the roller's model and gains in :mod:`~rollerrig.estimation.kalman_design`, the
steady-state recursion in Schur form in :mod:`~rollerrig.estimation.schur_recursion`; what it
shares with the smoothers: the estimate's type (:mod:`~rollerrig.estimation.contact_estimate`),
the models, default noises and validated parameters
(:mod:`~rollerrig.estimation.estimator_parameters`), the checked samples and the bearing loss
(:mod:`~rollerrig.estimation.estimator_inputs`). The estimate's type and the constants are
importable from here too.

The method, its tuning and its accuracy: :mod:`rollerrig.estimation.estimator`.
"""

from __future__ import annotations

import math

import numpy as np

from rollerrig.estimation.contact_estimate import ContactEstimate
from rollerrig.estimation.estimator_inputs import _bearing, _inputs
from rollerrig.estimation.estimator_parameters import (
    DEFAULT_PROCESS_NOISE,
    DEFAULT_TORQUE_NOISE,
    INITIAL_ACCELERATION_SD,
    INITIAL_SPEED_SD,
    MODELS,
    _check_model,
    _nonnegative,
    _positive,
    _roller_parameters,
)
from rollerrig.estimation.kalman_design import _Design, _design
from rollerrig.estimation.schur_recursion import _tail
from rollerrig.recordings.recording import RecordingError

__all__ = [
    "DEFAULT_PROCESS_NOISE",
    "DEFAULT_TORQUE_NOISE",
    "INITIAL_ACCELERATION_SD",
    "INITIAL_SPEED_SD",
    "MODELS",
    "ContactEstimate",
    "ContactObserver",
    "estimate_contact_torque",
]


def _step(d: _Design, z: np.ndarray, K: np.ndarray, dy: float, u_prev: float, u: float):
    """One filter step in scaled states relative to the measured angle.

    ``z[0]`` is θ̂ − y (the posterior angle minus the measured one), so that only the count
    increment ``dy`` [rad] enters and the states stay bounded over hours.
    """
    zp = d.F @ z + d.Ga * u_prev + d.Gb * u
    e = dy - zp[0]
    z = zp + K * e
    z[0] -= dy
    return z


class ContactObserver:
    """The causal contact-torque estimator, one sample at a time (the filter of
    :func:`estimate_contact_torque`, same parameters, same numbers to rounding).

    Parameters
    ----------
    sample_rate : float
        DAQ rate [Hz], > 0; samples are taken as uniformly spaced.
    counts_per_rev, roller_inertia, bearing_friction, bearing_radius, roller_weight,
    roller_radius, regularisation_speed, torque_noise, process_noise, model
        As :func:`estimate_contact_torque`.

    Examples
    --------
    A roller at 20 rad/s, no torque, no bearing loss: the contact torque stays at zero.

    >>> obs = ContactObserver(250.0, counts_per_rev=10000, roller_inertia=45.0,
    ...     bearing_friction=0.0, bearing_radius=0.065, roller_weight=5000.0,
    ...     roller_radius=0.452)
    >>> for k in range(500):
    ...     _ = obs.update(0.0, np.floor(20.0 * k / 250.0 * 10000 / (2 * np.pi)), 4300.0)
    >>> abs(obs.contact_torque) < 20.0, round(obs.roller_speed, 1)
    (True, 20.0)
    """

    def __init__(
        self,
        sample_rate: float,
        *,
        counts_per_rev: float,
        roller_inertia: float,
        bearing_friction: float,
        bearing_radius: float,
        roller_weight: float,
        roller_radius: float,
        regularisation_speed: float = 0.05,
        torque_noise: float | None = None,
        process_noise: float | None = None,
        model: str = "random_walk",
    ) -> None:
        self.model = _check_model(model)
        for name, value in _roller_parameters(
            sample_rate,
            counts_per_rev,
            roller_inertia,
            bearing_friction,
            bearing_radius,
            roller_weight,
            roller_radius,
            regularisation_speed,
        ).items():
            setattr(self, name, value)
        self.torque_noise = (
            DEFAULT_TORQUE_NOISE
            if torque_noise is None
            else _nonnegative("torque_noise", torque_noise, "N.m")
        )
        unit = "N^2.m^2/s" if model == "random_walk" else "N^2.m^2/s^3"
        self.process_noise = (
            DEFAULT_PROCESS_NOISE[model]
            if process_noise is None
            else _positive("process_noise", process_noise, unit)
        )
        self._design = _design(
            self.model,
            self.sample_rate,
            self.roller_inertia,
            self.counts_per_rev,
            self.process_noise,
            self.torque_noise,
        )
        self.reset()

    @property
    def gain(self) -> np.ndarray:
        """Steady-state Kalman gain in physical units (see :class:`ContactEstimate`)."""
        d = self._design
        return d.gain / d.scale

    @property
    def settling_samples(self) -> int:
        """Samples filtered with the time-varying gain [-]."""
        return int(self._design.gains.shape[0])

    def reset(self) -> None:
        """Forget every sample: the next :meth:`update` is a first sample."""
        self.samples = 0
        self._z = np.zeros(self._design.F.shape[0])
        self._counts = 0.0
        self._u = 0.0
        self.contact_torque = math.nan
        self.roller_speed = math.nan
        self.roller_acceleration = math.nan
        self.coa = math.nan

    def _input(self, torque: float, speed: float, load: float) -> float:
        return torque + float(
            _bearing(
                load,
                speed,
                self.bearing_friction,
                self.bearing_radius,
                self.roller_weight,
                self.regularisation_speed,
            )
        )

    def update(self, torque: float, counts: float, load: float) -> float:
        """Take one sample; return the contact torque F_x r_r [N.m] at it.

        Parameters
        ----------
        torque : float
            Measured roller-shaft torque T56 [N.m].
        counts : float
            Cumulative roller encoder count [-].
        load : float
            Normal load N [N], > 0.

        Returns
        -------
        float
            F_x r_r [N.m]; also in :attr:`contact_torque`, with :attr:`roller_speed`
            [rad/s], :attr:`roller_acceleration` [rad/s²] and :attr:`coa` [-].
        """
        values = []
        for name, value, unit in (
            ("torque", torque, "N.m"),
            ("counts", counts, "1"),
            ("load", load, "N"),
        ):
            try:
                v = float(value)
            except (TypeError, ValueError):
                raise RecordingError(
                    f"sample {self.samples}: {name} must be a number [{unit}], got {value!r}"
                ) from None
            if not math.isfinite(v):
                raise RecordingError(
                    f"sample {self.samples}: {name} is {v} [{unit}]; the estimator needs finite "
                    "samples: fill or cut the gap first (read_recording(..., lenient=True))"
                )
            values.append(v)
        t56, c, n = values
        if n <= 0.0:
            raise RecordingError(
                f"sample {self.samples}: load must be > 0 [N] (CoA = F_x r_r/(r_r N)), got {n!r}"
            )
        d = self._design
        scale = 2.0 * math.pi / self.counts_per_rev
        if self.samples == 0:
            u = self._input(t56, 0.0, n)
            z = np.zeros(d.F.shape[0])
            z[2] = u * d.h * d.h / d.inertia
        else:
            dy = (c - self._counts) * scale
            u = self._input(t56, dy * self.sample_rate, n)
            k = self.samples - 1
            K = d.gains[k] if k < d.gains.shape[0] else d.gain
            z = _step(d, self._z, K, dy, self._u, u)
        self._z, self._counts, self._u = z, c, u
        self.samples += 1
        self.contact_torque = float(z[2] / d.scale[2])
        self.roller_speed = float(z[1] / d.scale[1])
        self.roller_acceleration = (self.contact_torque - u) / d.inertia
        self.coa = self.contact_torque / (self.roller_radius * n)
        return self.contact_torque


def estimate_contact_torque(
    torque,
    roller_counts,
    normal_load,
    sample_rate: float,
    *,
    counts_per_rev: float,
    roller_inertia: float,
    bearing_friction: float,
    bearing_radius: float,
    roller_weight: float,
    roller_radius: float,
    regularisation_speed: float = 0.05,
    torque_noise: float | None = None,
    process_noise: float | None = None,
    model: str = "random_walk",
) -> ContactEstimate:
    """Causal Kalman estimate of the contact torque F_x r_r, its CoA and the roller speed.

    .. math:: J_5 \\dot\\omega_5 = F_x r_r - T_{56} - R_{05}, \\quad
              \\theta_5 = \\mathrm{counts}\\,2\\pi/\\mathrm{CPR}

    Each output uses only the samples up to its own instant (see the module docstring for the
    model, the tuning and its accuracy against the offline correction). O(n): a short Python
    loop while the gain settles, then :func:`scipy.signal.lfilter`.

    Parameters
    ----------
    torque : array_like, shape (n,)
        Measured roller-shaft torque T56 [N.m].
    roller_counts : array_like, shape (n,)
        Cumulative roller encoder counts [-].
    normal_load : array_like, shape (n,) or float
        Normal load N [N], > 0.
    sample_rate : float
        [Hz], > 0; the samples are taken as uniformly spaced.
    counts_per_rev : float
        Encoder counts per revolution after quadrature decoding [-].
    roller_inertia : float
        J5 [kg.m^2].
    bearing_friction : float
        f_g [-].
    bearing_radius : float
        Roller bearing friction radius r_b [m].
    roller_weight : float
        W_r [N].
    roller_radius : float
        r_r [m] (for the CoA).
    regularisation_speed : float
        ω_reg of the bearing model [rad/s].
    torque_noise : float, optional
        Standard deviation of the torque sensor's white noise [N.m]; default
        :data:`DEFAULT_TORQUE_NOISE`.
    process_noise : float, optional
        Spectral density of the contact torque's random walk [N².m²/s] (of its slope for the
        integrated random walk [N².m²/s³]); default :data:`DEFAULT_PROCESS_NOISE` of the model.
    model : str
        ``"random_walk"`` (default) or ``"integrated_random_walk"``.

    Returns
    -------
    ContactEstimate

    Raises
    ------
    RecordingError
        Arrays of different lengths, empty, not 1-D, with NaN/inf, or a load not > 0.
    ParameterError
        A parameter out of range (the message names it, its unit and the range).

    Examples
    --------
    A roller accelerating at 2 rad/s² with no shaft torque: the contact supplies J5·α5 = 90 N.m.

    >>> t = np.arange(2500) / 250.0
    >>> counts = np.floor((18.0 * t + t**2) * 10000 / (2 * np.pi))
    >>> est = estimate_contact_torque(np.zeros(t.size), counts, 4300.0, 250.0,
    ...     counts_per_rev=10000, roller_inertia=45.0, bearing_friction=0.0,
    ...     bearing_radius=0.065, roller_weight=5000.0, roller_radius=0.452)
    >>> round(float(np.mean(est.contact_torque[1250:])), 0)
    90.0
    """
    observer = ContactObserver(
        sample_rate,
        counts_per_rev=counts_per_rev,
        roller_inertia=roller_inertia,
        bearing_friction=bearing_friction,
        bearing_radius=bearing_radius,
        roller_weight=roller_weight,
        roller_radius=roller_radius,
        regularisation_speed=regularisation_speed,
        torque_noise=torque_noise,
        process_noise=process_noise,
        model=model,
    )
    t56, c, n_load = _inputs(torque, roller_counts, normal_load)
    n = t56.size
    d = observer._design
    fs = observer.sample_rate
    dy = np.empty(n)
    dy[0] = 0.0
    dy[1:] = np.diff(c) * (2.0 * math.pi / observer.counts_per_rev)
    speed_enc = dy * fs  # backward difference; 0 at the first sample
    u = t56 + _bearing(
        n_load,
        speed_enc,
        observer.bearing_friction,
        observer.bearing_radius,
        observer.roller_weight,
        observer.regularisation_speed,
    )

    nz = d.F.shape[0]
    z_hist = np.empty((n, nz))
    # The loop while the gain varies; the steady-state recursion from there on.
    n_loop = min(n, d.gains.shape[0] + 1)
    for k in range(n_loop):
        observer.update(t56[k], c[k], n_load[k])
        z_hist[k] = observer._z
    if n > n_loop:
        _tail(d, z_hist, n_loop, dy, u)
    contact = z_hist[:, 2] / d.scale[2]
    speed = z_hist[:, 1] / d.scale[1]
    return ContactEstimate(
        contact_torque=contact,
        roller_speed=speed,
        roller_acceleration=(contact - u) / d.inertia,
        coa=contact / (observer.roller_radius * n_load),
        sample_rate=fs,
        model=observer.model,
        process_noise=observer.process_noise,
        torque_noise=observer.torque_noise,
        gain=observer.gain,
        settling_samples=observer.settling_samples,
    )
