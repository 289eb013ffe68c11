"""The study file: the issue's minimal form, units, designs, bundled studies, clear errors."""

import math
import re
import tracemalloc

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rollerrig.studies.studyfile import (
    MAX_STUDY_POINTS,
    StudyFileError,
    bundled_studies,
    load_study,
    study_from_dict,
    study_from_toml_string,
)

MINIMAL = """
experiment = "seed-30kmh-dry"
[grid]
"stiffness.roller_shaft" = { values = [43.5e3, 83.5e3, 143.5e3], unit = "N.m/rad" }
"induction_motor.response_lag_clp" = { values = [2.75, 10000.0], unit = "1/s" }
[outputs]
metrics = ["release_overshoot"]
"""


def test_the_issues_minimal_study_reads_as_a_3_by_2_grid():
    spec = study_from_toml_string(MINIMAL)
    assert spec.design == "grid" and spec.size == 6
    assert spec.experiment == "seed-30kmh-dry"
    assert spec.keys == ("stiffness.roller_shaft", "induction_motor.response_lag_clp")
    assert spec.axes[0].values == (43.5e3, 83.5e3, 143.5e3)
    assert spec.metrics == ("release_overshoot",)
    assert spec.h_max is None and spec.output_rate == 1000.0


def test_units_are_converted_to_si_and_kept_for_labels():
    spec = study_from_toml_string(
        """
        [grid]
        "stiffness.roller_shaft" = { values = [43.5, 143.5], unit = "kN.m/rad", label = "k56" }
        load = { start = 4.3, stop = 20, num = 3, unit = "kN" }
        speed = { start = 10, stop = 30, num = 3, unit = "km/h", scale = "log" }
        "drive.roller_lag" = { values = [0, 360], unit = "ms" }
        """
    )
    k, load, speed, lag = spec.axes
    assert k.values == (43500.0, 143500.0) and k.show(43500.0) == "k56 = 43.5 kN.m/rad"
    assert load.values == pytest.approx((4300.0, 12150.0, 20000.0))
    # 10, 17.32, 30 km/h (geometric) in m/s
    assert speed.values == pytest.approx(np.geomspace(10, 30, 3) / 3.6)
    assert speed.scale == "log" and lag.values == (0.0, 0.36)


def test_sample_and_cases_designs_count_their_points():
    spec = study_from_toml_string(
        """
        [sample]
        method = "sobol"
        n = 8
        [sample.parameters]
        load = { distribution = "uniform", low = 4.3, high = 20, unit = "kN" }
        speed = { distribution = "normal", mean = 20, std = 2, unit = "km/h" }
        friction = { distribution = "choice", values = ["dry", "wet"] }
        """
    )
    # Saltelli's scheme without second order: N (D + 2) points.
    assert spec.size == 8 * (3 + 2)
    dist = spec.sample.parameters[0]
    assert dist.ppf(np.array([0.0, 0.5])) == pytest.approx([4300.0, 12150.0])
    assert spec.sample.parameters[2].ppf(np.array([0.1, 0.9])).tolist() == ["dry", "wet"]
    cases = load_study("drives")
    assert cases.design == "cases" and cases.size == 6
    assert cases.cases[2].settings == {"drive.roller_lag": 0.0, "stiffness.roller_shaft": 143.5e3}
    # 20 Hz bandwidth is 2π·20 rad/s inside.
    assert cases.cases[4].settings["servo_roller_drive.speed_bandwidth"] == pytest.approx(
        2 * math.pi * 20
    )


