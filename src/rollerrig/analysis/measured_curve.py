"""A creep–CoA curve measured on the rig, read from an analysis of ``rollerrig analyze`` or from
a CSV of points.

:class:`MeasuredCurve` holds the points in SI with the creep referred to the roller speed
(Kayaalp eq. 4.21); :func:`read_analysis`, :func:`curve_from_analysis` and
:func:`read_curve_csv` make one, with a clear error for what they cannot read
(:func:`curve_csv_columns` tells which columns a CSV has). The transfer to
the track is :func:`rollerrig.analysis.transfer.transfer_curve`.
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rollerrig._validation import ParameterError
from rollerrig.contact.kinematics import kalker_creepage, rig_creep

__all__ = [
    "CSV_COLUMNS",
    "MeasuredCurve",
    "curve_csv_columns",
    "curve_from_analysis",
    "read_analysis",
    "read_curve_csv",
]

CSV_COLUMNS = {
    "creep": ("required", {"-": 1.0, "1": 1.0, "%": 0.01}),
    "coa": ("required", {"-": 1.0, "1": 1.0}),
    "slip_velocity": ("optional", {"m/s": 1.0}),
    "normal_load": ("optional", {"N": 1.0, "kN": 1e3}),
    "rolling_speed": ("optional", {"m/s": 1.0, "km/h": 1 / 3.6}),
    "coa_uncertainty": ("optional", {"-": 1.0, "1": 1.0}),
}
"""Columns of a creep-curve CSV, ``name [unit]``: whether required, and the units accepted
(with the factor to SI). ``creep`` is the rig's (Kayaalp eq. 4.21) unless stated otherwise;
``rolling_speed`` the roller's peripheral speed; ``coa_uncertainty`` a standard uncertainty."""

_MIN_POINTS = 10


@dataclass(frozen=True)
class MeasuredCurve:
    """Creep–CoA points measured on the rig.

    Attributes
    ----------
    creep : ndarray
        The rig's creep s [-] (Kayaalp eq. 4.21, referred to the roller speed).
    coa : ndarray
        CoA F/N [-] on the contact's load.
    slip_velocity : ndarray
        w [m/s].
    normal_load : ndarray
        Contact load N at each point [N].
    rolling_speed : ndarray
        Roller peripheral speed at each point [m/s].
    coa_uncertainty : ndarray or None
        Standard uncertainty of each CoA [-], >= 0 and finite, one per point; NaN where a
        point's is not stated.
    source : str
        Where the points came from.
    notes : tuple of str
        What the reader found or assumed.
    analysis_fit : dict or None
        The analysis's own Polach fit (from its JSON), for comparison.
    rig_sha256 : str or None
        The rig the analysis was made with.
    """

    creep: np.ndarray
    coa: np.ndarray
    slip_velocity: np.ndarray
    normal_load: np.ndarray
    rolling_speed: np.ndarray
    coa_uncertainty: np.ndarray | None = None
    source: str = ""
    notes: tuple[str, ...] = ()
    analysis_fit: dict | None = None
    rig_sha256: str | None = None

    def __post_init__(self) -> None:
        if self.coa_uncertainty is None:
            return
        # A negative standard uncertainty had been taken as it was (its magnitude into the
        # transfer's band). NaN stays: a point without a stated uncertainty (the transfer
        # leaves such points out of the stated systematic error).
        # (require_nonnegative refuses NaN too, hence the test here.)
        u = np.asarray(self.coa_uncertainty, dtype=float)
        bad = np.flatnonzero(~(np.isnan(u) | ((u >= 0.0) & (u < np.inf))))
        if bad.size:
            k = int(bad[0])
            raise ParameterError(
                f"coa_uncertainty must be >= 0 and finite [-] (NaN where a point has none "
                f"stated), got {u.flat[k]:g} at index {k} ({bad.size} of {u.size} values)"
            )
        if u.shape != np.shape(self.coa):
            raise ParameterError(
                f"coa_uncertainty (shape {u.shape}) must have the shape of coa (shape "
                f"{np.shape(self.coa)}): one standard uncertainty [-] per point"
            )

    @property
    def creepage(self) -> np.ndarray:
        """Kalker's creepage ξ [-] of the points."""
        return kalker_creepage(self.creep)


