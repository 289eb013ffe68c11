"""The frame file: the bundled default, and one clear error per kind of bad frame."""

from __future__ import annotations

import copy
import re
import tempfile
import tomllib
from importlib import resources
from pathlib import Path

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from tests.frame.conftest import frame_dict

from rollerrig._validation import ParameterError
from rollerrig.frame import FrameFileError, default_frame, frame_from_dict, load_frame

NODES = {"a": (0, 0, 0), "b": (0, 0, 2), "c": (1, 0, 2)}
MEMBERS = {"col": ("a", "b"), "beam": ("b", "c")}


def _good():
    return frame_dict(
        NODES,
        MEMBERS,
        {"a": "fixed"},
        {"p": ("c", (0, 0, -1), (1, 0, 0))},
        gauges={"g": ("col", 0.1, "+x")},
    )


def _error(data) -> str:
    with pytest.raises(FrameFileError) as info:
        frame_from_dict(data, "f.toml")
    assert isinstance(info.value, ParameterError)
    return str(info.value)


def test_default_frame_every_value_has_its_provenance():
    frame = default_frame()
    assert len(frame.supports) == 4 and all(all(s) for s in frame.supports.values())
    assert set(frame.gauges) == {"top_beam", "column_rear_left", "column_rear_right"}
    text = resources.files("rollerrig.frame").joinpath("data/default-frame.toml").read_text()
    data = tomllib.loads(text)
    for name in data["nodes"]:
        assert frame.provenance[f"nodes.{name}"].get("assumption"), name
    for key, record in frame.provenance.items():
        assert record.get("source") or record.get("assumption"), key
    # The load points carry the whole test load: the normal pattern is a closed loop (the
    # frame takes the air spring's 1 N up and the bearings' 1 N down), the traction pattern
    # has no net force (its couple is the roller motor's reaction, outside the frame).
    for case in ("normal", "traction"):
        total = [sum(getattr(lp, case)[i] for lp in frame.load_points.values()) for i in range(3)]
        assert total == pytest.approx([0.0, 0.0, 0.0], abs=1e-12), case
    assert frame.top_nodes and all(frame.nodes[n][2] == 2.0 for n in frame.top_nodes)


def test_a_frame_file_reads_and_converts_units(tmp_path):
    text = resources.files("rollerrig.frame").joinpath("data/default-frame.toml").read_text()
    old = 'spring_plate = { value = [0.0, 0.0, 2.00], unit = "m",'
    assert old in text
    path = tmp_path / "f.toml"
    path.write_text(text.replace(old, 'spring_plate = { value = [0, 0, 2000], unit = "mm",'))
    frame = load_frame(path)
    assert frame.nodes["spring_plate"] == (0.0, 0.0, 2.0)
    assert frame.sections["column"].area == pytest.approx(78.08e-4)
    assert frame.sections["pedestal"].second_moment_strong == pytest.approx(13333e-8)
    assert frame.gauges["top_beam"].direction == (0.0, 0.0, 1.0)
    assert frame.origin == str(path)
    assert frame.provenance["nodes.spring_plate"]["unit"] == "mm"


def test_disconnected_node():
    data = _good()
    data["nodes"]["loose"] = {"value": [5.0, 0.0, 0.0], "unit": "m", "assumption": "t"}
    msg = _error(data)
    assert "f.toml: nodes.loose: is on no member (a disconnected node)" in msg


def test_unsupported_part():
    data = _good()
    data["nodes"] |= {
        "d": {"value": [5.0, 0.0, 0.0], "unit": "m", "assumption": "t"},
        "e": {"value": [6.0, 0.0, 0.0], "unit": "m", "assumption": "t"},
    }
    data["members"]["island"] = {"nodes": ["d", "e"], "section": "ipe"}
    msg = _error(data)
    assert "supports: the part of the frame with nodes d, e (members island)" in msg
    assert "connected to no supported node" in msg


@pytest.mark.parametrize(
    ("support", "where"),
    [("pinned", "can move in"), (["z", "rx", "ry", "rz"], "can move in")],
)
def test_mechanism_names_the_node_and_dof(support, where):
    pytest.importorskip("Pynite")
    from rollerrig.frame import analyze_frame

    data = _good()
    data["supports"] = {"a": support}
    frame = frame_from_dict(data, "f.toml")
    with pytest.raises(FrameFileError) as info:
        analyze_frame(frame, 1e3, 0.0, n_modes=1)
    msg = str(info.value)
    assert msg.startswith("f.toml: supports: the frame is a mechanism: ")
    assert where in msg and "add supports" in msg
    assert any(f"node {n!r}" in msg or f"member {m!r}" in msg for n in "abc" for m in MEMBERS)