def test_bundled_studies_load_and_the_seeds_three_are_there():
    names = bundled_studies()
    assert {"stiffness", "lag", "drives", "joint", "sensitivity"} <= set(names)
    for name in names:
        spec = load_study(name)
        assert spec.origin == f"bundled:{name}" and spec.size >= 6
    assert load_study("stiffness").axes[0].values == tuple(43.5e3 + 20e3 * np.arange(6))


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("[grid]\n'stiffness.shaft' = [1.0]", "stiffness.shaft: unknown key in the rig's"),
        ("[grid]\ncolour = [1.0]", "grid.colour: not a quantity a study can vary"),
        (
            "[grid]\n'stiffness.roller_shaft' = { values = [1.0], unit = 'furlong' }",
            "grid.stiffness.roller_shaft.unit: unit not accepted",
        ),
        ("[grid]\nfriction = ['dry', 'icy']", "grid.friction.values[1]: not a known friction"),
        ("[grid]\nload = [4300, -1]", "grid.load.values[1]: must be > 0"),
        ("[grid]\nload = [4300, 4300]", "grid.load.values: repeats a value"),
        ("[grid]\nload = { start = 1, stop = 2 }", "grid.load: missing num"),
        ("[grid]\nload = [1.0]\n[sample]\nn = 4", "give exactly one design"),
        ("name = 'x'", "give exactly one design"),
        ("[grid]\nload = [1.0]\n[outputs]\nmetrics = ['colour']", "outputs.metrics: unknown"),
        (
            "[sample]\nn = 6\n[sample.parameters]\nload={distribution='uniform',low=1,high=2}\n"
            "speed={distribution='uniform',low=1,high=2}",
            "sample.n: Sobol' sequences need a power of 2",
        ),
        (
            "[sample]\nn = 4\nmethod = 'lhs'\n[sample.parameters]\n"
            "load = { distribution = 'uniform', low = 2, high = 1 }",
            "uniform needs low < high",
        ),
        ("[[cases]]\nload = 4300", "cases[0].label: every case needs a label"),
        ("[grid]\nload = [1.0]\n[solver]\nh_max = { value = 1, unit = 's' }", "solver.h_max"),
        ("[grid\n", "not valid TOML"),
    ],
)
def test_a_bad_study_names_the_key_and_what_to_change(text, expected):
    with pytest.raises(StudyFileError) as info:
        study_from_toml_string(text, origin="my-study.toml")
    assert expected in str(info.value)
    assert all(line.startswith("my-study.toml") for line in info.value.problems)


def test_every_problem_of_a_file_is_reported_at_once():
    with pytest.raises(StudyFileError) as info:
        study_from_toml_string("colour = 1\n[grid]\nload = [-1]\nspeed = ['fast']")
    assert len(info.value.problems) == 3


def test_missing_study_file_is_a_clear_error(tmp_path):
    with pytest.raises(StudyFileError, match="neither a bundled study"):
        load_study(tmp_path / "nothing.toml")


def test_relative_experiment_and_rig_paths_are_resolved_against_the_study_file(tmp_path):
    (tmp_path / "study.toml").write_text(
        "experiment = 'exp.toml'\nrig = 'rig.toml'\n[grid]\nload = [4300.0]\n", encoding="utf-8"
    )
    spec = load_study(tmp_path / "study.toml")
    assert spec.experiment == str(tmp_path.resolve() / "exp.toml")
    assert spec.rig == str(tmp_path.resolve() / "rig.toml") and spec.name == "study"


_scalars = st.one_of(
    st.integers(-(10**6), 10**6),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=8),
    st.booleans(),
    st.sampled_from(["dry", "wet", "kN", "N.m/rad", "uniform", "sobol", "servo", "log"]),
)
_values = st.recursive(
    _scalars,
    lambda inner: st.lists(inner, max_size=4)
    | st.dictionaries(
        st.sampled_from(
            ["values", "start", "stop", "num", "unit", "scale", "label", "distribution", "low",
             "high", "mean", "std", "mode", "value", "x"]
        ),
        inner,
        max_size=5,
    ),
    max_leaves=12,
)  # fmt: skip
_keys = st.sampled_from(
    ["load", "speed", "friction", "drive.roller", "drive.roller_lag", "stiffness.roller_shaft",
     "inertia.roller", "induction_motor.response_lag_clp", "meta.name", "nothing", "a.b"]
)  # fmt: skip


# 200 examples (500 cost 7-10 s of CPU, most of it hypothesis drawing the nested tables): the
# bad-study cases above name each refusal deterministically, and the text and dict properties
# below fuzz the reader too.
@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    design=st.sampled_from(["grid", "sample", "cases"]),
    body=st.dictionaries(_keys, _values, max_size=4),
    extra=st.dictionaries(
        st.sampled_from(["name", "experiment", "outputs", "solver", "method", "n", "seed"]),
        _values,
        max_size=3,
    ),
)
def test_any_study_table_is_read_or_refused_with_a_study_file_error(design, body, extra):
    # What a user may write never escapes as another exception type.
    if design == "grid":
        data = {"grid": body, **extra}
    elif design == "sample":
        data = {"sample": {"n": 4, "parameters": body, **extra}}
    else:
        data = {"cases": [{"label": "a", **body}], **extra}
    try:
        spec = study_from_dict(data)
    except StudyFileError as exc:
        assert exc.problems
    else:
        assert spec.size >= 1


# --------------------------------------------------------------------------------------------
# The study's name names files: checked (issue 24, point 3)
# --------------------------------------------------------------------------------------------

GRID = "[grid]\nload = [4300.0]\n"


@pytest.mark.parametrize(
    "name",
    ["x/../../../escaped", "a/b", "", ".hidden", "..", "a b", "x" * 65, "ünïcode", "a\\b",
     "tab\there", "nul\x00"],
)  # fmt: skip
def test_a_study_name_that_is_not_a_plain_name_is_refused(name):
    with pytest.raises(StudyFileError) as info:
        study_from_dict({"name": name, "grid": {"load": [4300.0]}}, origin="s.toml")
    (line,) = info.value.problems
    assert line.startswith("s.toml: name: not a study name; allowed 1-64 characters of letters")
    assert "not starting with '.'" in line


