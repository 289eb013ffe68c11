"""Report of an analysed test: the overview and rig-versus-corrected figures, and the files
write_analysis writes (JSON summary, CF NetCDF with a unit on every channel, HTML report), each
with its provenance."""

from __future__ import annotations

import json
import re

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from rollerrig.measure.quantities import ANALYSIS_CHANNELS, DERIVED_CHANNELS
from rollerrig.recordings.recording import CANONICAL_CHANNELS
from rollerrig.report.analysis import (
    analysis_columns,
    overview_figure,
    rig_versus_corrected_figure,
)

DIMENSIONLESS = {
    "creep",
    "coa",
    "creep_smoothed",
    "coa_smoothed",
    "coa_corrected",
    "coa_corrected_standard_uncertainty",
    "coa_corrected_expanded_uncertainty",
    "coa_online",
}


def _legend(ax) -> list[str]:
    return [t.get_text() for t in ax.get_legend().get_texts()]


def test_overview_figure_panels_legends_and_phases(analysed):
    fig = overview_figure(analysed)
    a, b, c = fig.axes
    assert [ax.get_ylabel() for ax in (a, b, c)] == ["torque [N·m]", "speed [rad/s]", "creep [%]"]
    assert c.get_xlabel() == "time [s]"
    assert _legend(a) == [
        "torque request (wheel)",
        "roller-shaft torque T56 (raw)",
        "T56 smoothed",
    ]
    assert _legend(b) == ["wheel (encoder)", "roller (encoder)"]
    assert _legend(c) == ["creep from encoders", "smoothed"]
    phases = sorted({ph.name for ph in analysed.phases})
    entries = [t.get_text() for t in fig.legends[0].get_texts()]
    assert entries == [p.replace("_", " ") for p in phases]  # words: "ramp up", not "ramp_up"
    assert len(a.patches) == len(analysed.phases)  # every phase shaded
    plt.close(fig)


def test_rig_versus_corrected_figure(analysed):
    fig = rig_versus_corrected_figure(analysed)
    a, b = fig.axes
    assert (a.get_xlabel(), a.get_ylabel()) == ("time [s]", "CoA [-]")
    assert (b.get_xlabel(), b.get_ylabel()) == ("creep [%]", "CoA [-]")
    assert _legend(a) == ["rig: T56 / (r_r S)", "corrected: + J5·α5 + R05"]
    fits = [e for e in _legend(b) if e.startswith("Polach fit to")]
    assert [f.split(" (")[0] for f in fits] == [
        "Polach fit to rig CoA",
        "Polach fit to corrected CoA",
    ]
    assert any(e.startswith("rig CoA, whole test") for e in _legend(b))
    plt.close(fig)


def test_analysis_channels_table_covers_every_channel_the_analysis_adds(analysed):
    rec = analysed.recording
    added = set(rec.channels) - set(CANONICAL_CHANNELS) - set(DERIVED_CHANNELS)
    assert added and added <= set(ANALYSIS_CHANNELS)


def test_a_channel_with_nan_says_why(analysed):
    rec = analysed.recording
    torque = rec["torque"].copy()
    torque[3] = np.nan
    columns = analysis_columns(rec.with_channels(torque=torque))
    assert "nan_meaning" in columns["torque"][3]
    assert columns["wheel_speed"][3] == {}
    _, unit, long_name, _ = columns["roller_acceleration"]
    assert unit == "rad/s^2" and long_name.startswith("roller angular acceleration")


def test_netcdf_is_cf_with_a_unit_and_long_name_on_every_channel(written):
    nc = next(p for p in written if p.name.endswith("-analysis.nc"))
    with xr.open_dataset(nc, engine="h5netcdf") as ds:
        assert ds.attrs["Conventions"] == "CF-1.10"
        for key in ("title", "source", "history", "provenance"):
            assert ds.attrs[key], key
        prov = json.loads(ds.attrs["provenance"])
        assert (
            prov["software"] == "rollerrig" and prov["parameters"]["source"] == "synthetic-test.csv"
        )
        assert "commit" in prov and prov["created_utc"] in ds.attrs["history"]
        json.loads(ds.attrs["analysis_notes"])  # JSON, non-finite numbers as null
        assert ds["time"].attrs["units"] == "s"
        for name, var in ds.data_vars.items():
            assert var.attrs["long_name"] and var.attrs["long_name"] != name, name
            unit = var.attrs["units"]
            assert (unit == "1") == (name in DIMENSIONLESS), (name, unit)
        # The three channels the issue found labelled "1".
        assert ds["torque_smoothed"].attrs["units"] == "N.m"
        assert ds["slip_velocity_smoothed"].attrs["units"] == "m/s"
        assert ds["roller_acceleration"].attrs["units"] == "rad/s^2"
        assert "smoothed" in ds["torque_smoothed"].attrs["long_name"]


def test_json_summary_has_provenance_and_units_in_its_keys(written, analysed):
    path = next(p for p in written if p.name.endswith("-analysis.json"))
    text = path.read_text()
    assert "NaN" not in text and "Infinity" not in text
    summary = json.loads(text)
    prov = summary["provenance"]
    assert prov["software"] == "rollerrig" and prov["version"]
    assert prov["parameters"]["source"] == "synthetic-test.csv"
    assert set(summary["phases"][0]) == {"name", "start [s]", "end [s]", "cycle"}
    assert summary["smoothing"]["window [samples]"] == analysed.smoothing_window
    assert summary["polach_fit_corrected_coa"]["B [s/m]"] is not None