def _analysis_paths(path: Path) -> tuple[Path, Path]:
    name = path.name
    for suffix in ("-analysis.json", "-analysis.nc"):
        if name.endswith(suffix):
            stem = name[: -len(suffix)]
            return path.with_name(f"{stem}-analysis.json"), path.with_name(f"{stem}-analysis.nc")
    raise ParameterError(
        f"{path}: not an analysis of `rollerrig analyze` (expected <name>-analysis.json or "
        "<name>-analysis.nc beside each other)"
    )


_ANALYSIS_CHANNELS = (
    "creep_smoothed",
    "coa_corrected",
    "slip_velocity_smoothed",
    "normal_load",
    "roller_speed",
)


def read_analysis(path, rig=None) -> MeasuredCurve:
    """The ascending-branch creep–CoA points of a ``rollerrig analyze`` result.

    Reads ``<name>-analysis.json`` (the phases, the Polach fit, the rig's hash) and
    ``<name>-analysis.nc`` (the channels) beside it, and takes the points the analysis's fits
    took: the ascending branches of every cycle
    (:func:`rollerrig.measure.segmentation.adhesion_branches` on the smoothed creep), creep
    above 1e-4 and corrected CoA above 0.01; the CoA corrected for the rig's dynamics, on the
    contact's load N = (S + W_d)/(1 − σ(h/l)·CoA) (the swinging arm, the rig's ``[arm]``).

    Parameters
    ----------
    path : str or path-like
        ``<name>-analysis.json`` or ``<name>-analysis.nc``.
    rig : RigParameters, optional
        The rig the analysis was made with (default the bundled rig); a different hash from
        the analysis's is noted.

    Returns
    -------
    MeasuredCurve

    Raises
    ------
    ParameterError
        A missing or unreadable file, a missing channel or phase list, too few points.
    """
    import xarray as xr

    from rollerrig.measure.segmentation import Phase
    from rollerrig.output import rig_sha256
    from rollerrig.rig.parameters import default_rig

    json_path, nc_path = _analysis_paths(Path(path))
    for p in (json_path, nc_path):
        if not p.is_file():
            raise ParameterError(f"{p}: missing; `rollerrig analyze` writes both files")
    try:
        summary = json.loads(json_path.read_text())
    except (OSError, ValueError) as exc:
        raise ParameterError(f"{json_path}: not readable as JSON ({exc})") from None
    if not isinstance(summary, dict) or not isinstance(summary.get("phases"), list):
        raise ParameterError(f"{json_path}: no 'phases' list: not an analysis summary")
    try:
        phases = [
            Phase(str(p["name"]), float(p["start [s]"]), float(p["end [s]"]), int(p["cycle"]))
            for p in summary["phases"]
        ]
    except (KeyError, TypeError, ValueError) as exc:
        raise ParameterError(f"{json_path}: a phase lacks name/start/end/cycle ({exc})") from None
    try:
        ds = xr.load_dataset(nc_path, engine="h5netcdf")
    except Exception as exc:  # any reader fault: one message naming the file
        raise ParameterError(f"{nc_path}: not readable as NetCDF ({type(exc).__name__})") from None
    missing = [c for c in _ANALYSIS_CHANNELS if c not in ds]
    if missing:
        raise ParameterError(f"{nc_path}: channels {missing} missing (an analysis has them)")
    rig = default_rig() if rig is None else rig
    notes = []
    analysed_with = (summary.get("provenance") or {}).get("rig") or {}
    if analysed_with.get("sha256") and analysed_with["sha256"] != rig_sha256(rig):
        notes.append(
            f"the analysis was made with rig {analysed_with.get('name')!r} "
            f"(sha256 {str(analysed_with['sha256'])[:12]}...), not the rig given here "
            f"({rig.meta.name!r}, {rig_sha256(rig)[:12]}...): pass the analysis's rig with --rig"
        )
    u = None
    if "coa_corrected_standard_uncertainty" in ds:
        u = np.asarray(ds["coa_corrected_standard_uncertainty"].values, float)
    channels = {name: np.asarray(ds[name].values, float) for name in _ANALYSIS_CHANNELS}
    return _curve_from_channels(
        np.asarray(ds["time"].values, float),
        channels,
        u,
        phases,
        rig,
        source=str(json_path),
        notes=notes,
        fit=summary.get("polach_fit_corrected_coa"),
        sha=analysed_with.get("sha256"),
        where=str(nc_path),
    )


