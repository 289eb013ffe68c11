"""A validated study in memory: :class:`StudySpec` and its parts (grid axes, sampled
distributions, named cases), numbers in SI units.

Nothing here reads a file: :mod:`rollerrig.studies.studyfile` builds a :class:`StudySpec` from
one.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["Axis", "Case", "Distribution", "SampleDesign", "StudySpec"]


@dataclass(frozen=True)
class Axis:
    """One axis of a grid: a key and its values (SI, or names for a categorical key).

    ``unit`` is the unit the file gave (labels show values in it, ``factor`` converts it to SI);
    ``scale`` is ``"list"``, ``"linear"`` or ``"log"``; ``label`` names the axis in tables and
    figures (default: the key).
    """

    key: str
    values: tuple
    unit: str = ""
    factor: float = 1.0
    scale: str = "list"
    label: str = ""

    @property
    def categorical(self) -> bool:
        """True for an axis of names (friction, drive)."""
        return bool(self.values) and isinstance(self.values[0], str)

    def show(self, value) -> str:
        """``value`` (SI) as the file gave it: ``"k56 = 43.5 kN.m/rad"``."""
        name = self.label or self.key
        if isinstance(value, str):
            return f"{name} = {value}"
        shown = value / self.factor
        return f"{name} = {shown:.6g}" + (f" {self.unit}" if self.unit else "")


@dataclass(frozen=True)
class Distribution:
    """The distribution of one sampled parameter; numbers in SI (``values`` for ``choice``).

    :meth:`ppf` maps a uniform number in [0, 1) to the parameter (the inverse CDF), so one
    unit-cube design serves every distribution.
    """

    key: str
    kind: str
    params: Mapping[str, Any]
    unit: str = ""
    factor: float = 1.0
    label: str = ""

    def ppf(self, u: np.ndarray) -> np.ndarray:
        """Inverse CDF at ``u`` in [0, 1]: the parameter's values (SI, or names)."""
        from scipy import stats

        u = np.clip(np.asarray(u, dtype=float), 0.0, np.nextafter(1.0, 0.0))
        p = self.params
        if self.kind == "uniform":
            return p["low"] + u * (p["high"] - p["low"])
        if self.kind == "loguniform":
            return np.exp(np.log(p["low"]) + u * (np.log(p["high"]) - np.log(p["low"])))
        if self.kind == "normal":
            return stats.norm.ppf(u, loc=p["mean"], scale=p["std"])
        if self.kind == "triangular":
            width = p["high"] - p["low"]
            return stats.triang.ppf(u, (p["mode"] - p["low"]) / width, loc=p["low"], scale=width)
        values = np.asarray(p["values"], dtype=object)
        return values[np.minimum((u * len(values)).astype(int), len(values) - 1)]

    def to_dict(self) -> dict:
        """The distribution for the store's attributes (SI)."""
        return {"distribution": self.kind, **{k: _plain(v) for k, v in self.params.items()}}


@dataclass(frozen=True)
class SampleDesign:
    """A sampled design: method, base size ``n``, seed, second-order Sobol indices or not."""

    method: str
    n: int
    seed: int
    second_order: bool
    parameters: tuple[Distribution, ...]

    @property
    def size(self) -> int:
        """Number of points the design runs."""
        d = len(self.parameters)
        if self.method == "sobol":
            return self.n * (2 * d + 2 if self.second_order else d + 2)
        return self.n


@dataclass(frozen=True)
class Case:
    """A named case: its label and the values it sets (SI, or names)."""

    label: str
    settings: Mapping[str, Any]


@dataclass(frozen=True)
class StudySpec:
    """A validated study (:mod:`rollerrig.studies.studyfile` describes the file).

    Attributes
    ----------
    name, description : str
    experiment : str
        Bundled experiment name or the path of its file.
    rig : str or None
        Path of the rig file (relative paths resolved against the study file); None: the
        default rig.
    design : {"grid", "sample", "cases"}
    axes : tuple of Axis
        Grid axes (design "grid").
    sample : SampleDesign or None
    cases : tuple of Case
    metrics : tuple of str
    output_rate : float
        Sampling of each run's results [Hz].
    h_max : float or None
        A cap of the solver's step [s]; None: the sweeps' settings
        (:func:`rollerrig.solve.fast.sweep_settings`).
    origin : str
        The file (``bundled:<name>`` for a bundled study).
    sha256 : str
        Of the file's text: a store remembers it, so a resumed study is the same study.
    assumed_units : tuple of (str, str)
        ``(where, SI unit)`` of each place the file gave a dimensional number without a unit,
        taken in SI (``grid.stiffness.roller_shaft``, ``cases[1].load``); ``study run`` says
        so once.
    """

    name: str
    description: str
    experiment: str
    rig: str | None
    design: str
    axes: tuple[Axis, ...] = ()
    sample: SampleDesign | None = None
    cases: tuple[Case, ...] = ()
    metrics: tuple[str, ...] = ("release_overshoot",)
    output_rate: float = 1000.0
    h_max: float | None = None
    origin: str = "<string>"
    sha256: str = ""
    text: str = field(default="", repr=False)
    assumed_units: tuple[tuple[str, str], ...] = ()

    @property
    def keys(self) -> tuple[str, ...]:
        """The varied keys, in design order."""
        if self.design == "grid":
            return tuple(a.key for a in self.axes)
        if self.design == "sample":
            return tuple(d.key for d in self.sample.parameters)
        keys: list[str] = []
        for case in self.cases:
            keys += [k for k in case.settings if k not in keys]
        return tuple(keys)

    @property
    def size(self) -> int:
        """Number of points."""
        if self.design == "grid":
            return math.prod(len(a.values) for a in self.axes)
        if self.design == "sample":
            return self.sample.size
        return len(self.cases)


def _plain(value):
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    return value
