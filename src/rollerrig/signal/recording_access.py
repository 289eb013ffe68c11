"""One way to read a recording's channels, whether it is in memory or streamed from disk.

The spectrum workflow (:mod:`rollerrig.signal.workflow`) takes a
:class:`rollerrig.recordings.recording.Recording` or a chunked source (an object with
``iter_chunks``, such as :class:`rollerrig.recordings.source.RecordingSource`).
:class:`RecordingAccess` gives both the same interface: channel names and units, the rate and
length, chunks of chosen channels, per-channel (mean, first, last) in one pass, and errors that
name the recording.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence

import numpy as np

__all__ = ["DEFAULT_CHUNK", "RecordingAccess"]

DEFAULT_CHUNK = 1 << 20  # samples per chunk when streaming [samples]


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

    def stats(self, names: Sequence[str]) -> dict[str, tuple[float, float, float]]:
        """(mean, first value, last value) of each channel, in one pass when streaming."""
        names = [n for n in dict.fromkeys(names) if n in self.names]
        if not names:
            return {}
        if not self.streaming:
            out = {}
            for n in names:
                x = self.rec[n]
                out[n] = (float(np.mean(x)), float(x[0]), float(x[-1]))
            return out
        total = dict.fromkeys(names, 0.0)
        first: dict[str, float] = {}
        last: dict[str, float] = {}
        count = 0
        for chunk in self.chunks(names):
            if not chunk[0].size:
                continue
            count += chunk[0].size
            for n, x in zip(names, chunk, strict=True):
                total[n] += float(np.sum(x))
                first.setdefault(n, float(x[0]))
                last[n] = float(x[-1])
        if count == 0:
            return {}
        return {n: (total[n] / count, first[n], last[n]) for n in names}

    def block_mean_range(self, name: str, seconds: float) -> tuple[float, float] | None:
        """(least, largest) of the channel's means over consecutive blocks of ``seconds`` [s],
        in one pass when streaming; None when the channel is missing or shorter than two
        blocks. The block means smooth the noise away, so the range is the channel's drift.
        """
        if name not in self.names:
            return None
        block = max(1, round(seconds * self.sample_rate))
        means: list[float] = []
        carry = np.empty(0)
        for (x,) in self.chunks([name]):
            x = np.concatenate([carry, x]) if carry.size else x
            whole = x.size // block * block
            if whole:
                means.extend(np.mean(x[:whole].reshape(-1, block), axis=1).tolist())
            carry = x[whole:]
        if len(means) < 2 or not np.all(np.isfinite(means)):
            return None
        return float(min(means)), float(max(means))

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
