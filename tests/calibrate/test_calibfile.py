"""``calibration.json`` read back (issue 24, point 8): every hand edit is one error in the one
format naming ``file: key.field``; whatever JSON it holds, reading it (and binding it to a rig,
as ``analyze`` does) gives a result or the calibration's error.

No fit runs here: the files are built as :meth:`Calibration.to_json` writes them (the
parameters' entries, the correlation and the ``rig`` record: the ``calibration_doc`` fixture of
conftest.py); the end to
end run through ``rollerrig calibrate`` and ``analyze`` is in ``tests/cli/test_calibrate.py``.
"""

from __future__ import annotations

import copy
import json
import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rollerrig._validation import ParameterError
from rollerrig.calibrate import CalibrationError, free_parameter_catalogue
from rollerrig.calibrate.binding import check_rig, check_values_on_rig
from rollerrig.calibrate.calibfile import MAX_CALIBRATION_BYTES, check_calibration, read_calibration
from rollerrig.rig.parameters import default_rig

PROPERTIES = settings(
    max_examples=60,
    deadline=None,
    database=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)


def _write(tmp_path, doc, name="calibration.json") -> str:
    path = tmp_path / name
    path.write_text(json.dumps(doc), encoding="utf-8")
    return path


def _problems(doc, source="calibration.json") -> tuple[str, ...]:
    with pytest.raises(CalibrationError) as info:
        check_calibration(doc, source)
    assert str(info.value) == "\n".join(info.value.problems)
    return info.value.problems


def test_a_calibration_as_written_is_accepted_unchanged(calibration_doc, tmp_path):
    doc = calibration_doc()
    assert read_calibration(_write(tmp_path, doc)) == json.loads(json.dumps(doc))


# One row per hand edit of the audit: (key, field, edited value, the whole expected line after
# the file name). The standard error is bounded by what calibrate itself calls identified
# (MAX_RELATIVE_SE = 0.5 of the value) and by the resolution of the fit (1e-12 of it).
EDITS = [
    (
        "inertia.roller",
        "standard_error",
        1e300,
        "inertia.roller.standard_error: more than 0.5 times the value: rollerrig calibrate "
        "reports such a key as not identified (value null) [kg.m^2]; allowed 0, or "
        "[4.52e-11, 22.6]; got 1e+300",
    ),
    (
        "inertia.roller",
        "standard_error",
        1e-300,
        "inertia.roller.standard_error: less than 1e-12 times the value: finer than the fit "
        "resolves (0 states an exact value) [kg.m^2]; allowed 0, or [4.52e-11, 22.6]; got 1e-300",
    ),
    (
        "inertia.roller",
        "standard_error",
        -0.01,
        "inertia.roller.standard_error: must be >= 0 [kg.m^2]; allowed 0, or [4.52e-11, 22.6]; "
        "got -0.01",
    ),
    (
        "inertia.roller",
        "standard_error",
        math.nan,
        "inertia.roller.standard_error: must be finite [kg.m^2]; allowed 0, or "
        "[4.52e-11, 22.6]; got nan",
    ),
    (
        "inertia.roller",
        "standard_error",
        "0.01",
        "inertia.roller.standard_error: must be a number or null [kg.m^2]; allowed 0, or "
        "[4.52e-11, 22.6]; got '0.01'",
    ),
    (
        "inertia.roller",
        "value",
        "45",
        "inertia.roller.value: must be a number [kg.m^2]; got '45'",
    ),
    (
        "inertia.roller",
        "value",
        -45.0,
        "inertia.roller.value: must be > 0 [kg.m^2]; allowed (0, inf); got -45",
    ),
    (
        "inertia.roller",
        "value",
        1e300,
        "inertia.roller.value: not plausible: more than 1000 times away from its starting value "
        "45 [kg.m^2]; allowed [0.045, 45000]; got 1e+300",
    ),
    (
        "inertia.roller",
        "value",
        1e-300,
        "inertia.roller.value: not plausible: more than 1000 times away from its starting value "
        "45 [kg.m^2]; allowed [0.045, 45000]; got 1e-300",
    ),
    (
        "inertia.roller",
        "value",
        math.inf,
        "inertia.roller.value: must be finite [kg.m^2]; got inf",
    ),
    (
        "inertia.roller",
        "unit",
        "g.m^2",
        "inertia.roller.unit: must be the key's SI unit (calibration.json holds SI values); "
        "allowed 'kg.m^2'; got 'g.m^2'",
    ),
    (
        "stiffness.roller_shaft",
        "value",
        True,
        "stiffness.roller_shaft.value: must be a number [N.m/rad]; got true",
    ),
    (
        "damping.wheel_shaft",
        "standard_error",
        0.3,
        "damping.wheel_shaft.standard_error: must be null when the value is null (not "
        "identified) [N.m.s/rad]; got 0.3",
    ),
]


