"""Which roller-drive model does a recording support? Both fitted, compared by evidence.

:func:`compare_drives` calibrates the twin with each candidate roller drive
(:data:`~rollerrig.calibrate.problem.ROLLER_DRIVES`: the Thevenin torque with its lag,
``induction``, and the dq machine under open-loop V/f, ``induction_dq``) to the same recording,
with the same free rig keys plus each model's own drive keys
(:func:`~rollerrig.calibrate.problem.drive_keys`: c_lp for the lag model, the V/f settings for
the dq drive), and weighs the evidence:

1. **Residual whiteness** per channel: Ljung–Box p and lag-1 autocorrelation
   (:func:`rollerrig.calibrate.stats.whiteness`). A model is *adequate* when its fit is valid
   (converged, not worse than its start) and no channel's residuals show structure
   (:func:`rollerrig.calibrate.result.channel_structured`).
2. **Information criteria** from the residuals of the fitted channels, each channel Gaussian
   with its own unknown variance, profiled out: −2 ln L = Σ_c n_c (ln(2π RSS_c/n_c) + 1), with
   RSS_c the channel's sum of squared residuals (the torque after its lines are projected out)
   over its n_c samples; k = the identified free parameters + the nuisance parameters + one
   variance per channel (the torque's line amplitudes are the same for every model and not
   counted). AIC = −2 ln L + 2k, BIC = −2 ln L + k ln N with N = Σ n_c. The likelihood takes the
   samples as independent: with structured residuals it overstates the evidence (ΔBIC of
   thousands), the sign is what counts. The winner is the adequate model of smallest BIC (of all
   models when none is adequate, then marked inadequate).
3. **The ringing after each release** (a fall of the torque request by more than half its peak
   within 0.1 s): the time of the first minimum of the torque after the release, measured and
   each model's (both through the same zero-phase 20 Hz low-pass), and the dominant frequency of
   the ringing (peak of the Hann-windowed spectrum of the torque, a quadratic trend taken out,
   from 0.05 s to 5 s after the release or to the next one, 0.5 to 50 Hz and at least two
   cycles in that window; none where the spectrum only falls from the band's lower edge).

The spread of the values between adequate models is a type-B model-discrepancy term: per key,
half the range of the adequate models' values as the half-width of a rectangular distribution
(standard uncertainty half-width/√3), written into the winner's ``calibration.json``
(``model_discrepancy``) and added to the variance of that key by
:func:`rollerrig.estimation.uncertainty.calibration_covariance`.

Items 1 to 3 and the choice of the winner are :func:`weigh`, which
:func:`rollerrig.calibrate.lawcompare.compare_laws` shares to weigh creep laws the same way;
both results are a :class:`ModelComparison`.
"""

from __future__ import annotations

import dataclasses
import math
import time as _time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from rollerrig.calibrate.problem import ROLLER_DRIVES, CalibrationError, drive_keys

__all__ = [
    "COMPARE_JSON_NAME",
    "DriveComparison",
    "ModelComparison",
    "compare_drives",
    "information_criteria",
    "model_discrepancy",
    "ringing",
    "weigh",
    "write_comparison",
]

COMPARE_JSON_NAME = "calibration-compare.json"

_RELEASE_FRACTION = 0.5  # a release: the request falls by this fraction of its peak ...
_RELEASE_WITHIN = 0.1  # ... within this time [s]
_LOWPASS_HZ = 20.0  # zero-phase low-pass of the torque before the first minimum is sought [Hz]
_RING_WINDOW = (0.05, 5.0)  # window of the ringing spectrum after a release [s]
_RING_CYCLES = 2.0  # least cycles of a ringing frequency inside the window [-]
_RING_BAND = (0.5, 50.0)  # band of the dominant ringing frequency [Hz]


# --------------------------------------------------------------------------------------------
# Evidence
# --------------------------------------------------------------------------------------------