@pytest.mark.parametrize(
    ("key", "value", "expected"),
    [
        (
            "area",
            0.0,
            "sections.ipe.area.value: outside the plausible range (from 1 mm^2 to 100 m^2, a "
            "near-rigid link) [m^2]; allowed [1e-06, 100]; got 0 (0 cm^2)",
        ),
        (
            "second_moment_weak",
            -142.4,
            "sections.ipe.second_moment_weak.value: outside the plausible range",
        ),
        ("torsion_constant", 0.0, "sections.ipe.torsion_constant.value: outside the plausible"),
    ],
)
def test_zero_or_negative_section_properties(key, value, expected):
    data = _good()
    data["sections"]["ipe"][key]["value"] = value
    assert expected in _error(data)


def test_unknown_designation_names_the_closest():
    data = _good()
    data["sections"]["ipe"] = {"designation": {"value": "HEB 210", "assumption": "t"}}
    msg = _error(data)
    assert "f.toml: sections.ipe.designation.value: unknown designation: 'HEB 210'" in msg
    assert "closest: HEB 200, HEB 220" in msg or "closest: HEB 220, HEB 200" in msg


def test_unknown_node_in_a_member():
    data = _good()
    data["members"]["beam"]["nodes"] = ["b", "x"]
    msg = _error(data)
    assert "f.toml: members.beam.nodes: node 'x' is not defined under [nodes]" in msg


def test_load_point_on_no_node():
    data = _good()
    del data["load_points"]["p"]["node"]
    data["load_points"]["p"]["at"] = {"value": [0.5, 0.0, 2.0], "unit": "m", "assumption": "t"}
    msg = _error(data)
    assert "f.toml: load_points.p.at: is on no node of the frame; the nearest is" in msg
    data["load_points"]["p"]["at"]["value"] = [1.0, 0.0, 2.0]
    assert frame_from_dict(data).load_points["p"].node == "c"  # on a node: accepted
    data["load_points"]["p"] = {"node": "zz", "normal": [0, 0, 1], "assumption": "t"}
    assert "load_points.p.node: not a node of the frame" in _error(data)


def test_node_inside_a_member_span_must_split_it():
    data = _good()
    data["nodes"]["half"] = {"value": [0.0, 0.0, 1.0], "unit": "m", "assumption": "t"}
    data["members"]["stub"] = {"nodes": ["half", "c"], "section": "ipe"}
    msg = _error(data)
    assert "members.col.nodes: node 'half' lies on the member between its ends" in msg


def test_other_mistakes_each_named():
    data = _good()
    data["members"]["beam"]["section"] = "ipee"
    data["nodes"]["a"]["unit"] = "inch"
    data["strain_gauges"]["g"]["fibre"] = "+q"
    data["supports"]["a"] = "welded"
    data["extra"] = 1
    msg = _error(data)
    assert "members.beam.section: not a section of the frame (did you mean 'ipe'?)" in msg
    assert "nodes.a.unit: unit not accepted for length [m]" in msg
    assert "node 'a' is not defined" not in msg  # no cascade from the bad node
    assert "strain_gauges.g.fibre: not a face of the section" in msg
    assert "supports.a: not a support; allowed 'fixed', 'pinned'" in msg
    assert "f.toml: extra: unknown key" in msg


def test_gauge_checks():
    data = _good()
    data["strain_gauges"]["g"]["position"]["value"] = 2.5
    assert "strain_gauges.g.position: lies outside member 'col' (2 m long" in _error(data)
    data["strain_gauges"]["g"]["position"]["value"] = -0.5
    assert "strain_gauges.g.position: lies outside member 'col' (2 m long" in _error(data)
    data = _good()
    data["strain_gauges"]["g"]["fibre"] = "+z"
    assert "strain_gauges.g.fibre: is along member 'col''s axis" in _error(data)


def test_web_along_the_axis_and_missing_provenance():
    data = _good()
    data["members"]["col"]["web"] = [0, 0, 1]
    assert "members.col.web: is (nearly) along the member's axis" in _error(data)
    data = _good()
    del data["nodes"]["a"]["assumption"]
    assert "nodes.a: needs exactly one of 'source' or 'assumption'" in _error(data)


def test_missing_file_and_bad_toml(tmp_path):
    with pytest.raises(FrameFileError, match="frame file not found"):
        load_frame(tmp_path / "none.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[meta\n")
    with pytest.raises(FrameFileError, match="not valid TOML"):
        load_frame(bad)


