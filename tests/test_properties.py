"""Property-based tests at the boundary (issue 7, item 5): whatever a user feeds in, the readers,
the analysis, the spectrum, the filter study and their commands either give a result or stop
with one clear error; never another exception, never a partial output, never a changed input.

Inputs: files written the way acquisition software writes them (``tests/vendor_files.py``),
then corrupted (bytes overwritten), truncated (cut at any offset) or empty; and random
recordings (any length, constant, huge, NaN, random counts). Hypothesis runs a bounded number
of examples with no deadline and no example database (nothing left in the working tree).
"""

import functools
import hashlib
import json
import tempfile
import tomllib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

import vendor_files as vf
from rollerrig._validation import ParameterError
from rollerrig.cli import app
from rollerrig.recordings.readers import read_recording
from rollerrig.recordings.recording import Recording

runner = CliRunner()

FAST = settings(
    max_examples=30,
    deadline=None,
    database=None,
    derandomize=True,  # the same examples on every run; the @example()s are past findings
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
SLOW = settings(FAST, max_examples=8)


def _sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _no_nan(text: str):
    def refuse(name):
        raise ValueError(f"{name} in JSON output")

    return json.loads(text, parse_constant=refuse)


@pytest.fixture(scope="module")
def originals(tmp_path_factory):
    """Small files of every format (0.6 s at 250 Hz), with their maps as dicts."""
    folder = tmp_path_factory.mktemp("originals")
    rec = vf.bench_recording(0.6, 250.0, seed=11)
    files = {
        "tdms": vf.labview_waveform_tdms(folder, rec, segments=3),
        "daqmx": vf.daqmx_multitask_tdms(folder, duration_s=0.3, fast_rate_Hz=2000.0),
        "mf4": vf.inca_canape_mdf(folder, rec),
        "picoscope": vf.picoscope_csv(folder, rec),
        "catman": vf.catman_ascii(folder, rec, name="catman.csv"),
        "bench": vf.german_bench_csv(folder, duration_s=20),
        "lvm": vf.labview_lvm(folder, rec),
        "twincat": vf.twincat_scope_csv(folder, rec),
        "mat5": vf.matlab_struct_mat(folder, rec, version="5"),
        "mat73": vf.matlab_struct_mat(folder, rec, version="7.3"),
        "mat73cell": vf.matlab_struct_mat(
            folder, rec, version="7.3", time_cell="scalars", name="cell.mat"
        ),
    }
    return _Originals(
        {
            k: (v.path.read_bytes(), v.path.suffix, tomllib.loads(v.channel_map))
            for k, v in files.items()
        }
    )


class _Originals(dict):
    """format -> (bytes, suffix, channel map dict); a short repr for Hypothesis' reports."""

    def __repr__(self) -> str:
        return f"<vendor files: {', '.join(self)}>"


def _check_read(path: Path, cmap) -> Recording | None:
    """read_recording gives a Recording or a ParameterError naming the file; the file is kept."""
    before = _sha(path)
    try:
        rec = read_recording(path, cmap)
    except ParameterError as exc:
        assert path.name in str(exc), f"error does not name the file: {exc}"
        rec = None
    except Exception as exc:  # the property: nothing else escapes
        pytest.fail(f"{type(exc).__name__} escaped read_recording: {exc}")
    assert _sha(path) == before, "the input file was modified"
    if rec is not None:
        assert np.all(np.diff(rec.time) > 0)
        for name, values in rec.channels.items():
            assert np.all(np.isfinite(values)), name
    return rec


FORMATS = [
    "tdms",
    "daqmx",
    "mf4",
    "picoscope",
    "catman",
    "bench",
    "lvm",
    "twincat",
    "mat5",
    "mat73",
    "mat73cell",  # the time a cell array of per-sample scalars (HDF5 object references)
]


@FAST
@example(fmt="mat73", edits=[(0.4375, False, 1)])  # h5py: a dataset link resolved to None
@example(fmt="mat73", edits=[(0.4958873985541189, False, 1)])  # h5py: RuntimeError
@given(
    fmt=st.sampled_from(FORMATS),
    edits=st.lists(
        st.tuples(st.floats(0.0, 1.0), st.booleans(), st.integers(0, 255)), min_size=1, max_size=12
    ),
)
def test_corrupted_files_give_a_recording_or_a_clear_error(originals, fmt, edits):
    data, suffix, cmap = originals[fmt]
    buf = bytearray(data)
    for where, in_header, value in edits:
        span = min(len(buf), 4096) if in_header else len(buf)  # headers hold the structure
        buf[min(int(where * span), len(buf) - 1)] = value
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / f"corrupt{suffix}"
        path.write_bytes(bytes(buf))
        _check_read(path, cmap)


@FAST
@given(fmt=st.sampled_from(FORMATS), cut=st.floats(0.0, 1.0, exclude_max=True))
def test_truncated_files_give_a_recording_or_a_clear_error(originals, fmt, cut):
    data, suffix, cmap = originals[fmt]
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / f"cut{suffix}"
        path.write_bytes(data[: int(cut * len(data))])
        _check_read(path, cmap)


@pytest.mark.parametrize("fmt", FORMATS)
def test_empty_files_are_a_clear_error(originals, fmt, tmp_path):
    _, suffix, cmap = originals[fmt]
    path = tmp_path / f"empty{suffix}"
    path.write_bytes(b"")
    with pytest.raises(ParameterError) as err:
        read_recording(path, cmap)
    assert path.name in str(err.value)


# ------------------------------------------------------------------------------ random recordings


@st.composite
def recordings(draw, max_samples=400):
    """A Recording of any length and content a DAQ could deliver (and some it should not)."""
    n = draw(st.integers(2, max_samples))
    fs = draw(st.sampled_from([50.0, 250.0, 1000.0]))
    t = np.arange(n) / fs
    kind = draw(st.sampled_from(["constant", "noise", "huge", "nan", "ramp", "tiny"]))
    rng = np.random.default_rng(draw(st.integers(0, 2**16)))
    level = draw(st.sampled_from([0.0, 1.0, 150.0, -600.0]))
    torque = {
        "constant": np.full(n, level),
        "noise": level + rng.standard_normal(n),
        "huge": np.full(n, 1e300) * rng.choice([-1.0, 1.0], n),
        "nan": np.where(rng.random(n) < 0.1, np.nan, level + rng.standard_normal(n)),
        "ramp": np.linspace(0.0, 800.0, n) + rng.standard_normal(n),
        "tiny": 1e-300 * rng.standard_normal(n),
    }[kind]
    counts_per_sample = draw(st.sampled_from([0, 1, 12, 40]))
    jitter = draw(st.booleans())
    step = np.full(n, counts_per_sample) + (rng.integers(-1, 2, n) if jitter else 0)
    roller = np.cumsum(np.maximum(step, 0)).astype(float)
    wheel = np.cumsum(np.maximum(step + draw(st.integers(0, 3)), 0)).astype(float)
    pressure = np.full(n, draw(st.sampled_from([0.0, 86000.0, 5e5])))
    channels = {
        "torque": torque,
        "wheel_encoder_counts": wheel,
        "roller_encoder_counts": roller,
        "air_spring_pressure": pressure,
    }
    units = {
        "torque": "N.m",
        "wheel_encoder_counts": "1",
        "roller_encoder_counts": "1",
        "air_spring_pressure": "Pa",
    }
    return Recording(t, channels, units, {"source": "hypothesis"})


def _two_zero_samples(pressure: float = 0.0) -> Recording:
    """Found by Hypothesis: two samples of zeros (scipy's padlen ValueError escaped)."""
    z = np.zeros(2)
    channels = {
        "torque": z,
        "wheel_encoder_counts": z,
        "roller_encoder_counts": z,
        "air_spring_pressure": np.full(2, pressure),
    }
    units = {
        "torque": "N.m",
        "wheel_encoder_counts": "1",
        "roller_encoder_counts": "1",
        "air_spring_pressure": "Pa",
    }
    return Recording(np.array([0.0, 0.02]), channels, units, {"source": "hypothesis"})


def _result_or_parameter_error(func, *args, **kwargs):
    try:
        return func(*args, **kwargs)
    except ParameterError as exc:
        assert str(exc).strip()
        return None
    except Exception as exc:
        pytest.fail(f"{type(exc).__name__} escaped {func.__name__}: {exc}")


@functools.cache
def _rig():
    from rollerrig.rig.parameters import default_rig

    return default_rig()


@SLOW
@given(rec=recordings())
def test_analyze_test_gives_a_result_or_a_clear_error(rec):
    from rollerrig.analysis.adhesion import analyze_test

    _result_or_parameter_error(analyze_test, rec, _rig(), run_study=False)


def test_analyze_test_of_two_samples_is_a_clear_error():
    # Found by Hypothesis: segmentation.segment_test lets scipy's padlen ValueError escape.
    from rollerrig.analysis.adhesion import analyze_test

    _result_or_parameter_error(
        analyze_test, _two_zero_samples(pressure=86000.0), _rig(), run_study=False
    )


@FAST
@given(rec=recordings())
def test_spectrum_gives_a_result_or_a_clear_error(rec):
    rig = _rig()
    from rollerrig.measure.quantities import derive_quantities
    from rollerrig.rig.chain import modal_table
    from rollerrig.signal.spectra import explain_spectrum

    derived = _result_or_parameter_error(derive_quantities, rec, rig)
    if derived is None:
        return
    modes = [row.frequency for row in modal_table(rig) if row.frequency > 0]
    e = _result_or_parameter_error(explain_spectrum, derived, "torque", rig_modes=modes)
    if e is not None:
        json.dumps(list(e.table()), allow_nan=True)  # rows exist and are plain data


@SLOW
@example(rec=_two_zero_samples())
@given(rec=recordings(max_samples=300))
def test_filter_study_gives_a_result_or_a_clear_error(rec):
    from rollerrig.signal.scoring import filter_study, tune_savitzky_golay

    _result_or_parameter_error(filter_study, rec.time, rec["torque"])
    _result_or_parameter_error(tune_savitzky_golay, rec.time, rec["torque"])


# ------------------------------------------------------------------------------ the commands


def _csv_text(rec: Recording, header_units: bool) -> str:
    names = ["time", *rec.channels]
    units = {"time": "s", **rec.units}
    head = ",".join(f"{n} [{units[n]}]" if header_units else n for n in names)
    cols = [rec.time, *rec.channels.values()]
    rows = [",".join(repr(float(v)) for v in row) for row in zip(*cols, strict=True)]
    return "\n".join([head, *rows]) + "\n"


def _check_command(args: list[str], inputs: list[Path], out: Path) -> None:
    """Exit 0 with valid JSON (no NaN), or exit 2 with one error line and nothing written."""
    before = [_sha(p) for p in inputs]
    result = runner.invoke(app, [*args, "--out", str(out)])
    text = result.output
    assert "Traceback" not in text, text
    assert result.exit_code in (0, 2), f"exit {result.exit_code}: {text[-2000:]}"
    if result.exit_code == 2:
        errors = [ln for ln in text.splitlines() if ln.startswith("error:")]
        assert len(errors) == 1, text
        assert not out.exists() or not any(out.iterdir()), "partial output after an error"
    else:
        for path in out.glob("*.json"):
            _no_nan(path.read_text(encoding="utf-8"))
    assert [_sha(p) for p in inputs] == before, "an input file was modified"


def _command_on(rec: Recording, command: str) -> None:
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "random.csv"
        path.write_text(_csv_text(rec, header_units=True), encoding="utf-8")
        args = [command, str(path)] + (["--no-study"] if command == "analyze" else [])
        _check_command(args, [path], Path(d) / "out")


@SLOW
@example(rec=_two_zero_samples(), command="filters")
@given(rec=recordings(), command=st.sampled_from(["analyze", "spectrum", "filters"]))
def test_commands_on_random_recordings(rec, command):
    _command_on(rec, command)


def test_analyze_command_on_two_samples_is_one_clear_error():
    _command_on(_two_zero_samples(pressure=86000.0), "analyze")


@SLOW
@given(
    fmt=st.sampled_from(["tdms", "mf4", "catman", "mat73"]),
    cut=st.floats(0.05, 1.0),
    command=st.sampled_from(["spectrum", "filters"]),
)
def test_commands_on_truncated_vendor_files(originals, fmt, cut, command):
    data, suffix, cmap = originals[fmt]
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / f"cut{suffix}"
        path.write_bytes(data[: max(1, int(cut * len(data)))])
        cmap_path = Path(d) / "map.toml"
        cmap_path.write_text(_toml_dump(cmap), encoding="utf-8")
        _check_command(
            [command, str(path), "--channels", str(cmap_path)], [path, cmap_path], Path(d) / "out"
        )


def _toml_dump(data: dict, prefix: str = "") -> str:
    """Minimal TOML writer for the channel maps (tables of scalars)."""
    lines, tables = [], []
    for key, value in data.items():
        if isinstance(value, dict):
            tables.append((key, value))
        else:
            lines.append(f"{key} = {json.dumps(value)}")
    out = "\n".join(lines) + "\n"
    for key, value in tables:
        name = f"{prefix}{key}"
        if any(not isinstance(v, dict) for v in value.values()):
            out += f"\n[{name}]\n"
        out += _toml_dump(value, prefix=f"{name}.")
    return out


def test_toml_dump_round_trips_the_maps(originals):
    for _, _, cmap in originals.values():
        assert tomllib.loads(_toml_dump(cmap)) == cmap


# ----------------------------------------------------------- names, vendor files (issue 24)

NAME_TEXT = st.text(st.characters(codec="utf-8", exclude_categories=["Cs"]), max_size=80)


@FAST
@given(names=st.lists(NAME_TEXT, min_size=1, max_size=12, unique=True))
def test_every_name_maps_to_a_distinct_identifier(names):
    import re

    from rollerrig.output.varnames import MAX_NAME_LENGTH, storable_names

    for fmt in ("nc", "mat"):
        stored = storable_names(names, fmt, reserved=["time", "units"])
        assert list(stored) == names
        assert len(set(stored.values())) == len(names)
        for given_name, name in stored.items():
            assert re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", name), (given_name, name)
            assert len(name) <= MAX_NAME_LENGTH[fmt] and name not in ("time", "units")
            if re.fullmatch(r"[A-Za-z][A-Za-z0-9_]{0,62}", given_name) and given_name not in (
                "time",
                "units",
            ):
                assert name == given_name


@SLOW
@given(names=st.lists(NAME_TEXT.filter(lambda n: n.strip() not in ("", "time")), min_size=1,
                      max_size=5, unique_by=lambda n: n.strip()))  # fmt: skip
def test_netcdf_and_mat_files_take_any_channel_name_and_keep_it(names):
    import xarray as xr

    from rollerrig.output import write_table

    cols = {n: (np.arange(3.0) + i, "1") for i, n in enumerate(names)}
    with tempfile.TemporaryDirectory() as d:
        nc = write_table(Path(d) / "x.nc", cols, time=[0.0, 0.1, 0.2])
        with xr.open_dataset(nc, engine="h5netcdf") as ds:
            back = {v.attrs.get("original_name", k): v.values.tolist() for k, v in ds.items()}
        # HDF5 strings hold no NUL: the original name keeps it escaped as \x00
        expect = {n.replace("\x00", "\\x00"): i for i, n in enumerate(names)}
        assert back == {n: (np.arange(3.0) + i).tolist() for n, i in expect.items()}
        write_table(Path(d) / "x.mat", cols, time=[0.0, 0.1, 0.2])


@FAST
@given(
    magic=st.sampled_from([b"|CF,", b"DEWESOFT"]),
    tail=st.binary(max_size=64),
    suffix=st.sampled_from([".raw", ".dxd", ".d7d", ".csv", ".mf4", ".mat", ".tdms", ".txt"]),
)
def test_vendor_files_not_read_are_named_whatever_their_suffix(magic, tail, suffix):
    vendor = "imc FAMOS" if magic == b"|CF," else "Dewesoft"
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / f"file{suffix}"
        path.write_bytes(magic + tail)
        with pytest.raises(ParameterError, match=vendor):
            read_recording(path)
