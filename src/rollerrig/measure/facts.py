"""What is known about a recording beyond its samples, and how to name its channels.

- :func:`recording_facts` and :func:`recording_note_lines`: what the reader and, for synthetic
  recordings, the generator said (notes, interpolated NaN runs, gaps kept, resampling, lines
  injected by hand), JSON-ready or one line each;
- :func:`true_polach_parameters` and :func:`truth_coa`: the twin's truth of a synthetic
  recording (its Polach set, its contact CoA), checked against the recording;
- :func:`describe_channel` and :func:`source_prefix`: a channel and its file as error messages
  name them (channel, file column, channel-map entry).
"""

from __future__ import annotations

import ast
import json

import numpy as np

from rollerrig.recordings.recording import Recording, RecordingError
from rollerrig.recordings.validate import describe_gap

__all__ = [
    "describe_channel",
    "friction_schedule",
    "recording_facts",
    "recording_note_lines",
    "source_prefix",
    "true_polach_parameters",
    "truth_coa",
]


def describe_channel(recording: Recording, name: str) -> str:
    """How to find a channel in the user's file: its name, file column and map entry; for a
    channel the analysis computed from others, what it was computed from."""
    derived = recording.metadata.get("derived") or {}
    if name in (derived.get("channels") or ()):
        # what it was computed from, as derive_quantities recorded it
        source = (derived.get("from") or {}).get(name)
        return f"derived channel {name!r}" + (f" (from {source})" if source else "")
    columns = recording.metadata.get("columns") or {}
    column = columns.get(name) if isinstance(columns, dict) else None
    where = f", file column {column!r}" if column else ""
    return f"channel {name!r} (map entry [channels.{name}]{where})"


def source_prefix(recording: Recording) -> str:
    """``"<file>: "`` for messages about a recording read from a file, else ``""``."""
    src = recording.metadata.get("source")
    return f"{src}: " if src else ""


def _stored(recording: Recording) -> dict:
    stored = recording.metadata.get("stored_metadata")
    return stored if isinstance(stored, dict) else {}


def recording_facts(recording: Recording) -> dict:
    """What the reader and the generator said about a recording, JSON-ready.

    Returns
    -------
    dict
        ``source``, ``format``, ``sha256``, ``validate``; ``notes`` (the reader's notes and,
        for a synthetic recording, the generator's), ``interpolated`` (NaN/inf runs filled by
        a lenient read: channel, samples, times, method), ``gaps`` (dropped samples kept by a
        lenient read), ``resampled`` (channels put on a common time base), ``injected_lines``
        (lines injected by hand into a synthetic recording, with frequency and amplitude) and
        ``synthetic``.
    """
    md = recording.metadata
    stored = _stored(recording)
    notes = [str(n) for n in (md.get("notes") or [])]
    for n in stored.get("notes") or []:
        if str(n) not in notes:
            notes.append(str(n))
    injected = list(md.get("injected_lines") or stored.get("injected_lines") or [])
    synthetic = bool(
        md.get("synthetic")
        or stored.get("synthetic")
        or md.get("source") == "synthetic"
        or stored.get("source") == "synthetic"
    )
    return {
        "source": md.get("source"),
        "format": md.get("format"),
        "sha256": md.get("sha256"),
        "validate": md.get("validate"),
        "notes": notes,
        "interpolated": list(md.get("interpolated") or []),
        "gaps": list(md.get("gaps") or []),
        "resampled": md.get("resampled"),
        "injected_lines": injected,
        "synthetic": synthetic,
    }


def recording_note_lines(recording: Recording) -> list[str]:
    """The same facts as :func:`recording_facts`, one human-readable line each."""
    facts = recording_facts(recording)
    lines = list(facts["notes"])
    for run in facts["interpolated"]:
        lines.append(
            f"interpolated NaN/inf run (lenient read): channel {run.get('channel')!r}, samples "
            f"{run.get('first_sample')}..{run.get('last_sample')} "
            f"(t = {run.get('start_s', float('nan')):.6g}..{run.get('end_s', float('nan')):.6g} s),"
            f" {run.get('method', 'linear')}"
        )
    for gap in facts["gaps"]:
        lines.append(f"gap kept (lenient read): {describe_gap(gap)}")
    for line in facts["injected_lines"]:
        text = (
            f"synthetic recording: a line at {line.get('frequency [Hz]')} Hz, "
            f"{line.get('amplitude [N.m]')} N.m on {line.get('channel', 'torque')} was INJECTED"
        )
        if not any("INJECTED" in n for n in lines):
            lines.append(text + " by hand; it is not a finding")
    return lines


