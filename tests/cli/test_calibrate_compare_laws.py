"""``rollerrig calibrate --compare-laws`` (issue 19): the help shows the option with its units
([1], [N.m], [SI] survive Rich), and what cannot run is one clear error line before anything is
read or written: the comparison with --compare-drives, a single law to compare, a key of none
of the laws compared, several laws without the comparison. The comparison itself is tested on
recordings of each law in tests/calibrate/test_compare_laws.py."""

import pytest

from rollerrig.cli import app


def _flat(text: str) -> str:
    return " ".join(text.split())


def test_help_shows_compare_laws_with_its_units(runner):
    result = runner.invoke(app, ["calibrate", "--help"], terminal_width=100)
    assert result.exit_code == 0, result.output
    text = _flat(result.output)
    assert "--compare-laws" in text and "calibration-compare-laws.json" in text
    assert "BIC difference [-]" in text and "Not with --compare-drives" in text
    assert "[N.m]" in text and "[SI]" in text and "repeat it to name the laws compared" in text


@pytest.mark.parametrize(
    ("args", "start"),
    [
        (["--compare-laws", "--compare-drives"],
         "error: --compare-laws and --compare-drives (or --roller-drive compare) together "
         "would fit every drive with every law; run one comparison at a time"),
        (["--compare-laws", "--roller-drive", "compare"],
         "error: --compare-laws and --compare-drives"),
        (["--compare-laws", "--law", "fastsim"],
         "error: --compare-laws needs at least two creep laws: --law fastsim names one"),
        (["--law", "polach", "--law", "fastrip"],
         "error: --law names one creep law, got polach, fastrip; to fit several and compare "
         "them, add --compare-laws"),
        (["--compare-laws", "--law", "polach", "--law", "fastsim", "--free", "fastsim.k0"],
         "error: free parameter(s) 'fastsim.k0': not keys of the creep laws compared "
         "(polach, fastsim)"),
    ],
    ids=["with-compare-drives", "with-roller-drive-compare", "one-law",
         "several-laws-without-comparison", "key-of-no-law"],
)  # fmt: skip
def test_what_cannot_run_is_one_error_before_anything_is_read(runner, tmp_path, args, start):
    out = tmp_path / "o"
    free = [] if "--free" in args else ["--free", "polach.static_friction"]
    result = runner.invoke(
        app, ["calibrate", str(tmp_path / "missing.tdms"), *free, *args, "--out", str(out)]
    )
    assert result.exit_code == 2, result.output
    assert _flat(result.output).startswith(start), result.output
    assert "Traceback" not in result.output and not out.exists()


def test_list_keys_with_compare_laws_lists_every_compared_law_s_keys(runner):
    result = runner.invoke(app, ["calibrate", "--list-keys", "--compare-laws"])
    assert result.exit_code == 0, result.output
    keys = result.output.split()
    assert {"polach.k_slip", "fastsim.k0", "stiffness.roller_shaft"} <= set(keys)
    assert len(keys) == len(set(keys))  # the rig keys once


def test_an_invalid_fit_of_a_comparison_says_why_and_the_advice_does_not_name_it(capsys):
    # A review: "polach (winner) | valid no", then "calibrate with --law polach", the reason
    # (no convergence within the iterations) in the JSON alone.
    from types import SimpleNamespace

    from rollerrig.cli.calibrate import print_comparison

    def evidence(bic):
        return {"adequate": False, "valid": False, "information_criteria": {"BIC": bic},
                "channels": {}, "structured_channels": []}  # fmt: skip

    invalid = (
        "NOT A VALID CALIBRATION: the fit did not converge within 25 iterations: no calibrated "
        "rig is written and rollerrig analyze --calibration refuses this calibration.json"
    )
    comparison = SimpleNamespace(
        MODEL="creep law",
        winner="polach",
        adequate=False,
        evidence={"polach": evidence(1.0), "modified-fastsim": evidence(2.0)},
        ringing=[],
        discrepancy={},
        verdict=lambda: "no candidate creep law is adequate",
        calibrations={
            "polach": SimpleNamespace(warnings=[invalid], suggestion=None),
            "modified-fastsim": SimpleNamespace(
                warnings=[], suggestion="calibrate with --law polach"
            ),
        },
        losers=["modified-fastsim"],
    )
    print_comparison(comparison)
    out = capsys.readouterr()
    text = " ".join((out.out + out.err).split())
    assert "polach: not a valid fit: the fit did not converge within 25 iterations" in text
    assert "--max-iterations" in text and "--law polach" not in text
