"""What the recording commands read: recordings (whole or streamed), the twin's truth."""

from __future__ import annotations

import contextlib
import logging
from pathlib import Path

from rollerrig.cli._boundary import UserError, current_context, debug_wanted

__all__ = [
    "TWIN_RESULTS_CHANNEL",
    "calibration_for",
    "channel_names",
    "derived",
    "in_memory_limit",
    "load_calibration",
    "load_truth",
    "open_input",
    "read",
    "require_inputs",
    "suffix_in_cli_words",
    "twin_results_error",
]

TWIN_RESULTS_CHANNEL = "measured_t56"
"""A column of the twin's results (``rollerrig simulate``, any ``--format``) that no recording
has: what the rig's torque sensor would read, before the DAQ. A file that has it and no
``torque`` is the twin's results, not a recording."""


def require_inputs(*inputs: tuple[str, Path | None]) -> None:
    """Each input file that does not exist, one error naming it as the user gave it.

    Called first in a command, before it imports its modules: those take seconds on a loaded
    machine, and a mistyped path was answered only after them. ``inputs``: (option, path)
    pairs; the option ``""`` for an argument (the error reads as the boundary's own,
    ``file not found: PATH``); a path of None (an option not given) passes.

    Examples
    --------
    >>> require_inputs(("", None), ("--truth", None))
    >>> require_inputs(("--truth", Path("no-such-truth.nc")))
    Traceback (most recent call last):
    ...
    rollerrig.cli._boundary.UserError: --truth no-such-truth.nc: file not found
    """
    for option, path in inputs:
        if path is None or path.exists():
            continue
        raise UserError(f"{option} {path}: file not found" if option else f"file not found: {path}")


def twin_results_error(path: Path, *, netcdf: bool) -> UserError:
    """The error for the twin's results given where a recording belongs, saying how to get a
    recording of the twin (``netcdf``: the file is NetCDF, which no recording reader reads).

    ``rollerrig simulate`` writes the twin's true states and what its sensors measure, on the
    solver's output grid: no DAQ sampling, motor lines, noise or encoder counts, which the
    analysis's corrections and uncertainty are built for. A recording is made from them by
    :func:`rollerrig.synthetic_recording`, as ``rollerrig demo`` does.
    """
    nc = path if netcdf else path.with_suffix(".nc")
    if netcdf:
        what = (
            "NetCDF (.nc) is what rollerrig writes (the twin's results of `rollerrig simulate`, "
            "a truth, an analysis's channels), not a recording"
        )
        then = "in Python"
    else:
        what = (
            f"the twin's results (`rollerrig simulate`: it has {TWIN_RESULTS_CHANNEL!r} and no "
            "'torque'), not a recording: the twin's states without the DAQ's sampling, lines "
            "and noise"
        )
        then = "write its results as NetCDF (simulate's default --format nc), then in Python"
    return UserError(
        f"{path}: {what}. A recording of the twin: `rollerrig demo` writes the seed test's "
        f"(seed-30kmh-dry.tdms, its truth beside it for --truth); of any simulation, {then}: "
        f"rec, truth = rollerrig.synthetic_recording(xarray.load_dataset('{nc}')); "
        f"rollerrig.write_recording(rec, '{path.stem}.tdms')"
    )


def channel_names(loaded) -> list[str]:
    """The channels of a recording read whole or of an open source."""
    return list(loaded.names) if hasattr(loaded, "iter_chunks") else list(loaded.channels)


def in_memory_limit() -> int:
    """Samples per channel up to which a recording is read whole (``rollerrig.cli``'s
    ``_SPECTRUM_IN_MEMORY``, looked up at each call so that it can be changed)."""
    import rollerrig.cli

    return rollerrig.cli._SPECTRUM_IN_MEMORY


def quiet_reader_console_logs() -> None:
    """nptdms prints its warnings through its own console handler; the reader collects them as
    notes (or errors), so the console copy is dropped, except with --debug."""
    ctx = current_context()
    if ctx is not None and debug_wanted(ctx.find_root()):
        return
    try:
        from nptdms.log import log_manager
    except ImportError:  # no TDMS support installed: nothing to quiet
        return
    log_manager.console_handler.setLevel(logging.ERROR)


