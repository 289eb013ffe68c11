"""Reading the entries of a frame file, each problem collected rather than raised.

A physical entry is an inline table ``{ value, unit, source | assumption }``: its value comes
back in SI units and within its plausible range (:data:`rollerrig.frame.limits.PLAUSIBLE`),
with its provenance kept; a direction or a force per unit load is a plain list of three
numbers; a member's section, material or node is a reference by name. The reader records
every problem of the file (the key, what is wrong, what is allowed) so that all of them are
reported at once (:class:`rollerrig.frame.errors.FrameFileError`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from rollerrig._validation import Problem, Verbatim, show_value
from rollerrig.frame.limits import PLAUSIBLE
from rollerrig.units import UnitError, apply_factor, quantity_factor

__all__: list[str] = []

_ENTRY_FORM = "an inline table { value = ..., unit = ..., source | assumption = ... }"
_HINTED_PROBLEMS = 20
"""Problems after which no 'did you mean' hint is looked for."""


def _factor(unit: Any, quantity: str) -> float:
    """Factor to SI of ``unit`` for ``quantity`` (:mod:`rollerrig.units`); raises UnitError."""
    return quantity_factor(unit, quantity)


def _is_number(v) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool)


def _finite_or_nan(v) -> float:
    """``float(v)``; NaN for an integer too large for a float."""
    try:
        return float(v)
    except OverflowError:
        return math.nan


def _written(si: float, written, value, unit, si_unit: str):
    """A value as it was written (a whole list), with the SI value when the unit is not the
    SI one."""
    if isinstance(value, list):
        return value if unit == si_unit else Verbatim(f"{show_value(value)} {unit}")
    if unit == si_unit:
        return written
    return Verbatim(f"{si:.4g} ({show_value(written)} {unit})")


class _Reader:
    """Collects the problems of one file while reading it."""

    def __init__(self, origin: str):
        self.origin = origin
        self.problems: list[Problem] = []
        self.provenance: dict[str, Any] = {}
        self.invalid: set[tuple[str, str]] = set()
        """(kind, name) of entries given but invalid: references to them add no problem."""
        self.nodes_tree: tuple[list[str], Any] = ([], None)
        """The valid nodes' names and their k-d tree (rows in the same order)."""

    def problem(self, key: str, message: str, **kw) -> None:
        self.problems.append(Problem(key, message, **kw))

    def table(self, data: Mapping, key: str, *, required: bool = True) -> Mapping:
        value = data.get(key.rsplit(".", 1)[-1])
        if value is None:
            if required:
                self.problem(key, "missing table")
            return {}
        if not isinstance(value, Mapping):
            self.problem(key, "must be a table", got=value)
            return {}
        return value

    def unknown_keys(self, table: Mapping, prefix: str, known) -> None:
        for k in table:
            if k not in known:
                hint = self.hint(str(k), known)
                self.problem(
                    f"{prefix}.{k}" if prefix else str(k), f"unknown key{hint}", allowed=list(known)
                )

    def entry(
        self,
        table: Mapping,
        prefix: str,
        key: str,
        quantity: str,
        plausible: str,
        *,
        required: bool = True,
        size: int | None = None,
    ):
        """The SI value of a physical entry ``{ value, unit, source | assumption }`` (a number,
        or a list of ``size`` numbers) in its range ``PLAUSIBLE[plausible]``, or None with its
        problems recorded."""
        name = f"{prefix}.{key}"
        raw = table.get(key)
        if raw is None:
            if required:
                self.problem(name, f"missing key ({_ENTRY_FORM})")
            return None
        if not isinstance(raw, Mapping):
            self.problem(name, f"must be {_ENTRY_FORM}", got=raw)
            return None
        if not self._provenance(raw, name, ("value", "unit")):
            return None
        value, unit = raw.get("value"), raw.get("unit")
        if value is None or unit is None:
            self.problem(name, "needs both 'value' and 'unit'")
            return None
        try:
            factor = _factor(unit, quantity)
        except UnitError as exc:
            p = exc.problem
            self.problem(f"{name}.unit", p.message, unit=p.unit, allowed=p.allowed, got=p.got)
            return None
        numbers = value if size is not None else [value]
        if (
            not isinstance(numbers, list)
            or (size is not None and len(numbers) != size)
            or not all(_is_number(v) for v in numbers)
        ):
            what = f"a list of {size} numbers" if size is not None else "a number"
            self.problem(f"{name}.value", f"must be {what}", got=value)
            return None
        si = [_finite_or_nan(v) for v in numbers]
        si = [apply_factor(v, factor) if math.isfinite(v) else v for v in si]
        if not all(math.isfinite(v) for v in si):
            self.problem(f"{name}.value", "must be finite", got=value)
            return None
        rng = PLAUSIBLE[plausible]
        for v, written in zip(si, numbers, strict=True):
            if v not in rng:
                self.problem(
                    f"{name}.value",
                    f"outside the plausible range ({rng.why})",
                    unit=rng.unit,
                    allowed=rng.allowed,
                    got=_written(v, written, value, unit, rng.unit),
                )
                return None
        self.provenance[name] = dict(raw)
        return tuple(si) if size is not None else si[0]

    def _provenance(self, raw: Mapping, name: str, fields: tuple[str, ...]) -> bool:
        known = (*fields, "source", "assumption")
        self.unknown_keys(raw, name, known)
        given = [k for k in ("source", "assumption") if k in raw]
        if len(given) != 1:
            self.problem(name, "needs exactly one of 'source' or 'assumption'", got=given or "none")
            return False
        text = raw[given[0]]
        if not isinstance(text, str) or not text.strip():
            self.problem(f"{name}.{given[0]}", "must be a non-empty string", got=text)
            return False
        return True

    def vector(
        self,
        table: Mapping,
        prefix: str,
        key: str,
        *,
        default=None,
        unit_vector=False,
        plausible: str | None = None,
    ):
        """A plain list of three numbers (no unit: a direction, or a force per unit load in
        the range ``PLAUSIBLE[plausible]``)."""
        raw = table.get(key, default)
        if raw is None:
            return None
        if (
            not isinstance(raw, list)
            or len(raw) != 3
            or not all(_is_number(v) for v in raw)
            or not all(math.isfinite(_finite_or_nan(v)) for v in raw)
        ):
            self.problem(
                f"{prefix}.{key}", "must be a list of three finite numbers [x, y, z]", got=raw
            )
            return None
        v = tuple(float(x) for x in raw)
        if plausible is not None:
            rng = PLAUSIBLE[plausible]
            if not all(x in rng for x in v):
                self.problem(
                    f"{prefix}.{key}",
                    f"a component is outside the plausible range ({rng.why})",
                    unit=rng.unit,
                    allowed=rng.allowed,
                    got=raw,
                )
                return None
        if unit_vector:
            n = math.hypot(*v)  # no overflow or underflow in the squares
            if n == 0.0:
                self.problem(f"{prefix}.{key}", "must not be the zero vector", got=raw)
                return None
            v = tuple(x / n for x in v)
        return v

    def hint(self, raw, known) -> str:
        """`` (did you mean 'x'?)`` for a misspelt name; none once many problems are found
        (each costs a fuzzy match against every known name)."""
        if len(self.problems) >= _HINTED_PROBLEMS or not isinstance(raw, str):
            return ""
        import difflib

        close = difflib.get_close_matches(raw, list(known), n=1)
        return f" (did you mean {close[0]!r}?)" if close else ""

    def name_ref(self, table: Mapping, prefix: str, key: str, known, what: str) -> str | None:
        raw = table.get(key)
        if raw is None:
            self.problem(f"{prefix}.{key}", f"missing key (the name of a {what})")
            return None
        if isinstance(raw, str) and (what, raw) in self.invalid:
            return None  # its own problem is reported
        if not isinstance(raw, str) or raw not in known:
            hint = self.hint(raw, known)
            self.problem(
                f"{prefix}.{key}",
                f"not a {what} of the frame{hint}; define it under "
                f"[{_PLURAL[what]}] or name one that is",
                got=raw,
            )
            return None
        return raw


_PLURAL = {"node": "nodes", "section": "sections", "material": "materials", "member": "members"}