def test_the_input_is_not_modified():
    data = _good()
    before = copy.deepcopy(data)
    frame_from_dict(data)
    assert data == before


# --------------------------------------------------------------------------------------------
# Hostile files (issue 24, points 7 and 8): sizes, absurd numbers, anything at all
# --------------------------------------------------------------------------------------------


def _ladder_toml(columns: int) -> str:
    """A planar ladder frame as TOML text: ``columns`` fixed columns 1 m high, 1 m apart,
    joined at the top (2 columns - 1 members, 2 columns nodes)."""
    lines = [
        '[meta]\nname = "ladder"',
        "[materials.steel]",
        'youngs_modulus = { value = 210, unit = "GPa", source = "t" }',
        'poisson = { value = 0.3, unit = "1", source = "t" }',
        'density = { value = 7850, unit = "kg/m^3", source = "t" }',
        '[sections.s]\ndesignation = { value = "HEB 200", source = "t" }',
        "[nodes]",
    ]
    for i in range(columns):
        lines.append(f'b{i} = {{ value = [{i}, 0, 0], unit = "m", assumption = "t" }}')
        lines.append(f't{i} = {{ value = [{i}, 0, 1], unit = "m", assumption = "t" }}')
    lines.append("[members]")
    for i in range(columns):
        lines.append(f'v{i} = {{ nodes = ["b{i}", "t{i}"], section = "s", web = [1, 0, 0] }}')
        if i:
            lines.append(f'h{i} = {{ nodes = ["t{i - 1}", "t{i}"], section = "s" }}')
    lines.append("[supports]")
    lines += [f'b{i} = "fixed"' for i in range(columns)]
    lines.append('[load_points.p]\nnode = "t0"\nnormal = [0, 0, -1]\nassumption = "t"')
    return "\n".join(lines) + "\n"


def test_a_frame_of_20000_members_is_refused_before_it_is_read(tmp_path):
    from rollerrig.frame.framefile import MAX_ENTRIES, MAX_MEMBERS, MAX_NODES

    path = tmp_path / "huge.toml"
    path.write_text(_ladder_toml(10_001))  # 20 001 members, 20 002 nodes
    with pytest.raises(FrameFileError) as info:
        load_frame(path)
    assert info.value.problems == [
        f"{path}: nodes: too many entries for the frame analysis (each nodes entry adds to "
        f"the FE model; split the frame or merge entries); allowed at most {MAX_NODES}; "
        "got 20002",
        f"{path}: members: too many entries for the frame analysis (each members entry adds "
        f"to the FE model; split the frame or merge entries); allowed at most {MAX_MEMBERS}; "
        "got 20001",
        f"{path}: supports: too many entries for the frame analysis (each supports entry adds "
        f"to the FE model; split the frame or merge entries); allowed at most {MAX_ENTRIES}; "
        "got 10001",
    ]


def test_a_frame_at_the_size_limit_is_read():
    from rollerrig.frame.framefile import MAX_MEMBERS, MAX_NODES

    columns = (MAX_MEMBERS + 1) // 2  # 2 c - 1 members: 499 of 500
    data = tomllib.loads(_ladder_toml(columns))
    data["members"]["extra"] = {"nodes": ["b0", "b1"], "section": "s"}
    frame = frame_from_dict(data)
    assert len(frame.members) == MAX_MEMBERS and len(frame.nodes) <= MAX_NODES
    data["members"]["one_more"] = {"nodes": ["b1", "b2"], "section": "s"}
    assert "members: too many entries for the frame analysis" in _error(data)
    # Every check still runs on a frame that size: duplicates, a node on a span.
    del data["members"]["one_more"]
    data["nodes"]["twin"] = copy.deepcopy(data["nodes"][f"t{columns - 1}"])
    data["nodes"]["mid"] = {"value": [0.5, 0.0, 1.0], "unit": "m", "assumption": "t"}
    msg = _error(data)
    assert f"nodes.twin: is at the same point as node 't{columns - 1}'" in msg
    assert "members.h1.nodes: node 'mid' lies on the member between its ends" in msg