def _listed(value) -> list:
    """A list stored as it is or as its text (provenance keeps ``"['dry', 'wet']"``)."""
    if isinstance(value, str):
        try:
            value = ast.literal_eval(value)
        except (ValueError, SyntaxError):
            return []
    return list(value) if isinstance(value, list | tuple) else []


def _twin_provenances(recording: Recording, truth=None):
    """(where, provenance dict) of the twin that made a synthetic recording, best first."""
    stored = _stored(recording)
    candidates = [
        ("the twin's provenance in the recording", recording.metadata.get("twin_provenance")),
        ("the twin's provenance stored in the file", stored.get("twin_provenance")),
        (
            "the truth dataset's provenance",
            None if truth is None else truth.attrs.get("provenance"),
        ),
    ]
    for where, raw in candidates:
        if raw is None:
            continue
        try:
            prov = json.loads(raw) if isinstance(raw, str) else dict(raw)
        except (TypeError, ValueError):
            continue
        if isinstance(prov, dict):
            yield where, prov


def friction_schedule(recording: Recording, truth=None) -> list[tuple[float, str]] | None:
    """When each friction condition began, for a recording the twin made with several.

    Read from the twin's provenance (the protocol's ``friction_time [s]`` and
    ``friction_condition``) stored with the recording or in the ``truth`` dataset. A recording
    of a real rig says nothing about its friction: None.

    Parameters
    ----------
    recording : Recording
        The recording.
    truth : xarray.Dataset, optional
        The twin's truth of a synthetic recording.

    Returns
    -------
    list of (float, str) or None
        ``(start [s], condition)`` in time order, one entry per change; None when unknown.
    """
    for _, prov in _twin_provenances(recording, truth):
        protocol = prov.get("protocol") or {}
        if not isinstance(protocol, dict):
            continue
        times = _listed(protocol.get("friction_time [s]"))
        names = _listed(protocol.get("friction_condition"))
        if times and len(times) == len(names):
            try:
                return [(float(t), str(c)) for t, c in zip(times, names, strict=True)]
            except (TypeError, ValueError):
                continue
    return None


def true_polach_parameters(
    recording: Recording, truth=None, condition: str | None = None
) -> tuple[dict | None, str]:
    """The twin's Polach parameters of a synthetic recording, if it ran with one friction set
    (or ``condition``'s set, when it ran with several and the analysis used that one).

    Looked up in the recording's metadata (``true_polach_parameters``, written by
    :func:`rollerrig.recordings.synthetic.synthetic_recording`, also after a round trip through a
    file as ``stored_metadata``), else in the twin's provenance (``friction_sets`` and the
    protocol's ``friction_condition``) stored with the recording or in the ``truth`` dataset.

    Parameters
    ----------
    recording : Recording
        The recording.
    truth : xarray.Dataset, optional
        The twin's truth of a synthetic recording.
    condition : str, optional
        The friction condition whose set is wanted when the twin ran with several (the one
        the analysis fitted, :func:`friction_schedule`).

    Returns
    -------
    (dict or None, str)
        The parameters by :data:`rollerrig.fit.model.PARAMETER_NAMES` and where they came
        from; ``(None, reason)`` when no single true set is known, or when the twin's contact
        force came from another creep law (a FASTSIM-family law shares μ0, A and B with its
        friction set, not k_A and k_S: a Polach fit is not to be measured against them).
    """
    for where, prov in _twin_provenances(recording, truth):
        law = (prov.get("drives") or {}).get("law")
        if law is None:
            continue
        if str(law) != "polach":
            return None, (
                f"{where}: the twin's creep law was {law!r}, not Polach's: its friction set "
                "is not the true Polach set of the recording"
            )
        break
    md, stored = recording.metadata, _stored(recording)
    for where, holder in (("recording metadata", md), ("metadata stored in the file", stored)):
        sets = holder.get("true_polach_parameters")
        if isinstance(sets, dict) and sets:
            if len(sets) == 1:
                ((name, params),) = sets.items()
                return dict(params), f"{where}: the twin's '{name}' set"
            if condition in sets:
                return dict(sets[condition]), (
                    f"{where}: the twin's '{condition}' set, the condition the fits used"
                )
            return None, f"{where}: several friction sets ({', '.join(sets)}), no single truth"
    for where, prov in _twin_provenances(recording, truth):
        sets = prov.get("friction_sets") or {}
        used = sorted(set(_listed((prov.get("protocol") or {}).get("friction_condition"))))
        if len(used) == 1 and used[0] in sets:
            return dict(sets[used[0]]), f"{where}: the twin's '{used[0]}' set"
        if len(used) > 1 and condition in used and condition in sets:
            return dict(sets[condition]), (
                f"{where}: the twin's '{condition}' set, the condition the fits used"
            )
    return None, "no twin truth known (not a synthetic recording)"


