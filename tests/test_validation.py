"""The one error format of user files, and the range checks of the public functions.

``<file>: <dotted key>: <what is wrong> [<unit>]; allowed <range or choices>; got <value>``
"""

from __future__ import annotations

import math
import re
from typing import Annotated, Literal

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pydantic import AfterValidator, BaseModel, ConfigDict, Field, ValidationError, model_validator

from rollerrig._validation import (
    FieldProblem,
    ParameterError,
    Problem,
    Verbatim,
    field_error,
    from_pydantic,
    interval,
    pydantic_problems,
    require_broadcastable,
    require_finite,
    require_in_range,
    require_increasing,
    require_instants_within,
    require_names,
    require_nonnegative,
    require_number,
    require_positive,
    require_whole,
    show_value,
)

# The format as a pattern: file, dotted key, what is wrong, then the optional parts in order.
FORMAT = re.compile(
    r"^(?P<file>[^:]+): (?P<key>[\w.<>\[\]-]+): (?P<what>.+?)(?: \[(?P<unit>[^\]]+)\])?"
    r"(?:; allowed (?P<allowed>.+?))?(?:; got (?P<got>.+))?$"
)


def test_problem_has_every_part_in_order():
    text = Problem(
        "stiffness.roller_shaft", "must be > 0", unit="N.m/rad", allowed="(0, inf)", got=-3
    ).format("rig.toml")
    assert (
        text == "rig.toml: stiffness.roller_shaft: must be > 0 [N.m/rad]; allowed (0, inf); got -3"
    )
    m = FORMAT.match(text)
    assert m and m["key"] == "stiffness.roller_shaft" and m["unit"] == "N.m/rad"
    assert (m["allowed"], m["got"]) == ("(0, inf)", "-3")


@pytest.mark.parametrize(
    ("problem", "text"),
    [
        (Problem("a.b", "missing key"), "f: a.b: missing key"),
        (Problem("a", "must be > 0", unit="1", got=0.0), "f: a: must be > 0; got 0"),  # no [1]
        (Problem("", "maps no channels"), "f: maps no channels"),
        (Problem("x", "bad", allowed=["N", "kN"]), "f: x: bad; allowed 'N', 'kN'"),
        (Problem("x", "bad", allowed={",": "comma"}), "f: x: bad; allowed ',' (comma)"),
        (Problem("x", "bad", got=None), "f: x: bad; got None"),
        (Problem("x", "bad", got=Verbatim("3 kN")), "f: x: bad; got 3 kN"),
    ],
)
def test_problem_leaves_out_what_does_not_apply(problem, text):
    assert problem.format("f") == text


@pytest.mark.parametrize(
    ("value", "shown"),
    [
        (True, "true"),
        (np.bool_(False), "false"),
        (-3, "-3"),
        (np.int64(7), "7"),
        (43500.0, "43500"),
        (0.6, "0.6"),
        (1e-5, "1e-05"),
        (1e20, "1e+20"),
        (math.nan, "nan"),
        (-math.inf, "-inf"),
        ("bar", "'bar'"),
        ([1, 2], "[1, 2]"),
    ],
)
def test_values_are_shown_as_a_file_writes_them(value, shown):
    assert show_value(value) == shown


def test_interval_notation():
    assert interval(0, math.inf) == "(0, inf)"
    assert interval(0, 0.5) == "(0, 0.5)"
    assert interval(1, 4, low_inclusive=True, high_inclusive=True) == "[1, 4]"
    assert interval(-math.inf, 0, high_inclusive=True) == "(-inf, 0]"


def test_field_error_builds_the_requested_class():
    class MapError(ParameterError):
        pass

    err = field_error("map.toml", "time.unit", "not a time unit", allowed=["s", "ms"], got="min",
                      error=MapError)  # fmt: skip
    assert isinstance(err, MapError) and isinstance(err, ValueError)
    assert str(err) == "map.toml: time.unit: not a time unit; allowed 's', 'ms'; got 'min'"
    assert err.problems == (str(err),)
    assert FORMAT.match(str(err))


class _Inner(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False)

    poisson: float = Field(gt=0, lt=0.5)
    speed: float = Field(1.0, gt=0, json_schema_extra={"unit": "rad/s"})
    count: int = Field(1, ge=1)
    kind: Literal["delta", "star"] = "delta"
    name: str = Field("x", min_length=1, description="a short name")
    flag: bool = False


def _even(value: int) -> int:
    if value % 2:
        raise FieldProblem("", "must be even", allowed="0, 2, 4, ...", got=value)
    return value


class _Outer(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True)

    inner: _Inner | None = None
    table: dict[str, _Inner] = {}
    pairs: Annotated[int, AfterValidator(_even)] = 0
    low: float = 0.0
    high: float = 1.0

    @model_validator(mode="after")
    def _ordered(self):
        if self.high <= self.low:
            raise FieldProblem(
                "high", "must be above low", allowed=f"> {self.low:g}", got=self.high
            )
        return self