def information_criteria(channels: dict, n_params: int) -> dict[str, Any]:
    """AIC and BIC of a fit from its channels' residual RMS (module docstring, item 2).

    Parameters
    ----------
    channels : dict of str to ChannelFit
        ``samples`` and ``rms_after`` of each fitted channel.
    n_params : int
        Identified free and nuisance parameters [-] (one variance per channel is added).

    Examples
    --------
    >>> from types import SimpleNamespace as C
    >>> ic = information_criteria({"a": C(samples=100, rms_after=1.0)}, 1)
    >>> round(ic["minus_2_log_likelihood"], 3), ic["parameters"]
    (283.788, 2)
    """
    m2ll = 0.0
    n_total = 0
    for ch in channels.values():
        n = int(ch.samples)
        rss = n * float(ch.rms_after) ** 2
        m2ll += n * (math.log(2.0 * math.pi * max(rss, 1e-300) / n) + 1.0)
        n_total += n
    k = int(n_params) + len(channels)
    return {
        "minus_2_log_likelihood": m2ll,
        "parameters": k,
        "samples": n_total,
        "AIC": m2ll + 2.0 * k,
        "BIC": m2ll + k * math.log(max(n_total, 1)),
    }


def release_times(time: np.ndarray, request: np.ndarray) -> list[float]:
    """Instants [s] where the torque request falls by more than half its peak within 0.1 s.

    Examples
    --------
    >>> t = np.linspace(0, 4, 401); r = np.where((t > 1) & (t < 2.005), 500.0, 0.0)
    >>> release_times(t, r)
    [2.0]
    """
    time = np.asarray(time, dtype=float)
    request = np.asarray(request, dtype=float)
    peak = float(np.max(np.abs(request))) if request.size else 0.0
    if not peak > 0.0 or time.size < 3:
        return []
    dt = float(np.median(np.diff(time)))
    m = max(1, round(_RELEASE_WITHIN / dt))
    ahead = np.concatenate([request[m:], np.full(m, request[-1])])
    falls = np.flatnonzero(request - ahead > _RELEASE_FRACTION * peak)
    out: list[float] = []
    last = -np.inf
    for k in falls:
        if time[k] - last > 2 * _RELEASE_WITHIN:
            # the start of the fall: the last sample before the request moves down
            j = int(k)
            while j + 1 < request.size and request[j + 1] >= request[j] - 1e-9 * peak:
                j += 1
            out.append(float(time[j]))
        last = time[k]
    return out


def _lowpass(x: np.ndarray, dt: float) -> np.ndarray:
    from scipy.signal import butter, sosfiltfilt

    nyquist = 0.5 / dt
    if _LOWPASS_HZ >= nyquist or x.size < 16:
        return x
    sos = butter(2, _LOWPASS_HZ / nyquist, output="sos")
    return sosfiltfilt(sos, x)


def _first_minimum(t: np.ndarray, x: np.ndarray, t0: float, t_end: float) -> float | None:
    """Time [s] of the first local minimum of ``x`` after ``t0`` (before ``t_end``), once the
    torque has fallen (the first minimum of the ringing)."""
    k = np.flatnonzero((t >= t0) & (t <= t_end))
    if k.size < 3:
        return None
    seg = x[k]
    d = np.diff(seg)
    turns = np.flatnonzero((d[:-1] < 0.0) & (d[1:] >= 0.0))
    return None if turns.size == 0 else float(t[k[turns[0] + 1]])


def _dominant_frequency(t: np.ndarray, x: np.ndarray, t0: float, t_end: float) -> float | None:
    """The highest peak of the ringing's spectrum [Hz], or None where the spectrum has no peak
    inside the band that the window holds :data:`_RING_CYCLES` cycles of.

    A slow recovery after the release that is no oscillation leaves its energy at the lowest
    frequencies the window resolves, where the Hann window's main lobe made a "peak": 0.6561
    Hz on every release, measured and of every model alike, of a 1.95 s window (a review,
    2026-12-03). So the band starts at two cycles in the window, after a quadratic trend is
    taken out, and the maximum must be the largest within one resolution (1/span) on either
    side, the frequencies below the band included: a slope falling from the band's lower edge
    is no peak.
    """
    k = np.flatnonzero((t >= t0 + _RING_WINDOW[0]) & (t <= min(t_end, t0 + _RING_WINDOW[1])))
    if k.size < 32:
        return None
    dt = float(np.median(np.diff(t)))
    span = float(t[k[-1]] - t[k[0]])
    seg = x[k] - np.polyval(np.polyfit(t[k] - t[k[0]], x[k], 2), t[k] - t[k[0]])
    size = 1 << max(14, math.ceil(math.log2(8 * seg.size)))
    spec = np.abs(np.fft.rfft(seg * np.hanning(seg.size), size))
    freq = np.fft.rfftfreq(size, dt)
    band = np.flatnonzero(
        (freq >= max(_RING_BAND[0], _RING_CYCLES / span)) & (freq <= _RING_BAND[1])
    )
    if band.size < 3:
        return None
    j = band[int(np.argmax(spec[band]))]
    # A peak: the largest within one resolution (1/span) on either side, the frequencies below
    # the band included (a slope falling from the band's lower edge is no peak).
    w = max(1, round(1.0 / span / (freq[1] - freq[0])))
    if spec[j] < np.max(spec[max(0, j - w) : j + w + 1]):
        return None
    return float(freq[j])


