"""``rollerrig transfer``: help, a CSV curve end to end, clear errors."""

import json
import re

import numpy as np
import pytest

from rollerrig.cli import app
from rollerrig.contact import polach_creep_curve


def test_help_keeps_units(runner):
    result = runner.invoke(app, ["transfer", "--help"], terminal_width=200)
    assert result.exit_code == 0
    text = " ".join(result.output.split())
    for unit in ("[kN]", "[km/h]", "[mm]", "'creep [-]'", "'coa [-]'", "[m/s]"):
        assert unit in text, unit
    assert "transfer" in runner.invoke(app, ["--help"]).output


def _curve_csv(path):
    s = np.linspace(0.0005, 0.08, 40)
    c = polach_creep_curve(s, 4300.0, 30 / 3.6, 0.348, 0.291, 0.452, 1.89)
    rows = ["creep [-],coa [-],normal_load [kN],rolling_speed [km/h]"]
    rows += [f"{a:.9g},{b:.9g},4.3,30" for a, b in zip(s, c.adhesion_coefficient, strict=True)]
    path.write_text("\n".join(rows) + "\n")
    return path


def test_csv_end_to_end(tmp_path, runner):
    src = _curve_csv(tmp_path / "curve.csv")
    out = tmp_path / "out"
    result = runner.invoke(app, ["transfer", str(src), "--draws", "60", "--out", str(out)])
    assert result.exit_code == 0, result.output
    summary = json.loads((out / "curve-transfer.json").read_text())
    ratio = summary["transfer_factor"]["small_creepage (= creep stiffness ratio) [-]"]
    assert abs(1 / ratio - 0.757) < 0.001
    assert summary["provenance"]["inputs"]["source"]["sha256"]
    header = (out / "curve-transfer.csv").read_text().splitlines()[0]
    assert "coa_track [-]" in header and "creep [-]" in header
    assert (out / "curve-transfer.png").stat().st_size > 20_000
    assert "carried over" in summary["carried_over_as_measured"]["assumption"]


def test_load_kn_is_the_transfers_load_and_the_points_keep_a_measured_column(tmp_path, runner):
    # The help said --load-kn is the transfer's load, but a CSV with a normal_load column
    # refused it ("do not give the normal load"): the option now sets the transfer's load,
    # the points keep the file's, and the output says which load came from where.
    src = _curve_csv(tmp_path / "curve.csv")
    out = tmp_path / "out"
    args = ["transfer", str(src), "--draws", "50", "--load-kn", "6", "--out", str(out)]
    result = runner.invoke(app, args, terminal_width=400)
    assert result.exit_code == 0, result.output
    text = " ".join(result.output.split())
    assert "N = 6 kN" in text
    assert (
        "note: --load-kn 6 kN is the load of the transfer only; the points keep their measured "
        "loads (the 'normal_load' column of curve.csv, median 4.3 kN)"
    ) in text
    summary = json.loads((out / "curve-transfer.json").read_text())
    assert summary["conditions"]["normal_load [N]"] == 6000.0
    parameters = summary["provenance"]["parameters"]
    assert parameters["normal_load"].startswith("--load-kn 6 kN (the transfer's load)")
    assert parameters["rolling_speed"].startswith("30 km/h: the median of the points' speeds")
    # ... as the help says.
    result = runner.invoke(app, ["transfer", "--help"], terminal_width=200)
    assert "they keep them for the fit on the roller" in " ".join(result.output.split())