def curve_from_analysis(result, rig=None) -> MeasuredCurve:
    """The ascending-branch creep–CoA points of an analysis in memory
    (:func:`rollerrig.analysis.adhesion.analyze_test`'s result), as :func:`read_analysis`
    takes them from its files.

    Parameters
    ----------
    result : TestAnalysis
        The analysis.
    rig : RigParameters, optional
        The rig it was made with (its ``[arm]`` puts the CoA on the contact's load); default
        the bundled rig.

    Returns
    -------
    MeasuredCurve

    Raises
    ------
    ParameterError
        Too few points or a missing channel.
    """
    from rollerrig.rig.parameters import default_rig

    rig = default_rig() if rig is None else rig
    rec = result.recording
    missing = [c for c in _ANALYSIS_CHANNELS if c not in rec]
    if missing:
        raise ParameterError(f"the analysis has no channels {missing}")
    channels = {name: np.asarray(rec[name], float) for name in _ANALYSIS_CHANNELS}
    u = None
    budget = getattr(result, "coa_uncertainty", None)
    if budget is not None:
        unc = budget.uncertainty
        u = np.interp(rec.time, unc.time, np.asarray(unc.u, float))
    fit = result.summary().get("polach_fit_corrected_coa") if hasattr(result, "summary") else None
    return _curve_from_channels(
        np.asarray(rec.time, float),
        channels,
        u,
        list(result.phases),
        rig,
        source="the analysis",
        notes=[],
        fit=fit,
        sha=getattr(result, "rig_sha256", None),
        where="the analysis",
    )


def _curve_from_channels(t, ch, u, phases, rig, *, source, notes, fit, sha, where):
    """The points the analysis's fits took (ascending branches, creep > 1e-4, CoA > 0.01) on
    the contact's load of the rig's arm."""
    from rollerrig.measure.segmentation import adhesion_branches

    creep = ch["creep_smoothed"]
    coa = ch["coa_corrected"]
    branches = adhesion_branches(t, creep, phases)
    points = np.array([], dtype=int)
    if branches:
        points = np.concatenate([br.ascending for br in branches])
        points = points[(creep[points] > 1e-4) & (coa[points] > 0.01)]
    points = points[np.isfinite(creep[points]) & np.isfinite(coa[points])]
    if points.size < _MIN_POINTS:
        raise ParameterError(
            f"{where}: {points.size} ascending-branch points with creep > 1e-4 and CoA > 0.01"
            f", {_MIN_POINTS} needed"
        )
    spring = ch["normal_load"][points]
    arm = rig.arm
    load = (spring + arm.dead_weight) / (1.0 - arm.transfer_ratio * coa[points])
    speed = ch["roller_speed"][points] * rig.geometry.roller_radius_x
    if u is not None:
        u = u[points]
        if not np.all(np.isfinite(u)):
            u = None
    if isinstance(fit, dict) and fit.get("points") not in (None, points.size):
        notes.append(
            f"the analysis's Polach fit used {fit.get('points')} points, {points.size} read here"
        )
    notes.append(
        f"{points.size} ascending-branch points of {len(branches)} cycle(s): corrected CoA on the"
        f" contact's load (swinging arm h/l = {arm.transfer_ratio:.3g}, W_d = "
        f"{arm.dead_weight:g} N), smoothed creep (Kayaalp eq. 4.21) and slip velocity"
    )
    # The points' roller speed (the transfer's V by default) against the whole recording's:
    # a test's traction phases run at another roller speed than its mean.
    kmh = 3.6 * rig.geometry.roller_radius_x
    at_points = float(np.median(ch["roller_speed"][points])) * kmh
    overall = float(np.nanmean(ch["roller_speed"])) * kmh
    if f"{at_points:.3g}" != f"{overall:.3g}":
        notes.append(
            f"roller speed: median {at_points:.3g} km/h at the points fitted, mean "
            f"{overall:.3g} km/h over the whole recording"
        )
    return MeasuredCurve(
        creep=creep[points],
        coa=coa[points],
        slip_velocity=ch["slip_velocity_smoothed"][points],
        normal_load=load,
        rolling_speed=speed,
        coa_uncertainty=u,
        source=source,
        notes=tuple(notes),
        analysis_fit=fit if isinstance(fit, dict) else None,
        rig_sha256=sha,
    )


