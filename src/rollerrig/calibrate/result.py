"""The result of a calibration: values, standard errors, correlations, residuals, the rig.

:class:`~rollerrig.calibrate.calibration.Calibration` holds what
:func:`rollerrig.calibrate.calibrate` found; its
:meth:`~rollerrig.calibrate.calibration.Calibration.to_json` is the content of
``calibration.json``, its ``rig`` the calibrated
:class:`~rollerrig.rig.parameters.RigParameters` (written as ``calibrated-rig.toml`` by
:func:`~rollerrig.calibrate.files.write_calibration`, which every ``--rig`` accepts), and its
``fit_dataset()`` the recorded channels beside the simulated ones before and after the fit
(``calibration-fit.nc``) for the report's figure.

This module gathers the result's names; the code is split by concern:
:mod:`~rollerrig.calibrate.calibration` (the result types),
:mod:`~rollerrig.calibrate.assembly` (the result assembled from a finished fit),
:mod:`~rollerrig.calibrate.diagnostics` (what the residuals say: structure, validity) and
:mod:`~rollerrig.calibrate.files` (the files and their names).
"""

from __future__ import annotations

# build_calibration and channel_structured keep their import path from here
# (rollerrig.calibrate.fit imports build_calibration from this module).
from rollerrig.calibrate.assembly import build_calibration as build_calibration
from rollerrig.calibrate.calibration import Calibration, ChannelFit, FittedParameter
from rollerrig.calibrate.diagnostics import channel_structured as channel_structured
from rollerrig.calibrate.files import (
    CALIBRATED_RIG_NAME,
    CALIBRATION_JSON_NAME,
    FIT_DATASET_NAME,
    write_calibration,
)

__all__ = [
    "CALIBRATED_RIG_NAME",
    "CALIBRATION_JSON_NAME",
    "FIT_DATASET_NAME",
    "Calibration",
    "ChannelFit",
    "FittedParameter",
    "write_calibration",
]
