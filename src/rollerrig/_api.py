"""The notebook-level functions of :mod:`rollerrig` that are not a class of a subpackage.

Each is a thin layer over the subpackages: it accepts what a user has at hand (a path or an
object), validates at the boundary and returns the package's own result object.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Literal

__all__ = ["analyze", "explain_recording"]


def _rig(rig):
    """The rig: RigParameters as given, a rig TOML file loaded, None for the bundled rig."""
    from rollerrig.rig.parameters import RigParameters, default_rig, load_rig

    if rig is None:
        return default_rig()
    return rig if isinstance(rig, RigParameters) else load_rig(Path(rig))


def analyze(
    recording,
    *,
    channel_map=None,
    rig=None,
    truth=None,
    calibration=None,
    validate: Literal["strict", "lenient"] = "strict",
    run_study: bool = True,
):
    """Analyse one adhesion test recorded on the rig.

    Parameters
    ----------
    recording : Recording or str or path-like
        A :class:`rollerrig.recordings.recording.Recording` (SI units), or a DAQ file (CSV, LVM,
        Parquet, TDMS, MF4, MAT) read with :func:`rollerrig.recordings.readers.read_recording`.
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
        uncertainty.
    validate : {"strict", "lenient"}
        Strict: any NaN sample or gap is an error; lenient: short NaN runs are interpolated and
        listed in the result's notes.
    run_study : bool
        Run the smoothing-filter study as well (a few seconds more).

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
    from rollerrig.analysis.adhesion import analyze_test
    from rollerrig.recordings.readers import read_recording

    if isinstance(recording, str | os.PathLike):
        recording = read_recording(Path(recording), channel_map, validate=validate)
    rig = _rig(rig)
    if isinstance(truth, str | os.PathLike):
        import xarray as xr

        truth = xr.load_dataset(Path(truth), engine="h5netcdf")
    if isinstance(calibration, str | os.PathLike):
        import json

        calibration = json.loads(Path(calibration).read_text(encoding="utf-8"))
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
        return explain(recording, channel, rig, **kwargs)
    from rollerrig.recordings.source import open_recording

    with open_recording(Path(recording), channel_map) as source:
        return explain(source, channel, rig, **kwargs)
