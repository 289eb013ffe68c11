"""The frame file: the bundled default, and one clear error per kind of bad frame."""

from __future__ import annotations

import copy
import tomllib
from importlib import resources

import pytest
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
        ("area", 0.0, "sections.ipe.area.value: must be > 0 [m^2]; allowed (0, inf); got 0"),
        ("second_moment_weak", -142.4, "sections.ipe.second_moment_weak.value: must be > 0 [m^4]"),
        ("torsion_constant", 0.0, "sections.ipe.torsion_constant.value: must be > 0 [m^4]"),
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
    assert "strain_gauges.g.position: lies beyond member 'col' (2 m long" in _error(data)
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
