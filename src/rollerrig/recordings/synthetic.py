"""Synthetic DAQ recordings from a twin simulation: what the rig's DAQ would have written.

:func:`synthetic_recording` takes the labelled dataset of a simulation
(:func:`rollerrig.solve.results.build_dataset`) and produces a :class:`Recording` with the raw
channels the rig records (Kayaalp, section 4.1.3: torque sensor on the roller shaft, incremental
encoders on the wheel and roller shafts, air-spring pressure sensor, the torque request), with the
disturbances a real recording carries, and a ``truth`` dataset with the clean channels and the
exact frequency of every disturbance line over time (for spectral and filtering tests).

The torque channel is

.. math::
    T(t) = T_{56}(t) + \\sum_k a_k \\sin(k\\,p_{AM}\\,\\theta_r(t) + \\varphi_k)
         + b_1 \\sin(p_{PM}\\theta_w + \\varphi) + b_6 \\sin(6 p_{PM}\\theta_w + \\varphi')
         + \\sum_{m=1,2} c_m \\sin(m\\theta_w + \\cdot) + d_m \\sin(m\\theta_r + \\cdot)
         + e \\sin(2\\pi f_0 t + \\cdot) + n(t)

with θ_w, θ_r the shaft angles, so each line's instantaneous frequency follows the speed:
f = k·p·ω/(2π). The induction motor's electrical line is taken at p_AM·f_roller (its rotor
frequency; the supply frequency is higher by the slip, under 2 % at rated load), the PMSM
inverter ripple at p_PMSM·f_wheel and its 6th harmonic (the classic 6th-order ripple of a
three-phase inverter-fed PMSM), the out-of-roundness of wheel and roller at 1x and 2x their
rotation. Phases are random (from the seed), amplitudes are those of :class:`DisturbanceModel`.
The speed-independent line e·sin(2π f0 t) is a hand-injected test signal, not physics of the
twin: off by default (e = 0); when switched on, the recording's metadata (``injected_lines``,
``notes``) and the truth's attributes say that it was injected, at which frequency and amplitude.
The twin's Polach parameters for the friction conditions of the test are in
``metadata["true_polach_parameters"]`` (from the twin's provenance).

Sampling. All signals are built on the twin's time grid. If the twin's output rate is higher than
the DAQ rate, the analogue channels (torque, pressure) pass an anti-alias Butterworth low-pass at
``anti_alias_cutoff_ratio × sample_rate`` (zero-phase, so the torque stays aligned with the
encoder channels; a real analogue filter would add a group delay of a few ms) and are then
interpolated at the DAQ instants. If the twin runs at the DAQ rate, no filter is applied and the
lines above the Nyquist frequency alias, as they do on a DAQ without an anti-alias filter (the
NI USB-6341 of the seed has none); ``truth["line_alias_frequency"]`` gives where they land.
The encoder channels are exact: cumulative counts ``floor(θ·CPR/2π)`` of the shaft angle
integrated (trapezoid rule) from the twin's speeds on the twin's grid.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, replace
from typing import Any

import numpy as np
import xarray as xr
from scipy import integrate, signal

from rollerrig._validation import ParameterError, require_nonnegative, require_positive
from rollerrig.output.provenance import provenance
from rollerrig.recordings.recording import CANONICAL_CHANNELS, Recording, RecordingError

__all__ = ["LINE_NAMES", "DisturbanceModel", "injected_line_note", "synthetic_recording"]

LINE_NAMES = (
    "am_h1",
    "am_h2",
    "am_h3",
    "pmsm_h1",
    "pmsm_h6",
    "wheel_1x",
    "wheel_2x",
    "roller_1x",
    "roller_2x",
    "fixed",
)
"""Names of the disturbance lines in ``truth["line_frequency"]``, in this order."""


@dataclass(frozen=True)
class DisturbanceModel:
    """Disturbances of a recorded test (amplitudes of sine lines and noise levels).

    Defaults are plausible for the Pardubice rig (no measured spectrum survives in the text of
    the dissertation: they are assumptions of the right order, a few N.m on a channel whose test
    signal is 100-1000 N.m); :meth:`none` switches everything off.

    Parameters
    ----------
    am_line_amplitudes : tuple of float
        Amplitudes [N.m] of the induction motor's electrical line at k·p_AM·f_roller,
        k = 1, 2, 3: (3.0, 1.5, 0.75), decaying by half per harmonic (slot and supply
        harmonics of a 55 kW cage motor seen through a 43.5 kN.m/rad shaft).
    pmsm_ripple_amplitude : float
        Inverter ripple at p_PMSM·f_wheel [N.m]: 2.0 (cogging/ripple of a direct-drive PMSM is
        ~0.5-1 % of its 852 N.m rating at the motor; attenuated through contact and shafts).
    pmsm_ripple_6th_amplitude : float
        Its 6th harmonic at 6·p_PMSM·f_wheel [N.m]: 1.0 (Kayaalp 4.5.1.6 sees a switching
        ripple on the PMSM torque; ~500 Hz at 30 km/h, above the 125 Hz Nyquist frequency).
    wheel_order_amplitudes : tuple of float
        Wheel out-of-roundness at 1x and 2x the wheel rotation [N.m]: (1.5, 0.75).
    roller_order_amplitudes : tuple of float
        Roller out-of-roundness at 1x and 2x the roller rotation [N.m]: (2.0, 1.0) (the roller
        is a turned wagon wheel, its eccentricity carries through the contact to T56).
    fixed_line_frequency : float
        Frequency of an optional, hand-injected speed-independent line [Hz]: 1.333 Hz, the
        frequency of the line seen in the seed's recordings (its cause is unknown, so the twin
        cannot produce it).
    fixed_line_amplitude : float
        Its amplitude [N.m]: 0.0, off. It is not physics of the twin but a test signal: when it
        is switched on (> 0), the recording says so in ``metadata["injected_lines"]`` and
        ``metadata["notes"]`` (frequency and amplitude), and so does every output made from it.
    torque_noise : float
        Standard deviation of the white noise on the torque channel [N.m]: 1.0 (0.03 % of the
        3000 N.m sensor range, a typical strain-gauge torque-flange noise floor).
    pressure_noise : float
        Standard deviation of the white noise on the air-spring pressure [Pa]: 100 (5 N on
        the 0.05 m^2 air spring, about 0.1 % of the 4.3 kN load; DMP331 accuracy class 0.35 %
        of a 10 bar range is 3500 Pa, of which the random part is far smaller).
    shaft_eccentricity : float
        Amplitude of the roller-shaft run-out seen by the laser at the torque sensor [m]: 6e-5
        (Kayaalp 4.5.2.2 measured 0.12-0.15 mm peak to peak there), at the roller rotation
        order, with a quarter of it at twice that order.
    displacement_noise : float
        Standard deviation of the white noise on the laser displacement [m]: 1e-6 (Keyence
        LK-H 0.02 % of a 50-80 mm range is 10-16 µm full-scale accuracy, random part smaller).
    am_pole_pairs, pmsm_pole_pairs : int or None
        Pole pairs of the roller motor and the wheel motor [-]; ``None`` takes them from the
        rig in the twin's provenance (5 and 22 on the default rig, Kayaalp Tables 1-2).
    anti_alias : bool
        Apply the anti-alias filter when the twin's rate is above the DAQ rate: True.
    anti_alias_cutoff_ratio : float
        Cut-off of the anti-alias filter relative to the DAQ rate [-]: 0.4 (80 % of Nyquist).
    anti_alias_order : int
        Order of the Butterworth filter [-]: 8 (applied forward and backward, so the magnitude
        is squared: -31 dB at Nyquist, -56 dB at 0.6·fs, the lowest frequency that folds back
        below the cut-off).
    record_torque_request : bool
        Record the torque request sent to the PMSM controller: True.

    Examples
    --------
    >>> DisturbanceModel().am_line_amplitudes
    (3.0, 1.5, 0.75)
    >>> DisturbanceModel.none().torque_noise
    0.0
    >>> DisturbanceModel().fixed_line_amplitude  # the hand-injected line is off by default
    0.0
    """

    am_line_amplitudes: tuple[float, ...] = (3.0, 1.5, 0.75)
    pmsm_ripple_amplitude: float = 2.0
    pmsm_ripple_6th_amplitude: float = 1.0
    wheel_order_amplitudes: tuple[float, float] = (1.5, 0.75)
    roller_order_amplitudes: tuple[float, float] = (2.0, 1.0)
    fixed_line_frequency: float = 1.333
    fixed_line_amplitude: float = 0.0
    torque_noise: float = 1.0
    pressure_noise: float = 100.0
    shaft_eccentricity: float = 6e-5
    displacement_noise: float = 1e-6
    am_pole_pairs: int | None = None
    pmsm_pole_pairs: int | None = None
    anti_alias: bool = True
    anti_alias_cutoff_ratio: float = 0.4
    anti_alias_order: int = 8
    record_torque_request: bool = True

    def __post_init__(self) -> None:
        if len(self.am_line_amplitudes) != 3:
            raise ParameterError(
                "am_line_amplitudes must give 3 amplitudes [N.m] (harmonics 1-3), "
                f"got {self.am_line_amplitudes!r}"
            )
        for name in ("wheel_order_amplitudes", "roller_order_amplitudes"):
            if len(getattr(self, name)) != 2:
                raise ParameterError(f"{name} must give 2 amplitudes [N.m] (1x, 2x)")
        object.__setattr__(self, "am_line_amplitudes", tuple(map(float, self.am_line_amplitudes)))
        for name in ("wheel_order_amplitudes", "roller_order_amplitudes"):
            object.__setattr__(self, name, tuple(map(float, getattr(self, name))))
        for name in (
            "pmsm_ripple_amplitude",
            "pmsm_ripple_6th_amplitude",
            "fixed_line_amplitude",
            "torque_noise",
            "pressure_noise",
            "shaft_eccentricity",
            "displacement_noise",
        ):
            require_nonnegative(name, getattr(self, name), "N.m, Pa or m")
        require_nonnegative("am_line_amplitudes", self.am_line_amplitudes, "N.m")
        require_positive("fixed_line_frequency", self.fixed_line_frequency, "Hz")
        if not 0.0 < self.anti_alias_cutoff_ratio < 0.5:
            raise ParameterError(
                "anti_alias_cutoff_ratio must lie in (0, 0.5) [-] (below Nyquist), "
                f"got {self.anti_alias_cutoff_ratio!r}"
            )
        if int(self.anti_alias_order) < 1:
            raise ParameterError(f"anti_alias_order must be >= 1, got {self.anti_alias_order}")

    def injected_lines(self) -> list[dict[str, Any]]:
        """The lines injected by hand (not produced by the twin's physics), JSON-ready.

        Returns
        -------
        list of dict
            One entry per switched-on injected line: ``name``, ``frequency [Hz]``,
            ``amplitude [N.m]``, ``channel`` and ``what``; empty when none is on (the default).

        Examples
        --------
        >>> DisturbanceModel().injected_lines()
        []
        >>> DisturbanceModel(fixed_line_amplitude=2.0).injected_lines()[0]["frequency [Hz]"]
        1.333
        """
        if self.fixed_line_amplitude <= 0.0:
            return []
        return [
            {
                "name": "fixed",
                "frequency [Hz]": float(self.fixed_line_frequency),
                "amplitude [N.m]": float(self.fixed_line_amplitude),
                "channel": "torque",
                "what": "speed-independent sine injected by hand into the synthetic torque "
                "(DisturbanceModel.fixed_line_amplitude); not produced by the twin",
            }
        ]

    @classmethod
    def none(cls) -> DisturbanceModel:
        """No lines and no noise (the anti-alias filter stays on)."""
        return cls(
            am_line_amplitudes=(0.0, 0.0, 0.0),
            pmsm_ripple_amplitude=0.0,
            pmsm_ripple_6th_amplitude=0.0,
            wheel_order_amplitudes=(0.0, 0.0),
            roller_order_amplitudes=(0.0, 0.0),
            fixed_line_amplitude=0.0,
            torque_noise=0.0,
            pressure_noise=0.0,
            shaft_eccentricity=0.0,
            displacement_noise=0.0,
        )

    def scaled(self, factor: float) -> DisturbanceModel:
        """All amplitudes and noise levels multiplied by ``factor`` [-]."""
        f = require_nonnegative("factor", factor, "-", single=True)
        return replace(
            self,
            am_line_amplitudes=tuple(f * a for a in self.am_line_amplitudes),
            pmsm_ripple_amplitude=f * self.pmsm_ripple_amplitude,
            pmsm_ripple_6th_amplitude=f * self.pmsm_ripple_6th_amplitude,
            wheel_order_amplitudes=tuple(f * a for a in self.wheel_order_amplitudes),
            roller_order_amplitudes=tuple(f * a for a in self.roller_order_amplitudes),
            fixed_line_amplitude=f * self.fixed_line_amplitude,
            torque_noise=f * self.torque_noise,
            pressure_noise=f * self.pressure_noise,
            shaft_eccentricity=f * self.shaft_eccentricity,
            displacement_noise=f * self.displacement_noise,
        )


def _twin_provenance(ds: xr.Dataset) -> dict[str, Any]:
    """The twin's provenance record (its ``provenance`` attribute, JSON) with the rig; a
    :class:`RecordingError` naming what is missing where ``ds`` is not a twin simulation."""
    if not (hasattr(ds, "attrs") and hasattr(ds, "data_vars")):  # a name, a path, a Recording
        raise ParameterError(
            "ds must be a twin simulation, the xarray.Dataset of Simulation(...).run() or of "
            f"its *-truth.nc file, got {type(ds).__name__}"
        )
    missing = [
        name for name in ("time", "t56", "normal_load", "roller_speed") if name not in ds
    ] + ([] if "wheel_disc_speed" in ds or "wheel_speed" in ds else ["wheel_disc_speed"])
    if missing:
        raise RecordingError(
            f"the twin dataset lacks {missing} (a simulation of Simulation(...).run() has them)"
        )
    raw = ds.attrs.get("provenance")
    if raw is None:
        raise RecordingError("the twin dataset has no 'provenance' attribute (rig parameters)")
    return json.loads(raw) if isinstance(raw, str) else dict(raw)


def _fold(frequency: np.ndarray, sample_rate: float) -> np.ndarray:
    """Apparent frequency [Hz] of a line at ``frequency`` sampled at ``sample_rate``."""
    f = np.mod(np.abs(frequency), sample_rate)
    return np.minimum(f, sample_rate - f)


def _counts(angle: np.ndarray, cpr: int) -> np.ndarray:
    """Cumulative counts floor(θ·CPR/2π); a 1e-6-count guard keeps whole counts whole."""
    return np.floor(angle * (cpr / (2.0 * np.pi)) + 1e-6)


def synthetic_recording(
    ds: xr.Dataset,
    disturbances: DisturbanceModel | None = None,
    sample_rate: float | None = None,
    seed: int = 0,
) -> tuple[Recording, xr.Dataset]:
    """What the rig's DAQ would record during a simulated test.

    Parameters
    ----------
    ds : xarray.Dataset
        A twin simulation (:meth:`rollerrig.solve.simulation.Simulation.run`): needs ``t56``,
        ``normal_load``, ``roller_speed``, ``wheel_disc_speed`` (or ``wheel_speed``) and the
        ``provenance`` attribute with the rig parameters.
    disturbances : DisturbanceModel, optional
        Lines and noise; default :class:`DisturbanceModel` ().
    sample_rate : float, optional
        DAQ rate [Hz]; default the rig's ``sensors.daq_rate``. Must not exceed the twin's output
        rate (beyond a rounding tolerance).
    seed : int
        Seed of the random phases and noise; the result is deterministic for a given seed.

    Returns
    -------
    recording : Recording
        Channels ``torque`` [N.m], ``wheel_encoder_counts`` and ``roller_encoder_counts``
        (cumulative, from 0 at the first sample) [-], ``air_spring_pressure`` [Pa] and, if
        ``record_torque_request``, ``torque_request`` [N.m]. The metadata records the
        disturbance model, the seed, the rates, the rig parameters, the twin's provenance,
        ``provenance`` (:func:`rollerrig.output.provenance` of this generation),
        ``injected_lines`` and ``notes`` (the hand-injected lines, empty by default) and
        ``true_polach_parameters`` ({friction condition: parameters} of the twin, or None).
    truth : xarray.Dataset
        On the DAQ time axis: every numeric channel of the twin interpolated to it, the clean
        torque ``torque_clean`` (= T56), the deterministic disturbance ``torque_lines`` [N.m]
        before filtering, the shaft angles ``wheel_angle``, ``roller_angle`` [rad], and
        ``line_frequency`` / ``line_alias_frequency`` (time, line) [Hz] with ``line_amplitude``
        (line) [N.m] for the lines :data:`LINE_NAMES`.

    Examples
    --------
    >>> from rollerrig.solve.simulation import Simulation
    >>> ds = Simulation(experiment="seed-30kmh-dry").run()  # doctest: +SKIP
    >>> rec, truth = synthetic_recording(ds, seed=1)  # doctest: +SKIP
    >>> rec.sample_rate  # doctest: +SKIP
    250.0
    """
    dist = DisturbanceModel() if disturbances is None else disturbances
    prov = _twin_provenance(ds)
    rig = prov.get("rig_parameters") or prov["rig"]  # "rig": results written before 0.1.0
    sensors = rig["sensors"]
    fs = float(sensors["daq_rate"] if sample_rate is None else sample_rate)
    if not (np.isfinite(fs) and fs > 0):
        raise ParameterError(f"sample_rate must be > 0 [Hz], got {sample_rate!r}")
    cpr = int(sensors["encoder_pulses_per_revolution"]) * int(sensors["encoder_quadrature_factor"])
    area = float(sensors["air_spring_effective_area"])
    p_am = int(
        dist.am_pole_pairs
        if dist.am_pole_pairs is not None
        else rig.get("induction_motor", {}).get("pole_pairs", 5)
    )
    p_pm = int(
        dist.pmsm_pole_pairs
        if dist.pmsm_pole_pairs is not None
        else rig.get("pmsm", {}).get("pole_pairs", 22)
    )

    t_twin = np.asarray(ds["time"].values, dtype=float)
    twin_rate = float(1.0 / np.median(np.diff(t_twin)))
    if fs > twin_rate * (1.0 + 1e-6):
        raise ParameterError(
            f"sample_rate {fs:g} Hz exceeds the twin's output rate {twin_rate:g} Hz; "
            "simulate with a higher output_rate"
        )
    n_daq = int(np.floor((t_twin[-1] - t_twin[0]) * fs + 1e-9)) + 1
    t_daq = t_twin[0] + np.arange(n_daq) / fs
    t_daq = t_daq[t_daq <= t_twin[-1] + 1e-12]
    t_daq[-1] = min(t_daq[-1], t_twin[-1])

    wheel_name = "wheel_disc_speed" if "wheel_disc_speed" in ds else "wheel_speed"
    omega_w = np.asarray(ds[wheel_name].values, dtype=float)
    omega_r = np.asarray(ds["roller_speed"].values, dtype=float)
    theta_w = integrate.cumulative_trapezoid(omega_w, t_twin, initial=0.0)
    theta_r = integrate.cumulative_trapezoid(omega_r, t_twin, initial=0.0)

    rng = np.random.default_rng(seed)
    phases = rng.uniform(0.0, 2.0 * np.pi, len(LINE_NAMES))
    # (amplitude [N.m], multiplier of the angle, angle) per line; "fixed" uses time.
    a = dist
    lines = [
        (a.am_line_amplitudes[0], p_am, theta_r),
        (a.am_line_amplitudes[1], 2 * p_am, theta_r),
        (a.am_line_amplitudes[2], 3 * p_am, theta_r),
        (a.pmsm_ripple_amplitude, p_pm, theta_w),
        (a.pmsm_ripple_6th_amplitude, 6 * p_pm, theta_w),
        (a.wheel_order_amplitudes[0], 1, theta_w),
        (a.wheel_order_amplitudes[1], 2, theta_w),
        (a.roller_order_amplitudes[0], 1, theta_r),
        (a.roller_order_amplitudes[1], 2, theta_r),
        (a.fixed_line_amplitude, 2.0 * np.pi * a.fixed_line_frequency, t_twin - t_twin[0]),
    ]
    torque_lines = np.zeros_like(t_twin)
    for (amp, mult, angle), phase in zip(lines, phases, strict=True):
        if amp > 0.0:
            torque_lines += amp * np.sin(mult * angle + phase)

    t56 = np.asarray(ds["t56"].values, dtype=float)
    # The DAQ sees the air spring's pressure: its force S, not the contact's load (the arm).
    spring = "air_spring_force" if "air_spring_force" in ds else "normal_load"
    load = np.asarray(ds[spring].values, dtype=float)
    torque_analog = t56 + torque_lines + a.torque_noise * rng.standard_normal(t_twin.size)
    pressure_analog = load / area + a.pressure_noise * rng.standard_normal(t_twin.size)
    # Laser at the torque sensor (Kayaalp 4.5.2.1): the shaft's eccentricity runs at the roller
    # rotation order with the phase of the torque's roller-order line it causes.
    roller_1x = LINE_NAMES.index("roller_1x")
    displacement_analog = (
        a.shaft_eccentricity * np.sin(theta_r + phases[roller_1x])
        + 0.25 * a.shaft_eccentricity * np.sin(2.0 * theta_r + phases[roller_1x + 1])
        + a.displacement_noise * rng.standard_normal(t_twin.size)
    )

    filtered = bool(a.anti_alias and twin_rate > fs * (1.0 + 1e-6))
    if filtered:
        sos = signal.butter(
            int(a.anti_alias_order), a.anti_alias_cutoff_ratio * fs, fs=twin_rate, output="sos"
        )
        torque_analog = signal.sosfiltfilt(sos, torque_analog)
        pressure_analog = signal.sosfiltfilt(sos, pressure_analog)
        displacement_analog = signal.sosfiltfilt(sos, displacement_analog)

    def at_daq(values: np.ndarray) -> np.ndarray:
        return np.interp(t_daq, t_twin, values)

    theta_w_daq, theta_r_daq = at_daq(theta_w), at_daq(theta_r)
    channels = {
        "torque": at_daq(torque_analog),
        "wheel_encoder_counts": _counts(theta_w_daq, cpr),
        "roller_encoder_counts": _counts(theta_r_daq, cpr),
        "air_spring_pressure": at_daq(pressure_analog),
    }
    if a.shaft_eccentricity > 0.0 or a.displacement_noise > 0.0:
        channels["displacement_torque_sensor"] = at_daq(displacement_analog)
    if a.record_torque_request and "torque_request" in ds:
        channels["torque_request"] = at_daq(np.asarray(ds["torque_request"].values, dtype=float))
    units = {k: CANONICAL_CHANNELS[k][0] for k in channels}
    anti_alias = (
        f"Butterworth order {a.anti_alias_order} at {a.anti_alias_cutoff_ratio * fs:g} Hz, "
        "zero-phase, before decimation"
        if filtered
        else "none (twin at the DAQ rate: lines above Nyquist alias)"
    )
    injected = a.injected_lines()
    metadata = {
        "source": "synthetic",
        "format": "rollerrig.synthetic",
        "synthetic": True,
        "injected_lines": injected,
        "notes": [injected_line_note(line) for line in injected],
        "true_polach_parameters": _true_polach_parameters(prov, ds),
        "experiment": ds.attrs.get("experiment", ""),
        "disturbances": asdict(a),
        "seed": int(seed),
        "sample_rate_Hz": fs,
        "twin_output_rate_Hz": twin_rate,
        "anti_alias": anti_alias,
        "pole_pairs": {"am": p_am, "pmsm": p_pm},
        "encoder_counts_per_revolution": cpr,
        "rig": rig,
        "twin_provenance": ds.attrs["provenance"],
        "provenance": provenance(
            generator="synthetic_recording", seed=int(seed), sample_rate_Hz=fs
        ),
    }
    recording = Recording(t_daq, channels, units, metadata)

    # Truth on the DAQ axis.
    numeric = [v for v in ds.data_vars if np.issubdtype(ds[v].dtype, np.number)]
    data = {
        v: ("time", at_daq(np.asarray(ds[v].values, dtype=float)), ds[v].attrs) for v in numeric
    }
    data["torque_clean"] = ("time", at_daq(t56), {"units": "N.m", "long_name": "clean T56"})
    data["torque_lines"] = (
        "time",
        at_daq(torque_lines),
        {"units": "N.m", "long_name": "sum of the disturbance lines (unfiltered)"},
    )
    data["wheel_angle"] = ("time", theta_w_daq, {"units": "rad", "long_name": "wheel shaft angle"})
    data["roller_angle"] = ("time", theta_r_daq, {"units": "rad", "long_name": "roller angle"})
    f_w = at_daq(omega_w) / (2.0 * np.pi)
    f_r = at_daq(omega_r) / (2.0 * np.pi)
    freq = np.stack(
        [
            p_am * f_r,
            2 * p_am * f_r,
            3 * p_am * f_r,
            p_pm * f_w,
            6 * p_pm * f_w,
            f_w,
            2 * f_w,
            f_r,
            2 * f_r,
            np.full_like(f_r, a.fixed_line_frequency),
        ],
        axis=1,
    )
    data["line_frequency"] = (
        ("time", "line"),
        freq,
        {"units": "Hz", "long_name": "instantaneous frequency of each disturbance line"},
    )
    data["line_alias_frequency"] = (
        ("time", "line"),
        _fold(freq, fs),
        {"units": "Hz", "long_name": "apparent frequency at the DAQ rate (folded)"},
    )
    data["line_amplitude"] = (
        "line",
        np.array([line[0] for line in lines]),
        {"units": "N.m", "long_name": "amplitude of each line before the anti-alias filter"},
    )
    data["line_phase"] = ("line", phases, {"units": "rad", "long_name": "phase of each line"})
    if "friction_condition" in ds:
        idx = np.clip(np.searchsorted(t_twin, t_daq), 0, t_twin.size - 1)
        data["friction_condition"] = (
            "time",
            np.asarray(ds["friction_condition"].values)[idx],
            {"long_name": "friction condition of the contact (name of the Polach set)"},
        )
    truth = xr.Dataset(
        data,
        coords={
            "time": ("time", t_daq, {"units": "s"}),
            "line": ("line", list(LINE_NAMES), {"long_name": "disturbance line of the torque"}),
        },
    )
    truth.attrs.update({k: v for k, v in ds.attrs.items()})
    truth.attrs["synthetic_seed"] = int(seed)
    truth.attrs["synthetic_disturbances"] = json.dumps(asdict(a))
    truth.attrs["injected_lines"] = json.dumps(injected)
    return recording, truth


def injected_line_note(line: dict[str, Any]) -> str:
    """The sentence that discloses a hand-injected line (:meth:`DisturbanceModel.injected_lines`).

    Examples
    --------
    >>> line = DisturbanceModel(fixed_line_amplitude=2.0).injected_lines()[0]
    >>> injected_line_note(line)[:70]
    'synthetic recording: a speed-independent line at 1.333 Hz, 2 N.m on to'
    """
    return (
        f"synthetic recording: a speed-independent line at {line['frequency [Hz]']:g} Hz, "
        f"{line['amplitude [N.m]']:g} N.m on {line['channel']} was INJECTED by hand "
        "(DisturbanceModel.fixed_line_amplitude); it is not a finding"
    )


def _true_polach_parameters(prov: dict[str, Any], ds: xr.Dataset) -> dict[str, Any] | None:
    """The twin's Polach parameters by friction condition, for the conditions the test used.

    From the twin's provenance (``friction_sets``) and its ``friction_condition`` channel (or
    the protocol's list); ``None`` when the provenance does not hold them.
    """
    sets = prov.get("friction_sets")
    if not isinstance(sets, dict) or not sets:
        return None
    if "friction_condition" in ds:
        used = sorted({str(c) for c in np.asarray(ds["friction_condition"].values).tolist()})
    else:
        used = sorted({str(c) for c in prov.get("protocol", {}).get("friction_condition", [])})
    chosen = {c: sets[c] for c in used if c in sets}
    return chosen or None
