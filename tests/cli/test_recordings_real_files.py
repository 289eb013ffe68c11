"""The commands on files written the way real acquisition software writes them (issue 7).

A short adhesion test on the twin (``vendor_files.adhesion_recording``, with an extra 37 Hz line
in the torque that nothing explains) and closed-form free-rolling recordings are written as
LabVIEW TDMS, INCA/CANape MDF4, catman ASCII, CANape CSV, PicoScope CSV, DAQmx TDMS and a raw CAN
log; ``analyze``, ``spectrum`` and ``filters`` run on them with the channel maps a user would
write. Every run ends with a result (valid JSON, no NaN, the reader's notes carried) or one
clear error line (exit 2, no traceback, nothing written); inputs are never modified; units in
brackets survive in messages (``--help``: test_options.py).
"""

import hashlib
import json
import re
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import vendor_files as vf
from rollerrig.cli import app
from rollerrig.recordings.recording import CANONICAL_CHANNELS, Recording

runner = CliRunner()


def _sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _json(path: Path):
    """Parse JSON refusing NaN/Infinity (what json.dumps writes for non-finite floats)."""

    def refuse(name):
        raise AssertionError(f"{name} written to {path.name}")

    return json.loads(path.read_text(encoding="utf-8"), parse_constant=refuse)


def _walk(obj, key=None):
    """Every (key, value) pair of a JSON document, depth first."""
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield k, v
            yield from _walk(v, k)
    elif isinstance(obj, list):
        for v in obj:
            yield from _walk(v, key)


def _frequencies(doc) -> list[float]:
    """Peak frequencies [Hz] listed anywhere in a results document."""
    out = []
    for k, v in _walk(doc):
        key = str(k).lower()
        if isinstance(v, int | float) and re.match(r"^(f|frequency)[ _\[]", key) and "hz" in key:
            out.append(float(v))
    return out


def _run(args, inputs):
    """Invoke the command; check the rules every run must keep; return the result."""
    before = [_sha(p) for p in inputs]
    result = runner.invoke(app, args)
    text = result.output
    assert "Traceback" not in text, text
    assert "[/]" not in text and "[bold" not in text, "Rich markup printed literally"
    assert [_sha(p) for p in inputs] == before, "an input file was modified"
    return result


def _assert_clean_error(result, out: Path, *fragments: str) -> str:
    assert result.exit_code == 2, result.output
    errors = [ln for ln in result.output.splitlines() if ln.startswith("error:")]
    assert len(errors) == 1, result.output
    for fragment in fragments:
        assert fragment in result.output, result.output
    assert not out.exists() or not any(out.iterdir()), "partial output after an error"
    return errors[0]


@pytest.fixture(scope="module")
def adhesion_files(tmp_path_factory):
    """The adhesion test with a 37 Hz line, as three vendor tools write it."""
    folder = tmp_path_factory.mktemp("adhesion")
    rec, _ = vf.adhesion_recording()
    return {
        "labview-tdms": vf.labview_waveform_tdms(folder, rec),
        "inca-mdf": vf.inca_canape_mdf(folder, rec),
        "catman-csv": vf.catman_ascii(folder, rec, name="catman-export.csv"),
    }


@pytest.mark.parametrize(
    "kind", [pytest.param("labview-tdms", marks=pytest.mark.slow), "inca-mdf", "catman-csv"]
)
def test_analyze_finishes_on_vendor_files_with_an_unexplained_line(adhesion_files, kind, tmp_path):
    v = adhesion_files[kind]
    cmap = v.write_map(tmp_path / "map.toml")
    out = tmp_path / "out"
    result = _run(
        ["analyze", str(v.path), "--channels", str(cmap), "--no-study", "--out", str(out)],
        [v.path, cmap],
    )
    assert result.exit_code == 0, result.output
    docs = {p.name: _json(p) for p in out.glob("*.json")}
    assert docs, "no JSON written"
    analysis = next(d for name, d in docs.items() if "analysis" in name)
    keys = {k for k, _ in _walk(analysis)}
    assert {"notes", "interpolated", "gaps"} <= keys
    # The 37 Hz line of the quiet phase is listed (explained or said to be unexplained).
    assert any(abs(f - vf.EXTRA_LINE_HZ) < 0.5 for f in _frequencies(analysis))
    notes = [n for k, v in _walk(analysis) if k == "notes" and isinstance(v, list) for n in v]
    assert notes, "the reader's notes are not carried into the results"
    if kind == "inca-mdf":  # the 10 Hz pressure group was moved onto the torque's time base
        resampled = [v for k, v in _walk(analysis) if k == "resampled" and v]
        assert resampled and "air_spring_pressure" in json.dumps(resampled)


def test_analyze_of_a_raw_can_log_is_one_clear_error(tmp_path):
    v = vf.canedge_can_mdf(tmp_path)
    cmap = v.write_map()
    out = tmp_path / "out"
    result = _run(
        ["analyze", str(v.path), "--channels", str(cmap), "--out", str(out)], [v.path, cmap]
    )
    line = _assert_clean_error(result, out, "DBC")
    assert v.path.name in line


def test_an_error_keeps_the_bracketed_map_entry(tmp_path):
    v = vf.canape_ascii_csv(tmp_path, vf.bench_recording(2.0, 250.0))
    cmap = tmp_path / "bad-map.toml"
    cmap.write_text(v.channel_map.replace('column = "Torque"', 'column = "Torq"'), "utf-8")
    out = tmp_path / "out"
    result = _run(
        ["filters", str(v.path), "--channels", str(cmap), "--out", str(out)], [v.path, cmap]
    )
    _assert_clean_error(result, out, "[channels.torque]", "Torq")