def _lines(data, **kwargs) -> list[str]:
    with pytest.raises(ValidationError) as info:
        _Outer.model_validate(data)
    err = from_pydantic(info.value, "t.toml", model=_Outer, **kwargs)
    assert isinstance(err, ParameterError)
    assert str(err) == "\n".join(err.problems)
    for line in err.problems:
        assert FORMAT.match(line), line
    return list(err.problems)


@pytest.mark.parametrize(
    ("data", "line"),
    [
        ({"inner": {"poisson": 0.6}}, "inner.poisson: must be < 0.5; allowed (0, 0.5); got 0.6"),
        ({"inner": {"poisson": -1}}, "inner.poisson: must be > 0; allowed (0, 0.5); got -1"),
        (
            {"inner": {"poisson": math.nan}},
            "inner.poisson: must be finite; allowed (0, 0.5); got nan",
        ),
        ({"inner": {"poisson": "0.3"}}, "inner.poisson: must be a number; got '0.3'"),
        ({"inner": {}}, "inner.poisson: missing key"),
        (
            {"inner": {"poisson": 0.3, "speed": -2.0}},
            "inner.speed: must be > 0 [rad/s]; allowed (0, inf); got -2",
        ),
        (
            {"inner": {"poisson": 0.3, "count": 0}},
            "inner.count: must be >= 1; allowed [1, inf); got 0",
        ),
        ({"inner": {"poisson": 0.3, "count": 2.5}}, "inner.count: must be an integer; got 2.5"),
        (
            {"inner": {"poisson": 0.3, "kind": "zigzag"}},
            "inner.kind: not one of the allowed values; allowed 'delta' or 'star'; got 'zigzag'",
        ),
        ({"inner": {"poisson": 0.3, "name": ""}}, "inner.name: must not be empty; got ''"),
        (
            {"inner": {"poisson": 0.3, "flag": "yes"}},
            "inner.flag: must be true or false; got 'yes'",
        ),
        (
            {"inner": {"poisson": 0.3, "poison": 1}},
            "inner.poison: unknown key (did you mean 'poisson'?); allowed 'poisson', "
            "'speed', 'count', 'kind', 'name', 'flag'",
        ),
        ({"inner": 3}, "inner: must be a table; got 3"),
        (
            {"table": {"a": {"poisson": 0.7}}},
            "table.a.poisson: must be < 0.5; allowed (0, 0.5); got 0.7",
        ),
        ({"pairs": 3}, "pairs: must be even; allowed 0, 2, 4, ...; got 3"),
        ({"low": 2.0}, "high: must be above low; allowed > 2; got 1"),
    ],
)
def test_from_pydantic_names_key_unit_range_and_value(data, line):
    assert _lines(data) == [f"t.toml: {line}"]


def test_from_pydantic_reports_every_problem_and_takes_units_and_prefix():
    data = {"inner": {"poisson": 0.6, "count": 0}}
    lines = _lines(data, prefix="rig", units={"rig.inner.count": "1/s"})
    assert lines == [
        "t.toml: rig.inner.poisson: must be < 0.5; allowed (0, 0.5); got 0.6",
        "t.toml: rig.inner.count: must be >= 1 [1/s]; allowed [1, inf); got 0",
    ]


def test_missing_key_with_a_description_says_what_it_is():
    with pytest.raises(ValidationError) as info:
        _Inner.model_validate({"poisson": 0.3, "name": None})
    problems = pydantic_problems(info.value, model=_Inner)
    assert problems[0].message == "must be a string"
    with pytest.raises(ValidationError) as info:

        class _Named(BaseModel):
            name: str = Field(description="the channel's name")

        _Named.model_validate({})
    assert str(from_pydantic(info.value, "f", model=_Named)) == (
        "f: name: missing key (the channel's name)"
    )


def test_without_the_model_the_bound_in_the_error_is_given():
    with pytest.raises(ValidationError) as info:
        _Inner.model_validate({"poisson": 0.6})
    assert str(from_pydantic(info.value, "f")) == (
        "f: poisson: must be < 0.5; allowed (-inf, 0.5); got 0.6"
    )


def test_user_files_share_the_format(tmp_path):
    # The rig file and the channel map report through the same format.
    from rollerrig.recordings.channels import ChannelMap
    from rollerrig.recordings.recording import RecordingError
    from rollerrig.rig.parameters import RigFileError, default_rig

    with pytest.raises(RigFileError) as rig:
        default_rig().with_overrides({"stiffness.roller_shaft": -1.0})
    with pytest.raises(RecordingError) as cmap:
        ChannelMap.from_dict({"channels": {"torque": {"column": "T", "unit": "psi"}}})
    for err in (rig.value, cmap.value):
        assert all(FORMAT.match(line) for line in err.problems), err.problems
    assert FORMAT.match(rig.value.problems[0])["unit"] == "N.m/rad"
    assert FORMAT.match(cmap.value.problems[0])["key"] == "channels.torque.unit"


