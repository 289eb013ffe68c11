"""A calibration holds for the rig it was made on (issue 24, point 6): the rig it was made on and
its calibrated rig pass, another rig is one error naming both rigs and the keys that differ
(a warning when the user insists), older and hand-written files as documented.

The files are built as ``rollerrig calibrate`` writes them (the ``calibration_doc``
fixture of conftest.py);
the end to end run through ``calibrate`` and ``analyze`` is in ``tests/cli/test_calibrate.py``.
"""

from __future__ import annotations

import json

import pytest

from rollerrig.calibrate import CalibrationError
from rollerrig.calibrate.binding import check_rig, check_values_on_rig, rig_values
from rollerrig.calibrate.calibfile import check_calibration
from rollerrig.output import rig_sha256
from rollerrig.rig.parameters import default_rig


def test_the_rig_it_was_made_on_and_its_calibrated_rig_are_the_same_rig(calibration_doc):
    rig = default_rig()
    doc = calibration_doc(rig)
    assert check_rig(doc, rig) == ("same rig", None)
    calibrated = rig.with_overrides(doc["values"])
    calibrated = calibrated.model_copy(
        update={"meta": calibrated.meta.model_copy(update={"name": "x-calibrated"})}
    )
    assert check_rig(doc, calibrated) == ("same rig", None)
    # The record: every value outside [meta], the hash without the calibrated keys.
    record = doc["rig"]
    assert record["parameters"] == rig_values(rig)
    assert record["sha256"] == rig_sha256(rig)
    assert record["calibrated_keys"] == sorted(doc["values"])


def test_another_rig_is_an_error_naming_both_rigs_and_the_keys_that_differ(calibration_doc):
    made_on = default_rig()
    doc = calibration_doc(made_on)
    doc["provenance"]["inputs"] = {"rig": {"path": "/rigs/pardubice.toml", "sha256": "ab"}}
    other = made_on.with_overrides({"stiffness.am_mount": 2.0e5, "geometry.wheel_radius_x": 0.35})
    with pytest.raises(CalibrationError) as info:
        check_rig(doc, other, source="cal.json", rig_source="--rig other.toml")
    (line,) = info.value.problems
    assert line.startswith(
        "cal.json: rig: made on another rig: they differ in stiffness.am_mount (500000 there, "
        "200000 here), geometry.wheel_radius_x (0.348 there, 0.35 here). "
    )
    assert "--allow-other-rig" in line
    here = rig_values(other)
    here_hash = (
        __import__("hashlib")
        .sha256(
            json.dumps(
                {k: v for k, v in here.items() if k not in doc["values"]},
                sort_keys=True,
                separators=(",", ":"),
            ).encode()
        )
        .hexdigest()
    )
    assert (
        f"allowed the rig 'pardubice-tram-roller-rig' (/rigs/pardubice.toml; sha256 "
        f"{doc['rig']['parameters_sha256'][:12]}); got the rig 'pardubice-tram-roller-rig' "
        f"(--rig other.toml; sha256 {here_hash[:12]})"
    ) in line
    # Insisting: a warning with the same facts, for the outputs' provenance.
    status, warning = check_rig(doc, other, source="cal.json", allow_other_rig=True)
    assert status == "other rig"
    assert warning.startswith(
        "cal.json: made on another rig, used as --allow-other-rig asks: made on rig 'pardubice"
    )
    assert "stiffness.am_mount (500000 there, 200000 here)" in warning


def test_a_change_of_a_key_that_was_free_but_not_identified_is_another_rig(calibration_doc):
    # The fit assumed damping.wheel_shaft at the rig's value: changing it is another rig.
    rig = default_rig()
    doc = calibration_doc(rig)
    with pytest.raises(CalibrationError, match=r"damping\.wheel_shaft"):
        check_rig(doc, rig.with_overrides({"damping.wheel_shaft": 99.0}))


def test_an_older_file_is_checked_by_the_hash_of_its_whole_rig(calibration_doc):
    rig = default_rig()
    doc = calibration_doc(rig)
    doc.pop("rig")
    assert check_rig(doc, rig) == ("same rig", None)
    calibrated = rig.with_overrides(doc["values"])
    meta = calibrated.meta.model_copy(
        update={
            "name": f"{rig.meta.name}-calibrated",
            "description": f"{rig.meta.description} Calibrated by rollerrig calibrate on x: y.",
        }
    )
    assert check_rig(doc, calibrated.model_copy(update={"meta": meta})) == ("same rig", None)
    with pytest.raises(CalibrationError, match="records only the SHA-256 of its whole rig"):
        check_rig(doc, rig.with_overrides({"stiffness.am_mount": 2.0e5}))


def test_a_file_that_records_no_rig_is_a_warning():
    doc = {"parameters": {"inertia.roller": {"value": 46.0, "standard_error": 0.5}}}
    status, warning = check_rig(check_calibration(doc), default_rig(), rig_source="--rig a.toml")
    assert status == "not recorded" and "cannot be checked" in warning and "a.toml" in warning


def test_values_the_rig_in_use_does_not_take_name_the_key_and_field(calibration_doc):
    rig = default_rig()
    doc = {"parameters": {"pmsm.max_current": {"value": 1.0, "standard_error": 0.1}}}
    with pytest.raises(CalibrationError) as info:
        check_values_on_rig(check_calibration(doc), rig, "cal.json")
    (line,) = info.value.problems
    assert line.startswith("cal.json: pmsm.max_current.value: must be >= rated_current [A]")
    doc = {"parameters": {"inertia.roller": {"value": 1e6, "standard_error": 1.0}}}
    with pytest.raises(CalibrationError, match=r"cal\.json: inertia\.roller\.value: not plaus"):
        check_values_on_rig(check_calibration(doc), rig, "cal.json")
    check_values_on_rig(calibration_doc(rig), rig)  # the calibration's own values pass