@contextlib.contextmanager
def suffix_in_cli_words(path: Path | None = None):
    """A recording whose suffix names no format rollerrig reads (and whose content names
    none either): the reader's error in command-line terms, without the Python API's
    ``format=``, which has no option here; ``path`` a NetCDF file: what rollerrig writes, and
    how to get a recording of the twin (:func:`twin_results_error`). Every other error passes
    unchanged."""
    from rollerrig.recordings.readers import FORMATS
    from rollerrig.recordings.recording import RecordingError

    try:
        yield
    except RecordingError as exc:
        text = str(exc)
        if not text.endswith(" (or pass format=)") or "unsupported file suffix" not in text:
            raise
        if path is not None and Path(path).suffix.lower() == ".nc":
            raise twin_results_error(Path(path), netcdf=True) from None
        known = ", ".join(s for ss in FORMATS.values() for s in ss)
        head = text.split("; supported:", 1)[0]
        raise UserError(
            f"{head}; rollerrig reads {known}. A file in one of these formats under another "
            "name: rename it to its format's suffix"
        ) from None


def read(path: Path, channels: Path | None, lenient: bool, needed=None):
    """Read a recording; ``needed``: the channels the command needs (others only noted)."""
    from rollerrig.recordings.readers import read_recording

    quiet_reader_console_logs()
    with suffix_in_cli_words(path):
        return read_recording(
            path,
            channels,
            validate="lenient" if lenient else "strict",
            channels=None if needed is None else list(needed),
        )


def open_input(path: Path, channels, lenient: bool, needed, files, options=None):
    """The recording a command works on: read whole, or an open source streaming from the file.

    ``options``: channel -> the option that named it (``{"torqe": "--channel"}``): a needed
    channel the file does not have is then one error naming the option, with the file's
    channels and the nearest (:func:`_say_why_missing`); the twin's results given for a
    recording say so (:func:`twin_results_error`).

    Short files, multi-rate files (the reader resamples them onto one base) and ``--lenient``
    reads are read whole (:func:`read`), a ``Recording``. A file on one time base with more
    than :func:`in_memory_limit` samples per channel, read strictly, is opened for chunked
    reading (:func:`rollerrig.recordings.source.open_recording`, entered into the ExitStack
    ``files``) and returned as a ``RecordingSource``: the command streams it and never holds
    it whole. With ``--lenient`` such a file is still read whole (interpolating NaN runs and
    keeping gaps needs the whole file), and a note says so and how large it is.
    """
    from rollerrig.recordings.recording import RecordingError

    try:
        return _open_input(path, channels, lenient, needed, files)
    except RecordingError as exc:
        if needed:  # asked only now: a second reading of the file's head, on the error's path
            _say_why_missing(path, channels, needed, options or {}, str(exc))
        raise


def _say_why_missing(path: Path, channels, needed, options: dict, error: str = "") -> None:
    """Raise the error that says why a needed channel is missing, where more can be said than
    the reader's "add [channels.<name>] entries": the file is the twin's results, or the
    channel was named by an option (a typo: the nearest names). Returns otherwise (the
    reader's error stands)."""
    from rollerrig._validation import did_you_mean

    names = _offered_channels(path, channels)
    if names is None:
        return
    missing = [c for c in needed if c not in names]
    if channels is None and missing and TWIN_RESULTS_CHANNEL in names:
        raise twin_results_error(path, netcdf=False) from None
    for c in missing:
        if f"[channels.{c}]" in error:
            return  # the map's own entry for it is what is wrong: the reader's error names it
        if c in options:
            raise UserError(
                f"{path}: {options[c]} {c!r}: no such channel{did_you_mean(c, names)}; the "
                f"recording has {sorted(names)} (a column under another name: map it in a "
                "channel map, --channels)"
            )


def _offered_channels(path: Path, channels) -> list[str] | None:
    """The channels ``path`` offers under the map ``channels`` (canonical names and the
    file's other columns), or None where it cannot be read at all."""
    from rollerrig.recordings.recording import RecordingError
    from rollerrig.recordings.source import open_recording

    try:
        with open_recording(path, channels, channels=()) as source:
            return list(source.names)
    except (RecordingError, OSError):
        pass  # e.g. channels on several time bases: read whole below
    try:
        return list(read(path, channels, True, needed=()).channels)
    except (RecordingError, OSError, UserError):
        return None


