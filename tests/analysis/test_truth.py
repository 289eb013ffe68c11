"""The twin's truth of a synthetic recording (:mod:`rollerrig.analysis.truth`)."""


def test_a_truth_of_another_run_is_named_as_such():
    # The demo's perturbed truth given with its unperturbed recording had been compared with
    # it without a word (a review, 2026-12-03).
    import json
    from types import SimpleNamespace

    from rollerrig.analysis.truth import truth_mismatch

    def provenance(sha):
        return json.dumps({"rig": {"name": "r", "sha256": sha}})

    recording = {"stored_metadata": {"twin_provenance": provenance("a" * 64), "seed": 1,
                                     "experiment": "seed-30kmh-dry"}}  # fmt: skip
    same = SimpleNamespace(attrs={"provenance": provenance("a" * 64), "synthetic_seed": 1,
                                  "experiment": "seed-30kmh-dry"})  # fmt: skip
    other = SimpleNamespace(attrs={"provenance": provenance("b" * 64), "synthetic_seed": 2,
                                   "experiment": "seed-30kmh-dry"})  # fmt: skip
    assert truth_mismatch(recording, same) is None
    text = truth_mismatch(recording, other)
    assert "not this recording's" in text and "the rig" in text and "noise seed" in text
    assert truth_mismatch({}, other) is None  # a recording that says nothing: no claim


def test_a_recording_analysed_with_another_rig_than_its_own_is_named():
    # `analyze seed-30kmh-dry.tdms --rig vt-fra-quarter-scale` had printed a hold's CoA of 2.37
    # without a word, though the recording stores the rig it was made with.
    import json

    from rollerrig.analysis.truth import recorded_rig, rig_mismatch
    from rollerrig.output import rig_sha256
    from rollerrig.rig.parameters import default_rig, load_rig

    own, other = default_rig(), load_rig("vt-fra-quarter-scale")
    stored = {"rig": own.to_dict(), "twin_provenance": json.dumps(
        {"rig": {"name": own.meta.name, "sha256": rig_sha256(own)}})}  # fmt: skip
    metadata = {"stored_metadata": stored}  # as a file read back keeps it
    assert recorded_rig(metadata)["sha256"] == rig_sha256(own)
    assert rig_mismatch(metadata, own) is None
    text = rig_mismatch(metadata, other)
    assert f"made on rig {own.meta.name!r} (sha256 {rig_sha256(own)[:12]}…)" in text
    assert f"the analysis uses rig {other.meta.name!r} (sha256 {rig_sha256(other)[:12]}…)" in text
    # the keys the CoA is derived with first, with both values
    assert "they differ in geometry.roller_radius_x (0.452 there, 0.5715 here)" in text
    assert "more key(s)" in text and "analyse with the rig the recording was made on" in text

    # the same values read back to 12 digits, or renamed: the same rig
    renamed = own.to_dict()
    renamed["meta"]["name"] = "my-copy"
    renamed["pmsm"]["rated_speed"] = float(f"{renamed['pmsm']['rated_speed']:.12g}")
    assert rig_mismatch({"rig": renamed}, own) is None
    # one value changed: named; left out where a calibration replaces it
    changed = own.to_dict()
    changed["inertia"]["roller"] = 50.0
    text = rig_mismatch({"rig": changed}, own)
    assert "they differ in inertia.roller (50 there, 45 here)" in text
    assert rig_mismatch({"rig": changed}, own, ignore=["inertia.roller"]) is None
    # only a hash, or only a name
    assert "sha256 aaaaaaaaaaaa" in rig_mismatch({"rig": {"name": "r", "sha256": "a" * 64}}, own)
    assert "'other-rig'" in rig_mismatch({"rig": {"name": "other-rig"}}, own)
    assert rig_mismatch({"rig": {"name": own.meta.name}}, own) is None
    assert rig_mismatch({}, own) is None  # a recording that states no rig: no claim
