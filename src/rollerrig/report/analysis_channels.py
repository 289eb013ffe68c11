"""The analysed channels as the columns of the results file (``<stem>-analysis.nc``): each with
its unit and meaning, the corrected CoA's uncertainty per sample beside them.
"""

from __future__ import annotations

import numpy as np

from rollerrig.analysis.adhesion import TestAnalysis
from rollerrig.measure.quantities import ANALYSIS_CHANNELS, DERIVED_CHANNELS
from rollerrig.recordings.recording import CANONICAL_CHANNELS

__all__ = ["analysis_columns", "channel_attributes", "uncertainty_columns"]


def channel_attributes(recording) -> dict[str, dict[str, str]]:
    """NetCDF attributes of each channel of an analysed recording: ``units`` and ``long_name``.

    Units are the recording's (SI), except for the channels the analysis adds, whose units and
    meanings are :data:`ANALYSIS_CHANNELS`; meanings of the others come from
    :data:`rollerrig.recordings.recording.CANONICAL_CHANNELS` and
    :data:`rollerrig.measure.quantities.DERIVED_CHANNELS` (else the channel's name).

    Examples
    --------
    >>> from rollerrig.recordings.recording import Recording
    >>> rec = Recording(np.arange(3.0), {"roller_acceleration": np.zeros(3)},
    ...                 {"roller_acceleration": "1"})
    >>> channel_attributes(rec)["roller_acceleration"]["units"]
    'rad/s^2'
    """
    known = {**CANONICAL_CHANNELS, **DERIVED_CHANNELS, **ANALYSIS_CHANNELS}
    attrs = {}
    for name in recording.channels:
        unit, meaning = known.get(name, (None, name))
        if name not in ANALYSIS_CHANNELS:
            unit = recording.units.get(name, unit or "1")
        attrs[name] = {"units": unit, "long_name": meaning}
    return attrs


def analysis_columns(recording) -> dict[str, tuple]:
    """The analysed channels as :func:`rollerrig.output.write_table` columns.

    ``name -> (values, unit, long_name, attrs)`` with the units and meanings of
    :func:`channel_attributes`; a channel that holds NaN says why (``nan_meaning``), as the NaN
    policy of :mod:`rollerrig.output` asks.

    Parameters
    ----------
    recording : Recording
        The analysed recording (:attr:`rollerrig.analysis.adhesion.TestAnalysis.recording`).

    Returns
    -------
    dict
    """
    columns = {}
    for name, attrs in channel_attributes(recording).items():
        values = np.asarray(recording[name])
        extra = {}
        if values.dtype.kind == "f" and not np.all(np.isfinite(values)):
            extra["nan_meaning"] = (
                "no value at these samples in the recording as read (see the recording_notes, "
                "gaps and interpolated attributes)"
            )
        columns[name] = (values, attrs["units"], attrs["long_name"], extra)
    return columns


def uncertainty_columns(result: TestAnalysis) -> dict[str, tuple]:
    """The corrected CoA's uncertainty per sample (and the online CoA) as table columns.

    ``coa_corrected_standard_uncertainty`` and ``coa_corrected_expanded_uncertainty`` (k = 2),
    and ``coa_online`` when the analysis ran the causal estimator; empty without an
    uncertainty. Same form as :func:`analysis_columns`.
    """
    budget = result.coa_uncertainty
    if budget is None:
        return {}
    unc = budget.uncertainty
    k = unc.coverage_factor
    columns = {
        "coa_corrected_standard_uncertainty": (
            unc.u,
            "1",
            "combined standard uncertainty of the corrected CoA (JCGM 100 law of propagation)",
            {},
        ),
        "coa_corrected_expanded_uncertainty": (
            unc.expanded,
            "1",
            f"expanded uncertainty of the corrected CoA, k = {k:g}",
            {"coverage_factor": k},
        ),
    }
    if budget.online_coa is not None:
        columns["coa_online"] = (
            budget.online_coa,
            "1",
            "CoA from the causal online contact-torque estimator",
            {},
        )
    for name, (coa, what) in budget.model_coa.items():
        columns[name] = (coa, "1", what, {})
    return columns
