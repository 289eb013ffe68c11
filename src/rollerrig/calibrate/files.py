"""The files of a calibration: their names and :func:`write_calibration` (``calibration.json``,
``calibrated-rig.toml``, which every ``--rig`` accepts, and ``calibration-fit.nc``).
"""

from __future__ import annotations

import os
from pathlib import Path

from rollerrig.calibrate.calibration import Calibration

__all__ = ["CALIBRATED_RIG_NAME", "CALIBRATION_JSON_NAME", "FIT_DATASET_NAME", "write_calibration"]


CALIBRATION_JSON_NAME = "calibration.json"
CALIBRATED_RIG_NAME = "calibrated-rig.toml"
FIT_DATASET_NAME = "calibration-fit.nc"


def write_calibration(
    calibration: Calibration,
    folder: str | os.PathLike,
    *,
    overwrite: bool = True,
    write_rig: bool = True,
) -> list[Path]:
    """Write ``calibration.json``, ``calibrated-rig.toml`` and ``calibration-fit.nc``.

    A calibration that is not valid (:attr:`Calibration.valid`: no convergence, or worse than
    its start) gets no ``calibrated-rig.toml``: its ``calibration.json`` says ``"valid":
    false`` and why. ``write_rig=False`` leaves the rig out in any case (the comparison of drive
    models when no model is adequate).

    Every file carries the provenance of the run (:mod:`rollerrig.output`); the rig file holds
    it as its first comment line, and each calibrated key's own provenance names the
    recording and the standard error.

    Parameters
    ----------
    calibration : Calibration
    folder : path
        Existing folder.
    overwrite : bool
        Replace existing files.

    Returns
    -------
    list of Path
    """
    from rollerrig.output import write_dataset, write_json, write_text
    from rollerrig.rig.rigfile import write_sections
    from rollerrig.rig.sections import SECTIONS

    folder = Path(folder)
    rig = calibration.rig
    paths = [
        write_json(folder / CALIBRATION_JSON_NAME, calibration.to_json(), overwrite=overwrite),
        write_dataset(folder / FIT_DATASET_NAME, calibration.fit_dataset(), overwrite=overwrite),
    ]
    if calibration.valid and write_rig:
        text = write_sections({s: getattr(rig, s) for s in SECTIONS}, rig.provenance)
        paths.insert(
            1, write_text(folder / CALIBRATED_RIG_NAME, text, overwrite=overwrite, comment="#")
        )
    return paths
