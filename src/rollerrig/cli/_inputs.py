"""What the recording commands read: recordings (whole or streamed), the twin's truth."""

from __future__ import annotations

import contextlib
import logging
from pathlib import Path

from rollerrig.cli._boundary import UserError, current_context, debug_wanted

__all__ = [
    "calibration_for",
    "derived",
    "in_memory_limit",
    "load_calibration",
    "load_truth",
    "open_input",
    "read",
    "suffix_in_cli_words",
]


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
def suffix_in_cli_words():
    """A recording whose suffix names no format rollerrig reads (and whose content names
    none either): the reader's error in command-line terms, without the Python API's
    ``format=``, which has no option here. Every other error passes unchanged."""
    from rollerrig.recordings.readers import FORMATS
    from rollerrig.recordings.recording import RecordingError

    try:
        yield
    except RecordingError as exc:
        text = str(exc)
        if not text.endswith(" (or pass format=)") or "unsupported file suffix" not in text:
            raise
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
    with suffix_in_cli_words():
        return read_recording(
            path,
            channels,
            validate="lenient" if lenient else "strict",
            channels=None if needed is None else list(needed),
        )


def open_input(path: Path, channels, lenient: bool, needed, files):
    """The recording a command works on: read whole, or an open source streaming from the file.

    Short files, multi-rate files (the reader resamples them onto one base) and ``--lenient``
    reads are read whole (:func:`read`), a ``Recording``. A file on one time base with more
    than :func:`in_memory_limit` samples per channel, read strictly, is opened for chunked
    reading (:func:`rollerrig.recordings.source.open_recording`, entered into the ExitStack
    ``files``) and returned as a ``RecordingSource``: the command streams it and never holds
    it whole. With ``--lenient`` such a file is still read whole (interpolating NaN runs and
    keeping gaps needs the whole file), and a note says so and how large it is.
    """
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
