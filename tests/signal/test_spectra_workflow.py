"""The one spectrum workflow: settings from the signal, the twin's modes, honest outputs.

References: synthetic recordings with known lines (the seed's AM electrical frequency
p_AM f_r, Kayaalp 4.5.2.4, 5 pole pairs, roller radius 0.452 m), an extra 37 Hz line that no
source explains (a pump, say), scipy's Welch/coherence (through the streaming estimators
tested in test_spectra_streaming.py), and the demo's own free-rolling workflow for the
CLI-versus-demo coherence.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

from rollerrig.cli import app
from rollerrig.output import json_text
from rollerrig.recordings.readers import read_recording
from rollerrig.recordings.recording import Recording, RecordingError
from rollerrig.recordings.source import open_recording
from rollerrig.recordings.writers import write_recording
from rollerrig.rig.parameters import default_rig
from rollerrig.signal.workflow import explain_recording, explain_recordings

R_ROLLER, R_WHEEL = 0.452, 0.348  # [m], the default rig (Kayaalp 4.5.1.5)
PUMP = 37.0  # [Hz], a line no source explains
RIG = default_rig()
runner = CliRunner()


def free_rolling(
    v_kmh: float,
    duration: float = 60.0,
    fs: float = 250.0,
    seed: int = 0,
    pump: float = 1.0,
    torque=None,
    encoders: bool = False,
) -> Recording:
    """Torque with the AM line, a roller order and a 37 Hz line; laser with the roller order."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(duration * fs)) / fs
    w_r, w_w = v_kmh / 3.6 / R_ROLLER, v_kmh / 3.6 / R_WHEEL
    f_r = w_r / (2 * np.pi)
    run_out = np.sin(2 * np.pi * f_r * t + 0.4)
    if torque is None:
        torque = (
            50.0
            + 3.0 * np.sin(2 * np.pi * 5 * f_r * t + 1.0)
            + 2.0 * run_out
            + pump * np.sin(2 * np.pi * PUMP * t + 0.2)
            + 0.3 * rng.standard_normal(t.size)
        )
    channels = {
        "torque": torque,
        "displacement_torque_sensor": 1e-4 * run_out + 2e-6 * rng.standard_normal(t.size),
        "normal_load": 4300.0 + 10.0 * rng.standard_normal(t.size),
    }
    units = {"torque": "N.m", "displacement_torque_sensor": "m", "normal_load": "N"}
    if encoders:
        cpr = 10_000.0  # 2500 pulses x 4 (default rig)
        channels["roller_encoder_counts"] = np.floor(w_r * t * cpr / (2 * np.pi))
        channels["wheel_encoder_counts"] = np.floor(w_w * t * cpr / (2 * np.pi))
        units["roller_encoder_counts"] = units["wheel_encoder_counts"] = "1"
    else:
        channels["roller_speed"] = w_r + 0.01 * rng.standard_normal(t.size)
        channels["wheel_speed"] = w_w + 0.01 * rng.standard_normal(t.size)
        units["roller_speed"] = units["wheel_speed"] = "rad/s"
    return Recording(t, channels, units, {"source": f"free-{v_kmh:g}kmh"})


@pytest.fixture(scope="module")
def explained():
    return explain_recording(
        free_rolling(30.0), "torque", RIG, coherence_with=("displacement_torque_sensor")
    )


def test_unexplained_line_is_stated_and_the_json_is_valid(explained):
    rows = {round(r.frequency): r for r in explained.rows}
    am = rows[15]
    assert am.source == "am_electrical" and am.label.startswith("AM electrical ×1")
    pump = rows[37]
    assert pump.source == "unexplained" and pump.delta_f is None
    assert "nearest" in pump.reason and "misses by" in pump.reason
    summary = explained.summary()
    text = json.dumps(summary, allow_nan=False)  # no NaN or inf anywhere
    row = next(r for r in summary["peaks"] if round(r["frequency_hz"]) == 37)
    assert row["explained"] is False and row["delta_f_hz"] is None and row["reason"]
    assert "unexplained" in explained.format_table()
    # The settings are stated in the JSON and in the table's caption.
    s = summary["settings"]
    assert s["segments"] >= 8 and s["resolution [Hz]"] == pytest.approx(
        250.0 / s["nperseg [samples]"]
    )
    assert "Δf" in explained.format_table() and "segments" in explained.format_table()
    assert summary["operating_point"]["normal_load_source"] == "mean of the normal_load channel"
    assert summary["twin_modes"]["operating_point"]["normal_load [N]"] == pytest.approx(4300, 1e-2)
    assert "coherence with displacement_torque_sensor [-]" in text