# ---- range checks of the public functions --------------------------------------------------


def test_require_helpers_name_parameter_unit_and_range():
    with pytest.raises(ParameterError, match=r"^load must be > 0 \[N\], got -1$"):
        require_positive("load", -1.0, "N")
    with pytest.raises(ParameterError, match=r"must lie in \(0, 0.5\)"):
        require_in_range("poisson", 0.5, 0.0, 0.5)
    assert require_in_range("x", 1.0, 0.0, 1.0, high_inclusive=True) == 1.0


@pytest.mark.parametrize(
    "value, message",
    [
        (float("nan"), "must be finite, got nan"),
        (-0.0, "must be > 0, got -0"),
        (10**400, "must be finite, got an integer beyond 1.8e308"),  # was an OverflowError
        (np.array([1.0, -2.0]), r"must be > 0, got \[ 1. -2.\]"),
        (np.float32(0.0), "must be > 0, got 0"),
    ],
)
def test_scalars_and_arrays_take_the_same_checks(value, message):
    with pytest.raises(ParameterError, match=message):
        require_positive("k", value)
    assert require_positive("k", 2) == 2.0 and require_positive("k", [1, 2]).shape == (2,)
    assert require_nonnegative("k", 0.0) == 0.0 and require_nonnegative("k", np.zeros(3)).size == 3


def test_did_you_mean_is_the_one_hint_of_the_package():
    from rollerrig._validation import close_matches, did_you_mean

    assert did_you_mean("drivs", ["arm", "drives", "lag"]) == " (did you mean 'drives'?)"
    assert did_you_mean("drivs", ["arm", "drives"], style=";") == "; did you mean 'drives'?"
    assert did_you_mean("zzzz", ["arm", "drives"]) == ""
    # case and - versus _ first, then the closest spellings
    assert close_matches("Induction-DQ", ["induction", "induction_dq"])[0] == "induction_dq"
    three = did_you_mean("inertia.roler", ["inertia.roller", "inertia.rotor", "x.y"], n=3)
    assert three == " (did you mean 'inertia.roller' or 'inertia.rotor'?)"


@given(
    st.lists(
        st.one_of(
            st.floats(allow_nan=True, allow_infinity=True),
            st.floats(min_value=-1.0, max_value=3.0),
        ),
        max_size=12,
    )
)
@settings(max_examples=300, deadline=None)
def test_instants_are_returned_as_given_or_refused_with_a_parameter_error(values):
    """Any list of floats: back unchanged where finite, not decreasing and within [0, 2] s,
    else a ParameterError (never another exception, never a reordered array)."""
    arr = np.array(values, dtype=float)
    valid = (
        bool(np.all(np.isfinite(arr)))
        and bool(np.all(arr >= 0.0))
        and bool(np.all(arr <= 2.0))
        and bool(np.all(np.diff(arr) >= 0.0))
    )
    if valid:
        np.testing.assert_array_equal(require_instants_within("t_out", values, 0.0, 2.0), arr)
    else:
        with pytest.raises(ParameterError, match=r"^t_out must "):
            require_instants_within("t_out", values, 0.0, 2.0)


@pytest.mark.parametrize(
    ("values", "message"),
    [
        ([0.0, 2.5], r"in \[0, 2\] \[s\], the experiment's span; got t_out\[1\] = 2.5, after"),
        ([-0.1, 1.0], r"got t_out\[0\] = -0.1, before its start"),
        ([0.0, 1.0, 0.5], r"back in time \[s\]; got t_out\[2\] = 0.5 after t_out\[1\] = 1$"),
        ([0.0, 2.0 + 1e-13], r"in \[0.0, 2.0\] \[s\].*got t_out\[1\] = 2.0000000000001, after"),
        ([[0.0, 1.0]], r"1-D array of instants \[s\], got shape \(1, 2\)"),
    ],
)
def test_instants_outside_the_experiment_or_going_back_are_named(values, message):
    with pytest.raises(ParameterError, match=message):
        require_instants_within("t_out", values, 0.0, 2.0)


def test_broadcastable_arrays_are_returned_broadcast():
    a, b, c = require_broadcastable(x=[1.0, 2.0], y=3, z=np.ones((1, 2)))
    assert a.shape == b.shape == c.shape == (1, 2)
    assert b.tolist() == [[3.0, 3.0]]


