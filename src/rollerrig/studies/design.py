"""The points of a study, and what each point simulates.

:func:`design_points` turns a :class:`~rollerrig.studies.studyfile.StudySpec` into a table of
points (one value per varied key, in SI or as a name); :func:`point_setup` turns one point into
the rig, experiment and drives it runs. Points that share an experiment (the same load, speed
and friction) are run together: :func:`protocol_groups`.
"""

from __future__ import annotations

import dataclasses
import itertools
from dataclasses import dataclass
from typing import Any

import numpy as np

from rollerrig.experiment import Protocol
from rollerrig.rig.model import DriveConfig
from rollerrig.rig.parameters import RigParameters
from rollerrig.studies.studyfile import MODEL_KEYS, PROTOCOL_KEYS, StudySpec, si_unit

__all__ = ["DesignTable", "design_points", "point_setup", "protocol_groups"]


@dataclass(frozen=True)
class DesignTable:
    """The points of a study.

    Attributes
    ----------
    keys : tuple of str
        The varied keys, in design order.
    columns : dict of str to ndarray
        Key -> one value per point (float SI, or names as an object array; None where a case
        leaves the key at the base value).
    labels : tuple of str
        One short label per point.
    attrs : dict
        What the store keeps about the design (``design``, ``grid_shape``, ``grid_scales``,
        ``sample``).
    """

    keys: tuple[str, ...]
    columns: dict[str, np.ndarray]
    labels: tuple[str, ...]
    attrs: dict[str, Any]

    def __len__(self) -> int:
        return len(self.labels)

    def point(self, i: int) -> dict[str, Any]:
        """The values of point ``i`` (key -> value; keys a case leaves alone are left out)."""
        out = {}
        for key in self.keys:
            v = self.columns[key][i]
            if v is None:
                continue
            out[key] = v if isinstance(v, str) else float(v)
        return out


def _unit_cube(spec: StudySpec) -> np.ndarray:
    sample = spec.sample
    d = len(sample.parameters)
    if sample.method == "sobol":
        from rollerrig._optional import require

        sobol = require("SALib.sample.sobol", purpose="Sobol designs")
        problem = {"num_vars": d, "names": list(spec.keys), "bounds": [[0.0, 1.0]] * d}
        return sobol.sample(
            problem, sample.n, calc_second_order=sample.second_order, seed=sample.seed
        )
    if sample.method == "lhs":
        from scipy.stats import qmc

        return qmc.LatinHypercube(d, seed=sample.seed).random(sample.n)
    return np.random.default_rng(sample.seed).random((sample.n, d))


def design_points(spec: StudySpec) -> DesignTable:
    """The points of a study in design order.

    Grids are in C order over the axes (the last axis fastest: ``np.reshape(values,
    grid_shape)``); Sobol designs in SALib's order (Saltelli's scheme on the unit cube, each
    column mapped through the parameter's inverse CDF, so that ``SALib.analyze.sobol`` applies
    to the results in point order); Latin hypercube and random designs as drawn; cases as
    listed.

    Examples
    --------
    >>> from rollerrig.studies.studyfile import study_from_toml_string
    >>> spec = study_from_toml_string('''
    ... [grid]
    ... load = { values = [4.3, 20], unit = "kN" }
    ... friction = { values = ["dry", "wet"] }
    ... ''')
    >>> t = design_points(spec)
    >>> t.labels
    ('load = 4.3 kN, friction = dry', 'load = 4.3 kN, friction = wet', \
'load = 20 kN, friction = dry', 'load = 20 kN, friction = wet')
    """
    keys = spec.keys
    if spec.design == "grid":
        combos = list(itertools.product(*(a.values for a in spec.axes)))
        columns = {
            a.key: np.array([c[j] for c in combos], dtype=object if a.categorical else float)
            for j, a in enumerate(spec.axes)
        }
        labels = tuple(
            ", ".join(a.show(v) for a, v in zip(spec.axes, c, strict=True)) for c in combos
        )
        attrs = {
            "design": "grid",
            "grid_shape": [len(a.values) for a in spec.axes],
            "grid_scales": [a.scale for a in spec.axes],
        }
        return DesignTable(keys, columns, labels, attrs)
    if spec.design == "sample":
        cube = _unit_cube(spec)
        dists = spec.sample.parameters
        columns = {}
        for j, dist in enumerate(dists):
            values = dist.ppf(cube[:, j])
            columns[dist.key] = values if dist.kind == "choice" else values.astype(float)
        labels = tuple(f"sample {i}" for i in range(cube.shape[0]))
        attrs = {
            "design": "sample",
            "sample": {
                "method": spec.sample.method,
                "n": spec.sample.n,
                "seed": spec.sample.seed,
                "second_order": spec.sample.second_order,
                "parameters": {d.key: d.to_dict() for d in dists},
            },
        }
        return DesignTable(keys, columns, labels, attrs)
    columns = {}
    for key in keys:
        values = [case.settings.get(key) for case in spec.cases]
        columns[key] = np.array(values, dtype=object)
    return DesignTable(keys, columns, tuple(c.label for c in spec.cases), {"design": "cases"})


