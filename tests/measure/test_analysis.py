"""End-to-end analysis of a synthetic adhesion test recorded through a real file format.

The truth is the twin's (its contact CoA and its Polach dry set, Polach 2005 Table 2); the
recording is what the rig's DAQ would write (TDMS at 250 Hz with motor lines, ripple, noise,
encoder counts), read back through the reader.
"""

import json

import numpy as np
import pytest

from rollerrig.measure.analysis import analyze_test
from rollerrig.measure.readers import read_recording
from rollerrig.measure.synthetic import synthetic_recording
from rollerrig.measure.writers import write_recording
from rollerrig.report.analysis import write_analysis
from rollerrig.rig.parameters import default_rig
from rollerrig.solve.simulation import Simulation


@pytest.fixture(scope="module")
def analysed(tmp_path_factory):
    rig = default_rig()
    ds = Simulation(rig, "seed-30kmh-dry", output_rate=1000.0).run()
    rec, truth = synthetic_recording(ds, sample_rate=250.0, seed=3)
    path = write_recording(rec, tmp_path_factory.mktemp("rec") / "test.tdms")
    result = analyze_test(read_recording(path), rig, truth=truth)
    return result, truth, path


def test_phases_are_the_protocols(analysed):
    result, _, _ = analysed
    ramps = [ph for ph in result.phases if ph.name == "ramp_up"]
    # seed-30kmh-dry: ramps start at 2, 11 and 20 s.
    np.testing.assert_allclose([ph.start for ph in ramps], [2.0, 11.0, 20.0], atol=0.02)


def test_corrected_coa_is_closer_to_the_contact_than_the_rigs(analysed):
    result, _, _ = analysed
    e = result.truth_errors
    assert e["corrected_coa_vs_true_rms [-]"] < 0.3 * e["rig_coa_vs_true_rms [-]"]


def test_fit_to_corrected_coa_approaches_the_true_dry_set(analysed):
    # True set: Polach (2005) dry, mu0 = 0.55, kA = 1.0, kS = 0.40. Measured here: the fit to
    # the corrected CoA gives mu0 0.572, kA 0.98, kS 0.38; to the rig's CoA 0.596, 0.91, 0.33.
    result, _, _ = analysed
    p, q = result.fit.parameters, result.fit_rig_coa.parameters
    assert abs(p.static_friction - 0.55) < 0.04
    assert abs(p.k_adhesion - 1.0) < 0.05 and abs(p.k_slip - 0.40) < 0.05
    assert abs(p.static_friction - 0.55) < abs(q.static_friction - 0.55)


def test_spectrum_explains_the_motor_line_and_the_shaft_mode(analysed):
    result, _, _ = analysed
    sources = {row.source for row in result.spectrum.rows}
    assert {"am_electrical", "rig_mode"} <= sources
    am1 = [r for r in result.spectrum.rows if r.label.startswith("AM electrical ×1")]
    # 5 pole pairs x roller rotation frequency at 30 km/h (r_r = 0.452 m): 14.67 Hz.
    assert am1 and abs(am1[0].frequency - 5 * (30 / 3.6) / (2 * np.pi * 0.452)) < 0.15


def test_report_and_results_are_written(analysed, tmp_path):
    result, truth, path = analysed
    paths = write_analysis(result, tmp_path, "test", source=str(path), truth=truth)
    summary = json.loads(paths[0].read_text())
    assert summary["polach_fit_corrected_coa"]["mu0"] == pytest.approx(
        result.fit.parameters.static_friction
    )
    html = paths[2].read_text()
    assert html.count("data:image/png;base64") >= 5
    assert "true (twin)" in html  # the fit table shows the truth beside the fits
