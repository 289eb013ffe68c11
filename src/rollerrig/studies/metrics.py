"""Metrics of one simulated run: the numbers a study compares, chosen by name.

Each metric is a pure function of the run's channels (:class:`RunChannels`, numpy arrays on the
output time base) and the experiment; it returns one float, NaN where it is undefined for that
run (its ``nan_meaning`` says when). :data:`METRICS` is the documented set:

=========================  =======  ============================================================
name                       unit     what
=========================  =======  ============================================================
release_overshoot          1        how far the force the rig derives from its torque sensor,
                                    T56 / r_r, overshoots below zero after a sudden torque
                                    release, relative to its value before (largest over the
                                    releases; Kayaalp Figs. 42-43)
true_release_overshoot     1        the same for the true contact force F_x
release_minimum_time       s        time from the release to the first minimum of that swing
                                    (of the release with the largest overshoot)
release_ringing_frequency  Hz       frequency of that swing, 1/(2 Δt) from its first minimum to
                                    the next maximum
settling_time              s        time after a release until T56 stays within 5 % of its
                                    value before the release around its final value (largest)
coa_bias_rms               1        RMS of the CoA the rig reports, T56 / (r_r S), minus the true
                                    CoA F_x / N, over the loaded samples
coa_bias_peak              1        largest absolute value of that difference
peak_coa                   1        largest CoA the rig reports
peak_true_coa              1        largest true CoA
max_shaft_torque           N.m      largest absolute roller-shaft torque T56
t56_line_frequency         Hz       frequency of the largest line of T56 between 2 and 50 Hz
                                    in the rest after the first release (the ringing)
t56_line_amplitude         N.m      its amplitude (Hann window, amplitude-corrected)
=========================  =======  ============================================================
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rollerrig._validation import ParameterError, did_you_mean, require_names, require_positive
from rollerrig.experiment import Protocol

__all__ = [
    "METRICS",
    "Metric",
    "RunChannels",
    "compute_metrics",
    "release_overshoots",
    "rest_spectrum",
    "run_channels",
    "shown_unit",
]

RELEASE_WINDOW = 3.0
"""Time after a release searched for the overshoot's minimum [s]."""
SWING_SMOOTHING = 1.0 / 13.8
"""Width of the moving average before the swing after a release is timed [s]: one period of
the 13.8 Hz roller-shaft mode, which it removes (a moving average has a zero at 1/width)."""
RELEASE_MIN_COA = 0.005
"""Least CoA (force from T56 over the measured load) before a release for its overshoot to be
stated [-]: below it there is no traction to release (a test at standstill released 1 N and
"overshot" by 314 %)."""
SETTLING_BAND = 0.05
"""Settling band: this share of |T56| before the release [-]."""
LINE_BAND = (2.0, 50.0)
"""Band searched for the ringing line of T56 [Hz]: above the drive's slow mode (0.8 Hz, whose
window leakage a local-maximum search ignores), holding the 13.8 Hz roller-shaft mode."""


class RunChannels(NamedTuple):
    """The channels of one run the metrics need, on the output time base (SI).

    ``time`` [s]; ``t56`` [N.m] the roller-shaft torque (the sensor); ``contact_force`` [N] the
    true F_x; ``normal_load`` [N] the true normal load at the contact; ``roller_radius`` [m];
    ``air_spring_force`` [N] the load the rig measures and divides by (the swinging arm makes
    it differ from the contact's, :class:`rollerrig.rig.sections.ArmParameters`); None: the
    same as ``normal_load``.
    """

    time: np.ndarray
    t56: np.ndarray
    contact_force: np.ndarray
    normal_load: np.ndarray
    roller_radius: float
    air_spring_force: np.ndarray | None = None

    @property
    def measured_load(self) -> np.ndarray:
        """The load the rig divides by: the air-spring force S [N]."""
        return self.normal_load if self.air_spring_force is None else self.air_spring_force

    @classmethod
    def from_dataset(cls, ds, roller_radius: float | None = None) -> RunChannels:
        """The channels of a simulation's dataset (:func:`rollerrig.solve.results.
        build_dataset`); the roller radius [m] defaults to the dataset's T56 / (T56 / r_r)."""
        if roller_radius is None:
            with np.errstate(divide="ignore", invalid="ignore"):  # 0/0 at rest: left out
                rr = ds.measured_t56.values / ds.measured_force.values
            finite = np.isfinite(rr)
            roller_radius = float(np.median(rr[finite])) if finite.any() else np.nan
        return cls(
            ds.time.values,
            ds.measured_t56.values,
            ds.contact_force.values,
            ds.normal_load.values,
            roller_radius,
            ds.measured_normal_load.values if "measured_normal_load" in ds else None,
        )

    @property
    def measured_force(self) -> np.ndarray:
        """Force the rig derives from the torque sensor, T56 / r_r [N]."""
        return self.t56 / self.roller_radius