def ringing(time, request, measured, models: dict[str, np.ndarray]) -> list[dict[str, Any]]:
    """Per release: the first minimum of the torque and the dominant ringing frequency, measured
    and of each model (module docstring, item 3).

    Parameters
    ----------
    time : ndarray
        Time [s].
    request : ndarray
        Wheel-torque request [N.m] (finds the releases).
    measured : ndarray
        Recorded T56 [N.m].
    models : dict of str to ndarray
        Each model's fitted T56 [N.m].

    Returns
    -------
    list of dict
        ``release [s]``, ``first_minimum [s]`` and ``ringing_frequency [Hz]`` of the recording,
        and per model the same with ``first_minimum_error [s]`` (model − measured).
    """
    t = np.asarray(time, dtype=float)
    dt = float(np.median(np.diff(t)))
    releases = release_times(t, request)
    out = []
    for i, t0 in enumerate(releases):
        t_end = releases[i + 1] if i + 1 < len(releases) else float(t[-1])
        rows = {"measured": np.asarray(measured, dtype=float)} | {
            k: np.asarray(v, dtype=float) for k, v in models.items()
        }
        entry: dict[str, Any] = {"release [s]": t0}
        reference = None
        for name, x in rows.items():
            xf = _lowpass(x, dt)
            tmin = _first_minimum(t, xf, t0, t_end)
            freq = _dominant_frequency(t, x, t0, t_end)
            item: dict[str, Any] = {
                "first_minimum [s]": tmin,
                "first_minimum_after_release [s]": None if tmin is None else tmin - t0,
                "ringing_frequency [Hz]": freq,
            }
            if name == "measured":
                reference = item
            elif reference is not None:
                ref_t, ref_f = reference["first_minimum [s]"], reference["ringing_frequency [Hz]"]
                item["first_minimum_error [s]"] = (
                    None if tmin is None or ref_t is None else tmin - ref_t
                )
                item["ringing_frequency_error [Hz]"] = (
                    None if freq is None or ref_f is None else freq - ref_f
                )
            entry[name] = item
        out.append(entry)
    return out


def model_discrepancy(
    calibrations: dict[str, Any], *, models: str = "roller-drive models"
) -> dict[str, Any]:
    """The type-B model-discrepancy term from the spread of the values between adequate models.

    Per key identified by every model given: half-width a = (max − min)/2 of their values,
    rectangular, standard uncertainty a/√3 (JCGM 100, 4.3.7).

    Parameters
    ----------
    calibrations : dict of str to Calibration
        The adequate models' calibrations by model name (keys that mean the same thing under
        the same name in each).
    models : str
        What the models are, for the record's ``what``.
    """
    drives = list(calibrations)
    keys: dict[str, Any] = {}
    if len(drives) >= 2:
        common = [
            k
            for k, p in calibrations[drives[0]].parameters.items()
            if all(k in c.parameters and c.parameters[k].identified for c in calibrations.values())
            and p.identified
        ]
        for k in common:
            values = {d: float(calibrations[d].parameters[k].value) for d in drives}
            half = 0.5 * (max(values.values()) - min(values.values()))
            keys[k] = {
                "half_width": half,
                "standard_uncertainty": half / math.sqrt(3.0),
                "distribution": "rectangular",
                "unit": calibrations[drives[0]].parameters[k].unit,
                "values": values,
            }
    return {
        "what": "type-B model-discrepancy term: per key, half the spread of the values of the "
        f"adequate {models} as the half-width a of a rectangular distribution, "
        "standard uncertainty a/sqrt(3) (JCGM 100, 4.3.7); rollerrig analyze --calibration adds "
        "its square to the key's variance",
        "models": drives,
        "keys": keys,
        **(
            {}
            if len(drives) >= 2
            else {"note": "fewer than two adequate models: no spread between models to state"}
        ),
    }


