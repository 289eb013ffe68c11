"""The measured channels a calibration fits, their noise and the torque's lines.

What is fitted (:func:`prepare_measurement`, :data:`CHANNELS`): the torque sensor's T56
[N.m], the wheel and roller encoder speeds [rad/s] and the normal load [N]. The speeds come
from the cumulative encoder counts through the very function the analysis uses
(:func:`rollerrig.measure.quantities.encoder_speed`, a gate of one sample interval:
ω_i = 2π (c_i − c_{i−1}) / (CPR Δt)); the recording is never smoothed.

The encoders' quantisation is modelled, in the model and in the weights:

- the twin predicts what the counter reports: the encoder function applied to the simulated
  counts ``CPR θ(t)/2π`` of the simulated shaft angle (the state, not a speed sample), i.e. the
  mean speed over each gate, with the gate's half-sample delay;
- the counts are not floored in the simulation: ``floor`` is the expectation ``CPR θ/2π − ½``
  plus a quantisation error uniform on one count (the encoder's phase at the first sample is
  unknown), which makes each gated speed the model's value plus ``(q_{i−1} − q_i)·2π/(CPR Δt)``:
  variance ``(2π/(CPR Δt))²/6`` and lag-1 correlation −½ (:func:`quantisation_noise`). The
  count errors are not independent draws: at a constant speed they repeat with the fraction d
  of a count per sample (variance (2π/(CPR Δt))² d(1−d), 1/6 on average over d), and where d
  is near a whole number they drift slowly ("idle tones"); the weights use the mean, the
  Newey–West covariance of :mod:`rollerrig.calibrate.stats` sees the rest. Flooring the
  simulated counts instead would make the residuals piecewise constant in the parameters
  (finite-difference columns of noise), and on a synthetic recording made with the true
  parameters it would reproduce the recorded floors and fit better than the noise allows.

The torque's lines (:func:`line_regressors`): the induction motor's electrical line and its
harmonics, the PMSM's and its 6th harmonic, the rotation orders of both shafts, each a sine of
an order times the measured shaft angle with an unknown amplitude and phase: linear nuisance
parameters, projected out of the torque residuals (variable projection with a fixed basis).
Left in, these few-N.m lines near the 13.8 Hz shaft mode made the residuals strongly
correlated and the fit less precise.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from rollerrig._validation import require_positive
from rollerrig.calibrate.errors import CalibrationError
from rollerrig.estimation.gum_inputs import noise_level
from rollerrig.measure.checks import check_channel_values
from rollerrig.measure.facts import describe_channel, source_prefix
from rollerrig.measure.quantities import encoder_speed, normal_force_from_pressure
from rollerrig.recordings.recording import Recording, RecordingError
from rollerrig.recordings.timebase import require_uniform_time
from rollerrig.rig.parameters import RigParameters

__all__ = [
    "CHANNELS",
    "DEFAULT_TORQUE_NOISE_FRACTION",
    "Measurement",
    "line_orders",
    "line_regressors",
    "prepare_measurement",
    "quantisation_noise",
]

CHANNELS = ("torque", "wheel_speed", "roller_speed", "normal_load")
"""The fitted channels, in this order: T56 [N.m], wheel and roller encoder speeds [rad/s], the
normal load [N] (from the air-spring pressure: it fits the constant load of the replay, a
nuisance parameter; left out when the recording's load channel is exactly constant)."""

DEFAULT_TORQUE_NOISE_FRACTION = 1.0 / 3000.0
"""White noise of the torque channel as a fraction of ``sensors.torque_sensor_range`` [-],
assumed where the recording shows none (:func:`prepare_measurement` takes the recording's own):
1 N.m on the default rig's 3000 N.m range (an assumption: a strain-gauge torque flange's noise
floor of about 0.03 % of its range; the same value as
:attr:`rollerrig.recordings.synthetic.DisturbanceModel.torque_noise`). Only the first weights use
it: the fit then re-weights each channel by its own residual scatter (see
:mod:`rollerrig.calibrate.fit`)."""

_QUIET_FRACTION = 0.02  # torque request below 2 % of its peak: free rolling before the test
_MAX_QUIET_WINDOW = 2.0  # [s] of free rolling used for the starting roller speed


def quantisation_noise(counts_per_revolution: float, interval: float) -> float:
    """Standard deviation of a gated encoder speed from the quantisation of its two counts.

    .. math:: \\sigma_\\omega = \\frac{2\\pi}{\\mathrm{CPR}\\,\\Delta t}\\sqrt{\\frac{2}{12}}

    Each cumulative count is the shaft angle floored to a count: an error uniform on one count
    (variance 1/12 count²); the speed over one gate is the difference of two counts.

    Parameters
    ----------
    counts_per_revolution : float
        Counts per revolution after quadrature decoding [-].
    interval : float
        Gate duration Δt [s].

    Returns
    -------
    float
        σ_ω [rad/s].

    Examples
    --------
    >>> round(quantisation_noise(10000, 1 / 250), 4)  # the default rig at 250 Hz
    0.0641
    """
    # 0 had raised a ZeroDivisionError; a negative count or gate gave a negative σ, silently.
    cpr = require_positive("counts_per_revolution", counts_per_revolution, "-", single=True)
    gate = require_positive("interval", interval, "s", single=True)
    return float(2.0 * math.pi / (cpr * gate) * math.sqrt(2.0 / 12.0))


@dataclass(frozen=True)
class Measurement:
    """What the calibration fits, from one recording.

    Attributes
    ----------
    time : ndarray
        Sample instants from 0 [s] (the recording's time minus its first instant).
    start_time : float
        The recording's first instant [s].
    values : dict
        Channel (:data:`CHANNELS`) -> recorded values [N.m or rad/s].
    valid : dict
        Channel -> boolean mask of the samples fitted (a speed's first sample has no gate).
    channels : tuple of str
        The fitted channels (:data:`CHANNELS`, without ``normal_load`` when it is constant).
    sensor_noise : dict
        Channel -> standard deviation of the sensor noise [N.m or rad/s], with ``noise_basis``
        saying where each comes from.
    noise_basis : dict
        Channel -> text.
    counts_per_revolution : float
        Encoder counts per revolution [-] (of the rig given), or NaN without counts.
    encoder_counts : bool
        Whether the speeds come from encoder counts (else from speed channels).
    torque_request : ndarray
        The recorded wheel-torque request [N.m].
    line_basis : ndarray or None
        Orthonormal basis (n × k) of the torque lines' regressors (:func:`line_regressors`),
        projected out of the torque residuals; None when the lines are not modelled.
    line_labels : tuple of str
        The lines, two regressors (sine, cosine) each.
    line_regressors_raw : ndarray or None
        The regressors themselves (n × 2 lines) [-], for their fitted amplitudes.
    normal_load : float
        Mean normal load [N].
    normal_load_spread : float
        Standard deviation of the normal-load channel [N].
    roller_speed_start : float
        Roller peripheral speed before the first torque request [m/s] (mean of the encoder
        speed over the free rolling, at most 2 s): the set point's starting value.
    quiet_until : float
        End of that free rolling [s] (0 when the recording starts under load).
    source : str
        The recording's file (or "the recording").
    notes : list of str
        What was assumed or found while preparing.
    load_source : str
        The channel the normal load comes from: ``"air_spring_pressure"`` (times the air
        spring's area) or ``"normal_load"`` (given by the recording).
    normal_load_class : float
        Standard uncertainty of the load channel's mean from the sensors' stated classes [N]:
        the pressure sensor's offset times the area and the area's own, in quadrature (0 for a
        constant channel, which the replay takes as exact).
    torque_delay : float
        The torque channel's delay against the encoders removed before the fit [s]
        (:func:`rollerrig.calibrate.calibrate`'s ``torque_delay``; 0: none).
    """

    time: np.ndarray
    start_time: float
    values: dict[str, np.ndarray]
    valid: dict[str, np.ndarray]
    channels: tuple[str, ...]
    sensor_noise: dict[str, float]
    noise_basis: dict[str, str]
    counts_per_revolution: float
    encoder_counts: bool
    torque_request: np.ndarray
    line_basis: np.ndarray | None
    line_labels: tuple[str, ...]
    line_regressors_raw: np.ndarray | None
    normal_load: float
    normal_load_spread: float
    roller_speed_start: float
    quiet_until: float
    source: str
    notes: list[str] = dataclasses.field(default_factory=list)
    load_source: str = "air_spring_pressure"
    normal_load_class: float = 0.0
    torque_delay: float = 0.0

    def project_lines(self, torque: np.ndarray) -> np.ndarray:
        """``torque`` with its components along the line regressors removed [N.m]."""
        q = self.line_basis
        return torque if q is None else torque - q @ (q.T @ torque)

    def line_amplitudes(self, residual: np.ndarray) -> list[dict[str, Any]]:
        """Least-squares amplitude [N.m] and phase [rad] of each line in a torque residual."""
        x = self.line_regressors_raw
        if x is None:
            return []
        coef = np.linalg.lstsq(x, residual, rcond=None)[0]
        out = []
        for k, label in enumerate(self.line_labels):
            s, c = coef[2 * k], coef[2 * k + 1]
            out.append(
                {
                    "line": label,
                    "amplitude [N.m]": float(np.hypot(s, c)),
                    "phase [rad]": float(np.arctan2(c, s)),
                }
            )
        return out

    @property
    def sample_interval(self) -> float:
        """Δt [s]."""
        return float(self.time[1] - self.time[0])

    def predicted(
        self, t56: np.ndarray, wheel_angle: np.ndarray, roller_angle: np.ndarray, load: float
    ):
        """The channels the twin predicts, in the recording's form.

        Parameters
        ----------
        t56 : ndarray
            Simulated roller-shaft torque at the sample instants [N.m].
        wheel_angle, roller_angle : ndarray
            Simulated shaft angles (wheel disc, roller) at the sample instants [rad].
        load : float
            The replay's constant normal load [N].

        Returns
        -------
        dict
            Channel -> predicted values: the torque as it is, the speeds as the encoder
            function reports them from the (unfloored) counts CPR·θ/2π.
        """
        cpr = self.counts_per_revolution if self.encoder_counts else 2.0 * math.pi
        out = {"torque": t56, "normal_load": np.full(self.time.size, float(load))}
        for name, angle in (("wheel_speed", wheel_angle), ("roller_speed", roller_angle)):
            counts = (angle - angle[0]) * (cpr / (2.0 * math.pi))
            out[name] = encoder_speed(counts, self.time, cpr)
        return out


def line_orders(rig: RigParameters) -> tuple[tuple[str, int, str], ...]:
    """The torque lines at orders of the shaft rotations: ``(shaft, order, label)``.

    The sources :mod:`rollerrig.signal.attribution` attributes peaks to (Kayaalp 4.5.2.3-4):
    the roller's rotation orders 1 and 2 (out-of-roundness, shaft eccentricity), the induction
    motor's electrical line at p_AM times the roller's rotation and its harmonics 2 and 3 (taken
    at the rotor's frequency: the supply's is higher by the slip, under 2 %), the wheel's
    rotation orders 1 and 2, the PMSM's electrical line at p_PMSM times the wheel's rotation and
    its 6th harmonic (a three-phase inverter's ripple).

    Examples
    --------
    >>> from rollerrig.rig.parameters import default_rig
    >>> [order for _, order, _ in line_orders(default_rig())]
    [1, 2, 5, 10, 15, 1, 2, 22, 132]
    """
    p_am = int(rig.induction_motor.pole_pairs)
    p_pm = int(rig.pmsm.pole_pairs)
    return (
        ("roller", 1, "roller rotation x1"),
        ("roller", 2, "roller rotation x2"),
        ("roller", p_am, f"induction motor electrical x1 (roller order {p_am})"),
        ("roller", 2 * p_am, f"induction motor electrical x2 (roller order {2 * p_am})"),
        ("roller", 3 * p_am, f"induction motor electrical x3 (roller order {3 * p_am})"),
        ("wheel", 1, "wheel rotation x1"),
        ("wheel", 2, "wheel rotation x2"),
        ("wheel", p_pm, f"PMSM electrical x1 (wheel order {p_pm})"),
        ("wheel", 6 * p_pm, f"PMSM electrical x6 (wheel order {6 * p_pm})"),
    )


def line_regressors(
    wheel_angle: np.ndarray, roller_angle: np.ndarray, rig: RigParameters
) -> tuple[np.ndarray, tuple[str, ...]]:
    """Sine and cosine of each line's phase, ``order × shaft angle``, at the samples.

    Parameters
    ----------
    wheel_angle, roller_angle : ndarray
        Measured shaft angles [rad] (from the encoder counts).
    rig : RigParameters
        Pole pairs of the two motors.

    Returns
    -------
    regressors : ndarray, shape (n, 2 × lines)
        [sin, cos] per line of :func:`line_orders` [-].
    labels : tuple of str
    """
    angles = {"wheel": wheel_angle, "roller": roller_angle}
    columns, labels = [], []
    for shaft, order, label in line_orders(rig):
        phase = order * angles[shaft]
        columns += [np.sin(phase), np.cos(phase)]
        labels.append(label)
    return np.column_stack(columns), tuple(labels)


def _orthonormal(x: np.ndarray) -> np.ndarray:
    """Orthonormal basis of the column space of ``x`` (rank from the singular values)."""
    u, s, _ = np.linalg.svd(x, full_matrices=False)
    return u[:, s > 1e-8 * s[0]]


def _uniform(rec: Recording, source: str) -> None:
    """RecordingError naming the file when the time base is not uniform."""
    require_uniform_time(rec.time, source, "the calibration")


def prepare_measurement(
    rec: Recording,
    rig: RigParameters,
    *,
    torque_noise: float | None = None,
    lines: bool = True,
) -> Measurement:
    """The channels a calibration fits, from a recording read in SI units.

    Parameters
    ----------
    rec : Recording
        Needs ``torque``, ``torque_request``, the encoder counts (``wheel_encoder_counts``,
        ``roller_encoder_counts``; else ``wheel_speed`` and ``roller_speed`` are used as they
        are, with a note) and ``normal_load`` or ``air_spring_pressure``, on a uniform time
        base.
    rig : RigParameters
        Encoder resolution, air-spring area and torque sensor range (the rig the calibration
        starts from).
    torque_noise : float, optional
        Standard deviation of the torque channel's noise [N.m]; default the recording's own,
        type A (:func:`rollerrig.estimation.gum_inputs.noise_level`, as ``rollerrig analyze``
        takes it), or :data:`DEFAULT_TORQUE_NOISE_FRACTION` × ``sensors.torque_sensor_range``
        where the recording shows none.
    lines : bool
        Model the torque's lines at orders of the measured shaft angles
        (:func:`line_regressors`: their amplitudes and phases are fitted with the other
        parameters, as linear nuisance parameters projected out of the torque residuals).

    Returns
    -------
    Measurement

    Raises
    ------
    RecordingError
        A missing channel (named with its channel-map entry), non-finite values, a time base
        that is not uniform, a recording too short or without a torque request that moves.
    """
    source = str(rec.metadata.get("source") or "the recording")
    prefix = source_prefix(rec)
    if "torque_request" not in rec:
        raise RecordingError(
            f"{prefix}the calibration replays the recorded wheel-torque request through the "
            f"twin, and the recording has no channel 'torque_request' (map entry "
            f"[channels.torque_request]); it has {sorted(rec.channels)}"
        )
    needs = [("torque",), ("wheel_encoder_counts", "wheel_speed")]
    needs += [("roller_encoder_counts", "roller_speed"), ("normal_load", "air_spring_pressure")]
    missing = [names for names in needs if not any(n in rec for n in names)]
    if missing:
        wants = "; ".join(" or ".join(f"[channels.{n}]" for n in names) for names in missing)
        raise RecordingError(
            f"{prefix}the calibration needs {wants}; add these entries to the channel map "
            f"(--channels); the recording has {sorted(rec.channels)}"
        )
    used = [next(n for n in names if n in rec) for names in needs]
    check_channel_values(rec, ["torque_request", *used], rig)
    if rec.time.size < 50:
        raise RecordingError(
            f"{prefix}too short to calibrate: {rec.time.size} samples; need at least 50"
        )
    _uniform(rec, source)
    request = np.asarray(rec["torque_request"], dtype=float)
    peak = float(np.max(np.abs(request)))
    if not peak > 0.0:
        raise RecordingError(
            f"{prefix}{describe_channel(rec, 'torque_request')} is zero throughout: nothing "
            "excites the rig; calibrate on a recording of an adhesion test"
        )
    time = np.asarray(rec.time, dtype=float) - float(rec.time[0])
    dt = float(np.median(np.diff(time)))
    notes: list[str] = []
    counts = "wheel_encoder_counts" in rec and "roller_encoder_counts" in rec
    cpr = float(rig.sensors.encoder_counts_per_revolution)
    values = {"torque": np.asarray(rec["torque"], dtype=float)}
    angles = {}
    if counts:
        for which in ("wheel", "roller"):
            c = np.asarray(rec[f"{which}_encoder_counts"], dtype=float)
            values[f"{which}_speed"] = encoder_speed(c, time, cpr)
            angles[which] = (c - c[0]) * (2.0 * math.pi / cpr)
        speed_sigma = quantisation_noise(cpr, dt)
        speed_basis = (
            f"encoder quantisation: 2 pi/(CPR dt) sqrt(2/12) with CPR = {cpr:g} counts/rev "
            f"(sensors.encoder_pulses_per_revolution x encoder_quadrature_factor) and "
            f"dt = {dt:.6g} s"
        )
    else:
        for which in ("wheel", "roller"):
            values[f"{which}_speed"] = np.asarray(rec[f"{which}_speed"], dtype=float)
            w = values[f"{which}_speed"]
            angles[which] = np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * dt)])
        speed_sigma = quantisation_noise(cpr, dt)
        speed_basis = (
            "speed channels without encoder counts: taken as gated encoder speeds of the rig's "
            f"encoder (CPR = {cpr:g}); the first weights assume its quantisation"
        )
        notes.append(
            "the recording gives speeds, not encoder counts: the twin's speeds are compared as "
            "the mean over each sample interval (an encoder's gate); map the counts "
            "([channels.wheel_encoder_counts], [channels.roller_encoder_counts]) where the "
            "DAQ records them"
        )
    if torque_noise is None:
        # The recording's own noise, as rollerrig analyze takes it: a rig file cannot know the
        # DAQ's filter and rate (a 1000 Hz recording with 10 N.m of noise had been fitted right
        # and then told "check the rig file" against the assumed 1 N.m).
        sigma_t = noise_level(values["torque"])
        torque_basis = (
            "type A: white noise of the recorded torque (MAD of its second differences, "
            "rollerrig.estimation.gum_inputs.noise_level, as rollerrig analyze takes it; lines "
            "near the Nyquist frequency raise it)"
        )
        if not (math.isfinite(sigma_t) and sigma_t > 0.0):  # a noise-free (twin's) recording
            sigma_t = DEFAULT_TORQUE_NOISE_FRACTION * float(rig.sensors.torque_sensor_range)
            torque_basis = (
                f"the recording shows no noise: assumed white noise of the torque sensor, "
                f"{DEFAULT_TORQUE_NOISE_FRACTION:.3g} of sensors.torque_sensor_range = "
                f"{rig.sensors.torque_sensor_range:g} N.m"
            )
    else:
        sigma_t = float(torque_noise)
        if not (math.isfinite(sigma_t) and sigma_t > 0.0):
            raise CalibrationError(f"torque_noise must be > 0 [N.m], got {torque_noise!r}")
        torque_basis = "given (torque_noise)"
    if lines:
        raw, labels = line_regressors(angles["wheel"], angles["roller"], rig)
        basis = _orthonormal(raw)
    else:
        raw, labels, basis = None, (), None
    valid = {name: np.ones(time.size, dtype=bool) for name in CHANNELS}
    valid["wheel_speed"][0] = valid["roller_speed"][0] = False  # no gate before the first sample

    load_source = "normal_load" if "normal_load" in rec else "air_spring_pressure"
    if "normal_load" in rec:
        load = np.asarray(rec["normal_load"], dtype=float)
    else:
        load = normal_force_from_pressure(
            rec["air_spring_pressure"], rig.sensors.air_spring_effective_area
        )
    mean_load = float(np.mean(load))
    if not mean_load > 0.0:
        raise RecordingError(
            f"{prefix}the mean normal load is {mean_load:.4g} N; the calibration needs a "
            "loaded contact (check the normal_load or air_spring_pressure map entry)"
        )
    spread = float(np.std(load))
    # The load channel's mean is known only to the sensors' stated classes: the fit weighs it
    # as one measurement of the load with that error (:func:`load_sigma`).
    sensors = rig.sensors
    u_class = math.hypot(
        sensors.pressure_sensor_accuracy
        * sensors.pressure_sensor_range
        / math.sqrt(3.0)
        * sensors.air_spring_effective_area,
        sensors.air_spring_area_uncertainty * mean_load,
    )
    values["normal_load"] = np.asarray(load, dtype=float)
    channels = CHANNELS if spread > 0.0 else CHANNELS[:3]
    if spread == 0.0:
        notes.append(
            f"the normal-load channel is constant ({mean_load:.6g} N): the replay uses it as "
            "exact (no nuisance parameter for the load)"
        )

    quiet = np.flatnonzero(np.abs(request) > _QUIET_FRACTION * peak)
    first_load = int(quiet[0]) if quiet.size else time.size
    quiet_until = float(time[first_load - 1]) if first_load > 1 else 0.0
    if first_load < 3:
        window = slice(1, max(3, round(0.2 / dt)))
        notes.append(
            "the recording starts under a torque request: the twin starts from steady free "
            "rolling, so its first samples may not match; record a stretch of free rolling "
            "before the test"
        )
    else:
        start = max(1, first_load - round(_MAX_QUIET_WINDOW / dt))
        window = slice(start, first_load)
        if start >= first_load:  # samples farther apart than the window: nothing to average
            raise RecordingError(
                f"{prefix}no sample in the {_MAX_QUIET_WINDOW:g} s of free rolling before the "
                f"torque request rises (t = {time[first_load]:.6g} s; samples {dt:.6g} s apart): "
                "the calibration takes the starting roller speed from them. A rig records "
                "many samples a second: if the time is in milliseconds, declare it (unit = "
                '"ms" in the channel map\'s [time] section, or a header "time [ms]")'
            )
    omega0 = float(np.mean(values["roller_speed"][window]))
    speed0 = omega0 * rig.geometry.roller_radius_x
    if not speed0 > 0.0:
        raise RecordingError(
            f"{prefix}the roller is not turning before the test (mean speed "
            f"{omega0:.4g} rad/s): the calibration replays a test at a constant roller speed"
        )
    return Measurement(
        time=time,
        start_time=float(rec.time[0]),
        values=values,
        valid=valid,
        channels=channels,
        sensor_noise={
            "torque": sigma_t,
            "wheel_speed": speed_sigma,
            "roller_speed": speed_sigma,
            "normal_load": spread if spread > 0.0 else 1.0,
        },
        noise_basis={
            "torque": torque_basis,
            "wheel_speed": speed_basis,
            "roller_speed": speed_basis,
            "normal_load": "scatter of the normal-load channel about its mean (the twin's "
            "load is constant)",
        },
        counts_per_revolution=cpr if counts else float("nan"),
        encoder_counts=counts,
        torque_request=request,
        line_basis=basis,
        line_labels=labels,
        line_regressors_raw=raw,
        normal_load=mean_load,
        normal_load_spread=spread,
        roller_speed_start=speed0,
        quiet_until=quiet_until,
        source=source,
        notes=notes,
        load_source=load_source,
        normal_load_class=u_class if spread > 0.0 else 0.0,
    )


def load_sigma(measurement, scatter: float) -> float:
    """The σ [N] the fit weighs each sample of the normal-load channel by.

    The channel's scatter ``scatter`` and, spread over its n samples, the standard
    uncertainty of its mean from the sensors' stated classes (``normal_load_class``: the
    pressure sensor's offset, the air spring's area): σ² = scatter² + n u², so that the
    channel's mean weighs as one measurement of the load with the classes' error and the
    torque and the speeds can tell the load too. Weighted by the scatter alone (2 N on the
    bundled rig) the mean had pinned the replay's load to 0.03 N: a load offset inside the
    class (150 N of 4300) left the twin unable to reproduce the torque (30 N.m after the fit,
    against 0.44 N.m) and the free keys 4-13 standard errors off, or the fit diverged from a
    load 150 N low (2026-12-03).
    """
    n = int(measurement.valid["normal_load"].sum())
    u = float(measurement.normal_load_class)
    sigma = math.hypot(scatter, math.sqrt(n) * u)
    return sigma if sigma > 0.0 else 1.0