def test_load_kn_is_every_points_load_without_a_column(tmp_path, runner):
    s = np.linspace(0.0005, 0.08, 40)
    c = polach_creep_curve(s, 4300.0, 30 / 3.6, 0.348, 0.291, 0.452, 1.89)
    src = tmp_path / "bare.csv"
    rows = [f"{a:.9g},{b:.9g}" for a, b in zip(s, c.adhesion_coefficient, strict=True)]
    src.write_text("\n".join(["creep [-],coa [-]", *rows]) + "\n")
    out = tmp_path / "out"
    result = runner.invoke(app, ["transfer", str(src), "--speed-kmh", "30", "--out", str(out)])
    assert result.exit_code == 2
    # The brackets of the units are printed as written (rich markup is off).
    expected = (
        "bare.csv: no 'normal_load [N]' (or [kN]) column: give --load-kn (then every point's)"
    )
    assert expected in " ".join(result.output.split())
    args = ["transfer", str(src), "--load-kn", "4.3", "--speed-kmh", "30", "--draws", "50"]
    result = runner.invoke(app, [*args, "--out", str(out)])
    assert result.exit_code == 0, result.output
    parameters = json.loads((out / "bare-transfer.json").read_text())["provenance"]["parameters"]
    assert (
        parameters["normal_load"]
        == "--load-kn 4.3 kN, also every point's load (the file has no column for it)"
    )


def test_errors_are_one_line(tmp_path, runner):
    bad = tmp_path / "bad.csv"
    bad.write_text("creep,coa [-]\n0.1,0.2\n")
    result = runner.invoke(app, ["transfer", str(bad), "--load-kn", "4.3", "--speed-kmh", "30",
                                 "--out", str(tmp_path / "o")])  # fmt: skip
    assert result.exit_code == 2 and "has no unit" in result.output
    result = runner.invoke(app, ["transfer", str(tmp_path / "none.json"), "--out",
                                 str(tmp_path / "o")])  # fmt: skip
    assert result.exit_code == 2
    src = _curve_csv(tmp_path / "c.csv")
    result = runner.invoke(app, ["transfer", str(src), "--law", "fastsim", "--out",
                                 str(tmp_path / "o")])  # fmt: skip
    assert result.exit_code == 2
    # A negative seed was numpy's ValueError, reported as an internal error (exit 3).
    result = runner.invoke(app, ["transfer", str(src), "--seed", "-1", "--out",
                                 str(tmp_path / "o")])  # fmt: skip
    assert result.exit_code == 2 and "--seed" in result.output
    assert not (tmp_path / "o").exists()


def test_the_api_refuses_a_seed_numpy_cannot_take():
    import pytest

    from rollerrig._validation import ParameterError
    from rollerrig.analysis.transfer import transfer_curve

    with pytest.raises(ParameterError, match="seed must be an integer >= 0"):
        transfer_curve(None, None, None, "polach", draws=50, seed=-1)