def run_channels(inputs, t: np.ndarray, x: np.ndarray) -> RunChannels:
    """The channels of a solved run (:func:`rollerrig.solve.results.evaluate_terms`)."""
    from rollerrig.solve.results import evaluate_terms

    term = evaluate_terms(inputs, t, x)
    return RunChannels(
        t,
        term["t56"],
        term["contact_force"],
        term["normal_load"],
        inputs.rig.geometry.roller_radius_x,
        term["air_spring_force"],
    )


def _releases(protocol: Protocol) -> list:
    return [e for e in protocol.events if e.action == "release_torque"]


def _release_rows(run: RunChannels, protocol: Protocol, window: float) -> list[dict]:
    t = run.time
    measured_force = run.measured_force
    rows = []
    load = run.measured_load
    for event in _releases(protocol):
        k = int(np.argmin(np.abs(t - event.start)))
        before = float(measured_force[k])
        if not before > RELEASE_MIN_COA * abs(float(load[k])):
            continue  # no traction to release: an overshoot of a near-zero force is noise
        span = (t > event.start) & (t <= event.start + window)
        if not span.any():
            continue
        measured = float(measured_force[span].min())
        true = float(run.contact_force[span].min())
        t_min, f_ring = _swing(t[span] - event.start, measured_force[span])
        rows.append(
            {
                "time [s]": event.start,
                "force_before [N]": before,
                "measured_min [N]": measured,
                "measured_overshoot [-]": -measured / before,
                "true_min [N]": true,
                "true_overshoot [-]": -true / before,
                "time_to_minimum [s]": t_min,
                "ringing_frequency [Hz]": f_ring,
            }
        )
    return rows