@pytest.mark.parametrize(
    ("where", "value", "expected"),
    [
        (
            ("nodes", "b", "value"),
            [0.0, 0.0, 1e200],
            "nodes.b.value: outside the plausible range (a rig frame lies within 1 km of its "
            "origin) [m]; allowed [-1000, 1000]; got [0.0, 0.0, 1e+200]",
        ),
        (
            ("nodes", "b"),
            {"value": [0, 0, 1e200], "unit": "mm", "assumption": "t"},
            "nodes.b.value: outside the plausible range (a rig frame lies within 1 km of its "
            "origin) [m]; allowed [-1000, 1000]; got [0, 0, 1e+200] mm",
        ),
        (
            ("materials", "steel", "youngs_modulus"),
            {"value": 1e-300, "unit": "GPa", "source": "t"},
            "materials.steel.youngs_modulus.value: outside the plausible range (from soft "
            "rubber (1 MPa) to beyond diamond (1.2 TPa)) [Pa]; allowed [1e+06, 1e+13]; "
            "got 1e-291 (1e-300 GPa)",
        ),
        (
            ("materials", "steel", "density"),
            {"value": 1e300, "unit": "kg/m^3", "source": "t"},
            "materials.steel.density.value: outside the plausible range (from foams to the "
            "densest metals (osmium 22 590)) [kg/m^3]; allowed [10, 30000]; got 1e+300",
        ),
        (
            ("materials", "steel", "density"),
            {"value": -7850, "unit": "kg/m^3", "source": "t"},
            "materials.steel.density.value: outside the plausible range",
        ),
        (
            ("materials", "steel", "poisson"),
            {"value": 0.5, "unit": "1", "source": "t"},
            "materials.steel.poisson.value: outside the plausible range",
        ),
        (
            ("sections", "ipe", "area", "value"),
            1e-300,
            "sections.ipe.area.value: outside the plausible range (from 1 mm^2 to 100 m^2",
        ),
        (
            ("sections", "ipe", "second_moment_strong", "value"),
            1e300,
            "sections.ipe.second_moment_strong.value: outside the plausible range",
        ),
        (
            ("sections", "ipe", "depth", "value"),
            1e12,
            "sections.ipe.depth.value: outside the plausible range (a section's depth or "
            "width, 0.1 mm to 10 m) [m]; allowed [0.0001, 10]; got 1e+09 (1000000000000 mm)",
        ),
        (
            ("load_points", "p", "normal"),
            [0, 0, -1e200],
            "load_points.p.normal: a component is outside the plausible range (a force on "
            "the frame per newton of test load, at most 100 N/N) [N/N]; allowed [-100, 100]",
        ),
        (
            ("load_points", "p", "traction"),
            [float("nan"), 0, 0],
            "load_points.p.traction: must be a list of three finite numbers",
        ),
        (
            ("nodes", "c", "value"),
            [float("inf"), 0, 2],
            "nodes.c.value: must be finite; got [inf, 0, 2]",
        ),
        (("nodes", "c", "value"), [10**400, 0, 2], "nodes.c.value: must be finite"),
        (
            ("nodes", "c", "value"),
            [0, 0, 2.0001],
            "members.beam.nodes: too short: its nodes are 0.0001 m apart (a member shorter "
            "than 1 mm is a joint, not a beam); merge them [m]; allowed [0.001, inf)",
        ),
        (
            ("nodes", "c", "value"),
            [0, 0, 2.0 + 1e-8],
            "nodes.c: is at the same point as node 'b'; merge them or move one",
        ),
        (
            ("members", "beam", "web"),
            [1e200, 1e200, 0],
            None,  # a direction: only its sense matters, no overflow on the way
        ),
        (
            ("members", "beam", "web"),
            [0, 1e-320, 0],
            None,
        ),
        (
            ("members", "beam", "nodes"),
            ["b", "nowhere"],
            "members.beam.nodes: node 'nowhere' is not defined under [nodes]",
        ),
        (
            ("members", "beam", "nodes"),
            ["b", "b"],
            "members.beam.nodes: starts and ends at the same node",
        ),
        (
            ("masses",),
            {"m": {"node": "c", "mass": {"value": 1e300, "unit": "kg", "source": "t"}}},
            "masses.m.mass.value: outside the plausible range (a lumped mass of at most "
            "1000 t) [kg]; allowed [0, 1e+06]; got 1e+300",
        ),
        (
            ("strain_gauges", "g", "position", "value"),
            1e200,
            "strain_gauges.g.position.value: outside the plausible range",
        ),
        (
            ("load_points", "p", "assumption"),
            ["not", "text"],
            "load_points.p.assumption: must be a non-empty string",
        ),
        (
            ("output",),
            {"top_nodes": [["a"]]},
            "output.top_nodes: must be a non-empty list of node names",
        ),
    ],
)
def test_absurd_numbers_are_named_with_their_key_unit_and_range(where, value, expected):
    data = _good()
    table = data
    for key in where[:-1]:
        table = table[key]
    table[where[-1]] = value
    if expected is None:
        frame_from_dict(data)  # accepted
        return
    assert expected in _error(data)