def test_a_study_name_that_is_not_text_is_refused():
    with pytest.raises(StudyFileError, match=r"name: not a study name.*got 3"):
        study_from_toml_string("name = 3\n" + GRID)


@pytest.mark.parametrize("name", ["stiffness", "k56-v2.1", "a+b_c", "0", "x" * 64])
def test_plain_study_names_are_kept(name):
    assert study_from_toml_string(f"name = '{name}'\n" + GRID).name == name


@pytest.mark.parametrize(
    ("file_name", "expected"),
    [
        ("my study [v2].toml", "my_study__v2_"),
        (".hidden.toml", "hidden"),
        ("..toml", "_"),
        ("étude.toml", "_tude"),
        ("a" * 200 + ".toml", "a" * 64),
        ("semi;colon $(x).toml", "semi_colon___x_"),
    ],
)
def test_a_name_from_an_odd_file_name_is_made_safe(tmp_path, file_name, expected):
    path = tmp_path / file_name
    path.write_text(GRID, encoding="utf-8")
    assert load_study(path).name == expected


def test_the_name_given_by_a_caller_is_checked_too():
    with pytest.raises(StudyFileError, match=r"name: not a study name \(the name of the study"):
        study_from_toml_string(GRID, name="../x")


# --------------------------------------------------------------------------------------------
# Size bombs: the design's size is checked from the numbers first (issue 24, point 7)
# --------------------------------------------------------------------------------------------

LIMIT = f"allowed at most {MAX_STUDY_POINTS} points in a study"
SOBOL = (
    "[sample]\nn = {n}\n{extra}[sample.parameters]\n"
    "load = {{ distribution = 'uniform', low = 1, high = 2 }}\n"
    "speed = {{ distribution = 'uniform', low = 1, high = 2 }}\n"
)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("[grid]\nload = { start = 1, stop = 2, num = 1_000_000_000 }",
         "grid.load.num: too many values for one axis"),
        ("[grid]\nload = { start = 1, stop = 2, num = 10_000_000_000_000_000_000_000 }",
         "grid.load.num: too many values for one axis"),
        ("[grid]\nload = { start = 1, stop = 2, num = 1000 }\n"
         "speed = { start = 1, stop = 2, num = 1000 }\n"
         "'drive.roller_lag' = { start = 0, stop = 2, num = 1000 }",
         "grid: too many points: the product of the axis lengths (1000 x 1000 x 1000)"),
        (SOBOL.format(n=2**40, extra=""), "sample.n: too many points (1099511627776 x 4 ="),
        (SOBOL.format(n=2**18, extra="second_order = true\n"),
         "sample.n: too many points (262144 x 6 = 1572864 points)"),
        (SOBOL.format(n=10**12, extra="method = 'lhs'\n"),
         "sample.n: too many points (1000000000000 points)"),
        (SOBOL.format(n=2**70, extra="method = 'random'\n"), "sample.n: too many points"),
    ],
)  # fmt: skip
def test_a_size_bomb_is_refused_from_its_numbers_before_anything_is_made(text, expected):
    tracemalloc.start()
    try:
        with pytest.raises(StudyFileError) as info:
            study_from_toml_string(text)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert expected in str(info.value) and LIMIT in str(info.value)
    assert peak < 20 * 2**20  # [bytes]: nothing of the design's size was made


def test_a_design_at_the_limit_is_read_without_making_its_points():
    spec = study_from_toml_string(
        "[grid]\nload = { start = 1, stop = 2, num = 1000 }\n"
        "speed = { start = 1, stop = 2, num = 1000 }"
    )
    assert spec.size == MAX_STUDY_POINTS
    # Sobol': n (D + 2) with D = 2 parameters; 2**17 x 4 = 524288 points is within the limit.
    assert study_from_toml_string(SOBOL.format(n=2**17, extra="")).size == 2**19


# --------------------------------------------------------------------------------------------
# Whatever a user writes gives a StudySpec or a StudyFileError (properties)
# --------------------------------------------------------------------------------------------