def test_the_figure_in_the_format_asked(tmp_path, runner):
    src = _curve_csv(tmp_path / "curve.csv")
    out = tmp_path / "out"
    args = ["transfer", str(src), "--draws", "50", "--law", "polach", "--figure-format", "pdf"]
    result = runner.invoke(app, [*args, "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert (out / "curve-transfer.pdf").read_bytes()[:5] == b"%PDF-"
    assert not (out / "curve-transfer.png").exists()


@pytest.mark.parametrize(
    ("option", "value", "said"),
    [
        ("--contact-angle-deg", "95", "--contact-angle-deg must be in (-90, 90) deg, got 95 deg"),
        (
            "--rail-crown-radius-mm",
            "0",
            "--rail-crown-radius-mm must be >= 5 mm (a radius; a value typed in m?), got 0 mm",
        ),
        ("--curve-radius-m", "-5", "--curve-radius-m must be > 0 m, got -5 m"),
    ],
)
def test_rail_options_are_checked_as_typed(tmp_path, runner, option, value, said):
    """``--contact-angle-deg 95`` was answered "contact_angle must lie in (-pi/2, pi/2) [rad],
    got 1.658": the SI parameter, not the option the user typed (a review, 2026-12-03)."""
    src = _curve_csv(tmp_path / "curve.csv")
    result = runner.invoke(
        app, ["transfer", str(src), option, value, "--out", str(tmp_path / "out")],
        terminal_width=200,
    )  # fmt: skip
    assert result.exit_code == 2 and said in result.output, result.output
    assert not (tmp_path / "out").exists()


def test_one_speed_is_stated_everywhere(tmp_path, runner):
    # The console had said V = 31.4 km/h, the assumption 8.73 m/s, the figure "V (mean rolling
    # speed)" (it is the roller's): one speed, said the same way in every output.
    from rollerrig.analysis.transfer import ContactGeometry, read_curve_csv, transfer_curve
    from rollerrig.report.transfer import transfer_figure
    from rollerrig.rig.parameters import default_rig

    s = np.linspace(0.0005, 0.08, 40)
    kmh = np.linspace(29.0, 33.0, s.size)  # the roller's speed drifts along the test
    c = polach_creep_curve(s, 4300.0, 30 / 3.6, 0.348, 0.291, 0.452, 1.89).adhesion_coefficient
    rows = ["creep [-],coa [-],normal_load [kN],rolling_speed [km/h]"]
    rows += [f"{a:.9g},{b:.9g},4.3,{v:.6g}" for a, b, v in zip(s, c, kmh, strict=True)]
    src = tmp_path / "curve.csv"
    src.write_text("\n".join(rows) + "\n")
    out = tmp_path / "out"
    result = runner.invoke(app, ["transfer", str(src), "--draws", "50", "--out", str(out)])
    assert result.exit_code == 0, result.output
    speed = "V = 31 km/h (the median roller speed of the points fitted)"
    text = " ".join(result.output.split())
    assert f"N = 4.3 kN, {speed}" in text  # the table's title
    assert "rolling speed (V = 31 km/h, the median roller speed of the points fitted)" in text
    # any other speed says what it is: the fit's saturated points' (a diagnostic of the fit)
    others = re.findall(r"(\S+ \S+ [\d.]+) m/s", text)
    assert all(o.startswith("points' median") for o in others), others
    summary = json.loads((out / "curve-transfer.json").read_text())
    conditions = summary["conditions"]
    assert conditions["rolling_speed [km/h]"] == pytest.approx(31.0)
    assert conditions["rolling_speed_is"] == "the median roller speed of the points fitted"
    assert summary["provenance"]["parameters"]["rolling_speed"].startswith("31 km/h: the median")
    assert speed in (out / "curve-transfer.metadata.json").read_text()
    # the figure's title, from the same result
    measured = read_curve_csv(src)
    res = transfer_curve(measured, ContactGeometry.from_rig(default_rig()), draws=50)
    title = transfer_figure(res).axes[0].get_title()
    assert "V = 31 km/h" in title and "the median roller speed of the points fitted" in title
    assert "mean rolling speed" not in title


def test_console_notes_are_short_and_the_json_keeps_them_whole(tmp_path, runner):
    # Notes of 900-1100 characters had run over the console: each is now at most NOTE_MAX
    # characters, the finding first, with where the written JSON keeps it in full.
    from rollerrig.cli._console import NOTE_MAX

    src = _curve_csv(tmp_path / "curve.csv")
    out = tmp_path / "out"
    result = runner.invoke(app, ["transfer", str(src), "--draws", "50", "--out", str(out)])
    assert result.exit_code == 0, result.output
    notes = [line for line in result.output.splitlines() if line.startswith("note: ")]
    assert notes and all(len(line) <= NOTE_MAX + len("note: ") for line in notes), notes
    summary = json.loads((out / "curve-transfer.json").read_text())
    whole = summary["notes"] + summary["assumptions"]
    cut = [line for line in notes if "… (in full: " in line]
    assert cut, "the test's curve gives at least one long note"
    for line in cut:
        head, where = line.removeprefix("note: ").split(" … (in full: ")
        assert where.startswith(str(out / "curve-transfer.json"))
        assert any(w.startswith(head.rstrip(")")) for w in whole), head
