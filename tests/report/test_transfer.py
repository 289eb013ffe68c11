"""The roller-to-track transfer of an analysis: from memory and from its files alike, and its
report section (``rollerrig analyze --on-track``)."""

from pathlib import Path

import numpy as np
import pytest

from rollerrig.analysis.transfer import (
    ContactGeometry,
    RailGeometry,
    curve_from_analysis,
    read_analysis,
    transfer_curve,
)
from rollerrig.report.html import HtmlReport
from rollerrig.report.transfer import transfer_section
from rollerrig.rig.parameters import default_rig


def test_the_analysis_in_memory_gives_the_points_its_files_give(analysed, written):
    json_path = next(p for p in written if Path(p).name.endswith("-analysis.json"))
    from_files = read_analysis(json_path)
    in_memory = curve_from_analysis(analysed)
    assert in_memory.creep.size == from_files.creep.size > 100
    for name in ("creep", "coa", "slip_velocity", "normal_load", "rolling_speed"):
        np.testing.assert_allclose(
            getattr(in_memory, name), getattr(from_files, name), rtol=1e-6, err_msg=name
        )
    np.testing.assert_allclose(in_memory.coa_uncertainty, from_files.coa_uncertainty, rtol=1e-6)


def test_the_on_track_section_states_the_prediction_and_its_assumptions(analysed):
    rig = default_rig()
    result = transfer_curve(
        curve_from_analysis(analysed, rig),
        ContactGeometry.from_rig(rig),
        RailGeometry(),
        "polach",
        draws=60,
    )
    # The tangent rail with the roller's crown is stiffer in creep: ~1.32 at small creepage.
    assert result.stiffness_ratio == pytest.approx(1.321, abs=0.005)
    rep = HtmlReport("test")
    transfer_section(rep, result)
    html = rep.render()
    assert "On track" in html and "peak CoA (95 %)" in html
    assert "hold on the rail unchanged" in html  # the surface parameters: an assumption, said
    assert "<img" in html


def test_analyze_on_track_says_the_rail_prediction_on_the_console(
    analysed, tmp_path, monkeypatch, capsys
):
    # --on-track had written its files and said nothing of the rail on the console.
    import rollerrig.analysis.transfer as transfer
    from rollerrig.cli.recordings import _on_track_section

    real = transfer.transfer_curve
    monkeypatch.setattr(transfer, "transfer_curve", lambda *a, **k: real(*a, draws=60, **k))
    section = _on_track_section(analysed, default_rig(), tmp_path, "test")
    assert section is not None and (tmp_path / "test-transfer.csv").is_file()
    text = " ".join(capsys.readouterr().out.split())
    assert "note: on track (tangent rail, the roller's crown): peak CoA" in text
    assert "factor F_rail/F_roller at small creepage 1.32" in text
