"""One way to read a recording's channels, whether it is in memory or streamed from disk.

The spectrum workflow (:mod:`rollerrig.signal.workflow`) takes a
:class:`rollerrig.recordings.recording.Recording` or a chunked source (an object with
``iter_chunks``, such as :class:`rollerrig.recordings.source.RecordingSource`).
:class:`RecordingAccess` gives both the same interface: channel names and units, the rate and
length, chunks of chosen channels, per-channel statistics in one pass, and errors that
name the recording.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import NamedTuple

import numpy as np

__all__ = ["DEFAULT_CHUNK", "ChannelStats", "RecordingAccess"]

DEFAULT_CHUNK = 1 << 20  # samples per chunk when streaming [samples]


class ChannelStats(NamedTuple):
    """One channel's mean, first and last value, and the least and largest of its block means
    (None with fewer than two whole blocks or a non-finite one): the channel's drift, the
    noise averaged away."""

    mean: float
    first: float
    last: float
    block_low: float | None
    block_high: float | None


def _span(means: list[float]) -> tuple[float | None, float | None]:
    if len(means) < 2 or not np.all(np.isfinite(means)):
        return None, None
    return float(min(means)), float(max(means))


class RecordingAccess:
    """Uniform chunked access to a Recording or a chunked source (``iter_chunks``)."""

    def __init__(self, rec) -> None:
        self.rec = rec
        self.streaming = hasattr(rec, "iter_chunks") and not hasattr(rec, "channels")
        meta = getattr(rec, "metadata", {}) or {}
        self.metadata = meta
        self.source = str(meta.get("source", "") or meta.get("path", "") or "recording")
        self.names = tuple(rec.names if self.streaming else rec.channels)
        self.units = dict(rec.units)
        self.n_samples = int(rec.n_samples if self.streaming else rec.time.size)
        if self.streaming:  # a source's reader checked its time base when it opened the file
            self.sample_rate = float(rec.sample_rate)
        else:
            # A spectrum takes the samples as equally spaced: a 0.5 s gap in a Recording built
            # in Python had been read as one sample step, with no warning.
            from rollerrig.recordings.timebase import require_uniform_time

            require_uniform_time(rec.time, self.source, "the spectrum")
            self.sample_rate = float(rec.sample_rate)

    def __contains__(self, name: str) -> bool:
        return name in self.names

    def require(self, *names: str) -> None:
        """Raise the RecordingError of :meth:`fail` naming the first channel missing."""
        missing = [n for n in names if n not in self.names]
        if missing:
            raise self.fail(
                f"no channel {missing[0]!r} for the spectrum; it has {sorted(self.names)} (map "
                "it in the channel map, or choose --channel)"
            )

    def chunks(self, names: Sequence[str], size: int = DEFAULT_CHUNK) -> Iterator[tuple]:
        if self.streaming:
            for chunk in self.rec.iter_chunks(names=tuple(names), chunk_samples=size):
                yield tuple(np.asarray(chunk[n], dtype=float) for n in names)
        else:
            arrays = [self.rec[n] for n in names]
            for start in range(0, self.n_samples, size):
                yield tuple(a[start : start + size] for a in arrays)

    def stats(self, names: Sequence[str], block_seconds: float = 1.0) -> dict[str, ChannelStats]:
        """Mean, first and last value and the range of the ``block_seconds`` block means of
        each channel (:class:`ChannelStats`), in one pass when streaming."""
        names = [n for n in dict.fromkeys(names) if n in self.names]
        if not names:
            return {}
        block = max(1, round(block_seconds * self.sample_rate))
        total = dict.fromkeys(names, 0.0)
        first: dict[str, float] = {}
        last: dict[str, float] = {}
        means: dict[str, list[float]] = {n: [] for n in names}
        carry = {n: np.empty(0) for n in names}
        count = 0
        for chunk in self.chunks(names):
            if not chunk[0].size:
                continue
            count += chunk[0].size
            for n, x in zip(names, chunk, strict=True):
                total[n] += float(np.sum(x))
                first.setdefault(n, float(x[0]))
                last[n] = float(x[-1])
                x = np.concatenate([carry[n], x]) if carry[n].size else x
                whole = x.size // block * block
                if whole:
                    means[n].extend(np.mean(x[:whole].reshape(-1, block), axis=1).tolist())
                carry[n] = x[whole:]
        if count == 0:
            return {}
        return {
            n: ChannelStats(total[n] / count, first[n], last[n], *_span(means[n])) for n in names
        }

    @property
    def duration(self) -> float:
        """Time from the first to the last sample [s]."""
        if not self.streaming:
            return float(self.rec.time[-1] - self.rec.time[0])
        return float(getattr(self.rec, "duration", (self.n_samples - 1) / self.sample_rate))

    def fail(self, message: str):
        """A RecordingError ``"<source>: <message>"`` (to raise)."""
        from rollerrig.recordings.recording import RecordingError

        return RecordingError(f"{self.source}: {message}")
