"""Long and fast recordings: time and peak memory against recording length (issue 7, item 4).

Run from the repository root:

    python benchmarks/bench_long.py              # 1, 10 and 60 min at 19.2 kHz (~20 min)
    python benchmarks/bench_long.py --quick      # 1 and 10 min (~13 min on 2 cores)
    python benchmarks/bench_long.py --minutes 1 5 --limit 900

Data, in a temporary folder deleted after each length (at most ~5.1 GB on disk, for 60 min):

seed-like Parquet file (rows smoothing, filter study, decimation)
    4 channels at 19.2 kHz (the HBM QuantumX rate of the dissertation's laser and torque
    measurements): the seed-like torque (ramps, an adhesion peak, a 20 ms release, motor
    ripple, noise; :func:`rollerrig.signal.scoring.seed_like_torque`, repeated every minute
    with fresh noise) and three displacement channels (lines and noise), with a float64 time
    column, in Parquet row groups of 2^20 rows (~41 MB per minute). Read in chunks through the
    package's reader (:func:`rollerrig.recordings.source.open_recording` with a channel map:
    units, strict checks), so the chunked rows include the reader.
adhesion-test TDMS file (rows spectrum, analyze, filters)
    the digital twin's 30 s adhesion test (``seed-30kmh-dry``: three ramps, holds and
    releases; :func:`twin_test_pattern`, simulated once, not timed) interpolated from 1 kHz to
    19.2 kHz and repeated to the length (120 tests per hour) with fresh noise and a 2.35 kHz
    inverter line, 5 channels (torque, torque request, wheel and roller speed, normal load:
    ``analyze`` needs the load as well), written as NI TDMS the way DAQmx logs a task
    (waveform channels, ``wf_increment``, no time channel; ~44 MB per minute;
    :func:`write_test_data`).

Each case runs in its own Python subprocess; "peak" is that process's resident-set high-water
mark (``VmHWM``, i.e. ``ru_maxrss`` of a fresh process), imports and interpreter included (the
``python + imports`` line gives that floor). Time is the wall time of the work only (the common
imports excluded; the ``rollerrig`` rows include the command's own imports, matplotlib among
them, and writing its outputs). Cases:

smoothing
    Savitzky-Golay order 4 over 8525 samples (the seed's window 111 at 250 Hz, scaled to
    19.2 kHz) on all 4 channels: *chunked* (:func:`parquet_chunks` →
    :func:`rollerrig.signal.chunked.filter_chunks`, results reduced on the fly as a writer
    would consume them), *whole array* (pandas load,
    :func:`rollerrig.signal.smoothing.savitzky_golay` per column) and the *baseline* a user
    would write (``pandas.read_parquet`` + ``scipy.signal.savgol_filter`` per column; direct
    convolution, and at this window and order scipy's weights are numerically wrong: they sum
    to ~0 instead of 1, see tests/signal/test_smoothing.py);
filter study
    the seed's 51-filter study plus the Savitzky-Golay tuning (120 more) on the torque:
    *chunked* (:func:`rollerrig.signal.scoring.study_signal_from_chunks`: decimated to 250 Hz
    while reading) and the *baseline* (pandas load, the study at the full 19.2 kHz rate,
    ``analysis_rate=None``: what ``filter_study`` did before it decimated, run with today's
    smoothing; the code before issue 7 needed 104 s and 4.1 GB for 1 min, see below);
decimation
    all 4 channels to 1 kHz: *chunked* (:func:`rollerrig.signal.decimate.decimate_chunks`) and
    the *baseline* (``pandas.read_parquet`` + ``scipy.signal.resample_poly(x, 5, 96)``);
spectrum
    ``rollerrig spectrum FILE.tdms`` (the one spectrum workflow: Welch over segments, settings
    from the signal, peaks explained; streamed from the file above 2^22 samples per channel,
    i.e. at 10 and 60 min) and the *baseline* (``nptdms.TdmsFile.read`` + ``scipy.signal.welch``
    with 2^16-sample segments + ``find_peaks``: no settings chosen, nothing explained);
analyze
    ``rollerrig analyze FILE.tdms`` (decimated to 1 kHz while read at 10 and 60 min, read whole
    and decimated at 1 min; JSON, NetCDF of the processed channels, HTML report), the same
    analysis *in memory* (``read_recording`` + ``analyze_test``) and the *baseline* of the code
    before this change: the whole file analysed at 19.2 kHz with every ascending-branch point
    in the Polach fits (``analysis_rate=19200``, no cap);
filters
    ``rollerrig filters FILE.tdms`` (streamed through
    :func:`rollerrig.signal.scoring.study_signal_from_source` at 10 and 60 min) and the same
    study *in memory* (``read_recording`` + ``prepare_study_signal``).

A case whose time or memory, extrapolated linearly from the previous length, would exceed
``--limit`` seconds (default 300) or ``--max-mb`` (default 8000, and at most 70 % of the
available memory; the machine may be shared) is skipped, with the prediction printed; the three
``rollerrig`` rows are skipped only for memory.

Measured (x86_64, 2 shared CPUs, numpy 2.4, scipy 1.17; ``python + imports`` = 179 MB;
time [s] / peak [MB]; "pred." = skipped, linear extrapolation from 10 min):

=============================================  ===========  ============  ==================
case                                            1 min        10 min        60 min
=============================================  ===========  ============  ==================
smoothing, chunked                              0.6 / 421    2.5 / 547     14.1 / 544
smoothing, whole array (ours)                   0.3 / 427    3.8 / 2251    pred. 23 / 12 612
smoothing, baseline (pandas + savgol)           16 / 399     163 / 2125    pred. 976 / 11 853
filter study, chunked (250 Hz)                  0.6 / 381    4.3 / 429     24.2 / 456
filter study, baseline (19.2 kHz)               28 / 498     309 / 2458    pred. 1854 / 13 852
decimation to 1 kHz, chunked                    0.3 / 392    3.2 / 501     17.6 / 504
decimation, baseline (pandas + resample)        0.2 / 350    2.4 / 1622    pred. 15 / 8834
``rollerrig spectrum``                          1.6 / 375    5.2 / 349     13.5 / 349
spectrum, baseline (nptdms + scipy welch)       0.1 / 239    1.3 / 638     9.9 / 2832
``rollerrig analyze``                           4.0 / 367    12.7 / 511    56.6 / 995
analyze in memory (read_recording + analyze)    1.1 / 305    10.9 / 1422   62.7 / 7630
analyze, baseline (19.2 kHz, all fit points)    16.8 / 616   249 / 4226    pred. 1496 / 24 459
``rollerrig filters``                           1.8 / 385    5.7 / 365     24.1 / 407
filters in memory (read_recording + study)      0.8 / 347    7.6 / 1899    pred. 46 / 10 498
=============================================  ===========  ============  ==================

The three commands on one hour at 19.2 kHz stay within 1 GB and one minute; their peaks (and
those of the chunked rows) stay flat from 10 to 60 min but for ``analyze``, which holds the
1 kHz analysis channels (3.6 M samples per channel per hour, ~20 channels with the derived and
smoothed ones) and writes them to NetCDF. At 1 min the commands read the file whole (under
2^22 samples per channel) and their time is mostly imports, figures and the report. The
chunked rows read through ``open_recording`` (before: plain pyarrow batches, 12.5 / 536,
19.9 / 376 and 13.0 / 466 at 60 min). Before issue 7 the study (``filter_study`` +
``tune_savitzky_golay`` at 19.2 kHz) took 104 s and 4.1 GB for 1 min on this machine, and its
Savitzky-Golay candidates of order >= 4 were numerically wrong (scipy's weights).
``resample_poly``'s default filter is shorter than ours (Kaiser beta 5, ~50 dB, 10 zero
crossings against 70 dB with a stated pass band), hence its time.
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

FS = 19_200.0
CHANNELS = (
    "torque",
    "displacement_front_bearing",
    "displacement_rear_bearing",
    "displacement_torque_sensor",
)
CHANNEL_MAP = {  # the Parquet file's columns (SI units) for open_recording
    "time": {"column": "time", "unit": "s"},
    "channels": {c: {"column": c, "unit": "N.m" if c == "torque" else "m"} for c in CHANNELS},
}
ROW_GROUP = 1 << 20
SG_WINDOW, SG_ORDER = 8525, 4  # the seed's 111 samples at 250 Hz, at 19.2 kHz
TARGET_RATE = 1000.0

# The adhesion-test recording the command rows run on (NI TDMS as DAQmx/LabVIEW logs it).
TEST_UNITS = {
    "torque": "N.m",
    "torque_request": "N.m",
    "wheel_speed": "rad/s",
    "roller_speed": "rad/s",
    "normal_load": "N",
}
TEST_BLOCK = 1 << 18  # samples per TDMS segment (13.7 s at 19.2 kHz)
PWM_LINE = (2350.0, 2.0)  # [Hz], [N.m]: an inverter line far above any analysis band


# --------------------------------------------------------------------------------------------
# data
# --------------------------------------------------------------------------------------------
def write_data(path: Path, minutes: float) -> int:
    """Write the 4-channel recording to Parquet; returns the samples per channel."""
    import numpy as np
    import pyarrow as pa
    import pyarrow.parquet as pq

    from rollerrig.signal.scoring import seed_like_torque

    n = round(minutes * 60.0 * FS)
    pattern = seed_like_torque(sample_rate=FS, duration=60.0, noise=0.0).raw
    schema = pa.schema([("time", pa.float64())] + [(c, pa.float64()) for c in CHANNELS])
    with pq.ParquetWriter(path, schema, compression="snappy") as writer:
        for a in range(0, n, ROW_GROUP):
            m = min(ROW_GROUP, n - a)
            idx = a + np.arange(m)
            t = idx / FS
            rng = np.random.default_rng(a)
            cols = {"time": t, "torque": pattern[idx % pattern.size] + 5.0 * rng.standard_normal(m)}
            for k, name in enumerate(CHANNELS[1:], start=1):
                lines = 20e-6 * np.sin(2 * np.pi * 1.95 * k * t) + 5e-6 * np.sin(2 * np.pi * 98 * t)
                cols[name] = lines + 1e-6 * rng.standard_normal(m)
            writer.write_table(pa.table(cols, schema=schema), row_group_size=ROW_GROUP)
    return n


def parquet_chunks(path: str, columns):
    """Chunks of the Parquet file as float64 arrays, shape (m,) or (m, len(columns)), read
    through the package's reader (``open_recording(...).iter_chunks``: row groups, the channel
    map, SI units, strict checks), so that the chunked rows cover the reader too."""
    import numpy as np

    from rollerrig.recordings.source import open_recording

    with open_recording(path, CHANNEL_MAP, channels=columns) as src:
        for chunk in src.iter_chunks(tuple(columns), ROW_GROUP):
            cols = [chunk[c] for c in columns]
            yield cols[0] if len(cols) == 1 else np.column_stack(cols)


def twin_test_pattern(path: Path) -> None:
    """One 30 s adhesion test of the digital twin (seed-30kmh-dry, 1 kHz), saved as ``.npz``.

    The twin's clean roller-shaft torque plus the disturbance lines the synthetic DAQ adds
    (:func:`rollerrig.recordings.synthetic.synthetic_recording`: motor lines, ripple, orders),
    the torque request, wheel and roller speeds, normal load and the true contact CoA.
    """
    import numpy as np

    from rollerrig.recordings.synthetic import synthetic_recording
    from rollerrig.rig.parameters import default_rig
    from rollerrig.solve.simulation import Simulation

    ds = Simulation(default_rig(), "seed-30kmh-dry", output_rate=1000.0).run()
    _, truth = synthetic_recording(ds, sample_rate=1000.0, seed=1)
    np.savez(
        path,
        time=truth["time"].values,
        torque=truth["torque_clean"].values + truth["torque_lines"].values,
        **{c: truth[c].values for c in TEST_UNITS if c != "torque"},
    )


def write_test_data(path: Path, minutes: float, pattern: Path) -> int:
    """The twin's adhesion test at 19.2 kHz, repeated to ``minutes``, as an NI TDMS file.

    Every 30 s test of :func:`twin_test_pattern` is interpolated linearly from 1 kHz to
    19.2 kHz and repeated (3 cycles each: ramps, holds, releases; 120 tests per hour) with fresh
    white noise at 19.2 kHz (torque 1 N.m, speeds 1e-3 rad/s, load 20 N rms) and an inverter
    line at 2.35 kHz (2 N.m) that the decimation must not alias. Written the way DAQmx logs a
    task: one group, waveform channels (``wf_increment``, no time channel), one segment per
    2^18 samples. Returns the samples per channel.
    """
    import numpy as np
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    pat = np.load(pattern)
    t_pat = pat["time"] - pat["time"][0]
    period = float(t_pat[-1])
    n = round(minutes * 60.0 * FS)
    with TdmsWriter(str(path)) as writer:
        for a in range(0, n, TEST_BLOCK):
            m = min(TEST_BLOCK, n - a)
            t = (a + np.arange(m)) / FS
            tb = np.mod(t, period)
            rng = np.random.default_rng(a)
            cols = {c: np.interp(tb, t_pat, pat[c]) for c in TEST_UNITS}
            cols["torque"] += rng.standard_normal(m) + PWM_LINE[1] * np.sin(
                2 * np.pi * PWM_LINE[0] * t
            )
            for c in ("wheel_speed", "roller_speed"):
                cols[c] += 1e-3 * rng.standard_normal(m)
            cols["normal_load"] += 20.0 * rng.standard_normal(m)
            objects = [RootObject({"name": "bench_long"}), GroupObject("QuantumX")]
            for c, unit in TEST_UNITS.items():
                props = {
                    "wf_start_offset": 0.0,
                    "wf_increment": 1.0 / FS,
                    "wf_samples": m,
                    "unit_string": unit,
                }
                objects.append(ChannelObject("QuantumX", c, cols[c], properties=props))
            writer.write_segment(objects)
    return n


# --------------------------------------------------------------------------------------------
# cases (each runs in a subprocess: `python bench_long.py --case NAME --file PATH`)
# --------------------------------------------------------------------------------------------
def case_imports(path: str) -> dict:
    return {}


def case_smooth_chunked(path: str) -> dict:
    import numpy as np

    from rollerrig.signal.chunked import filter_chunks

    acc = np.zeros(len(CHANNELS))
    stream = filter_chunks(
        parquet_chunks(path, CHANNELS), "savitzky_golay", window=SG_WINDOW, order=SG_ORDER
    )
    for piece in stream:
        acc += piece.sum(axis=0)  # stands in for writing the chunk out
    return {"checksum": float(acc[0])}


def case_smooth_whole(path: str) -> dict:
    import pandas as pd

    from rollerrig.signal.smoothing import savitzky_golay

    frame = pd.read_parquet(path)
    out = {c: savitzky_golay(frame[c].to_numpy(), SG_WINDOW, SG_ORDER) for c in CHANNELS}
    return {"checksum": float(out["torque"].sum())}


def case_smooth_baseline(path: str) -> dict:
    import pandas as pd
    from scipy.signal import savgol_filter

    frame = pd.read_parquet(path)
    out = {c: savgol_filter(frame[c].to_numpy(), SG_WINDOW, SG_ORDER) for c in CHANNELS}
    return {"checksum": float(out["torque"].sum())}


def case_study_chunked(path: str) -> dict:
    from rollerrig.signal.scoring import study_signal_from_chunks

    sig = study_signal_from_chunks(parquet_chunks(path, ["torque"]), FS)
    rows = sig.filter_study()
    order, window, _ = sig.tune_savitzky_golay()
    return {"best": rows[0].label, "sg": f"order {order}, window {window}"}


def case_study_baseline(path: str) -> dict:
    import pandas as pd

    from rollerrig.signal.scoring import filter_study, tune_savitzky_golay

    frame = pd.read_parquet(path)
    t, x = frame["time"].to_numpy(), frame["torque"].to_numpy()
    rows = filter_study(t, x, analysis_rate=None)
    order, window, _ = tune_savitzky_golay(t, x, analysis_rate=None)
    return {"best": rows[0].label, "sg": f"order {order}, window {window}"}


def case_decimate_chunked(path: str) -> dict:
    from rollerrig.signal.decimate import decimate_chunks

    count = 0
    for piece in decimate_chunks(parquet_chunks(path, CHANNELS), FS, TARGET_RATE):
        count += piece.shape[0]
    return {"samples_out": count}


def case_decimate_baseline(path: str) -> dict:
    import pandas as pd
    from scipy.signal import resample_poly

    frame = pd.read_parquet(path)
    out = resample_poly(frame[list(CHANNELS)].to_numpy(), 5, 96, axis=0)
    return {"samples_out": int(out.shape[0])}


def _command(*args: str) -> dict:
    """Run one ``rollerrig`` command in this process (as the console script would)."""
    from rollerrig.cli import app

    out = tempfile.mkdtemp(prefix="rollerrig-bench-out-")
    try:
        code = app([*args, "--out", out], standalone_mode=False)
        if code not in (None, 0):
            raise SystemExit(f"rollerrig {args[0]} exited with {code}")
        return {"written_MB": sum(p.stat().st_size for p in Path(out).rglob("*")) / 2**20}
    finally:
        shutil.rmtree(out, ignore_errors=True)


def case_cli_spectrum(path: str) -> dict:
    return _command("spectrum", path)


def case_spectrum_baseline(path: str) -> dict:
    import numpy as np
    from nptdms import TdmsFile
    from scipy.signal import find_peaks, welch

    x = TdmsFile.read(path)["QuantumX"]["torque"][:]
    _, p = welch(x, FS, nperseg=1 << 16)  # 0.29 Hz bins, Hann, 50 % overlap
    peaks = find_peaks(10 * np.log10(p), prominence=6.0)[0]
    return {"peaks": int(peaks.size)}


def case_cli_analyze(path: str) -> dict:
    return _command("analyze", path)


def case_analyze_whole(path: str) -> dict:
    from rollerrig.analysis.adhesion import analyze_test
    from rollerrig.recordings.readers import read_recording

    result = analyze_test(read_recording(path))  # in memory, decimated to 1 kHz there
    return {"mu0": round(result.fit.parameters.static_friction, 4)}


def case_analyze_fullrate(path: str) -> dict:
    from rollerrig.analysis.adhesion import analyze_test
    from rollerrig.recordings.readers import read_recording

    # what `analyze` did before issue 7: every sample at 19.2 kHz, every ascending-branch point
    result = analyze_test(read_recording(path), analysis_rate=FS, max_fit_points=1 << 40)
    return {"mu0": round(result.fit.parameters.static_friction, 4)}


def case_cli_filters(path: str) -> dict:
    return _command("filters", path)


def case_filters_whole(path: str) -> dict:
    from rollerrig.recordings.readers import read_recording
    from rollerrig.signal.scoring import prepare_study_signal

    rec = read_recording(path, channels=["torque"])
    sig = prepare_study_signal(rec.time, rec["torque"])
    rows = sig.filter_study()
    order, window, _ = sig.tune_savitzky_golay()
    return {"best": rows[0].label, "sg": f"order {order}, window {window}"}


CASES = {name[5:]: fn for name, fn in globals().items() if name.startswith("case_")}

ROWS = [
    # (group, label, case, baseline case or None)
    ("smoothing", "chunked (row groups -> filter_chunks)", "smooth_chunked", "smooth_baseline"),
    ("smoothing", "whole array (pandas + savitzky_golay)", "smooth_whole", "smooth_baseline"),
    ("smoothing", "baseline: pandas + scipy savgol_filter", "smooth_baseline", None),
    ("filter study", "chunked, decimated to 250 Hz", "study_chunked", "study_baseline"),
    ("filter study", "baseline: pandas + study at 19.2 kHz", "study_baseline", None),
    ("decimation", "chunked (decimate_chunks) -> 1 kHz", "decimate_chunked", "decimate_baseline"),
    ("decimation", "baseline: pandas + resample_poly", "decimate_baseline", None),
    ("spectrum", "rollerrig spectrum FILE.tdms", "cli_spectrum", "spectrum_baseline"),
    ("spectrum", "baseline: nptdms whole + scipy welch", "spectrum_baseline", None),
    ("analyze", "rollerrig analyze FILE.tdms", "cli_analyze", "analyze_fullrate"),
    ("analyze", "whole file in memory + analyze_test", "analyze_whole", None),
    ("analyze", "baseline: whole file at 19.2 kHz, all points", "analyze_fullrate", None),
    ("filters", "rollerrig filters FILE.tdms", "cli_filters", "filters_whole"),
    ("filters", "whole file in memory + filter study", "filters_whole", None),
]

# Cases that run on the adhesion-test TDMS file (the others on the seed-like Parquet file).
TEST_FILE_CASES = {
    "cli_spectrum",
    "spectrum_baseline",
    "cli_analyze",
    "analyze_whole",
    "analyze_fullrate",
    "cli_filters",
    "filters_whole",
}
# The commands: measured at every length whatever their predicted time (memory cap still holds).
ALWAYS = {"cli_spectrum", "cli_analyze", "cli_filters"}


def run_child(case: str, path: str) -> None:
    """Child process: run one case, print one JSON line (seconds, peak MB, extras)."""
    import resource

    fn = CASES[case]
    # import what the cases import before timing, so that the time is the work only
    for module in ("numpy", "pandas", "pyarrow.parquet", "scipy.signal", "nptdms",
                   "rollerrig.signal.chunked", "rollerrig.signal.decimate",
                   "rollerrig.signal.scoring", "rollerrig.recordings.source"):  # fmt: skip
        importlib.import_module(module)

    start = time.perf_counter()
    extra = fn(path)
    seconds = time.perf_counter() - start
    print(json.dumps({"seconds": seconds, "peak_MB": _peak_mb(resource), **extra}))


def _peak_mb(resource) -> float:
    """This process's resident high-water mark [MB].

    ``VmHWM`` where Linux gives it: ``ru_maxrss`` of a child started by ``fork`` + ``exec``
    starts from the parent's high-water mark (Linux keeps ``signal->maxrss`` across exec), so
    a large driver would inflate every case; ``VmHWM`` belongs to the new address space.
    """
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


# --------------------------------------------------------------------------------------------
# driver
# --------------------------------------------------------------------------------------------
def _available_mb() -> float:
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return float("inf")


def measure(case: str, path: Path, limit: float) -> dict:
    cmd = [sys.executable, __file__, "--case", case, "--file", str(path)]
    try:
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=1.5 * limit + 60)
    except subprocess.TimeoutExpired:
        return {"error": f"timeout > {1.5 * limit + 60:.0f} s"}
    if done.returncode != 0:
        tail = (done.stderr.strip().splitlines() or ["?"])[-1]
        return {"error": f"failed ({tail[:80]})"}
    return json.loads(done.stdout.strip().splitlines()[-1])


def predict(history: dict, case: str, minutes: float, floor_mb: float):
    """Linear extrapolation (seconds, MB) from the longest measured length, or None."""
    past = [(m, r) for m, r in history.get(case, []) if "seconds" in r]
    if not past:
        return None
    m0, r0 = max(past, key=lambda p: p[0])
    k = minutes / m0
    return r0["seconds"] * k, floor_mb + max(r0["peak_MB"] - floor_mb, 0.0) * k


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="1 and 10 min only")
    parser.add_argument("--minutes", type=float, nargs="+", help="lengths to run [min]")
    parser.add_argument("--limit", type=float, default=300.0, help="skip cases predicted above [s]")
    parser.add_argument(
        "--max-mb", type=float, default=8000.0, help="skip cases predicted above [MB]"
    )
    parser.add_argument("--case", help=argparse.SUPPRESS)
    parser.add_argument("--file", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.case:
        run_child(args.case, args.file)
        return

    import numpy as np
    import scipy

    lengths = args.minutes or ([1.0, 10.0] if args.quick else [1.0, 10.0, 60.0])
    print(
        f"rollerrig long-recording benchmark - {platform.machine()}, {os.cpu_count()} CPUs, "
        f"python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}"
    )
    print(
        f"{FS:g} Hz x {len(CHANNELS)} channels (+ time) in Parquet, row groups of {ROW_GROUP} "
        f"rows; SG order {SG_ORDER} w{SG_WINDOW}; decimation to {TARGET_RATE:g} Hz; "
        f"limits {args.limit:g} s and {args.max_mb:g} MB per case\n"
    )
    history: dict[str, list] = {}
    header = f"{'length':>7s}  {'case':52s} {'time [s]':>9s} {'peak [MB]':>10s}  vs baseline"
    folder = Path(tempfile.mkdtemp(prefix="rollerrig-bench-long-"))
    try:
        floor = measure("imports", Path(os.devnull), args.limit)
        floor_mb = floor.get("peak_MB", 0.0)
        print(f"python + imports: {floor_mb:.0f} MB resident (included in every peak below)\n")
        pattern = folder / "twin-test.npz"
        start = time.perf_counter()
        twin_test_pattern(pattern)
        print(f"twin adhesion test simulated in {time.perf_counter() - start:.0f} s (not timed)\n")
        print(header)
        print("-" * len(header))
        for minutes in lengths:
            path = folder / f"rec-{minutes:g}min.parquet"
            test_path = folder / f"test-{minutes:g}min.tdms"
            start = time.perf_counter()
            n = write_data(path, minutes)
            write_test_data(test_path, minutes, pattern)
            size_mb = path.stat().st_size / 2**20
            test_mb = test_path.stat().st_size / 2**20
            print(
                f"{minutes:6g}m  data: {n:,} samples/channel, {size_mb:.0f} MB Parquet "
                f"({len(CHANNELS)} channels + time), {test_mb:.0f} MB TDMS ({len(TEST_UNITS)} "
                f"channels; written in {time.perf_counter() - start:.0f} s, not timed)"
            )
            results = {}
            for _group, _label, case, _ in ROWS:
                guess = predict(history, case, minutes, floor_mb)
                cap = min(args.max_mb, 0.7 * _available_mb())
                slow = guess and guess[0] > args.limit and case not in ALWAYS
                if guess and (slow or guess[1] > cap):
                    r = {
                        "skip": f"skipped: predicted {guess[0]:.0f} s, {guess[1]:.0f} MB",
                        "predicted": guess,
                    }
                else:
                    data = test_path if case in TEST_FILE_CASES else path
                    r = measure(case, data, args.limit if case not in ALWAYS else 1200.0)
                results[case] = r
                history.setdefault(case, []).append((minutes, r))
            for group, label, case, base in ROWS:
                r = results[case]
                name = f"{group}: {label}"
                if "seconds" not in r:
                    print(f"{minutes:6g}m  {name:52s} {r.get('skip') or r.get('error')}")
                    continue
                vs = ""
                b = results.get(base) if base else None
                if b and "seconds" in b:
                    vs = (
                        f"{b['seconds'] / r['seconds']:.1f}x faster, "
                        f"{b['peak_MB'] / r['peak_MB']:.1f}x less memory"
                    )
                elif b and "predicted" in b:
                    sec, mb = b["predicted"]
                    vs = (
                        f"~{sec / r['seconds']:.0f}x faster, ~{mb / r['peak_MB']:.0f}x less "
                        "memory (baseline predicted)"
                    )
                elif b:
                    vs = "baseline not run"
                print(f"{minutes:6g}m  {name:52s} {r['seconds']:9.1f} {r['peak_MB']:10.0f}  {vs}")
                if "best" in r:
                    print(f"{'':9s}{'':4s}(best: {r['best']}; Savitzky-Golay tuned: {r['sg']})")
            path.unlink()
            test_path.unlink()
            print()
    finally:
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