@pytest.mark.parametrize(("key", "field", "edited", "line"), EDITS)
def test_each_hand_edit_is_one_error_naming_the_key_and_field(
    calibration_doc, tmp_path, key, field, edited, line
):
    doc = calibration_doc()
    doc["parameters"][key][field] = edited
    doc.pop("values")  # the copy of the values has its own check, below
    path = _write(tmp_path, doc)
    with pytest.raises(CalibrationError) as info:
        read_calibration(path)
    assert info.value.problems == (f"{path}: {line}",)


def test_the_identification_bound_holds_for_the_statistical_part_where_the_file_splits_it(
    calibration_doc,
):
    # calibrate identifies a key by its statistical error; its total adds the sensor classes'
    # systematic part: the tour's bearing friction 0.0091 with 5.7e-6 statistical and 0.0071
    # in all had been refused by analyze --calibration as "not identified".
    doc = calibration_doc()
    doc.pop("values")
    entry = doc["parameters"]["bearing.friction_coefficient"] = {
        "value": 0.0091,
        "standard_error": 0.0071,
        "standard_error_statistical": 5.7e-6,
    }
    assert check_calibration(doc)["parameters"]["bearing.friction_coefficient"] == entry
    entry["standard_error_statistical"] = 0.006
    assert _problems(doc) == (
        "calibration.json: bearing.friction_coefficient.standard_error_statistical: more than "
        "0.5 times the value: rollerrig calibrate reports such a key as not identified (value "
        "null); allowed 0, or [9.1e-15, 0.00455]; got 0.006",
    )
    entry["standard_error_statistical"] = 1e-4
    entry["standard_error"] = 5e-5
    assert _problems(doc) == (
        "calibration.json: bearing.friction_coefficient.standard_error: must be a finite number, "
        "at least its statistical part; allowed >= standard_error_statistical (0.0001), finite; "
        "got 5e-05",
    )


def test_a_value_outside_the_rig_keys_range_is_the_rig_files_own_error(calibration_doc):
    # Exactly as in a rig file: bearing.friction_coefficient in [0, 1), poisson in (0, 0.5),
    # and the [roller_drive_vf] ranges.
    doc = calibration_doc()
    doc["parameters"]["bearing.friction_coefficient"] = {"value": 3.0, "standard_error": 0.1}
    doc["parameters"]["roller_drive_vf.current_limit"] = {"value": 1e-9, "standard_error": None}
    assert _problems(doc) == (
        "calibration.json: bearing.friction_coefficient.value: must be < 1; allowed [0, 1); got 3",
        "calibration.json: roller_drive_vf.current_limit.value: must be >= 1 "
        "[x induction_motor.rated_current]; allowed [1, 4]; got 1e-09",
    )


def test_a_key_calibrate_does_not_fit_is_named_with_the_closest_one(calibration_doc):
    doc = calibration_doc()
    doc["parameters"]["inertia.rolller"] = doc["parameters"].pop("inertia.roller")
    doc["values"]["inertia.rolller"] = doc["values"].pop("inertia.roller")
    problems = _problems(doc)
    assert problems[0] == (
        "calibration.json: inertia.rolller: not a key rollerrig calibrate fits (did you mean "
        "'inertia.roller'?); allowed the keys `rollerrig calibrate --list-keys` lists; got "
        "'inertia.rolller'"
    )
    assert "sensors.daq_rate" not in free_parameter_catalogue()
    doc = calibration_doc()
    doc["parameters"]["sensors.daq_rate"] = {"value": 1000.0, "standard_error": 1.0}
    assert "calibration.json: sensors.daq_rate: not a key" in _problems(doc)[0]