# --------------------------------------------------------------------------------------------
# The comparison
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ModelComparison:
    """What a comparison of models fitted to one recording found (:func:`compare_drives`,
    :func:`rollerrig.calibrate.lawcompare.compare_laws`).

    Attributes
    ----------
    calibrations : dict of str to Calibration
        Each candidate's calibration, by model name.
    evidence : dict of str to dict
        Per model: ``adequate``, ``valid``, ``structured_channels``, per channel whiteness,
        the information criteria.
    ringing : list of dict
        :func:`ringing` per release.
    winner : str
        The model the recording supports (module docstring).
    adequate : bool
        Whether the winner is adequate (only then are its calibrated rig files written).
    discrepancy : dict
        :func:`model_discrepancy` of the adequate models.
    wall_time : float
        [s].
    free : tuple of str
        The keys every model fitted.
    """

    calibrations: dict[str, Any]
    evidence: dict[str, dict[str, Any]]
    ringing: list[dict[str, Any]]
    winner: str
    adequate: bool
    discrepancy: dict[str, Any]
    wall_time: float = 0.0
    free: tuple[str, ...] = field(default=())

    MODEL: ClassVar[str] = "model"
    """What a candidate is, in the verdict (``roller-drive model``, ``creep law``)."""
    OPTION: ClassVar[str] = ""
    """The ``rollerrig calibrate`` option that runs the comparison."""
    JSON_NAME: ClassVar[str] = COMPARE_JSON_NAME
    """The file :func:`write_comparison` writes the comparison to."""

    @property
    def winning_calibration(self):
        """The winner's :class:`Calibration`, with the model-discrepancy term."""
        return self.calibrations[self.winner]

    def delta_bic(self, model: str) -> float:
        """BIC of ``model`` minus the winner's [-]."""
        ic = {m: e["information_criteria"]["BIC"] for m, e in self.evidence.items()}
        return float(ic[model] - ic[self.winner])

    def verdict(self) -> str:
        """One sentence: which model the recording supports and why."""
        ev = self.evidence[self.winner]
        others = [d for d in self.evidence if d != self.winner]
        if not self.adequate:
            return (
                f"no candidate {self.MODEL} is adequate: every fit leaves structure in "
                f"its residuals or is not a valid calibration; the smallest BIC is "
                f"{self.winner!r}'s (BIC {ev['information_criteria']['BIC']:.6g}); no calibrated "
                "rig is written"
            )
        text = f"the recording supports {self.winner!r}: its residuals are white"
        for o in others:
            why = (
                "also adequate"
                if self.evidence[o]["adequate"]
                else "structured residuals in "
                + (", ".join(self.evidence[o]["structured_channels"]) or "no channel")
                + ("" if self.evidence[o]["valid"] else ", not a valid fit")
            )
            text += f"; {o!r}: BIC larger by {self.delta_bic(o):.4g}, {why}"
        return text

    def _extra_json(self) -> dict[str, Any]:
        return {}

    def to_json(self) -> dict[str, Any]:
        """The content of the comparison's JSON file (:attr:`JSON_NAME`)."""
        return {
            "what": f"comparison of {self.MODEL}s fitted to one recording (rollerrig "
            f"calibrate {self.OPTION})",
            "free": list(self.free),
            **self._extra_json(),
            "winner": self.winner,
            "winner_adequate": bool(self.adequate),
            "verdict": self.verdict(),
            "criterion": (
                "adequate = a valid fit (converged, not worse than its start) whose residuals "
                "show no structure in any channel; the winner is the adequate model of smallest "
                "BIC (of all models when none is adequate). Likelihood: each channel Gaussian "
                "with its own variance profiled out, -2 ln L = sum_c n_c (ln(2 pi RSS_c/n_c) + "
                "1); k = identified free + nuisance parameters + one variance per channel; AIC "
                "= -2 ln L + 2k, BIC = -2 ln L + k ln N. The samples are taken as independent: "
                "with structured residuals the differences are overstated, their sign counts."
            ),
            "models": self.evidence,
            "ringing_after_releases": self.ringing,
            "model_discrepancy": self.discrepancy,
            "wall_time [s]": self.wall_time,
        }


