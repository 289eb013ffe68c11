"""What is known about a recording beyond its samples (rollerrig.measure.facts): the reader's
and the generator's notes, the twin's truth of a synthetic recording, channel names in errors."""

import json

import numpy as np
import pytest
import xarray as xr

from rollerrig.measure.facts import (
    describe_channel,
    recording_facts,
    recording_note_lines,
    source_prefix,
    true_polach_parameters,
    truth_coa,
)
from rollerrig.recordings.recording import Recording, RecordingError

DRY = {
    "static_friction": 0.55,
    "limit_ratio": 0.4,
    "friction_decay": 0.6,
    "k_adhesion": 1.0,
    "k_slip": 0.4,
}


def _recording(metadata: dict, n: int = 10) -> Recording:
    t = np.arange(n) / 250.0
    return Recording(t, {"torque": np.zeros(n)}, {"torque": "N.m"}, metadata)


def test_facts_merge_the_stored_notes_and_list_what_a_lenient_read_did():
    rec = _recording(
        {
            "source": "/data/run.csv",
            "format": "csv",
            "notes": ["separator ';' sniffed"],
            "interpolated": [
                {
                    "channel": "torque",
                    "first_sample": 3,
                    "last_sample": 4,
                    "start_s": 0.012,
                    "end_s": 0.016,
                    "method": "linear",
                }
            ],
            "gaps": [{"sample": 7, "start_s": 0.028, "duration_s": 0.012, "missing_samples": 2}],
            "stored_metadata": {"notes": ["separator ';' sniffed", "written by rollerrig"]},
        }
    )
    facts = recording_facts(rec)
    assert facts["notes"] == ["separator ';' sniffed", "written by rollerrig"]
    assert facts["synthetic"] is False and facts["format"] == "csv"
    lines = recording_note_lines(rec)
    assert lines[:2] == facts["notes"]
    assert "channel 'torque', samples 3..4 (t = 0.012..0.016 s), linear" in lines[2]
    assert "gap kept (lenient read): 0.012 s after t = 0.028 s (sample 7" in lines[3]
    assert json.loads(json.dumps(facts)) == facts


def test_an_injected_line_is_said_to_be_no_finding():
    line = {"frequency [Hz]": 37.0, "amplitude [N.m]": 5.0, "channel": "torque"}
    rec = _recording({"synthetic": True, "injected_lines": [line]})
    assert recording_facts(rec)["synthetic"] is True
    (text,) = recording_note_lines(rec)
    assert "37.0 Hz, 5.0 N.m on torque was INJECTED by hand; it is not a finding" in text


def test_true_polach_set_from_metadata_or_from_the_twins_provenance():
    params, where = true_polach_parameters(_recording({"true_polach_parameters": {"dry": DRY}}))
    assert params == DRY and "recording metadata: the twin's 'dry' set" == where
    two = _recording({"true_polach_parameters": {"dry": DRY, "wet": DRY}})
    assert true_polach_parameters(two)[0] is None
    prov = {"friction_sets": {"dry": DRY}, "protocol": {"friction_condition": ["dry", "dry"]}}
    stored = _recording({"stored_metadata": {"twin_provenance": json.dumps(prov)}})
    params, where = true_polach_parameters(stored)
    assert params == DRY and where.startswith("the twin's provenance stored in the file")
    assert true_polach_parameters(_recording({})) == (
        None,
        "no twin truth known (not a synthetic recording)",
    )


def test_a_twin_with_another_creep_law_has_no_true_polach_set():
    """A recording the twin made with a FASTSIM-family law carries its friction set (μ0, A, B
    and Polach's k_A, k_S, which that law does not use): the analysis used to measure its
    Polach fit against them ("kA 0.55 against 1 (73 σ)"). No true Polach set: None, and why."""
    prov = {
        "friction_sets": {"dry": DRY},
        "protocol": {"friction_condition": ["dry"]},
        "drives": {"roller": "induction", "law": "modified-fastsim"},
    }
    rec = _recording({"true_polach_parameters": {"dry": DRY}, "twin_provenance": json.dumps(prov)})
    params, why = true_polach_parameters(rec)
    assert params is None and "creep law was 'modified-fastsim', not Polach's" in why
    prov["drives"]["law"] = "polach"
    rec = _recording({"true_polach_parameters": {"dry": DRY}, "twin_provenance": json.dumps(prov)})
    assert true_polach_parameters(rec)[0] == DRY


def test_truth_coa_is_checked_against_the_recording():
    rec = _recording({})
    truth = xr.Dataset({"coa": ("time", np.linspace(0, 0.3, 10))}, coords={"time": rec.time})
    t, coa = truth_coa(truth, rec)
    assert t is rec.time and coa[-1] == pytest.approx(0.3)
    with pytest.raises(RecordingError, match="not the truth of this recording"):
        truth_coa(truth.isel(time=slice(0, 5)), rec)
    with pytest.raises(RecordingError, match="no 'coa' variable"):
        truth_coa(truth.rename({"coa": "mu"}), rec)
    shifted = truth.assign_coords(time=rec.time + 1.0)
    with pytest.raises(RecordingError, match="time axis differs"):
        truth_coa(shifted, rec)


def test_channels_are_named_with_file_column_and_map_entry():
    rec = _recording({"source": "run.csv", "columns": {"torque": "Tq [Nm]"}})
    assert describe_channel(rec, "torque") == (
        "channel 'torque' (map entry [channels.torque], file column 'Tq [Nm]')"
    )
    assert source_prefix(rec) == "run.csv: " and source_prefix(_recording({})) == ""
