"""The study file: which experiment, on which rig, varying what, measuring what.

A study is a TOML file (or a bundled name: :func:`bundled_studies`) in one of three designs:

``[grid]``
    A full-factorial grid: one axis per varied quantity, with ``values = [...]`` or
    ``start``/``stop``/``num`` (``scale = "linear"`` or ``"log"``), and a ``unit``.
``[sample]``
    A sampled design: ``method = "sobol"`` (Saltelli's scheme for Sobol indices, via SALib),
    ``"lhs"`` (Latin hypercube) or ``"random"``, ``n`` (the base sample size; Sobol runs
    ``n (D + 2)`` points, ``n (2D + 2)`` with ``second_order = true``), ``seed``, and a
    distribution per parameter in ``[sample.parameters]``.
``[[cases]]``
    Named cases, each a ``label`` and the values it sets (the drives study).

A varied quantity is named by

- its dotted rig key, e.g. ``"stiffness.roller_shaft"``, ``"induction_motor.response_lag_clp"``
  (:mod:`rollerrig.rig.sections`), in a unit that quantity accepts;
- a protocol quantity: ``"load"`` (the normal load [N]), ``"speed"`` (the roller speed [m/s]),
  ``"friction"`` (the friction condition, ``"dry"`` or ``"wet"``). A load or speed value
  scales the experiment's schedule so that its largest value is the one given (a constant
  schedule simply becomes that value); a friction value replaces every condition;
- a model choice: ``"drive.roller"`` (``"induction"``, ``"induction_linear"``, ``"servo"``,
  ``"ideal_speed"``), ``"drive.wheel"`` (``"pmsm"``, ``"ideal_torque"``),
  ``"drive.roller_lag"`` (the roller drive's response lag τ [s]; 0: none), ``"frame"``
  (``"rigid"`` or ``"flexible"``: the frame's degree of freedom at the contact, with the rig's
  ``frame.*`` keys), ``"contact.law"`` (the creep law of the contact force: ``"polach"``,
  ``"fastsim"``, ``"modified-fastsim"``, ``"fastrip"``; :class:`rollerrig.rig.model.
  DriveConfig`).

``name`` names the study and the files its run writes (``study-NAME.zarr``, ...): 1 to 64
letters, digits, ``.``, ``_``, ``+`` and ``-``, not starting with a dot; default: the file's
stem (made safe). A study has at most
:data:`~rollerrig.studies.design_tables.MAX_STUDY_POINTS` points, checked from the file's
numbers before any point is made.

A number without a unit is SI (``study run`` says once where it took a number so, and in which
unit: :attr:`StudySpec.assumed_units`; 0 and dimensionless numbers need no unit).
``[outputs] metrics`` chooses the metrics of each run by name
(:data:`rollerrig.studies.metrics.METRICS`); ``[solver]`` sets the output rate and the largest
step. The minimal study::

    experiment = "seed-30kmh-dry"
    [grid]
    "stiffness.roller_shaft" = { values = [43.5e3, 83.5e3, 143.5e3], unit = "N.m/rad" }
    "induction_motor.response_lag_clp" = { values = [2.75, 10000.0], unit = "1/s" }
    [outputs]
    metrics = ["release_overshoot"]

Where each part lives: the keys a study may vary in :mod:`~rollerrig.studies.varied_keys`, the
study in memory in :mod:`~rollerrig.studies.spec`, the design tables read in
:mod:`~rollerrig.studies.design_tables`; this module reads a whole file (or a bundled study)
into a :class:`~rollerrig.studies.spec.StudySpec`, and re-exports the names it exported before
them.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from rollerrig._toml import parse_toml
from rollerrig._validation import ParameterError, Problem, did_you_mean
from rollerrig.output.names import safe_file_name
from rollerrig.studies.bundled import bundled_studies, data_dir
from rollerrig.studies.design_tables import (
    MAX_STUDY_POINTS,
    _axis,
    _cases,
    _grid_size_ok,
    _Reader,
    _sample,
)
from rollerrig.studies.spec import Axis, Case, Distribution, SampleDesign, StudySpec
from rollerrig.studies.varied_keys import MODEL_KEYS, PROTOCOL_KEYS, key_quantity, si_unit

__all__ = [
    "MAX_NAME_LENGTH",
    "MAX_STUDY_POINTS",
    "MODEL_KEYS",
    "PROTOCOL_KEYS",
    "Axis",
    "Case",
    "Distribution",
    "SampleDesign",
    "StudyFileError",
    "StudySpec",
    "bundled_studies",
    "key_quantity",
    "load_study",
    "si_unit",
    "study_from_dict",
    "study_from_toml_string",
    "study_name_from_stem",
]

_DESIGNS = ("grid", "sample", "cases")
_TOP_KEYS = {
    "name",
    "description",
    "experiment",
    "rig",
    "grid",
    "sample",
    "cases",
    "outputs",
    "solver",
}
MAX_NAME_LENGTH = 64
"""Longest study name [characters]."""
_NAME = re.compile(f"[A-Za-z0-9_+-][A-Za-z0-9._+-]{{0,{MAX_NAME_LENGTH - 1}}}")
_NAME_RULE = (
    f"1-{MAX_NAME_LENGTH} characters of letters, digits, '.', '_', '+' and '-', not starting "
    "with '.' (it names the files a run writes: study-NAME.zarr, study-NAME.json)"
)
DEFAULT_EXPERIMENT = "release-test"
"""The experiment of a study that names none: one ramp, hold and sudden release at 30 km/h."""


class StudyFileError(ParameterError):
    """A study file is malformed: one line per problem, each naming the file and the key."""

    def __init__(self, origin: str, problems: list[Problem]):
        self.origin = origin
        self.problems = tuple(p.format(origin) for p in problems)
        super().__init__("\n".join(self.problems))


def _study_name(reader: _Reader, name, *, given: bool) -> str:
    """The study's name, checked (it names files: see :data:`MAX_NAME_LENGTH`)."""
    if isinstance(name, str) and _NAME.fullmatch(name):
        return name
    where = "" if given else " (the name of the study file, or the name given)"
    reader.problem("name", f"not a study name{where}", allowed=_NAME_RULE, got=name)
    return "study"