@dataclass(frozen=True)
class DriveComparison(ModelComparison):
    """What :func:`compare_drives` found: the candidates are roller drives
    (:class:`ModelComparison`)."""

    MODEL: ClassVar[str] = "roller-drive model"
    OPTION: ClassVar[str] = "--compare-drives"


def _evidence(cal) -> dict[str, Any]:
    n_params = sum(p.identified for p in cal.parameters.values()) + sum(
        p.identified for p in cal.nuisance.values()
    )
    return {
        "adequate": bool(cal.valid and not cal.conditional),
        "valid": bool(cal.valid),
        **({"invalid_reasons": list(cal.invalid_reasons)} if not cal.valid else {}),
        "converged": bool(cal.fit["converged"]),
        "structured_channels": list(cal.structured_channels),
        "channels": {
            c: {
                "rms_before": ch.rms_before,
                "rms_after": ch.rms_after,
                "unit": ch.unit,
                "ljung_box_p": ch.whiteness["ljung_box_p"],
                "lag1_autocorrelation": ch.whiteness["lag1_autocorrelation"],
                "structured": c in cal.structured_channels,
            }
            for c, ch in cal.channels.items()
        },
        "information_criteria": information_criteria(cal.channels, n_params),
        "parameters": {
            k: {
                "value": p.value,
                "standard_error": p.standard_error,
                "unit": p.unit,
                "identified": p.identified,
                "conditional_on_model": p.conditional_on_model,
            }
            for k, p in cal.parameters.items()
        },
        "iterations": cal.fit["iterations"],
        "wall_time [s]": cal.fit["wall_time [s]"],
    }


def compare_drives(
    recording,
    free: str | Iterable[str],
    *,
    drives: Sequence[str] = ROLLER_DRIVES,
    rig=None,
    channel_map=None,
    friction=None,
    max_iterations: int = 20,
    progress: Callable[[str, int, int, str], None] | None = None,
    **options,
) -> DriveComparison:
    """Fit each candidate roller-drive model to one recording and say which it supports.

    Parameters
    ----------
    recording : Recording or path
        As :func:`rollerrig.calibrate.calibrate`.
    free : str or iterable of str
        The free rig (and creep-law: ``polach.*``, or ``fastsim.*`` with ``law=``) keys every
        model fits; each model adds its own drive keys
        (:func:`~rollerrig.calibrate.problem.drive_keys`) unless they are named here already.
        V/f keys named here are freed for the dq drive only.
    drives : sequence of str
        The candidates (default both of :data:`~rollerrig.calibrate.problem.ROLLER_DRIVES`).
    rig, channel_map, friction, max_iterations
        As :func:`rollerrig.calibrate.calibrate`.
    progress : callable, optional
        ``progress(drive, iteration, max_iterations, text)``.
    **options
        Further keyword arguments of :func:`rollerrig.calibrate.calibrate` (``torque_noise``,
        ``search_width``, ``h_max``, ``law``, ...).

    Returns
    -------
    DriveComparison
    """
    from rollerrig.calibrate.fit import calibrate
    from rollerrig.calibrate.problem import VF_SECTION
    from rollerrig.recordings.recording import Recording
    from rollerrig.rig.parameters import default_rig

    started = _time.perf_counter()
    drives = list(dict.fromkeys(drives))
    bad = [d for d in drives if d not in ROLLER_DRIVES]
    if bad or len(drives) < 2:
        raise CalibrationError(
            f"compare at least two roller drives of {list(ROLLER_DRIVES)}; got {drives}"
        )
    if not isinstance(recording, Recording):
        from rollerrig.recordings.readers import read_recording

        recording = read_recording(recording, channel_map)
    rig = default_rig() if rig is None else rig
    keys = free.split(",") if isinstance(free, str) else list(free)
    keys = [str(k).strip() for k in keys if str(k).strip()]
    own = {d: set(drive_keys(d)) for d in drives}
    every_own = set().union(*own.values())
    shared = [k for k in keys if k not in every_own and not k.startswith(f"{VF_SECTION}.")]
    calibrations = {}
    for d in drives:
        vf = d == "induction_dq"
        named = [k for k in keys if k in own[d] or (vf and k.startswith(f"{VF_SECTION}."))]
        model_keys = list(dict.fromkeys([*shared, *named, *drive_keys(d)]))

        def report(i, n, text, d=d):
            if progress is not None:
                progress(d, i, n, text)

        calibrations[d] = calibrate(
            recording,
            model_keys,
            rig=rig,
            friction=friction,
            max_iterations=max_iterations,
            progress=report,
            roller_drive=d,
            **options,
        )
    return DriveComparison(
        **weigh(calibrations, recording, rig),
        wall_time=_time.perf_counter() - started,
        free=tuple(shared),
    )