def _parse_header(cell: str, path) -> tuple[str, str | None]:
    text = cell.strip()
    if text.endswith("]") and "[" in text:
        name, unit = text[:-1].split("[", 1)
        return name.strip().lower(), unit.strip()
    return text.lower(), None


def _csv_rows(path: Path) -> list[list[str]]:
    """The CSV's rows, header first, without blank and ``#`` comment lines."""
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise ParameterError(f"{path}: not readable as a text CSV ({exc})") from None
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise ParameterError(f"{path}: empty (a header row 'creep [-],coa [-]' and points needed)")
    try:
        return list(csv.reader(lines))
    except csv.Error as exc:
        raise ParameterError(f"{path}: not a CSV ({exc})") from None


def curve_csv_columns(path) -> frozenset[str]:
    """The columns of :data:`CSV_COLUMNS` that a creep-curve CSV's header names.

    Lets a caller tell, before :func:`read_curve_csv`, whether the file gives each point its
    own load and speed (then ``normal_load`` / ``rolling_speed`` must not be passed to it).
    Only the header is looked at: its units and the rows are checked by
    :func:`read_curve_csv`.

    Parameters
    ----------
    path : str or path-like
        The CSV.

    Returns
    -------
    frozenset of str
        Column names, without their units (``"normal_load"``, ...).

    Raises
    ------
    ParameterError
        The file is not readable, empty or not a CSV (naming the file).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "c.csv"
    >>> _ = p.write_text("# a test\\ncreep [%],coa [-],normal_load [kN],note\\n")
    >>> sorted(curve_csv_columns(p))
    ['coa', 'creep', 'normal_load']
    """
    path = Path(path)
    names = (_parse_header(c, path)[0] for c in _csv_rows(path)[0])
    return frozenset(n for n in names if n in CSV_COLUMNS)


