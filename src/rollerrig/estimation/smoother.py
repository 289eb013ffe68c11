"""The two-sided (Rauch-Tung-Striebel) smoothers of the contact torque
(:func:`smooth_contact_torque`): the roller alone or the roller-shaft-rotor-drive chain, their
default noises, the order lines removed and the drive noise found, the estimate returned.

The method, its tuning and its accuracy: :mod:`rollerrig.estimation.estimator`. The parts:
the model and its gains (:class:`~rollerrig.estimation.smoother_model.RollerChain`,
:mod:`~rollerrig.estimation.smoother_model`), the forward and backward passes
(:mod:`~rollerrig.estimation.smoother_passes`), the torque's order lines
(:mod:`~rollerrig.estimation.order_lines`), the innovations judged and the drive noise by
maximum likelihood (:mod:`~rollerrig.estimation.smoother_likelihood`).
"""

from __future__ import annotations

import math

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.estimation.contact_estimate import ContactEstimate
from rollerrig.estimation.estimator_inputs import _array, _bearing, _inputs
from rollerrig.estimation.estimator_parameters import (
    DEFAULT_TORQUE_NOISE,
    _check_model,
    _nonnegative,
    _positive,
    _roller_parameters,
)
from rollerrig.estimation.order_lines import LINE_BLOCK, _order_lines, _orders
from rollerrig.estimation.smoother_likelihood import (
    DRIVE_NOISE_RANGE,
    _innovation_whiteness,
    _most_likely_drive_noise,
)
from rollerrig.estimation.smoother_model import RollerChain, _smoother_design
from rollerrig.estimation.smoother_passes import (
    _innovations,
    _smoothed_variance,
    _smoother_backward,
    _smoother_forward,
    _start,
)
from rollerrig.recordings.recording import RecordingError

__all__ = [
    "DEFAULT_CHAIN_NOISE",
    "DEFAULT_CHAIN_TORQUE_NOISE",
    "DEFAULT_DRIVE_NOISE",
    "DEFAULT_SMOOTHER_NOISE",
    "DRIVE_NOISE_RANGE",
    "LINE_BLOCK",
    "RollerChain",
    "smooth_contact_torque",
]


DEFAULT_SMOOTHER_NOISE = {"random_walk": 3e4, "integrated_random_walk": 1e8}
"""Default spectral density of the contact torque's process noise of the smoother on the
roller alone (``chain=None``), by model [N².m²/s] or [N².m²/s³] (module docstring)."""

DEFAULT_CHAIN_NOISE = {"random_walk": 3e4, "integrated_random_walk": 1e9}
"""Default spectral density of the contact torque's process noise of the smoother on the
roller-shaft-rotor chain, by model [N².m²/s] or [N².m²/s³] (module docstring)."""

DEFAULT_DRIVE_NOISE = 1e2
"""Default spectral density of the random walk of the roller drive [N².m²/s]: of κ·ω_s, the
linearised induction motor's torque at standstill, or of the drive torque itself when the drive
is not modelled (module docstring)."""

DEFAULT_CHAIN_TORQUE_NOISE = {"lines": 1.5, "no_lines": 4.0}
"""Default standard deviation of the torque measurement of the chain model [N.m], with and
without the fit of the order lines: the sensor's white noise (1 N.m on the synthetic
recordings) and what the model does not explain (the lines when they are not fitted, the
motor's nonlinearity); chosen on synthetic recordings (module docstring)."""


def _smoother_noises(model, chain, torque_noise, process_noise, drive_noise, lines=False):
    """The validated model name and noises of the smoother, defaults filled in."""
    model = _check_model(model)
    if chain is not None and not isinstance(chain, RollerChain):
        raise ParameterError(
            f"chain must be a RollerChain (RollerChain.from_rig(rig)) or None, got "
            f"{type(chain).__name__}"
        )
    unit = "N^2.m^2/s" if model == "random_walk" else "N^2.m^2/s^3"
    defaults = DEFAULT_SMOOTHER_NOISE if chain is None else DEFAULT_CHAIN_NOISE
    q = (
        defaults[model]
        if process_noise is None
        else _positive("process_noise", process_noise, unit)
    )
    if chain is None:
        sigma_t = (
            DEFAULT_TORQUE_NOISE
            if torque_noise is None
            else _nonnegative("torque_noise", torque_noise, "N.m")
        )
        return model, q, sigma_t, 0.0
    sigma_t = (
        DEFAULT_CHAIN_TORQUE_NOISE["lines" if lines else "no_lines"]
        if torque_noise is None
        else _positive("torque_noise", torque_noise, "N.m")
    )
    if isinstance(drive_noise, str):
        if drive_noise != "ml":
            raise ParameterError(
                f"drive_noise must be a spectral density [N^2.m^2/s] or 'ml' (maximum "
                f"likelihood), got {drive_noise!r}"
            )
        return model, q, sigma_t, "ml"
    q_drive = (
        DEFAULT_DRIVE_NOISE
        if drive_noise is None
        else _positive("drive_noise", drive_noise, "N^2.m^2/s")
    )
    return model, q, sigma_t, q_drive