def truth_coa(truth, rec: Recording) -> tuple[np.ndarray, np.ndarray]:
    """The true contact CoA of a synthetic recording, checked against the recording's time.

    Returns ``(time, coa)``: the recording's time axis [s] when the truth has its samples, else
    the truth's own (a recording decimated by
    :func:`rollerrig.measure.prepare.analysis_recording` while it was read,
    whose truth is at the original rate). The analysis takes the truth at its own instants by
    linear interpolation (exact at coinciding instants).
    """
    if "coa" not in getattr(truth, "data_vars", {}):
        raise RecordingError(
            "the truth dataset has no 'coa' variable: give the *-truth.nc file that "
            "synthetic_recording wrote beside the recording"
        )
    coa = np.asarray(truth["coa"].values, dtype=float).reshape(-1)
    where = getattr(truth, "encoding", {}).get("source")
    what = f"the truth {where}" if where else "the truth"
    t_truth = (
        np.asarray(truth["time"].values, dtype=float).reshape(-1)
        if "time" in getattr(truth, "coords", {})
        else None
    )
    if t_truth is not None and t_truth.size != coa.size:
        raise RecordingError(f"{what}: its 'coa' and 'time' differ in length")
    if not np.all(np.isfinite(coa)):
        raise RecordingError(f"{what}: its 'coa' has NaN/inf samples")
    if coa.size == rec.time.size:
        if t_truth is not None:
            dt = float(np.max(np.abs(t_truth - rec.time)))
            if dt > 0.5 / rec.sample_rate:
                raise RecordingError(
                    f"{what}: its time axis differs from the recording's by up to {dt:.3g} s: "
                    "it is not the truth of this recording"
                )
        return rec.time, coa
    decimated = rec.metadata.get("decimated")
    if decimated and t_truth is not None and t_truth.size >= 2:
        # A recording decimated while it was read: the truth is at the original rate.
        f_in = float(decimated["from_rate_Hz"])
        step = float(np.median(np.diff(t_truth)))
        start_off = abs(float(t_truth[0] - rec.time[0]))
        end_off = float(t_truth[-1] - rec.time[-1])
        out_step = 1.0 / rec.sample_rate
        if (
            abs(step * f_in - 1.0) <= 1e-3
            and start_off <= 0.5 / f_in
            and -0.5 / f_in <= end_off < out_step + 0.5 / f_in
        ):
            return t_truth, coa
    rate = f" ({rec.sample_rate:.6g} Hz)"
    if decimated:
        rate = f" at {rec.sample_rate:.6g} Hz, decimated from {decimated['from_rate_Hz']:g} Hz"
    raise RecordingError(
        f"{what} has {coa.size} samples, the recording {rec.time.size}{rate}: it is not the "
        "truth of this recording (give the *-truth.nc written with it)"
    )