def read_curve_csv(
    path,
    *,
    creepage: str = "roller",
    normal_load: float | None = None,
    rolling_speed: float | None = None,
) -> MeasuredCurve:
    """Creep–CoA points from a CSV with named columns and units (:data:`CSV_COLUMNS`).

    The header names each column as ``name [unit]``: ``creep [-]`` or ``creep [%]`` and
    ``coa [-]`` are required; ``slip_velocity [m/s]``, ``normal_load [N]`` (or ``[kN]``),
    ``rolling_speed [m/s]`` (or ``[km/h]``) and ``coa_uncertainty [-]`` are optional, the load
    and speed then given as arguments. Other columns are ignored. The rows are points of one
    traction curve (creep ≥ 0), sorted by creep.

    Parameters
    ----------
    path : str or path-like
        The CSV (comma-separated, one header row; lines starting with ``#`` are skipped).
    creepage : {"roller", "mean"}
        What ``creep`` is referred to: the roller speed (the rig's, Kayaalp eq. 4.21) or the
        mean rolling speed (Kalker's ξ; converted to the rig's with :func:`rig_creep`).
    normal_load : float, optional
        N [N] of every point, when the file has no ``normal_load`` column.
    rolling_speed : float, optional
        Roller speed [m/s] of every point, when the file has no ``rolling_speed`` column.

    Returns
    -------
    MeasuredCurve

    Raises
    ------
    ParameterError
        Naming the file, the column and the row: a missing column or unit, an unknown unit, a
        cell that is not a number, NaN or inf, creep that decreases or is negative, a CoA
        beyond ±2, a non-positive load or speed, fewer than 10 points.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "c.csv"
    >>> rows = ["creep [%],coa [-]"] + [f"{0.2 * i},{0.04 * i}" for i in range(1, 12)]
    >>> _ = p.write_text("\\n".join(rows))
    >>> c = read_curve_csv(p, normal_load=4300.0, rolling_speed=8.33)
    >>> round(float(c.creep[-1]), 6), bool(np.isclose(c.slip_velocity[0], 0.002 * 8.33))
    (0.022, True)
    """
    path = Path(path)
    if creepage not in ("roller", "mean"):
        raise ParameterError(f"creepage must be 'roller' or 'mean', got {creepage!r}")
    rows = _csv_rows(path)
    header = [_parse_header(c, path) for c in rows[0]]
    names = [h[0] for h in header]
    index: dict[str, tuple[int, float]] = {}
    for i, (name, unit) in enumerate(header):
        if name not in CSV_COLUMNS:
            continue
        if name in index:
            raise ParameterError(f"{path}: column {name!r} appears twice")
        units = CSV_COLUMNS[name][1]
        if unit is None:
            raise ParameterError(
                f"{path}: column {name!r} has no unit: write '{name} [{next(iter(units))}]' "
                f"(units accepted: {', '.join(units)})"
            )
        if unit not in units:
            raise ParameterError(
                f"{path}: column '{name} [{unit}]': unit {unit!r} not accepted for {name} "
                f"(accepted: {', '.join(units)})"
            )
        index[name] = (i, units[unit])
    required = [n for n, (kind, _) in CSV_COLUMNS.items() if kind == "required"]
    lacking = [n for n in required if n not in index]
    if lacking:
        raise ParameterError(
            f"{path}: required column(s) {lacking} missing (found: {names}); the header needs "
            "'creep [-]' (or [%]) and 'coa [-]'"
        )
    data: dict[str, list[float]] = {n: [] for n in index}
    for r, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise ParameterError(f"{path}, row {r}: {len(row)} cells, the header has {len(header)}")
        for name, (i, factor) in index.items():
            try:
                value = float(row[i])
            except ValueError:
                raise ParameterError(
                    f"{path}, row {r}, column {name!r}: {row[i]!r} is not a number"
                ) from None
            if not math.isfinite(value):
                raise ParameterError(f"{path}, row {r}, column {name!r}: {row[i]!r} (not finite)")
            data[name].append(value * factor)
    arrays = {n: np.asarray(v, float) for n, v in data.items()}
    n = arrays["creep"].size
    if n < _MIN_POINTS:
        raise ParameterError(f"{path}: {n} points, at least {_MIN_POINTS} needed")
    s = arrays["creep"]
    if np.any(s < 0):
        r = int(np.flatnonzero(s < 0)[0]) + 2
        raise ParameterError(
            f"{path}, row {r}: negative creep; give one traction curve with creep >= 0 (mirror a "
            "braking curve: creep and CoA both negated)"
        )
    if np.any(np.diff(s) < 0):
        r = int(np.flatnonzero(np.diff(s) < 0)[0]) + 3
        raise ParameterError(
            f"{path}, row {r}: creep decreases (non-monotonic): the rows must be points of one "
            "ascending curve sorted by creep (a descending branch or a second test does not "
            "belong in the same file)"
        )
    if s[-1] >= 1.0:
        raise ParameterError(
            f"{path}: creep reaches {s[-1]:g} [-], 100 % or more: is it in per cent? label the "
            "column 'creep [%]'"
        )
    if creepage == "mean":
        s = rig_creep(s)
    y = arrays["coa"]
    if np.any(np.abs(y) > 2.0):
        r = int(np.flatnonzero(np.abs(y) > 2.0)[0]) + 2
        raise ParameterError(f"{path}, row {r}: CoA {y[r - 2]:g} beyond +-2: not a CoA [-]")
    if np.count_nonzero(s > 0) < _MIN_POINTS:
        raise ParameterError(f"{path}: fewer than {_MIN_POINTS} points with creep > 0")

    def per_point(name, given, unit, option):
        if name in arrays:
            if given is not None:
                raise ParameterError(f"{path}: the file has a {name} column; do not give {option}")
            v = arrays[name]
        elif given is None:
            raise ParameterError(
                f"{path}: no '{name} [{unit}]' column: give {option} for every point"
            )
        else:
            v = np.full(n, float(given))
        if np.any(v <= 0):
            raise ParameterError(f"{path}: {name} must be > 0 [{unit}]")
        return v

    q = per_point("normal_load", normal_load, "N", "the normal load")
    v = per_point("rolling_speed", rolling_speed, "m/s", "the rolling speed")
    w = arrays.get("slip_velocity", s * v)
    u = arrays.get("coa_uncertainty")
    if u is not None and np.any(u < 0):
        raise ParameterError(f"{path}: coa_uncertainty must be >= 0 [-]")
    notes = [
        f"{n} points from {path.name}; creep referred to the "
        + ("roller speed (Kayaalp eq. 4.21)" if creepage == "roller" else "mean rolling speed "
           "(Kalker), converted to the rig's: s = 2 xi/(2 - xi)")
    ]  # fmt: skip
    if "slip_velocity" not in arrays:
        notes.append("slip velocity w = s v (no slip_velocity column)")
    return MeasuredCurve(s, y, np.asarray(w, float), q, v, u, str(path), tuple(notes))