def _open_input(path: Path, channels, lenient: bool, needed, files):
    from rollerrig.recordings.recording import RecordingError
    from rollerrig.recordings.source import open_recording

    quiet_reader_console_logs()
    try:
        source = files.enter_context(open_recording(path, channels, channels=needed))
    except (RecordingError, OSError):
        # e.g. channels on several time bases (the reader resamples them); a file that cannot
        # be opened gets the reader's own error below
        source = None
    if source is None or source.n_samples <= in_memory_limit():
        return read(path, channels, lenient, needed=needed)
    if not lenient:
        files.enter_context(_strict_stream_hint())
        return source
    n, names = source.n_samples, len(source.names)
    rec = read(path, channels, lenient, needed=needed)
    meta = dict(rec.metadata)
    meta["notes"] = [
        *list(meta.get("notes") or []),
        f"read whole for --lenient ({n} samples per channel x {names} channels, "
        f"{n * names * 8 / 2**20:.3g} MiB as float64): without --lenient a file this long is "
        "streamed in chunks in bounded memory",
    ]
    return type(rec)(rec.time, rec.channels, rec.units, meta)


@contextlib.contextmanager
def _strict_stream_hint():
    """A streamed file that stops at a NaN/inf sample or a gap: say what the option is called."""
    from rollerrig.recordings.recording import RecordingError

    try:
        yield
    except RecordingError as exc:
        if "chunked reading is strict" not in str(exc):
            raise
        raise RecordingError(
            f"{exc}; on the command line: --lenient (reads the file whole, in memory)"
        ) from None


def derived(loaded, rig):
    """A recording read whole with the quantities the rig derives; a source as it is."""
    from rollerrig.measure.quantities import derive_quantities

    return loaded if hasattr(loaded, "iter_chunks") else derive_quantities(loaded, rig)


def load_truth(path: Path):
    """The twin's truth (NetCDF) of a synthetic recording, or one clear error naming
    ``--truth`` (:func:`rollerrig.analysis.truth.read_truth`)."""
    from rollerrig.analysis.truth import read_truth

    return read_truth(path, source=f"--truth {path}")


def load_calibration(path: Path, rig=None) -> dict:
    """The content of a ``calibration.json`` (``rollerrig calibrate``), checked
    (:func:`rollerrig.calibrate.read_calibration`, ``rig``: the rig in use): one error naming
    ``--calibration <file>`` and each bad ``key.field``."""
    from rollerrig.calibrate.calibfile import read_calibration

    return read_calibration(path, source=f"--calibration {path}", rig=rig)


def calibration_for(
    path: Path | None, rig, rig_file: Path | None, allow_other_rig: bool
) -> tuple[dict | None, dict]:
    """A ``--calibration`` checked and bound to the rig in use, and what the outputs' provenance
    records of that binding.

    The calibration must have been made on ``rig`` (``--rig``, default the bundled rig) or on
    the rig its ``calibrated-rig.toml`` came from (:func:`rollerrig.calibrate.check_rig`);
    another rig is one error unless ``allow_other_rig``, then a printed warning. Its values must
    pass the rig's own checks on ``rig``.

    Returns
    -------
    calibration : dict or None
        The file's content (None without ``--calibration``).
    record : dict
        Keyword parameters for :func:`rollerrig.cli._outputs.command_outputs`:
        ``calibration_rig`` (``"same rig"``, ``"other rig"`` or ``"not recorded"``),
        ``calibration_rig_warning`` and ``allow_other_rig``; empty without ``--calibration``.
    """
    from rollerrig.calibrate.binding import check_rig, check_values_on_rig
    from rollerrig.cli._console import print_warning

    if path is None:
        if allow_other_rig:
            raise UserError("--allow-other-rig needs --calibration (the calibration it allows)")
        return None, {}
    data = load_calibration(path, rig)
    source = f"--calibration {path}"
    status, warning = check_rig(
        data,
        rig,
        source=source,
        rig_source="the bundled rig" if rig_file is None else f"--rig {rig_file}",
        allow_other_rig=allow_other_rig,
    )
    check_values_on_rig(data, rig, source)
    if warning is not None:
        print_warning(warning)
    return data, {
        "calibration_rig": status,
        "calibration_rig_warning": warning,
        "allow_other_rig": allow_other_rig,
    }