def study_name_from_stem(stem: str) -> str:
    """A study name made from a file's stem: :func:`~rollerrig.output.names.safe_file_name`,
    cut to :data:`MAX_NAME_LENGTH` characters (a study file names its study unless it has a
    ``name`` key).

    Examples
    --------
    >>> study_name_from_stem("my study (v2)"), study_name_from_stem(".hidden")
    ('my_study__v2_', 'hidden')
    >>> study_name_from_stem("."), len(study_name_from_stem("x" * 300))
    ('_', 64)
    """
    # study names stay ASCII (_NAME), while output names keep letters of any script
    name = re.sub(r"[^A-Za-z0-9._+-]", "_", safe_file_name(stem))[:MAX_NAME_LENGTH]
    return name if _NAME.fullmatch(name) else "study"


def study_from_toml_string(
    text: str, *, origin: str = "<string>", base_dir: Path | None = None, name: str = "study"
) -> StudySpec:
    """Read and validate a study from TOML text.

    Parameters
    ----------
    text : str
        The file's text.
    origin : str
        Where it came from (errors name it).
    base_dir : Path, optional
        Relative ``experiment`` and ``rig`` paths are resolved against it.
    name : str
        The study's name when the file gives none (for a file: its stem made safe,
        :func:`study_name_from_stem`). A name, given either way, is 1 to
        :data:`MAX_NAME_LENGTH` letters, digits, ``.``, ``_``, ``+`` and ``-``, not starting
        with a dot: it names the files of the study's run.

    Returns
    -------
    StudySpec

    Raises
    ------
    StudyFileError
        Every problem of the file, one line each, naming the key.

    Examples
    --------
    >>> spec = study_from_toml_string('''
    ... [grid]
    ... "stiffness.roller_shaft" = { values = [43.5, 143.5], unit = "kN.m/rad" }
    ... "drive.roller_lag" = { values = [0, 0.36], unit = "s" }
    ... ''')
    >>> spec.design, spec.size, spec.axes[0].values, spec.experiment
    ('grid', 4, (43500.0, 143500.0), 'release-test')
    """
    try:
        data = parse_toml(text)
    except tomllib.TOMLDecodeError as exc:
        raise StudyFileError(origin, [Problem("", f"not valid TOML ({exc})")]) from None
    return study_from_dict(data, origin=origin, base_dir=base_dir, name=name, text=text)