def test_the_second_copy_of_the_values_must_agree(calibration_doc):
    doc = calibration_doc()
    doc["values"]["inertia.roller"] = 50.0
    assert _problems(doc) == (
        "calibration.json: values.inertia.roller: differs from parameters.inertia.roller.value "
        "(45.2); the file states each value twice: edit both; got 50",
    )


@pytest.mark.parametrize(
    ("matrix", "message"),
    [
        ([[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]], "outside [-1, 1]"),
        ([[1.0, 0.9, 0.9], [0.9, 1.0, -0.9], [0.9, -0.9, 1.0]], "not positive semi-definite"),
        ([[1.0, 0.5, 0.0], [0.1, 1.0, 0.0], [0.0, 0.0, 1.0]], "must be symmetric"),
        ([[1.0, 0.1], [0.1, 1.0]], "must be a 3 x 3 array"),
        ([[1.0, "x", 0.0], [0.1, 1.0, 0.0], [0.0, 0.0, 1.0]], "must be a 3 x 3 array"),
        ([[0.5, 0.1, 0.0], [0.1, 1.0, 0.0], [0.0, 0.0, 1.0]], "1 on its diagonal"),
    ],
)
def test_a_correlation_that_no_variables_can_have_is_refused(calibration_doc, matrix, message):
    # rho = 0.9, 0.9, -0.9 among three keys: eigenvalue 1 - 0.9 - 0.9 - ... < 0.
    doc = calibration_doc()
    doc["correlation"]["matrix"] = matrix
    (line,) = _problems(doc)
    assert line.startswith("calibration.json: correlation.matrix: ") and message in line


def test_a_null_correlation_entry_is_unknown_not_an_error(calibration_doc):
    doc = calibration_doc()
    doc["correlation"]["matrix"][0][1] = doc["correlation"]["matrix"][1][0] = None
    assert check_calibration(doc) is doc


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (b"", "not a JSON file"),
        (b"\xff\xfe{", "not UTF-8"),
        (b"[" * 100_000, "nested too deep"),
        (b"[1, 2]", "must be a JSON object"),
        (b'{"free": []}', "parameters: missing key"),
        (b'{"parameters": 3}', "parameters: must be an object"),
        (b'{"parameters": {"inertia.roller": 45}}', "inertia.roller: must be an object"),
        (b'{"parameters": {"inertia.roller": {}}}', "inertia.roller.value: missing key"),
        (b'{"parameters": {}, "warnings": [1]}', "warnings: must be an array of strings"),
        (b'{"parameters": {}, "rig": {"parameters": 1}}', "rig.parameters: must be an object"),
        (b'{"parameters": {}, "x": 1' + b"0" * 5000 + b"}", "not a JSON file"),
    ],
)
def test_a_file_that_is_not_a_calibration_is_one_clear_error(tmp_path, content, message):
    path = tmp_path / "calibration.json"
    path.write_bytes(content)
    with pytest.raises(CalibrationError) as info:
        read_calibration(path)
    assert str(info.value).startswith(f"{path}: ") and message in str(info.value)
    assert isinstance(info.value, ParameterError)  # the CLI's boundary: one error line, exit 2


def test_a_huge_file_is_refused_before_it_is_read(tmp_path):
    path = tmp_path / "calibration.json"
    with path.open("wb") as f:
        f.truncate(MAX_CALIBRATION_BYTES + 1)
    with pytest.raises(CalibrationError, match=r"too large for a calibration\.json"):
        read_calibration(path)
    with pytest.raises(FileNotFoundError):
        read_calibration(tmp_path / "none.json")


# --------------------------------------------------------------------------------------------
# Property: any JSON gives a result or the calibration's error, never another exception
# --------------------------------------------------------------------------------------------

