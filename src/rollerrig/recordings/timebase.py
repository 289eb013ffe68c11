"""Put channels recorded on their own time bases onto one common time base.

Acquisition software writes channels of one file on different rasters (TDMS waveforms with their
own ``wf_increment``/``wf_start_offset``/``wf_start_time``, DAQmx files with one task per rate,
MDF4 data groups with their own master channel). Analyses need one time base; this module
chooses it and moves every channel onto it. Channels with different time bases are never
index-aligned.

The common base
    ``[time] resample_Hz`` of the channel map when given (a uniform grid at that rate over the
    span all channels cover); else the file's time column when the map names one; else the
    time base of the torque channel when it is mapped; else that of the fastest channel. The
    result is trimmed to the span every channel covers (noted).
Downsampling (a channel faster than the common base)
    Anti-alias FIR, then polyphase resampling (:func:`scipy.signal.resample_poly`) by the
    rational factor ``up/down`` nearest to the rate ratio: a Kaiser-windowed sinc designed at
    the up-sampled rate, pass band ``0 .. 0.4·R`` (ripple 1e-3: an in-band tone keeps its
    amplitude within 0.1 %), stop band from the new Nyquist frequency ``0.5·R`` up, attenuated
    by at least :data:`ATTENUATION_DB` (a tone above the new Nyquist cannot alias into the
    result by more than 1e-3 of its amplitude). The filter is shifted by the fraction of a
    sample between the two grids, so the outputs fall on the common base's instants (no
    interpolation of the band-limited result). A source grid with jitter (MDF masters of bus
    loggers) is first put on a uniform grid at its median rate by linear interpolation (noted).
Upsampling (a channel slower than, or as fast as, the common base)
    Linear interpolation (:func:`numpy.interp`).

Both are recorded in ``metadata["resampled"]`` (``onto``, ``rate_Hz``, and per channel
``from_rate_Hz``, ``method`` and the filter's figures) and in a note.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping
from fractions import Fraction
from typing import Any

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.recordings.recording import RecordingError
from rollerrig.recordings.uniform import uniform_sample_rate
from rollerrig.recordings.validate import check_grid, check_nan_runs

__all__ = [
    "ATTENUATION_DB",
    "PASSBAND",
    "align_channels",
    "require_uniform_time",
    "resample_onto",
]

ATTENUATION_DB = 60.0
"""Stop-band attenuation and pass-band ripple ``10^(-A/20)`` of the anti-alias FIR [dB]."""

PASSBAND = 0.8
"""Pass-band edge of the anti-alias FIR as a fraction of the new Nyquist frequency [-]."""

_MAX_DENOMINATOR = 10_000
"""Largest ``down`` of the rational resampling factor (the FIR has about 36·down taps)."""

_UNIFORM = 1e-3
"""A grid whose intervals differ from their median by more than this fraction is jittered."""


def _rate(t: np.ndarray, where: str = "") -> float:
    """Sample rate [Hz] from the median step of ``t`` [s]; NaN for fewer than 2 samples.

    ``where`` prefixes the messages (the file, as in :func:`align_channels`): a bad time
    stamp is in one file of perhaps many the user read.
    """
    prefix = f"{where} " if where else ""
    if t.size < 2:
        return float("nan")
    bad = ~np.isfinite(t)
    if bad.any():  # else the median step below is NaN, and the message about it misleads
        k = int(np.flatnonzero(bad)[0])
        raise RecordingError(
            f"{prefix}time stamp {k} (of {t.size}) is {t[k]:g}, and {int(bad.sum())} in all are "
            "not finite numbers; the time base must be finite and strictly increasing (an "
            "empty or NaN cell in the time column?)"
        )
    step = float(np.median(np.diff(t)))
    if not step > 0.0:  # most stamps repeat (e.g. absolute times written to too few digits)
        raise RecordingError(
            f"{prefix}time stamps repeat or fall: the median step is {step:g} s over {t.size} "
            "samples (absolute times rounded to too few digits?); the time base must be "
            "strictly increasing. Where the samples are evenly spaced, give [time] "
            "sample_rate_Hz in the channel map instead of the time column"
        )
    return 1.0 / step


def _kernel(pad: int, shift: float, fs_up: float, rate_out: float) -> np.ndarray:
    """Kaiser-windowed sinc at the up-sampled rate, shifted by ``shift`` (0..``pad``) samples.

    Returns the taps (sum 1; :func:`scipy.signal.resample_poly` multiplies them by ``up``).
    """
    from scipy.special import i0

    cutoff = 0.5 * (PASSBAND + 1.0) * rate_out / 2.0  # mid transition band [Hz]
    beta = 0.1102 * (ATTENUATION_DB - 8.7)  # Kaiser (1974)
    half = _half_length(fs_up, rate_out)
    # resample_poly centres output j on tap (len - 1) // 2 at up-sampled input position j·down;
    # the kernel's centre is moved left by `shift`, so output j lies at j·down + shift
    length = 2 * (half + pad) + 1
    u = np.arange(length) - (half + pad) + shift
    inside = np.abs(u) <= half
    window = np.zeros(length)
    window[inside] = i0(beta * np.sqrt(1.0 - (u[inside] / half) ** 2)) / i0(beta)
    taps = np.sinc(2.0 * cutoff / fs_up * u) * window
    return taps / taps.sum()


def _half_length(fs_up: float, rate_out: float) -> int:
    """Half length of :func:`_kernel` [up-sampled samples] (Kaiser's length formula)."""
    width = (1.0 - PASSBAND) * rate_out / 2.0 / fs_up * 2.0 * np.pi  # transition [rad/sample]
    return int(np.ceil((ATTENUATION_DB - 7.95) / (2.285 * width) / 2.0)) + 1


def resample_onto(
    values: np.ndarray, time: np.ndarray, target: np.ndarray
) -> tuple[np.ndarray, dict[str, Any]]:
    """``values`` sampled at ``time`` [s], resampled onto the instants ``target`` [s].

    Downsampling uses the anti-alias FIR and polyphase resampling of the module docstring,
    upsampling linear interpolation. ``target`` must lie inside ``time``'s span.

    Parameters
    ----------
    values : ndarray, shape (n,)
        Samples [any unit].
    time : ndarray, shape (n,)
        Their instants [s], strictly increasing.
    target : ndarray, shape (m,)
        Instants of the result [s], increasing (uniform for downsampling; jitter is tolerated).

    Returns
    -------
    out : ndarray, shape (m,)
        The resampled values [unit of ``values``].
    how : dict
        ``from_rate_Hz``, ``method`` (``"linear"`` or ``"fir_polyphase"``) and, for the FIR,
        ``up``, ``down``, ``passband_Hz``, ``stopband_Hz``, ``attenuation_dB``.

    Examples
    --------
    >>> t = np.arange(19200) / 19200.0
    >>> x = np.sin(2 * np.pi * 50 * t) + np.sin(2 * np.pi * 700 * t)  # 700 Hz: above 500 Hz
    >>> tt = np.arange(100, 900) / 1000.0
    >>> y, how = resample_onto(x, t, tt)
    >>> how["method"], how["up"], how["down"]
    ('fir_polyphase', 5, 96)
    >>> bool(np.max(np.abs(y - np.sin(2 * np.pi * 50 * tt))) < 2e-3)
    True
    """
    from scipy.signal import resample_poly

    values = np.asarray(values, dtype=float)
    time = np.asarray(time, dtype=float)
    target = np.asarray(target, dtype=float)
    if values.shape != time.shape or time.ndim != 1:
        # On the FIR path a shorter series had been resampled as if it spanned the time.
        raise ParameterError(
            f"values {values.shape} and time {time.shape} must be 1-D and of the same length"
        )
    r_in = _rate(time)
    r_out = _rate(target) if target.size > 1 else r_in
    how: dict[str, Any] = {"from_rate_Hz": r_in if np.isfinite(r_in) else None}
    if not r_in > r_out * (1.0 + 1e-9) or target.size < 2:
        how["method"] = "linear"
        return np.interp(target, time, values), how
    dt = np.diff(time)
    if np.max(np.abs(dt * r_in - 1.0)) > _UNIFORM:
        check_grid(time[-1] - time[0], r_in, "", "a uniform grid at the source's median rate")
        grid = time[0] + np.arange(int(np.floor((time[-1] - time[0]) * r_in)) + 1) / r_in
        values, time = np.interp(grid, time, values), grid
        how["regularised"] = "jittered source grid put on a uniform one (linear) first"
    ratio = Fraction(r_out / r_in).limit_denominator(_MAX_DENOMINATOR)
    up, down = ratio.numerator, ratio.denominator
    fs_up = r_in * up
    # outputs lie at up-sampled positions j·down + shift after the first input used: start a
    # filter length before target[0] (the filter's context) and shift the filter by the
    # remainder, so that one output lands on target[0]
    s_total = max(0.0, (target[0] - time[0]) * fs_up)
    context = int(np.ceil(_half_length(fs_up, r_out) / up)) + 2
    q = max(0, int(np.floor(s_total / up)) - context)
    shift = (s_total - q * up) % down
    taps = _kernel(down, shift, fs_up, r_out)
    y = resample_poly(values[q:], up, down, window=taps, padtype="line")
    t_y = time[0] + (q * up + shift) / fs_up + np.arange(y.size) * down / fs_up
    how.update(
        method="fir_polyphase",
        up=up,
        down=down,
        passband_Hz=PASSBAND * r_out / 2.0,
        stopband_Hz=r_out / 2.0,
        attenuation_dB=ATTENUATION_DB,
    )
    return np.interp(target, t_y, y), how


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    if a is b:
        return True
    if a.size != b.size:
        return False
    step = float(np.median(np.abs(np.diff(b)))) if b.size > 1 else 1.0
    return bool(np.allclose(a, b, rtol=0.0, atol=1e-6 * step))


def _base_times(
    time, loaded, own_times, exact, columns, where, notes, exact_channels=(), groups=None
) -> tuple[list[np.ndarray], list]:
    """The time base [s] each channel was recorded on, and ``loaded`` with the samples that
    repeat their time stamp and value dropped (:func:`_repeated_stamps`).

    ``exact``: ``own_time_exact``; ``columns``: channel -> file column, for messages;
    ``groups``: channel -> its group in the file, for messages; the others as for
    :func:`align_channels`.
    """
    bases: list[np.ndarray] = []
    kept: list = []
    fallback = next((o for o in own_times if o is not None), None)
    for (spec, values, *rest), own in zip(loaded, own_times, strict=True):
        column = columns.get(spec.name, spec.name)
        if time is not None:
            use_own = own is not None and not _same(own, time)
            use_own = use_own and (exact or spec.name in exact_channels or values.size != time.size)
            base = own if use_own else time
        else:
            base = own if own is not None else fallback
        if base is None or base.size != values.size:
            n_time = "no time base" if base is None else f"time has {base.size}"
            fix = (
                "; it was sampled at another rate than the time column: read it with a map "
                "of its own, whose [time] is a time column of its length or sample_rate_Hz = "
                "its rate"
                if base is time
                else ""
            )
            raise RecordingError(
                f"{where} column {column!r} (channel map entry {spec.entry}) has "
                f"{values.size} samples, {n_time}{fix}"
            )
        if base is not time and base.size > 1 and np.any(np.diff(base) <= 0):
            group = (groups or {}).get(spec.name)
            what = f"column {column!r}" + (f" in {group}" if group else "")
            base, values = _repeated_stamps(base, values, what, spec, rest[0], where, notes)
        bases.append(base)
        kept.append((spec, values, *rest))
    return bases, kept


def _shown(value) -> str:
    try:
        return f"{float(value):.9g}"
    except (TypeError, ValueError):
        return repr(value)


def _repeated_stamps(base, values, column: str, spec, unit, where: str, notes: list[str]):
    """A channel's own time base [s] and values with the samples that repeat the time stamp
    *and* the value of the sample before them dropped (noted: an event group, such as CAN
    frames, logged twice with one stamp); RecordingError naming the sample, the times and the
    fix for any other step that does not increase."""
    dt = np.diff(base)
    bad = np.flatnonzero(dt <= 0)
    a, b = values[bad], values[bad + 1]
    try:
        same = (a == b) | ((a != a) & (b != b))  # NaN repeated: the same
    except TypeError:
        same = np.zeros(bad.size, dtype=bool)
    same = np.asarray(same, dtype=bool) & (dt[bad] == 0)
    wrong = bad[~same]
    if wrong.size:
        k = int(wrong[0])
        kind = "repeats" if dt[k] == 0 else "goes back from"
        raise RecordingError(
            f"{where} {column} (channel map entry {spec.entry}): its own time base (the "
            f"channel's group in the file) {kind} t = {base[k]:.9g} s at sample {k + 1} "
            f"(t[{k}] = {base[k]:.9g} s, t[{k + 1}] = {base[k + 1]:.9g} s; {wrong.size} such "
            f"step(s) of {dt.size}) with another value ({_shown(values[k])} then "
            f"{_shown(values[k + 1])}{' ' + unit if unit else ''}), so "
            "it is not strictly increasing; correct the time stamps in the logger's or "
            "converter's tool (or remove the sample there), or map the quantity from a group "
            "on an increasing raster"
        )
    keep = np.ones(base.size, dtype=bool)
    keep[bad + 1] = False
    first = int(bad[0])
    notes.append(
        f"{column} (channel map entry {spec.entry}): {bad.size} sample(s) repeating the time "
        f"stamp and the value of the sample before them dropped (first: sample {first + 1}, "
        f"t = {base[first]:.9g} s; an event such as a CAN frame logged twice)"
    )
    return base[keep], values[keep]


def align_channels(
    time: np.ndarray | None,
    loaded: list,
    own_times: list,
    *,
    own_time_exact: bool,
    info: dict[str, Any],
    notes: list[str],
    where: str,
    resample_Hz: float | None = None,
    exact_channels: Collection[str] = (),
    validate: str = "strict",
    groups: Mapping[str, str] | None = None,
) -> tuple[np.ndarray, dict[str, np.ndarray], dict[str, str]]:
    """Channels on one common time base (see the module docstring for the choice and methods).

    Parameters
    ----------
    time : ndarray or None
        The file's time column (or the time implied by the map's sample rate) [s]; None: the
        channels' own time bases decide.
    loaded : list of (ChannelSpec, values, SI unit, own time or None)
        Channels as read, in SI units.
    own_times : list of ndarray or None
        Each channel's own time base [s] (None: sample-aligned with ``time``, or, when ``time``
        is None, with the first channel that has one).
    own_time_exact : bool
        Own time bases beat index alignment with ``time`` even when the lengths agree (MDF
        masters); otherwise a channel as long as ``time`` is taken to be sampled with it.
    info, notes : dict, list
        Provenance and reader notes, extended in place (``info["resampled"]``,
        ``info["columns"]["time"]`` when the time comes from a channel).
    where : str
        Prefix of error messages (the file).
    resample_Hz : float, optional
        The common rate [Hz] (the map's ``[time] resample_Hz``).
    exact_channels : collection of str
        Channels whose own time base beats index alignment with ``time`` whatever
        ``own_time_exact`` says (a TDMS channel timed by its group's time channel).
    validate : {"strict", "lenient"}
        What a NaN/inf sample of a channel that is resampled does: its runs are checked (and,
        lenient, interpolated) on the channel's own time base before resampling
        (:func:`~rollerrig.recordings.validate.check_nan_runs`; listed in
        ``info["interpolated"]``), as resampling would spread one bad sample over every
        output sample its interpolation or filter touches.
    groups : mapping of str to str, optional
        Channel -> the file's group it is in (an MDF data group, a TDMS group), for messages.

    Returns
    -------
    time, channels, units
        The common time [s], channel values on it and their SI units.

    Raises
    ------
    RecordingError
        A channel whose length does not match its time base, a time base that is not strictly
        increasing, channels whose time ranges do not overlap.
    """
    if not loaded:
        raise RecordingError(f"{where} no channels to put on a time base")
    columns = info["columns"]
    bases, loaded = _base_times(
        time, loaded, own_times, own_time_exact, columns, where, notes, exact_channels, groups
    )
    names = [spec.name for spec, *_ in loaded]
    units = {spec.name: si for spec, _v, si, _o in loaded}
    distinct: list[np.ndarray] = []
    for b in bases:
        if not any(_same(b, d) for d in distinct):
            distinct.append(b)
    single = len(distinct) == 1 and (time is None or _same(distinct[0], time))
    rates = [_rate(b, where) for b in bases]

    # --- the common base
    if resample_Hz is not None:
        rate = float(resample_Hz)
        if single and abs(rates[0] - rate) <= 1e-9 * rate:
            notes.append(f"[time] resample_Hz = {rate:g} Hz is the file's own rate: not resampled")
            resample_Hz = None
    if resample_Hz is None and single:
        base = distinct[0]
        if time is None:
            columns["time"] = f"time base of {columns.get(names[0], names[0])!r}"
        return (
            np.asarray(base, dtype=float),
            {spec.name: values for spec, values, _si, _o in loaded},
            units,
        )
    lo = max(float(b[0]) for b in bases)
    hi = min(float(b[-1]) for b in bases)
    if lo > hi:
        spans = ", ".join(
            f"{columns.get(n, n)} {float(b[0]):.6g}..{float(b[-1]):.6g} s"
            for n, b in zip(names, bases, strict=True)
        )
        raise RecordingError(f"{where} the channels' time ranges do not overlap ({spans})")
    if resample_Hz is not None:
        rate = float(resample_Hz)
        check_grid(hi - lo, rate, where, "[time] resample_Hz")
        target = lo + np.arange(int(np.floor((hi - lo) * rate * (1 + 1e-12))) + 1) / rate
        onto = f"uniform {rate:g} Hz grid ([time] resample_Hz)"
        reason = "[time] resample_Hz"
    elif time is not None:
        target = time
        onto = columns.get("time", "time")
        reason = "the time column"
    else:
        if "torque" in names:
            k = names.index("torque")
            reason = "the torque channel's rate"
        else:
            k = int(np.argmax(rates))
            reason = "the fastest channel's rate"
        target = bases[k]
        onto = f"time base of {columns.get(names[k], names[k])!r}"
        columns["time"] = onto
    keep = (target >= lo - 1e-9 * abs(lo)) & (target <= hi + 1e-9 * abs(hi))
    if keep.sum() < 2:
        raise RecordingError(
            f"{where} the channels' time ranges overlap by less than two samples of the common "
            f"time base ({lo:.6g} s .. {hi:.6g} s)"
        )
    new_time = target[keep]
    rate_out = _rate(new_time, where)

    channels: dict[str, np.ndarray] = {}
    resampled: dict[str, dict[str, Any]] = {}
    for (spec, values, _si, _o), base in zip(loaded, bases, strict=True):
        if base is target or _same(base, target):
            channels[spec.name] = values[keep]
            continue
        if base.size == new_time.size and _same(base, new_time):
            channels[spec.name] = values
            continue
        values, runs = check_nan_runs(
            base,
            spec.name,
            values,
            validate,
            where,
            f" of its own time base ({columns.get(spec.name, spec.name)!r}, "
            f"{_rate(base, where):.6g} Hz, before resampling)",
        )
        info.setdefault("interpolated", []).extend(runs)
        channels[spec.name], resampled[spec.name] = resample_onto(values, base, new_time)

    if resampled:
        info["resampled"] = {"onto": onto, "rate_Hz": rate_out, "channels": resampled}
        parts = []
        for name, how in resampled.items():
            if how["method"] == "linear":
                rate = how["from_rate_Hz"]
                shown = "a single sample" if rate is None else f"{rate:.6g} Hz"
                parts.append(f"{name} {shown} (linear interpolation)")
            else:
                parts.append(
                    f"{name} {how['from_rate_Hz']:.6g} Hz (anti-alias FIR, pass band "
                    f"0-{how['passband_Hz']:.6g} Hz, {how['attenuation_dB']:g} dB above "
                    f"{how['stopband_Hz']:.6g} Hz, polyphase {how['up']}/{how['down']})"
                )
        notes.append(
            f"channels on different time bases put on one ({reason}): {onto}, "
            f"{rate_out:.6g} Hz; resampled: " + "; ".join(parts)
        )
    if not keep.all():
        notes.append(
            f"time trimmed to the span every channel covers, {lo:.6g} s .. {hi:.6g} s "
            f"({int((~keep).sum())} samples of the common time base dropped)"
        )
    return np.asarray(new_time, dtype=float), channels, units


def require_uniform_time(time, source: str, purpose: str) -> float:
    """Rate [Hz] of a uniform time base, or one RecordingError naming the file and the remedy.

    The one check of every analysis that needs equally spaced samples (the analysis, the
    filter study, the spectrum, decimation, the calibration): :func:`uniform_sample_rate`'s
    error with ``source`` (the file) and what to do: put the samples on one base with the
    channel map's ``[time] resample_Hz`` (the rate suggested is the median step's).

    Examples
    --------
    >>> require_uniform_time(np.arange(5) / 250.0, "run.csv", "the analysis")
    250.0
    >>> t = np.arange(6) / 250.0 + np.r_[0, 0, 4e-4, 0, 0, 0]
    >>> try:
    ...     require_uniform_time(t, "run.csv", "the analysis")
    ... except RecordingError as exc:
    ...     print(str(exc)[:64])
    run.csv: the analysis needs samples on a uniform time base: a no
    """
    time = np.asarray(time, dtype=float)
    try:
        return uniform_sample_rate(time)
    except ParameterError as exc:
        steps = np.diff(time)
        good = steps[np.isfinite(steps) & (steps > 0)]
        span = float(time[-1] - time[0]) if time.size > 1 else 0.0
        # the span's rate: stamps rounded to whole ms of a 600 Hz clock step by 1 and 2 ms,
        # whose median says 500 Hz
        rate = (
            f"{float(f'{(time.size - 1) / span:.4g}'):g}"
            if good.size and np.isfinite(span) and span > 0
            else "<the DAQ rate>"
        )
        raise RecordingError(
            f"{source}: {purpose} needs samples on a uniform time base: {exc}. Time stamps "
            f"that jitter around one rate: put them on one base with resample_Hz = {rate} in "
            "the channel map's [time] section (--channels); dropped samples: read with "
            "--lenient (short gaps are filled) or cut the recording there"
        ) from None