def study_from_dict(
    data: Mapping[str, Any],
    *,
    origin: str = "<dict>",
    base_dir: Path | None = None,
    name: str = "study",
    text: str | None = None,
) -> StudySpec:
    """Validate a study given as the dict its TOML file reads as.

    ``text`` is the file's text (kept in the store, and hashed so that a resumed study is the
    same one); default: the dict as JSON. Other parameters and errors as
    :func:`study_from_toml_string`.
    """
    from rollerrig.studies.metrics import METRICS

    if text is None:
        text = json.dumps(data, sort_keys=True, default=str)
    reader = _Reader(origin)
    if not isinstance(data, Mapping):
        raise StudyFileError(origin, [Problem("", "a study is a table of keys", got=data)])
    for extra in sorted(set(data) - _TOP_KEYS):
        reader.problem(extra, "unknown key", allowed=sorted(_TOP_KEYS))
    designs = [d for d in _DESIGNS if d in data]
    if len(designs) != 1:
        reader.problem(
            "",
            "give exactly one design: [grid], [sample] or [[cases]]",
            got=designs or "none",
        )
        raise StudyFileError(origin, reader.problems)
    design = designs[0]
    axes: tuple[Axis, ...] = ()
    sample = None
    cases: tuple[Case, ...] = ()
    if design == "grid":
        grid = data["grid"]
        if not isinstance(grid, dict) or not grid:
            reader.problem("grid", "give at least one axis")
        elif _grid_size_ok(reader, grid):
            parsed = [_axis(reader, k, v) for k, v in grid.items()]
            axes = tuple(a for a in parsed if a is not None)
    elif design == "sample":
        sample = _sample(reader, data["sample"])
    else:
        cases = _cases(reader, data["cases"]) or ()

    def text_of(key: str, default):
        value = data.get(key, default)
        if value is not None and not isinstance(value, str):
            reader.problem(key, "must be text", got=value)
            return default
        return value

    study_name = _study_name(reader, data.get("name", name), given="name" in data)
    description = text_of("description", "")
    experiment = text_of("experiment", DEFAULT_EXPERIMENT)
    rig = text_of("rig", None)
    if base_dir is not None:
        from rollerrig.experiment.tomlfile import bundled_protocols

        if experiment not in bundled_protocols() and not Path(experiment).is_absolute():
            experiment = str(base_dir / experiment)
        if rig is not None and not Path(rig).is_absolute():
            rig = str(base_dir / rig)

    metrics: tuple[str, ...] = ("release_overshoot",)
    outputs = data.get("outputs", {})
    if not isinstance(outputs, dict):
        reader.problem("outputs", "must be a table", got=outputs)
    else:
        for extra in sorted(set(outputs) - {"metrics"}):
            reader.problem(f"outputs.{extra}", "unknown key", allowed=["metrics"])
        chosen = outputs.get("metrics", list(metrics))
        if chosen == "all":
            chosen = list(METRICS)
        if not isinstance(chosen, list) or not chosen:
            reader.problem("outputs.metrics", 'give a list of metric names (or "all")', got=chosen)
        else:
            for m in chosen:
                if not isinstance(m, str) or m not in METRICS:
                    reader.problem(
                        "outputs.metrics", "unknown metric", allowed=list(METRICS), got=m
                    )
            metrics = tuple(dict.fromkeys(m for m in chosen if isinstance(m, str) and m in METRICS))

    output_rate, h_max = 1000.0, None
    solver = data.get("solver", {})
    if not isinstance(solver, dict):
        reader.problem("solver", "must be a table", got=solver)
    else:
        for extra in sorted(set(solver) - {"output_rate", "h_max"}):
            reader.problem(f"solver.{extra}", "unknown key", allowed=["output_rate", "h_max"])
        if "output_rate" in solver:
            rate = reader.quantity("solver.output_rate", solver["output_rate"], "frequency")
            if rate is not None and not 10.0 <= rate <= 1e5:
                reader.problem(
                    "solver.output_rate",
                    "out of range",
                    unit="Hz",
                    allowed="[10, 100000]",
                    got=rate,
                )
            output_rate = rate or output_rate
        if "h_max" in solver:
            h_max = reader.quantity("solver.h_max", solver["h_max"], "time")
            if h_max is not None and not 1e-6 <= h_max <= 0.01:
                reader.problem(
                    "solver.h_max", "out of range", unit="s", allowed="[1e-6, 0.01]", got=h_max
                )
    if reader.problems:
        raise StudyFileError(origin, reader.problems)
    return StudySpec(
        name=study_name,
        description=description,
        experiment=experiment,
        rig=rig,
        design=design,
        axes=axes,
        sample=sample,
        cases=cases,
        metrics=metrics,
        output_rate=output_rate,
        h_max=h_max,
        origin=origin,
        sha256=hashlib.sha256(text.encode("utf-8")).hexdigest(),
        text=text,
        assumed_units=tuple(reader.assumed.items()),
    )


def load_study(path_or_name: str | os.PathLike) -> StudySpec:
    """Load a study by bundled name (e.g. ``"stiffness"``) or from a TOML file.

    Raises
    ------
    StudyFileError
        Unknown name, unreadable file, or a file with problems (each named).

    Examples
    --------
    >>> load_study("stiffness").axes[0].key
    'stiffness.roller_shaft'
    """
    if isinstance(path_or_name, str) and path_or_name in bundled_studies():
        text = data_dir().joinpath(f"{path_or_name}.toml").read_text(encoding="utf-8")
        return study_from_toml_string(text, origin=f"bundled:{path_or_name}", name=path_or_name)
    path = Path(path_or_name)
    if not path.is_file():
        raise StudyFileError(
            str(path_or_name),
            [
                Problem(
                    "",
                    f"neither a bundled study ({', '.join(bundled_studies())}) nor an "
                    "existing TOML file"
                    + did_you_mean(str(path_or_name), bundled_studies(), style=";"),
                )
            ],
        )
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise StudyFileError(str(path), [Problem("", f"cannot read the file ({exc})")]) from None
    return study_from_toml_string(
        text,
        origin=str(path),
        base_dir=path.parent.resolve(),
        name=study_name_from_stem(path.stem),
    )