def test_html_report_holds_the_figures_tables_and_provenance(written):
    names = [p.name for p in written]
    assert names == ["synthetic-analysis.json", "synthetic-analysis.nc", "synthetic-report.html"]
    html = written[2].read_text(encoding="utf-8")
    assert html.count('src="data:image/png;base64,') >= 5
    assert "<h2>Provenance</h2>" in html and "&quot;software&quot;: &quot;rollerrig&quot;" in html
    for heading in ("Phases of the test", "Smoothing-filter study"):
        assert f"<h2>{heading}" in html
    # Table headers keep their units in brackets; numbers' columns are right-aligned.
    assert re.search(r'<th class="n">start \[s\]</th>', html)
    assert '<th class="n">lag [ms]</th>' in html


def test_html_report_speaks_the_readers_language(written, analysed):
    html = written[2].read_text(encoding="utf-8")
    tables = re.findall(r"<table>.*?</table>", html, flags=re.S)
    text = " ".join(tables)
    # phases as words, cycles numbered 1..n as the console numbers them
    phases = next(t for t in tables if "<th>phase</th><th" in t and "end [s]" in t)
    assert "ramp_up" not in phases and "<td>ramp up</td>" in phases
    cycles = {int(c) for c in re.findall(r'<td>[a-z ]+</td><td class="n">(\d+)</td>', phases)}
    assert cycles == {1, 2, 3}
    assert '<td>free rolling</td><td class="n">–</td>' in phases  # before the first cycle
    # typeset units and symbols, no e-notation, no dimensionless "[-]"
    assert "N·m" in text and "N.m" not in text and "m^2" not in text and "m²" in text
    assert "W<sub>d</sub>" in text and "e<sub>res,s</sub>" in text
    assert not re.search(r"\d\.?\d*e[-+]\d", text) and "[-]" not in text
    assert "e<sub>res</sub>" in html  # the uncertainty model as a formula
    # provenance: no absolute path, every path relative to the report's folder
    provenance = html[html.index("<h2>Provenance</h2>") :]
    assert str(written[2].parent) not in provenance
    assert not re.search(r"&quot;/", provenance)


def test_coa_uncertainty_figure_shows_the_band_the_points_and_the_budget(analysed):
    from matplotlib.collections import PolyCollection

    from rollerrig.report.analysis import coa_uncertainty_figure
    from rollerrig.report.analysis_figures import _labels

    fig = coa_uncertainty_figure(analysed)
    a, z, b, c = fig.axes
    for ax in (a, z):
        assert (ax.get_xlabel(), ax.get_ylabel()) == ("time [s]", "CoA [-]")
        assert any(isinstance(p, PolyCollection) for p in ax.collections)  # the band
    assert _legend(a)[:3] == ["corrected ± U (k = 2)", "rig CoA", "corrected CoA"]
    assert (b.get_xlabel(), b.get_ylabel()) == ("creep [%]", "CoA [-]")
    assert any(e.startswith("corrected, ascending ± U") for e in _legend(b))
    labels = [t.get_text() for t in c.get_yticklabels()]
    budget = analysed.coa_uncertainty
    kinds = {r["name"] for r in budget.phases}
    # an input of zero contribution in every phase is named under the panel, not drawn
    zero = [
        n
        for n in budget.uncertainty.contributions
        if all(r["budget_sample_median [-]"][n] == 0.0 for r in budget.phases)
    ]
    assert len(labels) == len(budget.uncertainty.contributions) - len(zero)
    words = _labels(budget.uncertainty)
    assert all(words[n] not in labels and words[n] in c.get_xlabel() for n in zero)
    # this recording gives the roller speed, not encoder counts: α5's noise is the speed's
    assert "pressure sensor class" in labels
    assert "roller speed noise (α5)" in labels or "roller speed noise (α5)" in c.get_xlabel()
    assert len(c.patches) == len(labels) * len(kinds)
    plt.close(fig)


def test_results_carry_the_uncertainty(written):
    summary = json.loads(written[0].read_text())
    unc = summary["coa_uncertainty"]
    assert unc["coverage_factor"] == 2.0 and unc["phases"] and unc["curve_points"]
    assert "null_values" not in summary
    # speeds and load given by this recording: no quantisation, the pressure derived from N/A
    assert any("no air_spring_pressure" in n for n in unc["notes"])
    with xr.open_dataset(written[1], engine="h5netcdf") as ds:
        u = ds["coa_corrected_expanded_uncertainty"]
        assert u.attrs["units"] == "1" and u.attrs["coverage_factor"] == 2.0
        assert float(u.min()) > 0
    html = written[2].read_text(encoding="utf-8")
    assert "<h2>Uncertainty of the corrected CoA (JCGM 100 and JCGM 101)" in html
    assert '<th class="n">U of the mean</th>' in html and "JCGM 101 §8" in html


def test_every_input_of_the_budget_has_words():
    from rollerrig.estimation.uncertainty import INPUT_NAMES
    from rollerrig.report.analysis_figures import _BUDGET_LABELS

    assert set(INPUT_NAMES) <= set(_BUDGET_LABELS)