def test_coherence_separates_run_out_from_the_motor_line(explained):
    freqs = [round(r.frequency) for r in explained.rows]
    gamma = dict(zip(freqs, explained.coherence_at_peaks(), strict=True))
    assert gamma[3] > 0.9  # roller order 1: the shaft's run-out, seen by both sensors
    assert gamma[15] < 0.2 and gamma[37] < 0.2  # AM line and the pump: torque only
    assert explained.coherence.n_segments == explained.spectrum.n_segments >= 8


def test_no_peak_gives_an_empty_table_and_a_sentence():
    rng = np.random.default_rng(4)
    rec = free_rolling(30.0, torque=50.0 + rng.standard_normal(15_000))
    e = explain_recording(rec, "torque", RIG)
    assert e.rows == ()
    assert "no peak above the thresholds" in e.format_table()
    summary = e.summary()
    json.dumps(summary, allow_nan=False)
    assert summary["peaks"] == [] and "no peak above the thresholds" in summary["message"]


@pytest.mark.parametrize(
    ("torque", "message"),
    [
        (np.zeros(15_000), r"'torque' is constant \(0"),
        (np.full(15_000, 120.0), r"'torque' is constant \(120"),
        (np.r_[np.ones(100), 1e300, np.ones(14_899)], r"'torque' reaches 1e\+300 at sample 100"),
    ],
)
def test_unusable_channel_is_a_clear_error(torque, message):
    rec = free_rolling(30.0, torque=torque)
    with pytest.raises(RecordingError, match=message) as info:
        explain_recording(rec, "torque", RIG)
    assert str(info.value).startswith("free-30kmh:")  # the file is named


def test_missing_channels_and_speed_are_named():
    rec = free_rolling(30.0, duration=20.0)
    with pytest.raises(RecordingError, match="no channel 'laser'"):
        explain_recording(rec, "torque", RIG, coherence_with="laser")
    bare = Recording(rec.time, {"torque": rec["torque"]}, {"torque": "N.m"})
    with pytest.raises(RecordingError, match="roller_speed or roller_encoder_counts"):
        explain_recording(bare, "torque", RIG)