@pytest.mark.parametrize(
    ("arrays", "message"),
    [
        ({"creep": [1.0, 2.0, 3.0], "load": [1.0, 2.0]},
         "creep (shape (3,)) and load (shape (2,)) must have the same shape, or one of them"),
        ({"a": [1.0, 2.0], "b": 1.0, "c": [1.0, 2.0, 3.0]},
         "a (shape (2,)) and c (shape (3,)) must have the same shape, or one of them"),
        ({"a": [1.0, 2.0], "b": [1.0] * 3, "c": [1.0] * 4},
         "a (shape (2,)), b (shape (3,)) and c (shape (4,)) must have the same shape, or some"),
        ({"a": "x", "b": 1.0}, "a must be a number"),
    ],
)  # fmt: skip
def test_unbroadcastable_arrays_are_named_with_their_shapes(arrays, message):
    with pytest.raises(ParameterError, match=re.escape(message)):
        require_broadcastable(**arrays)


@pytest.mark.parametrize(
    ("values", "strict", "message"),
    [
        ([0.0, 1.0, 1.0], True, "time must be strictly increasing [s]; got time[2] = 1 after "
         "time[1] = 1"),
        ([0.0, 1.0, 0.5], False, "time must be non-decreasing [s]; got time[2] = 0.5 after"),
        ([0.0, np.nan], True, "time must be finite [s]"),
        ([[0.0, 1.0]], True, "time must be a 1-D array [s], got shape (1, 2)"),
    ],
)  # fmt: skip
def test_increasing_names_the_first_sample_that_does_not(values, strict, message):
    with pytest.raises(ParameterError, match=re.escape(message)):
        require_increasing("time", values, strict=strict)


def test_increasing_accepts_ties_only_when_not_strict():
    assert require_increasing("t", [0.0, 1.0, 1.0], strict=False).tolist() == [0.0, 1.0, 1.0]
    assert require_increasing("t", []).size == 0


@pytest.mark.parametrize("value", [3, 3.0, np.int64(3), np.float64(3.0), np.array(3.0)])
def test_whole_numbers_come_back_as_int(value):
    out = require_whole("n", value, minimum=1)
    assert out == 3 and type(out) is int


@pytest.mark.parametrize(
    "value", [2.5, math.nan, math.inf, True, "3", None, [3], np.array([3]), 0, 101]
)
def test_not_a_whole_number_in_range_is_refused_with_what_it_got(value):
    with pytest.raises(
        ParameterError, match=re.escape("n must be a whole number in [1, 100] [-], got")
    ):
        require_whole("n", value, minimum=1, maximum=100)


@pytest.mark.parametrize(
    "check",
    [
        lambda v: require_finite("x", v, "m", single=True),
        lambda v: require_positive("x", v, "m", single=True),
        lambda v: require_nonnegative("x", v, "m", single=True),
        lambda v: require_in_range("x", v, 0.0, 10.0, "m", single=True),
    ],
)
def test_a_single_number_comes_back_as_float_and_an_array_is_named(check):
    for value in (2.0, np.float64(2.0), np.array(2.0), np.array([2.0]), 2):
        out = check(value)
        assert out == 2.0 and type(out) is float
    # float() of it had raised "only 0-dimensional arrays can be converted to Python scalars"
    with pytest.raises(
        ParameterError, match=re.escape("x must be a single number [m], got an array of shape (2,)")
    ):
        check([2.0, 3.0])
    with pytest.raises(ParameterError, match=re.escape("got an array of shape (0,)")):
        check([])


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ("torque", "names must be a list of names, got the single name 'torque'"),
        (b"torque", "got the single name b'torque'"),
        (5, "names must be a list of names, got a value of type int"),
        (["torque", 3], "names[1] must be a str, got 3 (int)"),
    ],
)
def test_require_names_refuses_one_name_and_what_is_not_names(value, message):
    # One str had been taken letter by letter ("torque" as six names) in three places.
    with pytest.raises(ParameterError) as caught:
        require_names("names", value)
    assert message in str(caught.value)


def test_require_names_gives_a_list_of_any_collection_of_str():
    assert require_names("names", ("a", "b")) == ["a", "b"]
    assert require_names("names", iter(["a"])) == ["a"]
    assert require_names("names", []) == []


@pytest.mark.parametrize("bad", [True, np.False_, "1e4", b"2", ["1", "2"], [True, False]], ids=repr)
def test_flags_and_text_are_no_numbers(bad):
    # numpy reads True as 1 and "1e4" as 1e4: a load of True had been a load of 1 N
    with pytest.raises(ParameterError, match=r"^normal_load must be (a number|numbers) \[N\]"):
        require_positive("normal_load", bad, "N")
    with pytest.raises(ParameterError, match=r"^radius must be"):
        require_number("radius", bad, "m")


def test_require_number_passes_infinities_and_nan():
    got = require_number("radius", [0.35, np.inf, np.nan], "m")
    assert got[0] == 0.35 and np.isinf(got[1]) and np.isnan(got[2])
