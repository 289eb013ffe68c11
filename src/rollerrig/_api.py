"""The notebook-level functions of :mod:`rollerrig` that are not a class of a subpackage.

Each is a thin layer over the subpackages: it accepts what a user has at hand (a path or an
object), validates at the boundary and returns the package's own result object.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Literal

__all__ = ["analyze"]


def analyze(
    recording,
    *,
    channels=None,
    rig=None,
    truth=None,
    validate: Literal["strict", "lenient"] = "strict",
    run_study: bool = True,
):
    """Analyse one adhesion test recorded on the rig.

    Parameters
    ----------
    recording : Recording or str or path-like
        A :class:`rollerrig.measure.recording.Recording` (SI units), or a DAQ file (CSV, LVM,
        Parquet, TDMS, MF4, MAT) read with :func:`rollerrig.measure.readers.read_recording`.
    channels : ChannelMap, path or dict, optional
        Channel map of the file (which column is which quantity, in which unit); ignored for a
        :class:`Recording`.
    rig : RigParameters, path or None
        The rig the test ran on; a rig TOML file; None for the bundled default rig.
    truth : xarray.Dataset, path or None
        The twin's truth of a synthetic recording (``*-truth.nc``), for the error of the rig's and
        the corrected CoA against the true contact CoA.
    validate : {"strict", "lenient"}
        Strict: any NaN sample or gap is an error; lenient: short NaN runs are interpolated and
        listed in the result's notes.
    run_study : bool
        Run the smoothing-filter study as well (a few seconds more).

    Returns
    -------
    rollerrig.measure.analysis.TestAnalysis
        Phases, creep and CoA as the rig computes them, the corrected CoA, creep–CoA branches,
        Polach fits, the explained spectrum and (optionally) the filter study. Write it with
        :func:`rollerrig.report.analysis.write_analysis`.

    Examples
    --------
    >>> import rollerrig
    >>> result = rollerrig.analyze("run.tdms", channels="map.toml")  # doctest: +SKIP
    >>> result.phases  # doctest: +SKIP
    """
    from rollerrig.measure.analysis import analyze_test
    from rollerrig.measure.readers import read_recording
    from rollerrig.rig.parameters import RigParameters, default_rig, load_rig

    if isinstance(recording, str | os.PathLike):
        recording = read_recording(Path(recording), channels, validate=validate)
    if rig is None:
        rig = default_rig()
    elif not isinstance(rig, RigParameters):
        rig = load_rig(Path(rig))
    if isinstance(truth, str | os.PathLike):
        import xarray as xr

        truth = xr.load_dataset(Path(truth), engine="h5netcdf")
    return analyze_test(recording, rig, truth=truth, run_study=run_study)