def test_a_roller_at_rest_gives_a_spectrum_with_the_orders_unattributed(tmp_path):
    """Issue 24, point 9: a recording at standstill was refused ("record at speed"). Its
    spectrum is a result: the peaks (the 37 Hz line and the lines the test puts in) listed,
    none attributed to a rotation order or motor line, a note saying why; the JSON is valid."""
    rec = free_rolling(30.0, duration=20.0)
    n = rec.time.size
    at_rest = rec.with_channels(roller_speed=np.zeros(n), wheel_speed=np.zeros(n))
    e = explain_recording(at_rest, "torque", RIG)
    assert e.roller_speed is None and e.operating_point.at_rest
    assert e.roller_frequency is None and e.am_frequency is None and e.modes is None
    found = [r.frequency for r in e.rows]
    assert any(abs(f - PUMP) < 0.2 for f in found)
    assert e.rows and not any(r.explained for r in e.rows)
    assert any("at rest" in n and "not attributed" in n for n in e.notes)
    assert "roller at rest" in e.caption() and "rest" in e.settings.reason
    summary = json.loads(json.dumps(e.summary(), allow_nan=False))
    assert summary["roller_speed [rad/s]"] is None
    assert "at rest" in summary["operating_point"]["roller_speed_source"]
    # A line present at rest and at speed is speed-independent (it is not k f_r).
    both = explain_recordings([rec, at_rest], "torque", RIG)
    assert any(abs(f - PUMP) < 0.2 for f in both.speed_independent)
    assert both.order_map().frequency.size == sum(len(x.rows) for x in both.spectra)
    write_recording(at_rest, tmp_path / "rest.csv")
    out = tmp_path / "out"
    result = runner.invoke(app, ["spectrum", str(tmp_path / "rest.csv"), "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "roller at rest, rotation orders unattributed" in result.output
    assert (out / "rest-spectrum.png").is_file()


def test_operating_point_from_encoders_and_default_load():
    rec = free_rolling(20.0, duration=30.0, encoders=True)
    no_load = Recording(
        rec.time, {k: v for k, v in rec.channels.items() if k != "normal_load"}, rec.units
    )
    e = explain_recording(no_load, "torque", RIG)
    op = e.operating_point
    assert op.roller_speed == pytest.approx(20 / 3.6 / R_ROLLER, rel=1e-3)
    assert op.wheel_speed == pytest.approx(20 / 3.6 / R_WHEEL, rel=1e-3)
    assert "encoder" in op.speed_source and op.normal_load == 4.3e3
    assert "4.3 kN" in op.load_source and any("default load" in n for n in e.notes)


class _ChunkedSource:
    """The chunked-source interface (as rollerrig.recordings.source.RecordingSource)."""

    def __init__(self, rec: Recording):
        self.rec = rec
        self.names = tuple(rec.channels)
        self.units = dict(rec.units)
        self.sample_rate = rec.sample_rate
        self.n_samples = rec.time.size
        self.metadata = dict(rec.metadata)

    def iter_chunks(self, names, chunk_samples):
        for a in range(0, self.n_samples, chunk_samples):
            yield {n: self.rec[n][a : a + chunk_samples] for n in names}


def test_a_roller_speed_that_is_not_steady_is_said(explained):
    # A whole adhesion test had its motor lines read "unexplained" at the mean speed with no
    # word why; steady free rolling says nothing, a speed swept by 6 % says so, streamed too.
    assert not any("not steady" in n for n in explained.notes)
    rec = free_rolling(30.0, duration=20.0)
    t = rec.time
    swept = dict(rec.channels)
    swept["roller_speed"] = rec["roller_speed"] * (1.0 + 0.06 * t / t[-1])
    rec = Recording(t, swept, rec.units, rec.metadata)
    for source in (rec, _ChunkedSource(rec)):
        e = explain_recording(source, "torque", RIG, chunk_samples=777)
        (note,) = [n for n in e.notes if "not steady" in n]
        assert "its 1 s means span" in note and "(6 % of the mean" in note
    given = explain_recording(
        rec, "torque", RIG, roller_speed=float(np.mean(swept["roller_speed"]))
    )
    assert not any("not steady" in n for n in given.notes)  # a speed given is the user's


def test_streamed_source_gives_the_same_spectrum(explained):
    rec = free_rolling(30.0)
    streamed = explain_recording(
        _ChunkedSource(rec),
        "torque",
        RIG,
        coherence_with="displacement_torque_sensor",
        chunk_samples=1001,
    )
    assert streamed.settings == explained.settings
    np.testing.assert_allclose(streamed.spectrum.power, explained.spectrum.power, rtol=1e-9)
    assert [r.label for r in streamed.rows] == [r.label for r in explained.rows]
    np.testing.assert_allclose(
        streamed.coherence.coherence, explained.coherence.coherence, atol=1e-10
    )


def test_speed_independent_line_across_recordings():
    # The 37 Hz line stays put at 10 and 30 km/h: unexplained alone, speed-independent together.
    recs = [free_rolling(v, duration=60.0, seed=int(v)) for v in (10.0, 30.0)]
    result = explain_recordings(recs, "torque", RIG)
    assert result.speed_independent == pytest.approx([PUMP], abs=0.05)
    for e in result.spectra:
        row = next(r for r in e.rows if abs(r.frequency - PUMP) < 0.1)
        assert row.source == "speed_independent" and row.delta_f is not None
    json.dumps(result.summary(), allow_nan=False)
    assert result.order_map().frequency.size == sum(len(e.rows) for e in result.spectra)


def test_cli_and_demo_give_the_same_coherence_on_the_same_file(tmp_path):
    from rollerrig.demo import explain_free_rolling

    path = write_recording(free_rolling(30.0, duration=40.0, fs=600.0), tmp_path / "run30.mf4")
    out = tmp_path / "out"
    args = ["spectrum", str(path), "--coherence", "displacement_torque_sensor"]
    r = runner.invoke(app, [*args, "--out", str(out)])
    assert r.exit_code == 0, r.output
    assert "[Hz]" in r.output and "Δf" in r.output  # units and settings printed literally
    cli = json.loads((out / "run30-spectra.json").read_text())["run30.mf4"]
    _, demo = explain_free_rolling([path], RIG)
    # The demo's numbers as the JSON writer writes them (12 significant digits).
    written = json.loads(json_text(demo.spectra[0].summary()))
    key = "coherence with displacement_torque_sensor [-]"
    assert [p[key] for p in cli["peaks"]] == [p[key] for p in written["peaks"]]
    assert cli["settings"] == written["settings"]
    roller = next(p for p in cli["peaks"] if p["label"].startswith("roller order ×1"))
    am = next(p for p in cli["peaks"] if p["label"].startswith("AM electrical ×1"))
    assert roller[key] > 0.9 and am[key] < 0.2


def test_cli_spectrum_streams_a_long_file_and_reads_it_whole_alike(tmp_path, monkeypatch):
    import rollerrig.cli as cli

    path = write_recording(free_rolling(30.0, duration=60.0), tmp_path / "run.parquet")
    whole = runner.invoke(app, ["spectrum", str(path), "--out", str(tmp_path / "a")])
    assert whole.exit_code == 0, whole.output
    monkeypatch.setattr(cli, "_SPECTRUM_IN_MEMORY", 1000)  # everything counts as long
    streamed = runner.invoke(app, ["spectrum", str(path), "--out", str(tmp_path / "b")])
    assert streamed.exit_code == 0, streamed.output
    a = json.loads((tmp_path / "a" / "run-spectra.json").read_text())["run.parquet"]
    b = json.loads((tmp_path / "b" / "run-spectra.json").read_text())["run.parquet"]
    assert a["settings"] == b["settings"]
    assert [p["label"] for p in a["peaks"]] == [p["label"] for p in b["peaks"]]
    with open_recording(path) as src:
        assert src.n_samples > 1000
    assert read_recording(path)["torque"].size == src.n_samples


def test_cli_spectrum_without_peaks_and_with_a_constant_channel(tmp_path):
    rng = np.random.default_rng(9)
    quiet = write_recording(
        free_rolling(30.0, duration=30.0, torque=50.0 + rng.standard_normal(7500)),
        tmp_path / "quiet.csv",
    )
    r = runner.invoke(app, ["spectrum", str(quiet), "--out", str(tmp_path / "q")])
    assert r.exit_code == 0, r.output
    assert "no peak above the thresholds" in r.output and "attribute_peaks" not in r.output
    flat = write_recording(
        free_rolling(30.0, duration=30.0, torque=np.zeros(7500)), tmp_path / "flat.csv"
    )
    r = runner.invoke(app, ["spectrum", str(flat), "--out", str(tmp_path / "f")])
    assert r.exit_code == 2 and "'torque' is constant" in r.output and "flat.csv" in r.output
    assert "Traceback" not in r.output and not (tmp_path / "f").exists()


def test_two_recordings_spectra_into_one_folder_keep_both_summaries(tmp_path):
    # One recording's summary is named by it, as its figure is: the second run into the same
    # --out had replaced the first's spectra.json beside the first's figure (a user's review).
    out = tmp_path / "out"
    for kmh in (10.0, 30.0):
        path = write_recording(free_rolling(kmh, duration=8.0), tmp_path / f"run{kmh:.0f}.parquet")
        r = runner.invoke(app, ["spectrum", str(path), "--out", str(out)])
        assert r.exit_code == 0, r.output
    names = {p.name for p in out.iterdir()}
    assert {"run10-spectra.json", "run30-spectra.json"} <= names
    assert "spectra.json" not in names
