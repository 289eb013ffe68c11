"""Calibrate the twin to a recorded test: fitted rig and friction parameters with their errors.

:func:`calibrate` replays a recording's wheel-torque request through the twin (fast backend)
and fits the free parameters, named by their dotted rig-file keys and the creep law's keys
(``polach.*``; ``fastsim.*`` with ``law="modified-fastsim"``, ``"fastsim"`` or ``"fastrip"``:
the law is a choice), so that the simulated roller-shaft torque T56 and both encoder speeds
match the recording. The result,
a :class:`Calibration`, holds each value with its standard error, the correlations, the
residuals before and after with their whiteness, warnings for what the recording cannot
identify, and the calibrated rig (:attr:`Calibration.rig`), written by
:func:`write_calibration` as ``calibration.json``, ``calibrated-rig.toml`` and
``calibration-fit.nc``.

- :mod:`~rollerrig.calibrate.problem` — free keys, the friction law, the replayed protocol;
- :mod:`~rollerrig.calibrate.measurement` — the measured channels, their noise, the torque's
  lines;
- :mod:`~rollerrig.calibrate.model` — the twin as a function of the parameters, in batches;
- :mod:`~rollerrig.calibrate.fit` — Levenberg–Marquardt, identifiability, :func:`calibrate`;
- :mod:`~rollerrig.calibrate.stats` — Newey–West covariance, whiteness checks;
- :mod:`~rollerrig.calibrate.systematic` — the sensors' stated classes in the standard errors;
- :mod:`~rollerrig.calibrate.result` — the result's names, gathered from
  :mod:`~rollerrig.calibrate.calibration` (:class:`Calibration` and its parts),
  :mod:`~rollerrig.calibrate.assembly` (the result of a finished fit),
  :mod:`~rollerrig.calibrate.diagnostics` (structure in the residuals, validity) and
  :mod:`~rollerrig.calibrate.files` (:func:`write_calibration` and the file names);
- :mod:`~rollerrig.calibrate.calibfile` — ``calibration.json`` read back and checked
  (:func:`read_calibration`);
- :mod:`~rollerrig.calibrate.binding` — a calibration bound to the rig it was made on
  (:func:`check_rig`).

Examples
--------
>>> from rollerrig.calibrate import free_parameter_catalogue
>>> "induction_motor.response_lag_clp" in free_parameter_catalogue()
True
"""

from rollerrig.calibrate.binding import check_rig
from rollerrig.calibrate.calibfile import check_calibration, read_calibration
from rollerrig.calibrate.calibration import Calibration, ChannelFit, FittedParameter
from rollerrig.calibrate.files import (
    CALIBRATED_RIG_NAME,
    CALIBRATION_JSON_NAME,
    FIT_DATASET_NAME,
    write_calibration,
)
from rollerrig.calibrate.fit import FD_STEP, HAC_WINDOW, MAX_RELATIVE_SE, calibrate
from rollerrig.calibrate.measurement import quantisation_noise
from rollerrig.calibrate.problem import (
    CALIBRATION_LAWS,
    FASTSIM_KEYS,
    POLACH_KEYS,
    CalibrationError,
    free_parameter_catalogue,
    law_keys,
)

__all__ = [
    "CALIBRATED_RIG_NAME",
    "CALIBRATION_JSON_NAME",
    "CALIBRATION_LAWS",
    "FASTSIM_KEYS",
    "FD_STEP",
    "FIT_DATASET_NAME",
    "HAC_WINDOW",
    "MAX_RELATIVE_SE",
    "POLACH_KEYS",
    "Calibration",
    "CalibrationError",
    "ChannelFit",
    "FittedParameter",
    "calibrate",
    "check_calibration",
    "check_rig",
    "free_parameter_catalogue",
    "law_keys",
    "quantisation_noise",
    "read_calibration",
    "write_calibration",
]