def _scaled(schedule: np.ndarray, value: float) -> np.ndarray:
    peak = float(np.max(schedule))
    return schedule * (value / peak) if peak > 0 else np.full_like(schedule, value)


def point_setup(
    rig: RigParameters, protocol: Protocol, values: dict[str, Any]
) -> tuple[RigParameters, Protocol, DriveConfig]:
    """The rig, experiment and drives of one point.

    Rig keys become overrides (validated: a non-physical value raises the rig's error naming
    the key); ``load`` and ``speed`` scale the experiment's schedule to that largest value;
    ``friction`` replaces every friction condition; ``drive.*`` choose the drives,
    ``frame`` the frame model and ``contact.law`` the creep law.

    Raises
    ------
    ParameterError
        A value the rig, the experiment or the drives refuse (the point is then reported as
        ``invalid parameters`` with this message).
    """
    overrides = {k: v for k, v in values.items() if k not in PROTOCOL_KEYS and k not in MODEL_KEYS}
    if overrides:
        rig = rig.with_overrides(overrides)
    changes = {}
    if "load" in values:
        changes["normal_load"] = _scaled(protocol.normal_load, values["load"])
    if "speed" in values:
        changes["roller_speed"] = _scaled(protocol.roller_speed, values["speed"])
    if "friction" in values:
        changes["friction_condition"] = (values["friction"],) * len(protocol.friction_condition)
    if changes:
        protocol = dataclasses.replace(protocol, **changes)
    drive = DriveConfig(
        wheel=values.get("drive.wheel", "pmsm"),
        roller=values.get("drive.roller", "induction"),
        roller_lag=values.get("drive.roller_lag"),
        frame=values.get("frame", "rigid"),
        law=values.get("contact.law", "polach"),
    )
    return rig, protocol, drive


def protocol_groups(table: DesignTable, indices: np.ndarray) -> list[np.ndarray]:
    """Split point indices into groups that share one experiment (load, speed, friction) and
    one compiled model (the dq roller drive has its own)."""
    keys = [k for k in table.keys if k in PROTOCOL_KEYS]
    dq = table.columns.get("drive.roller")  # the dq drive is another compiled model
    if not keys and dq is None:
        return [np.asarray(indices, dtype=int)]
    groups: dict[tuple, list[int]] = {}
    for i in indices:
        key = tuple(table.columns[k][i] for k in keys)
        if dq is not None:
            key += (dq[i] == "induction_dq",)
        groups.setdefault(key, []).append(int(i))
    return [np.array(g, dtype=int) for g in groups.values()]


def parameter_attrs(key: str, axis_label: str = "") -> dict[str, str]:
    """Attributes of a varied key's array in the store."""
    unit = si_unit(key)
    return {"units": unit, "long_name": axis_label or key}