JSON = st.recursive(
    st.none()
    | st.booleans()
    | st.integers(min_value=-(10**30), max_value=10**30)
    | st.floats(allow_nan=True, allow_infinity=True)
    | st.text(max_size=12),
    lambda inner: (
        st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=12), inner, max_size=4)
    ),
    max_leaves=12,
)
PLACES = [
    ("parameters",),
    ("parameters", "inertia.roller"),
    ("parameters", "inertia.roller", "value"),
    ("parameters", "inertia.roller", "standard_error"),
    ("parameters", "inertia.roller", "initial"),
    ("parameters", "inertia.roller", "unit"),
    ("parameters", "inertia.roller", "identified"),
    ("parameters", "damping.wheel_shaft", "value"),
    ("parameters", "roller_drive_vf.filter_time"),
    ("values",),
    ("values", "inertia.roller"),
    ("correlation",),
    ("correlation", "keys"),
    ("correlation", "matrix"),
    ("keys",),
    ("warnings",),
    ("recording",),
    ("rig",),
    ("rig", "parameters"),
    ("rig", "calibrated_keys"),
    ("provenance",),
    ("provenance", "rig"),
    ("provenance", "inputs"),
]


def _outcome(doc, rig):
    """check_calibration, then the rig binding and the values on the rig, as analyze runs them:
    a result or CalibrationError."""
    try:
        data = check_calibration(doc)
        check_rig(data, rig, allow_other_rig=True)
        check_values_on_rig(data, rig)
    except CalibrationError:
        return "error"
    return "ok"


@PROPERTIES
@given(doc=JSON)
def test_any_json_is_a_result_or_a_calibration_error(doc):
    _outcome(doc, default_rig())


@PROPERTIES
@given(place=st.sampled_from(PLACES), value=JSON)
def test_any_json_anywhere_in_a_calibration_is_a_result_or_a_calibration_error(
    calibration_doc, place, value
):
    doc = copy.deepcopy(calibration_doc())
    node = doc
    for part in place[:-1]:
        node = node[part]
    node[place[-1]] = value
    _outcome(doc, default_rig())


@PROPERTIES
@given(text=st.binary(max_size=64) | JSON.map(lambda v: json.dumps(v).encode()))
def test_any_bytes_are_a_result_or_a_calibration_error(tmp_path_factory, text):
    path = tmp_path_factory.mktemp("cal") / "calibration.json"
    path.write_bytes(text)
    try:
        read_calibration(path)
    except CalibrationError:
        pass


def test_a_calibration_of_another_creep_law_is_read_with_its_own_keys(calibration_doc):
    """``law`` names the creep law fitted: its keys (``fastsim.*`` for the modified FASTSIM)
    are checked against that law's ranges; another law's keys, or an unknown law, are errors."""
    entry = {"value": 0.6, "standard_error": 0.002, "unit": "1", "initial": 0.54}
    doc = calibration_doc()
    doc["law"] = "modified-fastsim"
    doc["parameters"]["fastsim.k0"] = dict(entry)
    assert check_calibration(doc)["parameters"]["fastsim.k0"]["value"] == 0.6

    doc["parameters"]["fastsim.k0"]["value"] = 1.2  # 0 < k0 <= 1
    assert _problems(doc) == (
        "calibration.json: fastsim.k0.value: must lie in (0, 1]; allowed (0, 1]; got 1.2",
    )
    doc = calibration_doc()  # no law: Polach's, which has no k0
    doc["parameters"]["fastsim.k0"] = dict(entry)
    assert _problems(doc) == (
        "calibration.json: fastsim.k0: not a parameter of the calibration's creep law 'polach' "
        "(its keys: polach.static_friction, polach.limit_ratio, polach.friction_decay, "
        "polach.k_adhesion, polach.k_slip); got 'fastsim.k0'",
    )
    doc["law"] = "modified-fastsm"
    assert (
        "law: not a creep law rollerrig calibrate fits (did you mean 'modified-fastsim'?)"
        in (_problems(doc)[0])
    )