def smooth_contact_torque(
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
    chain: RollerChain | None = None,
    drive_noise: float | None = None,
    roller_orders=(),
    wheel_counts=None,
    wheel_orders=(),
) -> ContactEstimate:
    """Offline (two-sided) estimate of the contact torque F_x r_r: a Rauch-Tung-Striebel
    smoother.

    The Kalman filter of :func:`estimate_contact_torque` run forward, then the RTS recursion
    backward (Rauch, Tung and Striebel 1965; Särkkä 2013, section 8.2): each output uses every
    sample of the recording. With ``chain=None`` the model is the causal filter's (the roller
    alone, T56 an input); with a :class:`~rollerrig.estimation.smoother_model.RollerChain`, the
    roller, the roller shaft, the motor's rotor and the roller drive, with T56 a second
    measurement (of the shaft's twist): the torque sensor then also tells the roller's
    acceleration, through the shaft's dynamics. Order lines of the torque channel
    (``roller_orders`` of the roller's rotation, ``wheel_orders`` of the wheel's; chain only)
    are estimated by maximum likelihood, constant within blocks of
    :data:`~rollerrig.estimation.order_lines.LINE_BLOCK` (weighted least squares on the forward
    filter's innovations), and removed before the smoother runs. See the module docstring for the
    tuning and the accuracy.

    Exact time-varying gains while the filter settles, then the steady-state filter and
    smoother gains, run as triangular recursions by :func:`scipy.signal.lfilter` (an hour at
    250 Hz in seconds).

    Parameters
    ----------
    torque, roller_counts, normal_load, sample_rate, counts_per_rev, roller_inertia,
    bearing_friction, bearing_radius, roller_weight, roller_radius, regularisation_speed
        As :func:`estimate_contact_torque`.
    torque_noise : float, optional
        Standard deviation of the torque sensor [N.m]: a white input noise on the roller alone
        (default :data:`DEFAULT_TORQUE_NOISE`), the torque measurement's noise in the chain
        model, > 0 (default :data:`DEFAULT_CHAIN_TORQUE_NOISE`, ``"lines"`` when orders are
        given).
    process_noise : float, optional
        Spectral density of the contact torque's random walk [N².m²/s] (of its slope for the
        integrated random walk [N².m²/s³]); default :data:`DEFAULT_SMOOTHER_NOISE` (roller
        alone) or :data:`DEFAULT_CHAIN_NOISE` (chain).
    model : str
        ``"random_walk"`` (default) or ``"integrated_random_walk"``.
    chain : RollerChain, optional
        The roller shaft, the rotor and the drive
        (:meth:`~rollerrig.estimation.smoother_model.RollerChain.from_rig`); None: the roller
        alone.
    drive_noise : float or "ml", optional
        Spectral density of the drive's random walk [N².m²/s] (chain only); default
        :data:`DEFAULT_DRIVE_NOISE`. ``"ml"``: the one in
        :data:`~rollerrig.estimation.smoother_likelihood.DRIVE_NOISE_RANGE` that maximises the
        likelihood of the innovations (a drive the lag model does not describe, such as the dq
        machine under slip compensation, takes 10³–10⁴ times the default and the chain then
        leans on the torque sensor: RMS CoA error 0.0039–0.0043 on such recordings, against
        0.0093–0.0124 at the default and 0.0044–0.0046 for the roller alone; the twin's own
        recording keeps 0.0022).
    roller_orders : sequence of float
        Orders of the roller's rotation whose lines are fitted and removed from the torque
        (e.g. 1, 2 and the roller motor's pole pairs p, 2p, 3p); default none.
    wheel_counts : array_like, optional
        Cumulative wheel encoder counts [-] (same CPR), for ``wheel_orders``.
    wheel_orders : sequence of float
        Orders of the wheel's rotation to remove (e.g. 1, 2 and the wheel motor's pole pairs).

    Returns
    -------
    ContactEstimate
        With ``contact_torque_variance`` (the smoother's P of the contact torque, per sample
        [N².m²]), ``smoother_gain`` and ``torque_lines`` (the lines removed [N.m]);
        ``settling_samples`` counts the forward filter's time-varying gains.

    Raises
    ------
    RecordingError
        As :func:`estimate_contact_torque` (and for ``wheel_counts``).
    ParameterError
        A parameter out of range (the message names it, its unit and the range).

    Examples
    --------
    A roller accelerating at 2 rad/s² with no shaft torque: the contact supplies J5·α5 = 90 N.m.

    >>> t = np.arange(2500) / 250.0
    >>> counts = np.floor((18.0 * t + t**2) * 10000 / (2 * np.pi))
    >>> est = smooth_contact_torque(np.zeros(t.size), counts, 4300.0, 250.0,
    ...     counts_per_rev=10000, roller_inertia=45.0, bearing_friction=0.0,
    ...     bearing_radius=0.065, roller_weight=5000.0, roller_radius=0.452)
    >>> round(float(np.mean(est.contact_torque)), 0), round(float(est.contact_torque.std()), 0)
    (90.0, 5.0)
    """
    par = _roller_parameters(
        sample_rate,
        counts_per_rev,
        roller_inertia,
        bearing_friction,
        bearing_radius,
        roller_weight,
        roller_radius,
        regularisation_speed,
    )
    r_orders = _orders("roller_orders", roller_orders)
    w_orders = _orders("wheel_orders", wheel_orders)
    model, q, sigma_t, q_drive = _smoother_noises(
        model, chain, torque_noise, process_noise, drive_noise, bool(r_orders or w_orders)
    )
    if chain is None and (r_orders or w_orders):
        raise ParameterError(
            "roller_orders and wheel_orders need chain=RollerChain(...): on the roller alone "
            "a line of the torque sensor cannot be told from the contact torque (T56 is an "
            "input there)"
        )
    t56, c, n_load = _inputs(torque, roller_counts, normal_load)
    n = t56.size
    fs = par["sample_rate"]
    to_rad = 2.0 * math.pi / par["counts_per_rev"]
    angles_orders = []
    if r_orders:
        angles_orders.append(((c - c[0]) * to_rad, r_orders))
    if w_orders:
        if wheel_counts is None:
            raise ParameterError("wheel_orders need wheel_counts (the wheel encoder's counts)")
        wc = _array("wheel_counts", wheel_counts, "1", "cumulative wheel encoder counts")
        if wc.shape != t56.shape:
            raise RecordingError(
                f"wheel_counts has {wc.size} samples and torque {n}: give both on the same "
                "time axis (same length)"
            )
        angles_orders.append(((wc - wc[0]) * to_rad, w_orders))
    dth = np.empty(n)
    dth[0] = 0.0
    dth[1:] = np.diff(c) * to_rad
    speed_enc = dth * fs
    if n > 1:
        speed_enc[0] = speed_enc[1]
    bearing = _bearing(
        n_load,
        speed_enc,
        par["bearing_friction"],
        par["bearing_radius"],
        par["roller_weight"],
        par["regularisation_speed"],
    )

    def filtered(q_drive, lines=None, judge=True):
        sd = _smoother_design(
            model, fs, par["roller_inertia"], par["counts_per_rev"], q, sigma_t, chain, q_drive
        )
        if lines is None:
            lines = np.zeros(n)
            if angles_orders and n > 1:  # chain only: u is the bearing loss
                lines = _order_lines(sd, dth, t56, bearing, angles_orders, fs)
        t_clean = t56 - lines
        u = t_clean + bearing if chain is None else bearing
        Z = _smoother_forward(sd, dth, t_clean, u, _start(sd, t_clean[0], u[0]))
        innovations = _innovation_whiteness(sd, _innovations(sd, dth, t_clean, u, Z), judge)
        return sd, lines, u, Z, innovations

    if q_drive == "ml":
        # The lines hardly depend on the drive noise: fitted once at the default for the
        # search (the likelihood alone at each trial), again at the noise found.
        fixed = filtered(DEFAULT_DRIVE_NOISE, judge=False)[1]
        q_drive = _most_likely_drive_noise(lambda qd: filtered(qd, fixed, judge=False)[-1])
    sd, lines, u, Z, innovations = filtered(q_drive)
    x = _smoother_backward(sd, Z, dth, u) * sd.scale
    contact = x[:, sd.i_d]
    variance = _smoothed_variance(sd, n) * sd.scale[sd.i_d] ** 2
    gain_phys = sd.scale[:, None] * sd.gain / sd.meas_scale[None, :]
    return ContactEstimate(
        contact_torque=contact,
        roller_speed=x[:, sd.i_w],
        roller_acceleration=x @ sd.accel[:-1] + sd.accel[-1] * u,
        coa=contact / (par["roller_radius"] * n_load),
        sample_rate=fs,
        model=model,
        process_noise=q,
        torque_noise=sigma_t,
        gain=gain_phys if gain_phys.shape[1] > 1 else gain_phys[:, 0],
        settling_samples=int(sd.gains.shape[0]),
        contact_torque_variance=variance,
        smoother_gain=(sd.scale[:, None] * sd.C / sd.scale[None, :]),
        torque_lines=lines,
        smoothed=True,
        innovations=innovations,
        drive_noise=q_drive if chain is not None else None,
    )