def _swing(t, y) -> tuple[float, float]:
    """Time of the first minimum of the swing after a release [s] (from the release) and the
    frequency of that swing [Hz], 1/(2 (t_max − t_min)) from the first minimum to the next
    maximum; NaN where the window holds no minimum, or no maximum after it.

    The signal is first smoothed over :data:`SWING_SMOOTHING` (a centred moving average, so
    that the lightly damped 13.8 Hz roller-shaft ringing riding on it makes no extrema of its
    own); the first minimum is the first local minimum below zero (the overshoot), else the
    lowest sample.
    """
    if t.size < 3:
        return np.nan, np.nan
    dt = float(np.median(np.diff(t)))
    width = max(1, round(SWING_SMOOTHING / dt)) if dt > 0 else 1
    width = min(width, max(1, t.size // 4))
    pad = np.pad(y, (width // 2, width - 1 - width // 2), mode="edge")
    smooth = np.convolve(pad, np.ones(width) / width, mode="valid")
    inner = np.arange(1, smooth.size - 1)
    minima = inner[(smooth[inner] < smooth[inner - 1]) & (smooth[inner] <= smooth[inner + 1])]
    below = minima[smooth[minima] < 0.0]
    k = int(below[0]) if below.size else int(np.argmin(smooth))
    if k == 0 or k == smooth.size - 1:
        return np.nan, np.nan
    after = inner[(inner > k) & (smooth[inner] > smooth[inner - 1])]
    after = after[smooth[after] >= smooth[np.minimum(after + 1, smooth.size - 1)]]
    f_ring = 1.0 / (2.0 * (t[after[0]] - t[k])) if after.size else np.nan
    return float(t[k]), float(f_ring)


def release_overshoots(ds, protocol: Protocol, window: float = RELEASE_WINDOW) -> list[dict]:
    """Overshoot below zero after each sudden torque release.

    Parameters
    ----------
    ds : xarray.Dataset or RunChannels
        Simulation results (:func:`rollerrig.solve.results.build_dataset`) or a run's channels.
    protocol : Protocol
        The experiment (its ``release_torque`` events).
    window : float
        Time after each release searched for the minimum [s].

    Returns
    -------
    list of dict
        Per release from traction (a CoA above :data:`RELEASE_MIN_COA`): time [s], force
        from T56 before it [N], its minimum after [N], the relative overshoot [-], the true
        contact force's minimum and relative overshoot, the time from the release to the
        swing's first minimum (``time_to_minimum [s]``) and the swing's frequency
        (``ringing_frequency [Hz]``, from the first minimum to the next maximum: 1/(2 Δt));
        see :func:`_swing`.
    """
    # A window of 0, NaN or below 0 had found no release: an empty list, with no error.
    window = require_positive("window", window, "s", single=True)
    if not isinstance(ds, RunChannels):
        ds = RunChannels.from_dataset(ds)
    return _release_rows(ds, protocol, window)


def _release_overshoot(run, protocol):
    rows = _release_rows(run, protocol, RELEASE_WINDOW)
    return max((r["measured_overshoot [-]"] for r in rows), default=np.nan)


def _largest_release(run, protocol):
    rows = _release_rows(run, protocol, RELEASE_WINDOW)
    return max(rows, key=lambda r: r["measured_overshoot [-]"], default=None)


def _release_minimum_time(run, protocol):
    row = _largest_release(run, protocol)
    return np.nan if row is None else row["time_to_minimum [s]"]


def _release_ringing_frequency(run, protocol):
    row = _largest_release(run, protocol)
    return np.nan if row is None else row["ringing_frequency [Hz]"]


def _true_release_overshoot(run, protocol):
    rows = _release_rows(run, protocol, RELEASE_WINDOW)
    return max((r["true_overshoot [-]"] for r in rows), default=np.nan)


def _rest_after(protocol: Protocol, start: float) -> float:
    """End of the rest after a release: the next step that changes the torque, or the end."""
    later = [e.start for e in protocol.events if e.start > start and e.action != "hold"]
    return min(later, default=protocol.duration)


def _settling_time(run, protocol):
    t, t56 = run.time, run.t56
    worst = np.nan
    for event in _releases(protocol):
        before = abs(float(t56[np.argmin(np.abs(t - event.start))]))
        end = _rest_after(protocol, event.start)
        span = (t > event.start) & (t <= end)
        if not before > 0 or span.sum() < 10:
            continue
        tt, yy = t[span], t56[span]
        tail = tt >= tt[-1] - 0.1 * (tt[-1] - tt[0])  # the final value: the last 10 % of the rest
        outside = np.abs(yy - yy[tail].mean()) > SETTLING_BAND * before
        if outside[tail].any():
            return np.nan  # not settled within the rest: no number to report
        last = np.flatnonzero(outside)
        settle = (tt[last[-1] + 1] if last.size else tt[0]) - event.start
        worst = settle if not np.isfinite(worst) else max(worst, settle)
    return worst


def _loaded_bias(run):
    """The rig's CoA, T56 / (r_r S), minus the true F_x / N where both loads are positive."""
    loaded = (run.normal_load > 0) & (run.measured_load > 0)
    if not loaded.any():
        return None
    return (
        run.measured_force[loaded] / run.measured_load[loaded]
        - run.contact_force[loaded] / run.normal_load[loaded]
    )


def _coa_bias_rms(run, protocol):
    bias = _loaded_bias(run)
    return np.nan if bias is None else float(np.sqrt(np.mean(bias**2)))


def _coa_bias_peak(run, protocol):
    bias = _loaded_bias(run)
    return np.nan if bias is None else float(np.max(np.abs(bias)))


def _peak_coa(run, protocol):
    loaded = run.measured_load > 0
    if not loaded.any():
        return np.nan
    return float(np.max(run.measured_force[loaded] / run.measured_load[loaded]))


def _peak_true_coa(run, protocol):
    loaded = run.normal_load > 0
    if not loaded.any():
        return np.nan
    return float(np.max(run.contact_force[loaded] / run.normal_load[loaded]))


def _max_shaft_torque(run, protocol):
    return float(np.max(np.abs(run.t56)))


def rest_spectrum(run: RunChannels, protocol: Protocol) -> tuple[np.ndarray, np.ndarray] | None:
    """Amplitude spectrum of T56 in the rest after the first release (the ringing).

    From 0.05 s after the release to the next step that changes the torque (or the end), the
    linear trend removed, Hann window, amplitude-corrected (a sinusoid of amplitude A shows A),
    zero-padded to 8 times the length (the peak's frequency to about 1/8 of a bin).

    Returns
    -------
    (frequency [Hz], amplitude [N.m]) or None
        None when the experiment has no release or the rest is shorter than 32 samples.
    """
    releases = _releases(protocol)
    if not releases:
        return None
    start = releases[0].start + 0.05  # past the release ramp itself
    end = _rest_after(protocol, releases[0].start)
    span = (run.time > start) & (run.time <= end)
    n = int(span.sum())
    if n < 32:
        return None
    y = run.t56[span]
    tt = run.time[span]
    y = y - np.polyval(np.polyfit(tt - tt[0], y, 1), tt - tt[0])
    w = np.hanning(n)
    dt = float(np.median(np.diff(tt)))
    nfft = 1 << int(np.ceil(np.log2(8 * n)))
    return np.fft.rfftfreq(nfft, dt), np.abs(np.fft.rfft(y * w, nfft)) * 2.0 / w.sum()


def _ringing_line(run, protocol) -> tuple[float, float]:
    spectrum = rest_spectrum(run, protocol)
    if spectrum is None:
        return np.nan, np.nan
    f, spec = spectrum
    nyquist = 0.5 / float(np.median(np.diff(run.time)))
    band = (f >= LINE_BAND[0]) & (f <= min(LINE_BAND[1], 0.8 * nyquist))
    # A line is a local maximum inside the band: the band's edge on the flank of a slower
    # mode is not one.
    peak = np.zeros_like(band)
    peak[1:-1] = (spec[1:-1] > spec[:-2]) & (spec[1:-1] >= spec[2:])
    candidates = np.flatnonzero(band & peak)
    if not candidates.size:
        return np.nan, np.nan
    k = candidates[np.argmax(spec[candidates])]
    return float(f[k]), float(spec[k])


@dataclass(frozen=True)
class Metric:
    """One metric: its unit, what it says, when it is undefined, and its function;
    ``needs_release``: it measures what follows a torque release, so an experiment without a
    ``release_torque`` step cannot give it; ``percent``: a fraction shown in % on a console
    (:func:`shown_unit`), stored as a fraction."""

    name: str
    units: str
    long_name: str
    nan_meaning: str
    function: Callable[[RunChannels, Protocol], float]
    needs_release: bool = False
    percent: bool = False


_NO_RELEASE = "the experiment has no torque release from a positive force, or the run failed"
METRICS: dict[str, Metric] = {
    m.name: m
    for m in (
        Metric(
            "release_overshoot",
            "1",
            "overshoot of T56/r_r below zero after a release",
            _NO_RELEASE,
            _release_overshoot,
            needs_release=True,
            percent=True,
        ),
        Metric(
            "true_release_overshoot",
            "1",
            "overshoot of F_x below zero after a release",
            _NO_RELEASE,
            _true_release_overshoot,
            needs_release=True,
            percent=True,
        ),
        Metric(
            "release_minimum_time",
            "s",
            "time from the release to the first minimum of T56/r_r",
            _NO_RELEASE + "; or no minimum in the window",
            _release_minimum_time,
            needs_release=True,
        ),
        Metric(
            "release_ringing_frequency",
            "Hz",
            "frequency of the swing after the release, first minimum to next maximum",
            _NO_RELEASE + "; or no maximum after the first minimum in the window",
            _release_ringing_frequency,
            needs_release=True,
        ),
        Metric(
            "settling_time",
            "s",
            "time for T56 to settle within 5 % after a release",
            _NO_RELEASE + "; or T56 had not settled by the end of the rest",
            _settling_time,
            needs_release=True,
        ),
        Metric(
            "coa_bias_rms",
            "1",
            "RMS of the reported minus the true CoA",
            "no loaded sample, or the run failed",
            _coa_bias_rms,
        ),
        Metric(
            "coa_bias_peak",
            "1",
            "largest |reported minus true CoA|",
            "no loaded sample, or the run failed",
            _coa_bias_peak,
        ),
        Metric(
            "peak_coa",
            "1",
            "largest CoA the rig reports, T56/(r_r S)",
            "no loaded sample, or the run failed",
            _peak_coa,
        ),
        Metric(
            "peak_true_coa",
            "1",
            "largest true CoA, F_x/N",
            "no loaded sample, or the run failed",
            _peak_true_coa,
        ),
        Metric("max_shaft_torque", "N.m", "largest |T56|", "the run failed", _max_shaft_torque),
        Metric(
            "t56_line_frequency",
            "Hz",
            "frequency of the largest T56 line after a release",
            "no release with a rest long enough for a spectrum, or the run failed",
            lambda run, p: _ringing_line(run, p)[0],
            needs_release=True,
        ),
        Metric(
            "t56_line_amplitude",
            "N.m",
            "amplitude of the largest T56 line after a release",
            "no release with a rest long enough for a spectrum, or the run failed",
            lambda run, p: _ringing_line(run, p)[1],
            needs_release=True,
        ),
    )
}
"""The metrics a study can compute, by name (see the module docstring)."""


def shown_unit(name: str, unit: str | None = None) -> tuple[str, float]:
    """The unit a metric is shown in on a console, and the factor from its stored value.

    The relative overshoots (:attr:`Metric.percent`) in % (stored as a fraction, unit ``1``),
    as ``simulate`` and ``study frame`` print them; another dimensionless metric (``1``) in
    ``-``, as the CSV headers have it; any other in its own unit. ``unit`` is the stored unit
    (a dataset's ``units`` attribute); default the metric's.

    Examples
    --------
    >>> shown_unit("release_overshoot"), shown_unit("peak_coa"), shown_unit("settling_time")
    (('%', 100.0), ('-', 1.0), ('s', 1.0))
    """
    metric = METRICS.get(name)
    if unit is None:
        unit = metric.units if metric is not None else "1"
    if unit in ("", "1"):
        if metric is not None and metric.percent:
            return "%", 100.0
        return "-", 1.0
    return unit, 1.0


def misses_its_releases(run: RunChannels, protocol: Protocol) -> bool:
    """Whether the experiment releases the torque but the run shows no release from a positive
    force: the run does not show the experiment (its channels are not finite, or a parameter
    far out of range makes T56 a rounding error: a roller-shaft stiffness of 1e300 N.m/rad)."""
    if not (np.all(np.isfinite(run.measured_force)) and np.all(np.isfinite(run.contact_force))):
        return True
    return bool(_releases(protocol)) and not _release_rows(run, protocol, RELEASE_WINDOW)


def require_measurable(protocol: Protocol, names) -> None:
    """Refuse metrics none of which the experiment can give.

    Every release metric (:attr:`Metric.needs_release`) is undefined on an experiment without
    a ``release_torque`` step: a study asking only for such metrics would run every point and
    measure nothing. Where some of the metrics apply, the study runs (the others come back
    undefined, with their ``nan_meaning``).

    Raises
    ------
    ParameterError
        When every metric of ``names`` needs a release and ``protocol`` has none.
    """
    names = _metric_names(names)
    if not names or _releases(protocol) or not all(METRICS[n].needs_release for n in names):
        return
    others = sorted(n for n, m in METRICS.items() if not m.needs_release)
    raise ParameterError(
        f"the metrics {', '.join(names)} measure what follows a torque release, and the "
        f"experiment {protocol.name!r} has no release_torque step: add one to the experiment, "
        f"or choose metrics of the whole run ({', '.join(others)})"
    )


def compute_metrics(run: RunChannels, protocol: Protocol, names) -> dict[str, float]:
    """The named metrics of one run (NaN where undefined).

    Examples
    --------
    >>> import numpy as np
    >>> from rollerrig.experiment import load_protocol
    >>> p = load_protocol("release-test")
    >>> t = np.arange(0, p.duration, 1e-3)
    >>> torque = p.torque_at(t) * 0.99  # a shaft that follows the request exactly, 1 % lower
    >>> run = RunChannels(t, torque, torque / 0.2, np.full(t.size, 4300.0), 0.2)
    >>> m = compute_metrics(run, p, ["release_overshoot", "max_shaft_torque"])
    >>> round(m["release_overshoot"], 6), round(m["max_shaft_torque"], 1)
    (-0.0, 594.0)
    """
    return {name: float(METRICS[name].function(run, protocol)) for name in _metric_names(names)}


def _metric_names(names) -> tuple[str, ...]:
    """``names`` as a tuple of known metric names, or a ParameterError naming the unknown one
    (it had raised a KeyError; a single string had been taken letter by letter)."""
    names = tuple(require_names("metric names", names))
    for name in names:
        if name not in METRICS:
            raise ParameterError(
                f"unknown metric {name!r}{did_you_mean(str(name), METRICS)}; known: "
                f"{', '.join(METRICS)}"
            )
    return names