def weigh(
    calibrations: dict[str, Any],
    recording,
    rig,
    *,
    models: str = "roller-drive models",
    same_keys: Callable[[str, Any], Any] | None = None,
) -> dict[str, Any]:
    """The evidence of each fitted model and the winner (module docstring, items 1 to 3).

    Parameters
    ----------
    calibrations : dict of str to Calibration
        Each candidate's calibration (in the order of preference on a tie); the winner's is
        replaced by one with the model-discrepancy term.
    recording : Recording
        The recording they were fitted to (its torque request finds the releases).
    rig : RigParameters
        The rig the fits started from.
    models : str
        What the candidates are, for the discrepancy's record.
    same_keys : callable, optional
        ``same_keys(winner, calibration)``: the calibration with its keys named as the winner
        names the same quantities (a creep law's μ0 is ``polach.static_friction`` under one law
        and ``fastsim.static_friction`` under another), for the model-discrepancy term.

    Returns
    -------
    dict
        ``calibrations``, ``evidence``, ``ringing``, ``winner``, ``adequate``,
        ``discrepancy``: the fields of a :class:`ModelComparison`.
    """
    from rollerrig.calibrate.measurement import prepare_measurement

    names = list(calibrations)
    calibrations = dict(calibrations)
    evidence = {d: _evidence(c) for d, c in calibrations.items()}
    adequate = [d for d in names if evidence[d]["adequate"]]
    pool = adequate or names
    winner = min(pool, key=lambda d: evidence[d]["information_criteria"]["BIC"])
    rename = same_keys or (lambda _w, c: c)
    discrepancy = model_discrepancy(
        {d: rename(winner, calibrations[d]) for d in adequate}, models=models
    )
    calibrations[winner] = dataclasses.replace(calibrations[winner], model_discrepancy=discrepancy)
    measurement = prepare_measurement(recording, rig, lines=False)
    first = calibrations[names[0]]
    rings = ringing(
        first.series["time"],
        measurement.torque_request,
        first.series["torque"]["measured"],
        {d: c.series["torque"]["fitted"] for d, c in calibrations.items()},
    )
    return {
        "calibrations": calibrations,
        "evidence": evidence,
        "ringing": rings,
        "winner": winner,
        "adequate": bool(adequate),
        "discrepancy": discrepancy,
    }


def write_comparison(comparison: ModelComparison, folder, *, overwrite: bool = True) -> list:
    """Write the comparison's JSON (``calibration-compare.json`` of the roller drives,
    ``calibration-compare-laws.json`` of the creep laws: :attr:`ModelComparison.JSON_NAME`),
    and, only when the winner is adequate, its calibration files
    (:func:`rollerrig.calibrate.write_calibration`: ``calibration.json`` with the
    model-discrepancy term, ``calibrated-rig.toml``, ``calibration-fit.nc``)."""
    from pathlib import Path

    from rollerrig.calibrate.result import write_calibration
    from rollerrig.output import write_json

    folder = Path(folder)
    paths = [write_json(folder / comparison.JSON_NAME, comparison.to_json(), overwrite=overwrite)]
    if comparison.adequate:
        paths += write_calibration(comparison.winning_calibration, folder, overwrite=overwrite)
    return paths
