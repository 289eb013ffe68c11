"""Long and fast recordings: time and peak memory against recording length (issue 7, item 4).

Run from the repository root:

    python benchmarks/bench_long.py              # 1, 10 and 60 min at 19.2 kHz × 4 channels
    python benchmarks/bench_long.py --quick      # 1 and 10 min (a few minutes on 2 cores)
    python benchmarks/bench_long.py --minutes 1 5 --limit 900

Data: a 4-channel recording at 19.2 kHz (the HBM QuantumX rate of the dissertation's laser and
torque measurements): the seed-like torque (ramps, an adhesion peak, a 20 ms release, motor
ripple, noise; :func:`rollerrig.signal.scoring.seed_like_torque`, repeated every minute with
fresh noise) and three displacement-like channels (lines and noise), with a float64 time column,
written to Parquet (row groups of 2^20 rows, ~46 MB per minute) in a temporary folder that is
deleted after each length (at most ~2.8 GB on disk, for 60 min).

Each case runs in its own Python subprocess; "peak" is that process's resident-set high-water
mark (``VmHWM``, i.e. ``ru_maxrss`` of a fresh process), imports and interpreter included (the
``python + imports`` line gives that floor). Time is the wall time of the work only (imports
excluded). Cases:

smoothing
    Savitzky-Golay order 4 over 8525 samples (the seed's window 111 at 250 Hz, scaled to
    19.2 kHz) on all 4 channels: *chunked* (Parquet row groups → :func:`rollerrig.signal.
    chunked.filter_chunks`, results reduced on the fly as a writer would consume them), *whole
    array* (pandas load, :func:`rollerrig.signal.smoothing.savitzky_golay` per column) and the
    *baseline* a user would write (``pandas.read_parquet`` + ``scipy.signal.savgol_filter`` per
    column; direct convolution, and at this window and order scipy's weights are numerically
    wrong: they sum to ~0 instead of 1, see tests/signal/test_smoothing.py);
filter study
    the seed's 51-filter study plus the Savitzky-Golay tuning (120 more) on the torque:
    *chunked* (:func:`rollerrig.signal.scoring.study_signal_from_chunks`: decimated to 250 Hz
    while reading) and the *baseline* (pandas load, the study at the full 19.2 kHz rate,
    ``analysis_rate=None``: what ``filter_study`` did before it decimated, run with today's
    smoothing; the code before issue 7 needed 104 s and 4.1 GB for 1 min, see below);
decimation
    all 4 channels to 1 kHz: *chunked* (:func:`rollerrig.signal.decimate.decimate_chunks`) and
    the *baseline* (``pandas.read_parquet`` + ``scipy.signal.resample_poly(x, 5, 96)``).

A case whose time or memory, extrapolated linearly from the previous length, would exceed
``--limit`` seconds (default 300) or ``--max-mb`` (default 8000, and at most 70 % of the
available memory; the machine may be shared) is skipped, with the prediction printed.

Measured (x86_64, 2 shared CPUs, numpy 2.4, scipy 1.17; ``python + imports`` = 178 MB;
time [s] / peak [MB]; "pred." = skipped, linear extrapolation from 10 min):

==========================================  ===========  ============  ==================
case                                         1 min        10 min        60 min
==========================================  ===========  ============  ==================
smoothing, chunked                           0.5 / 395    2.5 / 546     12.5 / 536
smoothing, whole array (ours)                0.2 / 429    4.0 / 2249    pred. 24 / 12 606
smoothing, baseline (pandas + savgol)        16 / 402     165 / 2125    pred. 988 / 11 862
filter study, chunked (250 Hz)               0.5 / 306    3.5 / 364     19.9 / 376
filter study, baseline (19.2 kHz)            29 / 492     297 / 2455    pred. 1782 / 13 841
decimation to 1 kHz, chunked                 0.2 / 359    2.4 / 466     13.0 / 466
decimation, baseline (pandas + resample)     0.2 / 349    1.7 / 1618    pred. 10 / 8820
==========================================  ===========  ============  ==================

The chunked peaks stay flat from 10 to 60 min (allocator plateau after the first minutes).
Before issue 7 the study (``filter_study`` + ``tune_savitzky_golay`` at 19.2 kHz) took 104 s
and 4.1 GB for 1 min on this machine, and its Savitzky-Golay candidates of order >= 4 were
numerically wrong (scipy's weights). ``resample_poly``'s default filter is shorter than ours
(Kaiser beta 5, ~50 dB, 10 zero crossings against 70 dB with a stated pass band), hence its
time.
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
CHANNELS = ("torque", "displacement_front", "displacement_rear", "displacement_sensor")
ROW_GROUP = 1 << 20
SG_WINDOW, SG_ORDER = 8525, 4  # the seed's 111 samples at 250 Hz, at 19.2 kHz
TARGET_RATE = 1000.0


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
    """Row groups of the Parquet file as float64 arrays, shape (m,) or (m, len(columns)).

    HOOK(lead): once every format reads in chunks, read through
    ``rollerrig.measure.source.open_recording(path).iter_chunks(names, chunk_samples)`` here so
    that the benchmark covers the reader too.
    """
    import numpy as np
    import pyarrow.parquet as pq

    # pre_buffer=False: with pre-buffering pyarrow keeps what it read, and the resident size of a
    # chunked pass grows with the file (measured: 330 -> 800 MB over 10 min of data)
    f = pq.ParquetFile(path, pre_buffer=False)
    for batch in f.iter_batches(batch_size=ROW_GROUP, columns=list(columns)):
        cols = [batch.column(i).to_numpy(zero_copy_only=False) for i in range(batch.num_columns)]
        yield cols[0] if len(cols) == 1 else np.column_stack(cols)


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


# HOOK(lead): spectrum and analyze rows. Add cases here and rows to ROWS below, e.g.
#
# def case_spectrum_chunked(path):   # helper B's Welch over chunks
#     from rollerrig.signal.welch import welch_stream
#     s = welch_stream(parquet_chunks(path, ["torque"]), FS, nperseg=1 << 16)
#     return {"bins": int(s.frequency.size)}
#
# def case_spectrum_baseline(path):  # pandas + scipy.signal.welch on the whole column
#     ...
#
# def case_analyze_chunked(path):    # helper A2's reader -> decimate -> analyze
#     from rollerrig.measure.source import open_recording
#     from rollerrig.signal.decimate import decimate_recording
#     with open_recording(path, channel_map) as src:
#         rec = decimate_recording(src, TARGET_RATE)
#     analyze_test(rec, ...)
#
# (the analyze case needs a recording with encoder counts and air-spring pressure: write one
# from rollerrig.measure.synthetic and repeat it, as write_data repeats the seed-like torque.)

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
    # HOOK(lead): ("spectrum", "chunked (welch_stream)", "spectrum_chunked", "spectrum_baseline"),
    # HOOK(lead): ("analyze", "chunked (open_recording -> 1 kHz)", "analyze_chunked", None),
]


def run_child(case: str, path: str) -> None:
    """Child process: run one case, print one JSON line (seconds, peak MB, extras)."""
    import resource

    fn = CASES[case]
    # import what the cases import before timing, so that the time is the work only
    for module in ("numpy", "pandas", "pyarrow.parquet", "scipy.signal",
                   "rollerrig.signal.chunked", "rollerrig.signal.decimate",
                   "rollerrig.signal.scoring"):  # fmt: skip
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
        print(header)
        print("-" * len(header))
        for minutes in lengths:
            path = folder / f"rec-{minutes:g}min.parquet"
            start = time.perf_counter()
            n = write_data(path, minutes)
            size_mb = path.stat().st_size / 2**20
            print(
                f"{minutes:6g}m  data: {n:,} samples/channel, {size_mb:.0f} MB Parquet "
                f"(written in {time.perf_counter() - start:.0f} s, not timed)"
            )
            results = {}
            for _group, _label, case, _ in ROWS:
                guess = predict(history, case, minutes, floor_mb)
                cap = min(args.max_mb, 0.7 * _available_mb())
                if guess and (guess[0] > args.limit or guess[1] > cap):
                    r = {
                        "skip": f"skipped: predicted {guess[0]:.0f} s, {guess[1]:.0f} MB",
                        "predicted": guess,
                    }
                else:
                    r = measure(case, path, args.limit)
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
            print()
    finally:
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