def test_many_problems_are_capped_and_counted():
    from rollerrig.frame.framefile import MAX_PROBLEMS_SHOWN

    data = _good()
    for i in range(150):
        data["members"][f"m{i}"] = {"nodes": ["a", f"ghost{i}"], "section": "ipe"}
    with pytest.raises(FrameFileError) as info:
        frame_from_dict(data, "f.toml")
    problems = info.value.problems
    assert len(problems) == MAX_PROBLEMS_SHOWN + 1
    assert problems[-1].startswith("f.toml: ... and ") and "more problems" in problems[-1]


# Any input at all: a Frame or a FrameFileError, never another exception (issue 24). The
# examples are the bundled frame with one value replaced by anything a TOML file (or a dict)
# can hold, and the bundled file's text with a slice replaced by any text.

_FUZZ = settings(
    max_examples=60,
    deadline=None,
    database=None,
    derandomize=True,  # the same examples on every run
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
_DEFAULT_TEXT = (
    resources.files("rollerrig.frame").joinpath("data/default-frame.toml").read_text("utf-8")
)
_DEFAULT = tomllib.loads(_DEFAULT_TEXT)


def _paths(data, prefix=()):
    """Every (key path) of a nested dict/list, containers included."""
    out = []
    items = data.items() if isinstance(data, dict) else enumerate(data)
    for k, v in items:
        out.append((*prefix, k))
        if isinstance(v, dict | list):
            out += _paths(v, (*prefix, k))
    return out


_PATHS = _paths(_DEFAULT)
_SCALARS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([1e200, -1e200, 1e-300, -0.0, 0.0, 5e-324, 1.7976931348623157e308]),
    st.integers(min_value=-(2**63), max_value=2**63 - 1),
    st.integers(),  # beyond TOML's 64 bits: a dict may hold them
    st.booleans(),
    st.text(max_size=12),
    st.sampled_from(["m", "GPa", "fixed", "HEB 200", "a", "b", "+z", "~", "#", ""]),
    st.datetimes(),
    st.none(),
)
_VALUES = st.recursive(
    _SCALARS,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=8), inner, max_size=4)
    ),
    max_leaves=12,
)


def _replace(data, path, value):
    data = copy.deepcopy(data)
    table = data
    for k in path[:-1]:
        table = table[k]
    if value is _DELETE:
        del table[path[-1]]
    else:
        table[path[-1]] = value
    return data


_DELETE = object()


@_FUZZ
@given(
    st.lists(
        st.tuples(st.sampled_from(_PATHS), st.one_of(_VALUES, st.just(_DELETE))),
        min_size=1,
        max_size=3,
    )
)
@example([(("nodes", "roller_bearing_left", "value"), [0.0, 0.0, 1e200])])
@example([(("materials", "steel", "youngs_modulus", "value"), 1e-300)])
@example([(("output",), {"top_nodes": [["x"]]})])
@example([(("meta",), [1, 2])])
def test_any_dict_is_a_frame_or_a_frame_file_error(changes):
    data = _DEFAULT
    for path, value in changes:
        try:
            data = _replace(data, path, value)
        except (KeyError, IndexError, TypeError):
            continue  # an earlier change removed or replaced the path
    try:
        frame_from_dict(data, "f.toml")
    except FrameFileError as exc:
        assert exc.problems and all(p.startswith("f.toml: ") for p in exc.problems)


@_FUZZ
@given(st.integers(0, len(_DEFAULT_TEXT)), st.integers(0, 200), st.text(max_size=40))
@example(0, 0, "x = " + "[" * 40 + "]" * 40)
@example(0, len(_DEFAULT_TEXT), "")
def test_any_text_is_a_frame_or_a_frame_file_error(start, length, text):
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "f.toml"
        path.write_text(_DEFAULT_TEXT[:start] + text + _DEFAULT_TEXT[start + length :], "utf-8")
        try:
            load_frame(path)
        except FrameFileError as exc:
            assert exc.problems and all(p.startswith(f"{path}: ") for p in exc.problems)


@pytest.mark.parametrize("value", [None, 3])
def test_load_frame_refuses_what_is_not_a_path(value):
    """A bare TypeError from pathlib before."""
    from rollerrig.frame import FrameFileError, load_frame

    with pytest.raises(
        FrameFileError, match=re.escape(f"{value!r}: not a file path (str or Path)")
    ):
        load_frame(value)
