"""Rig sets by name: every bundled set loads and validates, the twin runs on each, and a
package's set registered through the entry-point group is found (or its failure listed)."""

import importlib.metadata as md

import pytest

import rollerrig as rr
from rollerrig._validation import ParameterError
from rollerrig.rig import library
from rollerrig.rig.library import ENTRY_POINT_GROUP, resolve_rig, rig_set, rig_sets
from rollerrig.rig.parameters import default_rig, load_rig, load_rig_set

LITERATURE = ("vt-fra-quarter-scale", "twin-disc-suros-type")


def test_the_bundled_sets_are_listed_with_their_meta():
    sets = rig_sets()
    assert {"pardubice", "default", *LITERATURE} <= set(sets)
    assert sets["pardubice"].title == "pardubice-tram-roller-rig"
    assert all(s.origin == "bundled" and not s.problem for s in sets.values())


def test_pardubice_by_name_is_the_default_rig():
    assert load_rig_set("pardubice") == default_rig()
    assert load_rig("pardubice") == default_rig()  # load_rig takes a set's name too


@pytest.mark.parametrize("name", LITERATURE)
def test_every_literature_value_has_a_source_or_a_stated_assumption(name):
    rig = load_rig_set(name)  # validated on load
    for key, entry in rig.provenance.items():
        said = entry.get("source") or entry.get("assumption")
        assert said and len(said) > 5, key


@pytest.mark.parametrize(
    ("name", "roller", "speed"),
    [("vt-fra-quarter-scale", "servo", 2.0), ("twin-disc-suros-type", "induction", 1.0)],
)
def test_the_twin_runs_briefly_on_each_literature_set(name, roller, speed):
    rig = load_rig_set(name)
    load = 5000.0
    torque = 0.3 * load * rig.geometry.wheel_radius_x  # CoA 0.3: below the adhesion peak
    protocol = rr.Protocol.from_steps(
        "short",
        [rr.Hold(0.2), rr.RampTorque(torque, 0.4), rr.ReleaseTorque(), rr.Hold(0.2)],
        normal_load=load,
        roller_speed=speed,
    )
    ds = rr.Simulation(rig, protocol, drives=rr.DriveConfig(roller=roller)).run()
    # the wheel's torque reaches the contact: CoA 0.3 at the end of the ramp (bearing losses
    # and the drive's small lag aside)
    assert float(ds["coa"].max()) == pytest.approx(0.3, abs=0.02)


def test_an_unknown_name_offers_the_nearest():
    with pytest.raises(ParameterError, match="did you mean 'pardubice'"):
        rig_set("pardubise")


def test_a_folder_is_not_taken_for_a_rig_set_name(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "rigs").mkdir()
    with pytest.raises(
        ParameterError, match="rig rigs is a folder, not a rig file; give a rig TOML file"
    ):
        resolve_rig("rigs")


def test_resolve_rig_takes_a_file_or_a_name(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text(rig_set("pardubice").path.read_text("utf-8"), "utf-8")
    assert resolve_rig(path) == path
    assert resolve_rig("vt-fra-quarter-scale").name == "vt-fra-quarter-scale.toml"
    with pytest.raises(ParameterError, match="not found"):
        resolve_rig(tmp_path / "missing.toml")


class _Dist:
    name, version = "ourlab-rigs", "1.0"


def _entry_points(points):
    def fake(*, group):
        assert group == ENTRY_POINT_GROUP
        return points

    return fake


def test_a_package_registers_a_set_through_the_entry_point_group(tmp_path, monkeypatch):
    rig_file = tmp_path / "ourlab.toml"
    rig_file.write_text(rig_set("pardubice").path.read_text("utf-8"), "utf-8")
    module = type("M", (), {"RIG_FILE": rig_file, "rig_path": staticmethod(lambda: str(rig_file))})
    monkeypatch.setitem(__import__("sys").modules, "ourlab_rigs_fake", module)
    points = [
        md.EntryPoint("ourlab-rig", "ourlab_rigs_fake:RIG_FILE", ENTRY_POINT_GROUP),
        md.EntryPoint("ourlab-callable", "ourlab_rigs_fake:rig_path", ENTRY_POINT_GROUP),
        md.EntryPoint("broken", "no_such_module_xyz:RIG", ENTRY_POINT_GROUP),
        md.EntryPoint("pardubice", "ourlab_rigs_fake:RIG_FILE", ENTRY_POINT_GROUP),
    ]
    monkeypatch.setattr(library.metadata, "entry_points", _entry_points(points))
    sets = rig_sets()
    assert sets["ourlab-rig"].path == rig_file and not sets["ourlab-rig"].problem
    assert sets["ourlab-callable"].path == rig_file
    assert "failed" in sets["broken"].problem
    assert sets["pardubice"].origin == "bundled"  # a package cannot take a bundled name
    assert any("shadowed" in s.problem for s in sets.values())
    assert load_rig_set("ourlab-rig") == default_rig()
    with pytest.raises(ParameterError, match="cannot be loaded"):
        load_rig_set("broken")
