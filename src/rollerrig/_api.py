"""The notebook-level functions of :mod:`rollerrig` that are not a class of a subpackage.

Each is a thin layer over the subpackages: it accepts what a user has at hand (a path or an
object), validates at the boundary and returns the package's own result object.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Literal

__all__ = ["analyze", "explain_recording"]


_VALIDATE = ("strict", "lenient")


def _rig(rig):
    """The rig: RigParameters as given, a rig TOML file loaded, None for the bundled rig."""
    from rollerrig._validation import ParameterError
    from rollerrig.rig.parameters import RigParameters, default_rig, load_rig

    if rig is None:
        return default_rig()
    if isinstance(rig, RigParameters):
        return rig
    if not isinstance(rig, str | os.PathLike):
        raise ParameterError(
            f"rig must be RigParameters, the path of a rig TOML file or None (the bundled rig), "
            f"got {type(rig).__name__}"
        )
    return load_rig(Path(rig))


def _recording(recording, what: str):
    """``recording`` if it is a Recording or an open source, else one error naming it."""
    from rollerrig._validation import ParameterError

    if hasattr(recording, "channels") or hasattr(recording, "iter_chunks"):
        return recording
    raise ParameterError(
        f"recording must be a Recording or the path of a DAQ file ({what}), got "
        f"{type(recording).__name__}"
    )


def _calibration(calibration, rig, allow_other_rig: bool):
    """A calibration read or taken as given, checked as ``rollerrig analyze --calibration``
    checks it: its form and values, and that it was made on ``rig`` (another rig is an error
    unless ``allow_other_rig``, then a warning)."""
    import warnings

    from rollerrig.calibrate.binding import check_rig, check_values_on_rig
    from rollerrig.calibrate.calibfile import check_calibration, read_calibration

    if isinstance(calibration, str | os.PathLike):
        source = f"calibration {calibration}"
        data = read_calibration(Path(calibration), source=source, rig=rig)
    else:
        source = "calibration"
        data = check_calibration(calibration, source, rig)
    _, warning = check_rig(
        data, rig, source=source, rig_source="the rig given", allow_other_rig=allow_other_rig
    )
    check_values_on_rig(data, rig, source)
    if warning is not None:
        warnings.warn(warning, UserWarning, stacklevel=3)
    return data


def analyze(
    recording,
    *,
    channel_map=None,
    rig=None,
    truth=None,
    calibration=None,
    validate: Literal["strict", "lenient"] = "strict",
    run_study: bool = True,
    allow_other_rig: bool = False,
):
    """Analyse one adhesion test recorded on the rig.

    Parameters
    ----------
    recording : Recording or str or path-like
        A :class:`rollerrig.recordings.recording.Recording` (SI units), or a DAQ file (CSV, LVM,
        Excel .xlsx, Parquet, TDMS, MF4, MAT) read with
        :func:`rollerrig.recordings.readers.read_recording`.
    channel_map : ChannelMap, path or dict, optional
        Channel map of the file (which column is which quantity, in which unit); ignored for a
        :class:`Recording`.
    rig : RigParameters, path or None
        The rig the test ran on; a rig TOML file; None for the bundled default rig.
    truth : xarray.Dataset, path or None
        The twin's truth of a synthetic recording (``*-truth.nc``), for the error of the rig's and
        the corrected CoA against the true contact CoA.
    calibration : dict, path or None
        A calibration (:func:`rollerrig.calibrate.calibrate`'s ``calibration.json``, or its
        content): its values replace the rig's and their covariance enters the corrected CoA's
        uncertainty. It is checked as ``rollerrig analyze --calibration`` checks it, and must
        have been made on ``rig``.
    validate : {"strict", "lenient"}
        Strict: any NaN sample or gap is an error; lenient: short NaN runs are interpolated and
        listed in the result's notes.
    run_study : bool
        Run the smoothing-filter study as well (a few seconds more).
    allow_other_rig : bool
        Use a ``calibration`` made on another rig than ``rig`` (a warning instead of the error).

    Returns
    -------
    rollerrig.analysis.adhesion.TestAnalysis
        Phases, creep and CoA as the rig computes them, the corrected CoA, creep–CoA branches,
        Polach fits, the explained spectrum and (optionally) the filter study. Write it with
        :func:`rollerrig.report.analysis.write_analysis`.

    Examples
    --------
    >>> import rollerrig
    >>> result = rollerrig.analyze("run.tdms", channel_map="map.toml")  # doctest: +SKIP
    >>> result.phases  # doctest: +SKIP
    """
    from rollerrig._validation import ParameterError, did_you_mean
    from rollerrig.analysis.adhesion import analyze_test
    from rollerrig.analysis.truth import check_truth, read_truth
    from rollerrig.recordings.readers import read_recording

    # What the command checks, the function checks: the same loaders, the same errors.
    if validate not in _VALIDATE:
        raise ParameterError(
            f"validate must be one of {_VALIDATE}, got {validate!r}"
            + did_you_mean(str(validate), _VALIDATE)
        )
    rig = _rig(rig)
    if isinstance(truth, str | os.PathLike):
        truth = read_truth(Path(truth), source=f"truth {truth}")
    elif truth is not None:
        truth = check_truth(truth)
    if calibration is not None:
        calibration = _calibration(calibration, rig, allow_other_rig)
    if isinstance(recording, str | os.PathLike):
        recording = read_recording(Path(recording), channel_map, validate=validate)
    recording = _recording(recording, "CSV, LVM, Excel .xlsx, Parquet, TDMS, MF4, MAT")
    return analyze_test(recording, rig, truth=truth, run_study=run_study, calibration=calibration)


def explain_recording(recording, channel: str = "torque", rig=None, *, channel_map=None, **kwargs):
    """The spectrum of one channel of a recording, every peak explained.

    :func:`rollerrig.signal.workflow.explain_recording` for a recording in memory or a file:
    a file is streamed from disk (:func:`rollerrig.recordings.source.open_recording`), never held
    whole.

    Parameters
    ----------
    recording : Recording or str or path-like
        The recording, or a DAQ file.
    channel : str
        The channel analysed, e.g. ``"torque"``.
    rig : RigParameters, path or None
        The rig (radii, drives, the twin's modes); a rig TOML file; None for the bundled rig.
    channel_map : ChannelMap, path or dict, optional
        Channel map of the file; ignored for a :class:`Recording`.
    **kwargs
        Passed on (``coherence_with``, ``settings``, ``roller_speed``, ...).

    Returns
    -------
    rollerrig.signal.explained_spectrum.ExplainedSpectrum

    Examples
    --------
    >>> import rollerrig
    >>> spectrum = rollerrig.explain_recording("free-rolling-10kmh.mf4")  # doctest: +SKIP
    >>> spectrum.table()[0]  # doctest: +SKIP
    """
    from rollerrig.signal.workflow import explain_recording as explain

    rig = _rig(rig)
    if not isinstance(recording, str | os.PathLike):
        return explain(_recording(recording, "streamed from disk"), channel, rig, **kwargs)
    from rollerrig.recordings.source import open_recording

    with open_recording(Path(recording), channel_map) as source:
        return explain(source, channel, rig, **kwargs)