PROPERTY = settings(
    max_examples=150,
    deadline=None,
    database=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
_big_ints = st.one_of(
    st.integers(-3, 5),
    st.sampled_from([2**10, 2**20, 2**40, 10**9, 10**30, 2**64 + 1, -(2**63)]),
)
_fragments = st.sampled_from(
    ["[grid]", "[sample]", "[sample.parameters]", "[[cases]]", "[outputs]", "[solver]",
     "load = [4300.0, 1e4]", "speed = {{ start = 1, stop = 10, num = {i} }}",
     "'drive.roller_lag' = {{ values = [0, {i}], unit = 's' }}",
     "friction = ['dry', 'wet']", "n = {i}", "method = 'lhs'", "method = 'sobol'",
     "second_order = true", "seed = {i}", "label = 'a'",
     "load = {{ distribution = 'uniform', low = 1, high = {i} }}",
     "speed = {{ distribution = 'normal', mean = 1, std = {i} }}",
     "name = '{s}'", "name = 'ok-name'", "description = '{s}'", "experiment = '{s}'",
     "metrics = ['release_overshoot']", "metrics = 'all'", "output_rate = {i}",
     "h_max = {i}", "x = {i}", "= broken", "[grid", "load = [{i}]"]
)  # fmt: skip


@st.composite
def _study_texts(draw):
    lines = []
    for fragment in draw(st.lists(_fragments, max_size=12)):
        i = draw(_big_ints)
        s = draw(st.text(alphabet=st.characters(blacklist_characters="'\\\n\r"), max_size=12))
        lines.append(fragment.format(i=i, s=s))
    return "\n".join(lines)


@PROPERTY
@given(text=st.one_of(_study_texts(), st.text(max_size=200)))
def test_any_study_text_is_read_or_refused_with_a_study_file_error(text):
    tracemalloc.start()
    try:
        try:
            spec = study_from_toml_string(text, origin="p.toml")
        except StudyFileError as exc:
            assert exc.problems and all(p.startswith("p.toml") for p in exc.problems)
        else:
            assert 1 <= spec.size <= MAX_STUDY_POINTS
            assert re.fullmatch(r"[A-Za-z0-9_+-][A-Za-z0-9._+-]{0,63}", spec.name)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 64 * 2**20  # [bytes]


@PROPERTY
@given(
    name=st.one_of(st.text(max_size=80), st.integers(), st.none(), st.lists(st.text(), max_size=2)),
    num=_big_ints,
    n=_big_ints,
    design=st.sampled_from(["grid", "sample", "cases"]),
)
def test_any_study_dict_is_read_or_refused_with_a_study_file_error(name, num, n, design):
    params = {"load": {"distribution": "uniform", "low": 1.0, "high": 2.0},
              "speed": {"distribution": "uniform", "low": 1.0, "high": 2.0}}  # fmt: skip
    body = {
        "grid": {"grid": {"load": {"start": 1.0, "stop": 2.0, "num": num}, "speed": [1.0, 2.0]}},
        "sample": {"sample": {"n": n, "method": "sobol", "parameters": params}},
        "cases": {"cases": [{"label": "a", "load": 4300.0}] * max(1, min(num, 3))},
    }[design]
    try:
        spec = study_from_dict({"name": name, **body})
    except StudyFileError as exc:
        assert exc.problems
    else:
        assert spec.name == name and 1 <= spec.size <= MAX_STUDY_POINTS


# --------------------------------------------------------------------------------------------
# A dimensional number without a unit is SI, and the study says where it took one so
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("[grid]\n'stiffness.roller_shaft' = [43.5, 143.5]",
         (("grid.stiffness.roller_shaft", "N.m/rad"),)),
        ("[grid]\nload = { start = 4300, stop = 2e4, num = 3 }\nfriction = ['dry']",
         (("grid.load", "N"),)),
        ("[sample]\nmethod = 'lhs'\nn = 4\n[sample.parameters]\n"
         "speed = { distribution = 'uniform', low = 1, high = 8 }",
         (("sample.parameters.speed", "m/s"),)),
        ("[[cases]]\nlabel = 'a'\nload = 4300.0\n[[cases]]\nlabel = 'b'\n"
         "'stiffness.roller_shaft' = { value = 4e4 }\n[solver]\noutput_rate = 500",
         (("cases[0].load", "N"), ("cases[1].stiffness.roller_shaft", "N.m/rad"),
          ("solver.output_rate", "Hz"))),
        # With a unit, a zero (0 in every unit), a name: nothing taken for want of a unit.
        ("[grid]\n'stiffness.roller_shaft' = { values = [43.5], unit = 'kN.m/rad' }\n"
         "'drive.roller_lag' = [0.0]\n'drive.roller' = ['servo']", ()),
        ("[[cases]]\nlabel = 'no lag'\n'drive.roller_lag' = 0.0", ()),
    ],
)  # fmt: skip
def test_numbers_without_a_unit_are_si_and_listed_where_they_are(text, expected):
    assert study_from_toml_string(text).assumed_units == expected


def test_the_bundled_studies_give_every_unit():
    for name in bundled_studies():
        assert load_study(name).assumed_units == (), name
