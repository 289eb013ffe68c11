"""Benchmark of the smoothing filters: throughput per pass and memory of the chunked path.

Run from the repository root:

    python benchmarks/bench_filters.py          # small sizes (well under a minute on 2 cores)
    python benchmarks/bench_filters.py --full   # 1 h at 19.2 kHz, 4 channels (69 M samples each)

Two tables:

1. throughput [M samples/s] of one filter pass through
   :func:`rollerrig.signal.chunked.filter_chunks` over synthetic torque-like chunks already in
   memory (generation not timed): Savitzky-Golay (order 4, 111 samples), Butterworth 2 @ 1.2 Hz
   zero-phase and causal, moving average (111), LOESS (131); and, for reference, the same pass as
   one whole-array call;
2. peak Python-heap memory (``tracemalloc``, which numpy reports its buffers to) for a 4-channel
   recording of several lengths: the chunked path (chunks generated, Savitzky-Golay streamed,
   results reduced on the fly) versus loading everything into a pandas DataFrame and calling
   ``scipy.signal.savgol_filter`` per column. The chunked peak stays flat with the length; the
   pandas one grows with it.

The baseline in table 2 is skipped when its estimated footprint exceeds half the free memory.
"""

from __future__ import annotations

import argparse
import os
import platform
import time
import tracemalloc

import numpy as np

from rollerrig.signal.chunked import filter_chunks
from rollerrig.signal.smoothing import smooth

FS_DAQ = 19_200.0
CHANNELS = 4

PASSES = [
    ("Savitzky-Golay order 4, w111", "savitzky_golay", {"window": 111, "order": 4}),
    ("Butterworth 2 @ 1.2 Hz zero-phase", "butterworth", {"cutoff": 1.2, "order": 2}),
    ("Butterworth 2 @ 1.2 Hz causal", "butterworth",
     {"cutoff": 1.2, "order": 2, "zero_phase": False}),
    ("moving average w111", "moving_average", {"window": 111}),
    ("LOESS w131", "loess", {"window": 131}),
]  # fmt: skip


def synthetic_chunk(start: int, size: int, channels: int = 1, fs: float = FS_DAQ) -> np.ndarray:
    """Torque-like samples [N·m] for global indices start..start+size: level, ripple, noise."""
    t = (start + np.arange(size)) / fs
    rng = np.random.default_rng(start)
    base = 200.0 + 100.0 * np.sin(2 * np.pi * 0.05 * t) + 15.0 * np.sin(2 * np.pi * 14.7 * t)
    out = base[:, None] + 5.0 * rng.standard_normal((size, channels))
    return out[:, 0] if channels == 1 else out


def chunk_source(total: int, chunk: int, channels: int = 1):
    for start in range(0, total, chunk):
        yield synthetic_chunk(start, min(chunk, total - start), channels)


def throughput(total: int, chunk: int, repeat: int) -> list[tuple[str, float, float]]:
    chunks = list(chunk_source(total, chunk))
    whole = np.concatenate(chunks)
    rows = []
    for label, method, params in PASSES:
        best_chunked = best_whole = np.inf
        for _ in range(repeat):
            start = time.perf_counter()
            for _piece in filter_chunks(chunks, method, sample_rate=FS_DAQ, **params):
                pass
            best_chunked = min(best_chunked, time.perf_counter() - start)
            start = time.perf_counter()
            smooth(whole, method, sample_rate=FS_DAQ, **params)
            best_whole = min(best_whole, time.perf_counter() - start)
        rows.append((label, total / best_chunked / 1e6, total / best_whole / 1e6))
    return rows


def chunked_peak(total: int, chunk: int) -> tuple[float, float]:
    """Peak heap [MiB] and seconds of streaming SG over 4 generated channels (result reduced)."""
    tracemalloc.start()
    start = time.perf_counter()
    acc = np.zeros(CHANNELS)
    for piece in filter_chunks(
        chunk_source(total, chunk, CHANNELS), "savitzky_golay", window=111, order=4
    ):
        acc += piece.sum(axis=0)  # stands in for writing the chunk to disk
    seconds = time.perf_counter() - start
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return peak / 2**20, seconds


def pandas_peak(total: int, chunk: int) -> tuple[float, float]:
    """Peak heap [MiB] and seconds of: all chunks into a DataFrame, savgol_filter per column."""
    import pandas as pd
    from scipy.signal import savgol_filter

    tracemalloc.start()
    start = time.perf_counter()
    frame = pd.DataFrame(
        np.concatenate(list(chunk_source(total, chunk, CHANNELS))),
        columns=[f"ch{j}" for j in range(CHANNELS)],
    )
    filtered = pd.DataFrame(
        {c: savgol_filter(frame[c].to_numpy(), 111, 4, mode="interp") for c in frame.columns}
    )
    _ = filtered.sum()
    seconds = time.perf_counter() - start
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    del frame, filtered
    return peak / 2**20, seconds


def _available_bytes() -> float:
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return float("inf")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--full", action="store_true", help="1 h at 19.2 kHz, 4 channels")
    parser.add_argument("--chunk", type=int, default=1 << 20, help="samples per chunk")
    args = parser.parse_args()

    hour = int(3600 * FS_DAQ)
    through_n = hour if args.full else 1 << 23
    lengths = [hour // 16, hour // 4, hour] if args.full else [1 << 20, 1 << 22, 1 << 23]
    repeat = 1 if args.full else 2

    print(f"rollerrig filter benchmark — {platform.processor() or platform.machine()}, "
          f"{os.cpu_count()} CPUs, numpy {np.__version__}")  # fmt: skip
    print(f"chunk = {args.chunk} samples; windows in samples; fs = {FS_DAQ:g} Hz\n")

    print(f"1. throughput, one channel of {through_n:,} samples [M samples/s]")
    print(f"{'filter pass':38s} {'chunked':>10s} {'whole array':>12s}")
    for label, chunked, whole in throughput(through_n, args.chunk, repeat):
        print(f"{label:38s} {chunked:10.1f} {whole:12.1f}")

    print(f"\n2. peak heap memory, {CHANNELS} channels, Savitzky-Golay order 4 w111 [MiB]")
    print(f"{'samples/channel':>16s} {'duration':>10s} {'chunked':>9s} {'(s)':>6s} "
          f"{'pandas+scipy':>13s} {'(s)':>6s}")  # fmt: skip
    for n in lengths:
        c_peak, c_sec = chunked_peak(n, args.chunk)
        estimate = 4 * n * CHANNELS * 8
        if estimate < 0.5 * _available_bytes():
            p_peak, p_sec = pandas_peak(n, args.chunk)
            baseline = f"{p_peak:13.0f} {p_sec:6.1f}"
        else:
            baseline = f"{'skipped':>13s} {'':>6s}"
        print(f"{n:16,d} {n / FS_DAQ:9.0f}s {c_peak:9.1f} {c_sec:6.1f} {baseline}")


if __name__ == "__main__":
    main()
