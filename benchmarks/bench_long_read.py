"""Benchmark of reading long recordings: whole (read_recording) versus in chunks (open_recording).

Run from the repository root:

    python benchmarks/bench_long_read.py            # 1 and 10 min at 19.2 kHz (about 2 min)
    python benchmarks/bench_long_read.py --full     # adds 60 min (2.2 GB per file on disk)
    python benchmarks/bench_long_read.py --minutes 2 5

For each length it writes a 4-channel recording at 19.2 kHz (the HBM QuantumX rate of the
dissertation's torque and laser measurements; torque in kN.m, speed in rpm, pressure in bar,
displacement in mm, float64) as

- NI TDMS the way DAQmx logging writes it (one segment per second, waveform properties), and
- ASAM MDF4 the way INCA/CANape write one raster (one data group, master ``time``),

into a temporary folder (deleted at the end), then measures in a fresh subprocess each

- ``read_recording`` with a channel map (everything converted to SI, validated, in memory), and
- ``open_recording(...).iter_chunks(chunk_samples=2**20)`` over the same channels, each chunk
  reduced to a sum and a sum of squares (what a streaming analysis keeps),

and prints wall time and peak memory added by the read (over the subprocess after its imports):
``heap MB``, the peak of its anonymous resident memory (``RssAnon``, sampled every 5 ms: numpy
arrays, library buffers) over its value after the imports, and ``RSS MB``, the peak resident set
of the whole process (``ru_maxrss``, interpreter and libraries included), which also counts pages
of the file that asammdf maps into memory (page cache, given back under memory pressure). The
chunked heap stays flat with the length; the whole read grows with it.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

RATE = 19_200.0
CHANNELS = {  # file column -> (unit in the file, canonical channel)
    "T56": ("kN.m", "torque"),
    "n_roller": ("rpm", "roller_speed"),
    "p_air": ("bar", "air_spring_pressure"),
    "laser_ts": ("mm", "displacement_torque_sensor"),
}
CHUNK = 1 << 20


def _signals(t: np.ndarray) -> dict[str, np.ndarray]:
    return {
        "T56": 0.4 + 0.05 * np.sin(2 * np.pi * 13.84 * t),
        "n_roller": 300.0 + 0.5 * np.sin(2 * np.pi * 0.1 * t),
        "p_air": 2.0 + 0.01 * np.sin(2 * np.pi * 0.05 * t),
        "laser_ts": 0.02 * np.sin(2 * np.pi * 47.0 * t),
    }


def write_tdms(path: Path, n: int) -> None:
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    block = int(RATE)  # DAQmx logs about once a second
    with TdmsWriter(str(path)) as w:
        for a in range(0, n, block):
            b = min(n, a + block)
            sig = _signals(np.arange(a, b) / RATE)
            objects = [RootObject({"name": "bench"}), GroupObject("QuantumX")]
            for name, (unit, _) in CHANNELS.items():
                props = {
                    "wf_start_time": np.datetime64("2024-08-05T13:46:13", "us"),
                    "wf_start_offset": 0.0,
                    "wf_increment": 1.0 / RATE,
                    "wf_samples": b - a,
                    "unit_string": unit,
                }
                objects.append(ChannelObject("QuantumX", name, sig[name], properties=props))
            w.write_segment(objects)


def write_mf4(path: Path, n: int) -> None:
    from asammdf import MDF, Signal

    t = np.arange(n) / RATE
    sig = _signals(t)
    mdf = MDF(version="4.10")
    mdf.append(
        [Signal(sig[k], t, name=k, unit=u) for k, (u, _) in CHANNELS.items()],
        acq_name="QuantumX 19.2 kHz",
    )
    mdf.save(path, overwrite=True)
    mdf.close()


CHANNEL_MAP = {
    "channels": {canon: {"column": col, "unit": unit} for col, (unit, canon) in CHANNELS.items()}
}

_CHILD = r"""
import json, resource, sys, threading, time
import numpy as np
from rollerrig.recordings.readers import read_recording
from rollerrig.recordings.source import open_recording
import nptdms, asammdf  # imported before the baseline: library code is not the read
path, mode, cmap, chunk = sys.argv[1], sys.argv[2], json.loads(sys.argv[3]), int(sys.argv[4])

def anon_kib():
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith("RssAnon:"):
                return int(line.split()[1])
    return 0

peak = [0]
done = threading.Event()
def sample():
    while not done.is_set():
        peak[0] = max(peak[0], anon_kib())
        time.sleep(0.005)
base_anon = anon_kib()
sampler = threading.Thread(target=sample, daemon=True)
sampler.start()
start = time.perf_counter()
n = 0
if mode == "whole":
    rec = read_recording(path, cmap)
    acc = {k: (float(v.sum()), float((v * v).sum())) for k, v in rec.channels.items()}
    n = rec.time.size
else:
    with open_recording(path, cmap) as src:
        acc = {k: [0.0, 0.0] for k in src.names}
        for c in src.iter_chunks(chunk_samples=chunk):
            for k in src.names:
                v = c[k]
                acc[k][0] += float(v.sum())
                acc[k][1] += float((v * v).sum())
            n += len(c)
elapsed = time.perf_counter() - start
done.set()
sampler.join()
peak_anon = max(peak[0], anon_kib()) - base_anon
peak_rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(json.dumps({"seconds": elapsed, "anon_kib": peak_anon, "rss_kib": peak_rss, "n": n,
                  "sum": acc["torque"][0]}))
"""


def measure(path: Path, mode: str) -> dict:
    out = subprocess.run(
        [sys.executable, "-c", _CHILD, str(path), mode, json.dumps(CHANNEL_MAP), str(CHUNK)],
        check=True,
        capture_output=True,
        text=True,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--full", action="store_true", help="add a 60 min recording")
    parser.add_argument("--minutes", type=float, nargs="+", help="lengths [min]")
    args = parser.parse_args()
    minutes = args.minutes or ([1.0, 10.0, 60.0] if args.full else [1.0, 10.0])
    print(
        f"# {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}, numpy {np.__version__}"
    )
    print(f"# 4 channels x {RATE:g} Hz, float64; chunks of {CHUNK} samples")
    print(
        f"{'length':>8} {'samples/ch':>11} {'format':>6} {'file MB':>8} {'read':>8} "
        f"{'time s':>8} {'heap MB':>8} {'RSS MB':>8}"
    )
    folder = Path(tempfile.mkdtemp(prefix="rollerrig-bench-"))
    try:
        for m in minutes:
            n = round(m * 60 * RATE)
            for fmt, write in (("tdms", write_tdms), ("mf4", write_mf4)):
                path = folder / f"bench_{m:g}min.{fmt}"
                write(path, n)
                size = path.stat().st_size / 1e6
                sums = []
                for mode in ("whole", "chunks"):
                    r = measure(path, mode)
                    if r["n"] != n:
                        raise SystemExit(f"{path}: read {r['n']} samples, wrote {n}")
                    sums.append(r["sum"])
                    print(
                        f"{m:>6g} min {n:>11d} {fmt:>6} {size:>8.0f} {mode:>8} "
                        f"{r['seconds']:>8.2f} {r['anon_kib'] / 1024:>8.0f} "
                        f"{r['rss_kib'] / 1024:>8.0f}",
                        flush=True,
                    )
                if not np.isclose(sums[0], sums[1], rtol=1e-9):
                    raise SystemExit(f"{path}: chunked and whole reads disagree: {sums}")
                path.unlink()
    finally:
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    start = time.perf_counter()
    main()
    print(f"# total {time.perf_counter() - start:.0f} s")
