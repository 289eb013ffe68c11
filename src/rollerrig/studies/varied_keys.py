"""What a study may vary: the protocol and model keys, and each key's quantity or choices.

A varied key is a protocol quantity (:data:`PROTOCOL_KEYS`), a model choice
(:data:`MODEL_KEYS`) or a dotted key of the rig file (``"stiffness.roller_shaft"``,
:mod:`rollerrig.rig.sections`). :func:`key_quantity` says which quantity its numbers are (a key
of :data:`rollerrig.units.QUANTITIES`) or which names it takes; :func:`si_unit` the SI unit of
its values.
"""

from __future__ import annotations

from typing import Any

from rollerrig._validation import Problem
from rollerrig.units import QUANTITIES, UnitError, quantity_factor

__all__ = ["MODEL_KEYS", "PROTOCOL_KEYS", "key_quantity", "si_unit"]

PROTOCOL_KEYS = {"load": "force", "speed": "speed", "friction": None}
"""Protocol quantities a study may vary -> their quantity (None: a name)."""
MODEL_KEYS = {
    "drive.roller": None,
    "drive.wheel": None,
    "drive.roller_lag": "time",
    "frame": None,
    "contact.law": None,
}
"""Model choices a study may vary (the drives, the frame, the creep law) -> their quantity
(None: a name)."""


def key_quantity(key: str) -> tuple[str | None, list[str] | None]:
    """``(quantity, choices)`` of a varied key; raises :class:`Problem` as ``ValueError``.

    Returns the quantity name (a key of :data:`rollerrig.units.QUANTITIES`) of a numeric key, or
    None and the allowed names of a categorical one.
    """
    from rollerrig.contact.creep import POLACH_PARAMETER_SETS
    from rollerrig.rig.model import FRAME_MODES, LAW_CODES, ROLLER_MODES, WHEEL_MODES
    from rollerrig.rig.sections import SECTIONS, quantity_of

    if key in PROTOCOL_KEYS:
        q = PROTOCOL_KEYS[key]
        return (q, None) if q else (None, sorted(POLACH_PARAMETER_SETS))
    if key in MODEL_KEYS:
        q = MODEL_KEYS[key]
        if q:
            return q, None
        modes = {
            "drive.roller": ROLLER_MODES,
            "drive.wheel": WHEEL_MODES,
            "frame": FRAME_MODES,
            "contact.law": LAW_CODES,
        }
        return None, sorted(modes[key])
    section, _, name = key.partition(".")
    allowed = [*PROTOCOL_KEYS, *MODEL_KEYS, "<section>.<key> of the rig file"]
    if section not in SECTIONS or section == "meta":
        raise _KeyProblem(Problem(key, "not a quantity a study can vary", allowed=allowed))
    fields = SECTIONS[section].model_fields
    if name not in fields:
        raise _KeyProblem(
            Problem(key, f"unknown key in the rig's [{section}]", allowed=list(fields))
        )
    return quantity_of(fields[name]), None


class _KeyProblem(ValueError):
    def __init__(self, problem: Problem):
        super().__init__(problem.message)
        self.problem = problem


def _factor(key: str, quantity: str, unit: Any) -> float:
    """SI factor of ``unit`` for ``quantity``; raises _KeyProblem naming ``key.unit``."""
    if unit is None:
        return 1.0
    try:
        return quantity_factor(unit, quantity)
    except UnitError as exc:
        p = exc.problem
        raise _KeyProblem(Problem(f"{key}.unit", p.message, p.unit, p.allowed, p.got)) from None


def si_unit(key: str) -> str:
    """The SI unit of a varied key's values (``""`` for a categorical key).

    Examples
    --------
    >>> si_unit("stiffness.roller_shaft"), si_unit("load"), si_unit("friction")
    ('N.m/rad', 'N', '')
    """
    quantity, _ = key_quantity(key)
    return QUANTITIES[quantity].si_unit if quantity else ""