@pytest.fixture(scope="module")
def free_rolling(tmp_path_factory):
    """Free rolling at 10, 20 and 30 km/h (8 s, 250 Hz) as CANape MDF4 files, with the 37 Hz
    line at every speed."""
    folder = tmp_path_factory.mktemp("free")
    files = [
        vf.inca_canape_mdf(
            folder, vf.bench_recording(8.0, 250.0, speed_kmh=kmh, seed=kmh), name=f"run{kmh}.mf4"
        )
        for kmh in (10, 20, 30)
    ]
    cmap = files[0].write_map(folder / "canape.toml")
    return [v.path for v in files], cmap


def test_spectrum_of_several_vendor_files_finds_the_speed_independent_line(free_rolling, tmp_path):
    paths, cmap = free_rolling
    out = tmp_path / "out"
    result = _run(
        ["spectrum", *map(str, paths), "--channels", str(cmap), "--out", str(out)], [*paths, cmap]
    )
    assert result.exit_code == 0, result.output
    doc = _json(out / "spectra.json")
    fixed = next(v for k, v in doc.items() if k.startswith("speed_independent"))
    assert any(abs(f - vf.EXTRA_LINE_HZ) < 0.1 for f in fixed)
    keys = {k for k, _ in _walk(doc)}
    assert {"notes", "interpolated", "gaps"} <= keys


def _quiet_recording(duration_s=8.0, fs=250.0) -> Recording:
    """Free rolling without any line: constant torque plus a little white noise."""
    base = vf.bench_recording(duration_s, fs, extra_line_Hz=None)
    rng = np.random.default_rng(3)
    channels = dict(base.channels)
    channels["torque"] = 150.0 + 0.01 * rng.standard_normal(base.time.size)
    units = {k: CANONICAL_CHANNELS[k][0] for k in channels}
    return Recording(base.time, channels, units, {"source": "quiet"})


def test_spectrum_with_no_peaks_is_an_empty_table_not_an_error(tmp_path):
    v = vf.canape_ascii_csv(tmp_path, _quiet_recording())
    cmap = v.write_map()
    out = tmp_path / "out"
    result = _run(
        ["spectrum", str(v.path), "--channels", str(cmap), "--out", str(out)], [v.path, cmap]
    )
    assert result.exit_code == 0, result.output
    doc = _json(out / f"{v.path.stem}-spectra.json")  # one recording's: named by it
    peaks = [v for k, v in _walk(doc) if k == "peaks"]
    assert peaks and all(p == [] for p in peaks)


def test_spectrum_with_coherence_on_the_adhesion_tdms(adhesion_files, tmp_path):
    v = adhesion_files["labview-tdms"]
    cmap = v.write_map(tmp_path / "map.toml")
    out = tmp_path / "out"
    result = _run(
        [
            "spectrum",
            str(v.path),
            "--channels",
            str(cmap),
            "--coherence",
            "displacement_torque_sensor",
            "--out",
            str(out),
        ],
        [v.path, cmap],
    )
    assert result.exit_code == 0, result.output
    _json(out / f"{v.path.stem}-spectra.json")


def test_filters_ignore_an_unrelated_missing_sensor_and_say_so(tmp_path):
    # A PicoScope capture holds the torque only; the lab's map also names the load cell.
    v = vf.picoscope_csv(tmp_path, vf.bench_recording(4.0, 250.0))
    cmap = tmp_path / "lab-map.toml"
    cmap.write_text(
        v.channel_map + '\n[channels.normal_load]\ncolumn = "Fz"\nunit = "kN"\n', "utf-8"
    )
    out = tmp_path / "out"
    result = _run(
        ["filters", str(v.path), "--channels", str(cmap), "--out", str(out)], [v.path, cmap]
    )
    assert result.exit_code == 0, result.output
    doc = _json(next(out.glob("*filters.json")))
    notes = " ".join(str(n) for k, v in _walk(doc) if k == "notes" for n in v)
    assert "Fz" in notes or "normal_load" in notes
    assert {"notes", "interpolated", "gaps"} <= {k for k, _ in _walk(doc)}


def test_filters_on_a_fast_daqmx_file(tmp_path):
    v = vf.daqmx_multitask_tdms(tmp_path, duration_s=2.0)
    cmap = v.write_map()
    out = tmp_path / "out"
    result = _run(
        ["filters", str(v.path), "--channels", str(cmap), "--out", str(out)], [v.path, cmap]
    )
    assert result.exit_code == 0, result.output
    for path in out.glob("*.json"):
        _json(path)


@pytest.mark.parametrize(
    "build",
    [
        pytest.param(lambda d: vf.labview_lvm(d), id="lvm"),
        pytest.param(lambda d: vf.matlab_struct_mat(d, version="5"), id="mat5"),
        pytest.param(lambda d: vf.daqmx_multitask_tdms(d, duration_s=0.5), id="daqmx"),
        pytest.param(lambda d: vf.german_bench_csv(d), id="german-bench"),
        pytest.param(lambda d: vf.picoscope_csv(d), id="picoscope"),
    ],
)
def test_spectrum_on_other_vendor_files_ends_with_a_result_or_one_clear_error(build, tmp_path):
    # Some of these files lack what a spectrum needs (the roller speed, the torque): one error.
    v = build(tmp_path)
    cmap = v.write_map()
    out = tmp_path / "out"
    result = _run(
        ["spectrum", str(v.path), "--channels", str(cmap), "--out", str(out)], [v.path, cmap]
    )
    if result.exit_code == 0:
        _json(out / f"{v.path.stem}-spectra.json")
    else:
        _assert_clean_error(result, out, v.path.name)
