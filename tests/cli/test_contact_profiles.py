"""``rollerrig contact --wheel-profile F --rail-profile F``: CONTACT on real profiles (issue 19,
point 3). Without CONTACT every misuse is one error line; with ``CONTACT_DIR`` (and
``CONTACT_SOURCE`` for its example profiles) set, a live run checks the table and the JSON."""

import json
import os

import pytest

from rollerrig.cli import app
from rollerrig.contact.cntc import contact_dir


def _one_error(result, *words):
    assert result.exit_code != 0
    lines = [ln for ln in result.output.splitlines() if ln.strip()]
    assert lines[-1].startswith("error:") and "Traceback" not in result.output
    for w in words:
        assert w in result.output, w


def test_help_names_the_profile_options(runner):
    text = runner.invoke(app, ["contact", "--help"], terminal_width=200).output
    assert "--wheel-profile" in text and "--rail-profile" in text and "CONTACT_DIR" in text


def test_one_profile_alone_is_one_error(runner, tmp_path):
    result = runner.invoke(app, ["contact", "--wheel-profile", "w.prw", "--out", str(tmp_path)])
    _one_error(result, "--wheel-profile and --rail-profile go together")


def test_a_missing_profile_file_is_one_error(runner, tmp_path):
    args = ["contact", "--wheel-profile", str(tmp_path / "none.prw"), "--rail-profile",
            str(tmp_path / "none.prr"), "--out", str(tmp_path)]  # fmt: skip
    _one_error(runner.invoke(app, args), "--wheel-profile: no such file")


def test_the_example_profiles_without_contact_name_what_is_missing(runner, tmp_path, monkeypatch):
    for name in ("CONTACT_DIR", "CONTACTDIR", "CONTACT_SOURCE"):
        monkeypatch.delenv(name, raising=False)
    args = ["contact", "--wheel-profile", "example", "--rail-profile", "example", "--out",
            str(tmp_path)]  # fmt: skip
    _one_error(runner.invoke(app, args), "CONTACT", "tools/build_contact.sh")


@pytest.mark.skipif(
    contact_dir() is None or not os.environ.get("CONTACT_SOURCE"),
    reason="CONTACT_DIR and CONTACT_SOURCE are not both set: no CONTACT build and examples",
)
def test_live_profiles_on_the_rail_and_the_roller(runner, tmp_path, monkeypatch):
    from rollerrig.cli import _contact_profiles

    monkeypatch.setattr(_contact_profiles, "PROFILE_CREEPAGES", (1e-4, 6e-3))
    args = ["contact", "--wheel-profile", "example", "--rail-profile", "example", "--out",
            str(tmp_path), "--quiet"]  # fmt: skip
    result = runner.invoke(app, args, terminal_width=200)
    assert result.exit_code == 0, result.output
    profiles = json.loads((tmp_path / "contact-report.json").read_text())["profiles"]
    factor = profiles["factor_rail_over_roller [-]"]
    # S1002 on UIC60 at 10 kN, mu 0.55 (1.391 at +-1e-4, measured 2026-11-29): the rail is the
    # stiffer contact at small creepage; both saturate at mu N at 6e-3.
    assert 1.3 < factor[0] < 1.5
    assert factor[1] == pytest.approx(1.0, abs=0.01)
