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
