"""Which creep law does a recording support? Each fitted, compared by evidence.

:func:`compare_laws` calibrates the twin under each candidate creep law
(:data:`~rollerrig.calibrate.problem.CALIBRATION_LAWS`; default :data:`DEFAULT_LAWS`, Polach's
law against the modified FASTSIM) to the same recording and weighs the evidence exactly as
:func:`rollerrig.calibrate.compare.compare_drives` weighs roller drives
(:func:`rollerrig.calibrate.compare.weigh`: residual whiteness per channel, AIC and BIC with each
channel's variance profiled out, the ringing after each release; the winner is the adequate
law of smallest BIC, of all laws when none is adequate, then marked inadequate).

The free keys of each law:

- the rig keys given, the same in every law;
- the friction coefficient's parameters every law shares (Polach 2005, eq. 8:
  μ = μ0 [(1 − A) e^(−B w) + A], which every law here takes, :mod:`rollerrig.contact.laws`):
  μ0, A, B (:data:`SHARED_LAW_PARAMETERS`), named with either law's prefix
  (``polach.static_friction`` or ``fastsim.static_friction``) and freed under each law's own
  key;
- the law's own shape keys (:func:`shape_keys`: Polach's k_A, k_S; the modified FASTSIM's k0,
  α_∞, β; FASTSIM and FaStrip have none): those named, to that law only; a law with none named
  frees all of its shape keys except one whose starting value lies on a bound of its range,
  which stays at its start and is recorded (``shape_keys_held``). Measured: Polach's dry set
  starts k_A on its upper bound 1.0, and a fit freeing it there ran 40 iterations without
  converging (an invalid fit, which would lose the comparison for a reason that is not the
  law's).

The spread of the shared keys between adequate laws is the type-B model-discrepancy term
(:func:`rollerrig.calibrate.compare.model_discrepancy`), written under the winner's key names.
Every calibration's advice then names the comparison's result
(:func:`rollerrig.calibrate.diagnostics.law_comparison_suggestion`): a law that lost says so and
names the winner; a winner with structured residuals points at the roller drive model.

One comparison per run: :func:`compare_laws` fits one roller drive (``roller_drive=``) and
:func:`~rollerrig.calibrate.compare.compare_drives` one law (``law=``); ``rollerrig calibrate``
refuses ``--compare-laws`` with ``--compare-drives`` (every pair would be four or more fits of
several minutes each, and the two questions separate: compare the drives under one law, then
the laws under the winning drive).

References
----------
.. [1] O. Polach, Wear 258 (2005) 992-1000.
.. [2] M. Spiryagin, O. Polach, C. Cole, Vehicle System Dynamics 51 (2013) 1765-1783.
.. [3] G. Schwarz, Annals of Statistics 6 (1978) 461-464 (BIC).

Examples
--------
>>> from rollerrig.calibrate.lawcompare import law_free_keys
>>> fit, held = law_free_keys(["inertia.roller", "polach.static_friction"])
>>> fit["modified-fastsim"]
('inertia.roller', 'fastsim.static_friction', 'fastsim.k0', 'fastsim.alpha_inf', 'fastsim.beta')
>>> fit["polach"], held["polach"]
(('inertia.roller', 'polach.static_friction', 'polach.k_slip'), ('polach.k_adhesion',))
"""

from __future__ import annotations

import dataclasses
import time as _time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from types import SimpleNamespace
from typing import Any, ClassVar

from rollerrig.calibrate.compare import ModelComparison, weigh
from rollerrig.calibrate.diagnostics import law_comparison_suggestion
from rollerrig.calibrate.problem import (
    _FASTSIM_RANGES,
    _LAW_KIND,
    _POLACH_RANGES,
    CALIBRATION_LAWS,
    CalibrationError,
    friction_parameters,
    is_law_key,
    law_keys,
)

__all__ = [
    "DEFAULT_LAWS",
    "LAW_COMPARE_JSON_NAME",
    "SHARED_LAW_PARAMETERS",
    "LawComparison",
    "compare_laws",
    "law_free_keys",
    "shape_keys",
]

LAW_COMPARE_JSON_NAME = "calibration-compare-laws.json"

DEFAULT_LAWS = ("polach", "modified-fastsim")
"""The laws :func:`compare_laws` fits unless told: Polach's closed form against the modified
FASTSIM (the two with a slope that falls with creepage)."""

SHARED_LAW_PARAMETERS = ("static_friction", "limit_ratio", "friction_decay")
"""μ0 [-], A [-], B [s/m] of the friction coefficient every law takes (Polach 2005, eq. 8):
the same quantity under each law's prefix."""


def _prefix(law: str) -> str:
    return "polach." if _LAW_KIND[law] == "polach" else "fastsim."


def _check_laws(laws: Iterable[str]) -> list[str]:
    from rollerrig._validation import did_you_mean

    laws = list(dict.fromkeys(str(lw) for lw in laws))
    bad = [lw for lw in laws if lw not in CALIBRATION_LAWS]
    if bad:
        each = "; ".join(f"{lw!r}{did_you_mean(lw, CALIBRATION_LAWS)}" for lw in bad)
        raise CalibrationError(f"not a creep law: {each}; choose of {list(CALIBRATION_LAWS)}")
    if len(laws) < 2:
        raise CalibrationError(
            f"compare at least two creep laws of {list(CALIBRATION_LAWS)}; got {laws}"
        )
    return laws


def shape_keys(law: str) -> tuple[str, ...]:
    """The keys of ``law`` that set the shape of its creep curve: its keys other than μ0, A, B.

    Examples
    --------
    >>> shape_keys("polach"), shape_keys("fastrip")
    (('polach.k_adhesion', 'polach.k_slip'), ())
    """
    return tuple(k for k in law_keys(law) if k.partition(".")[2] not in SHARED_LAW_PARAMETERS)


def _on_bound(key: str, law: str, friction) -> bool:
    """Whether the starting value of the law key ``key`` lies on a bound of its range."""
    name = key.partition(".")[2]
    lower, upper = (_POLACH_RANGES if _LAW_KIND[law] == "polach" else _FASTSIM_RANGES)[name]
    value = float(getattr(friction_parameters(friction, law), name))
    return not value > lower or (upper is not None and value >= upper)


def law_free_keys(
    free: str | Iterable[str],
    laws: Sequence[str] = DEFAULT_LAWS,
    friction=None,
) -> tuple[dict[str, tuple[str, ...]], dict[str, tuple[str, ...]]]:
    """The free keys of each law, and the shape keys each holds at its start (module docstring).

    Parameters
    ----------
    free : str or iterable of str
        Rig keys, shared law keys under either prefix (``polach.static_friction`` or
        ``fastsim.static_friction``: μ0 in every law), shape keys of the laws compared.
    laws : sequence of str
        The creep laws compared (at least two of
        :data:`~rollerrig.calibrate.problem.CALIBRATION_LAWS`).
    friction : str or PolachParameters, optional
        The friction set every law starts from (default ``"dry"``,
        :func:`~rollerrig.calibrate.problem.friction_parameters`).

    Returns
    -------
    tuple of dict
        Per law, the keys it fits, and the shape keys it holds at a start on a bound.

    Raises
    ------
    CalibrationError
        A law key none of the compared laws has (one line naming their keys), fewer than two
        laws, an unknown law.
    """
    laws = _check_laws(laws)
    keys = free.split(",") if isinstance(free, str) else list(free)
    keys = list(dict.fromkeys(str(k).strip() for k in keys if str(k).strip()))
    rig_keys = [k for k in keys if not is_law_key(k)]
    shared: list[str] = []
    named: dict[str, list[str]] = {lw: [] for lw in laws}
    wrong = []
    for key in (k for k in keys if is_law_key(k)):
        name = key.partition(".")[2]
        if name in SHARED_LAW_PARAMETERS:
            shared += [] if name in shared else [name]
            continue
        owners = [lw for lw in laws if key in law_keys(lw)]
        for lw in owners:
            named[lw].append(key)
        if not owners:
            wrong.append(key)
    if wrong:
        every = list(dict.fromkeys(k for lw in laws for k in law_keys(lw)))
        raise CalibrationError(
            f"free parameter(s) {', '.join(map(repr, wrong))}: not keys of the creep laws "
            f"compared ({', '.join(laws)}), whose keys are {', '.join(every)} (mu0, A, B under "
            "either prefix)"
        )
    fit: dict[str, tuple[str, ...]] = {}
    held: dict[str, tuple[str, ...]] = {}
    for lw in laws:
        own = named[lw]
        hold: list[str] = []
        if not own:
            hold = [k for k in shape_keys(lw) if _on_bound(k, lw, friction)]
            own = [k for k in shape_keys(lw) if k not in hold]
        fit[lw] = tuple([*rig_keys, *(_prefix(lw) + n for n in shared), *own])
        held[lw] = tuple(hold)
    return fit, held


def _same_keys(winner: str, calibration) -> Any:
    """``calibration`` with its shared law keys under the winner's prefix (for the
    model-discrepancy term)."""
    prefix = _prefix(winner)
    out = {}
    for key, p in calibration.parameters.items():
        name = key.partition(".")[2]
        out[prefix + name if is_law_key(key) and name in SHARED_LAW_PARAMETERS else key] = p
    return SimpleNamespace(parameters=out)


@dataclass(frozen=True)
class LawComparison(ModelComparison):
    """What :func:`compare_laws` found: the candidates are creep laws
    (:class:`~rollerrig.calibrate.compare.ModelComparison`).

    Attributes
    ----------
    keys : dict of str to tuple of str
        The keys each law fitted.
    shape_keys_held : dict of str to tuple of str
        The shape keys each law held at their start (on a bound of their range).
    roller_drive : str
        The roller drive model of every fit.
    """

    keys: dict[str, tuple[str, ...]] = field(default_factory=dict)
    shape_keys_held: dict[str, tuple[str, ...]] = field(default_factory=dict)
    roller_drive: str = "induction"

    MODEL: ClassVar[str] = "creep law"
    OPTION: ClassVar[str] = "--compare-laws"
    JSON_NAME: ClassVar[str] = LAW_COMPARE_JSON_NAME

    @property
    def losers(self) -> tuple[str, ...]:
        """The laws the recording supports less than the winner."""
        return tuple(lw for lw in self.evidence if lw != self.winner)

    def _extra_json(self) -> dict[str, Any]:
        return {
            "roller_drive": self.roller_drive,
            "laws": {
                lw: {
                    "free": list(self.keys.get(lw, ())),
                    "shape_keys_held_at_start": list(self.shape_keys_held.get(lw, ())),
                    "advice": self.calibrations[lw].suggestion,
                }
                for lw in self.evidence
            },
            "shared_law_parameters": "mu0, A, B of Polach's friction coefficient (Polach 2005, "
            "eq. 8), which every law takes: polach.<name> and fastsim.<name> are the same "
            "quantity; a law's shape keys are its own; a shape key starting on a bound of its "
            "range is held there",
        }


def compare_laws(
    recording,
    free: str | Iterable[str],
    *,
    laws: Sequence[str] = DEFAULT_LAWS,
    rig=None,
    channel_map=None,
    friction=None,
    max_iterations: int = 20,
    progress: Callable[[str, int, int, str], None] | None = None,
    **options,
) -> LawComparison:
    """Fit the recording under each creep law and say which it supports, and by how much.

    Parameters
    ----------
    recording : Recording or path
        As :func:`rollerrig.calibrate.calibrate`.
    free : str or iterable of str
        Rig keys, μ0, A, B under either law's prefix, shape keys of the compared laws
        (:func:`law_free_keys`).
    laws : sequence of str
        The candidates (default :data:`DEFAULT_LAWS`).
    rig, channel_map, friction, max_iterations
        As :func:`rollerrig.calibrate.calibrate`; ``friction`` is the set every law starts from
        (a Polach set's name or :class:`~rollerrig.contact.creep.PolachParameters`).
    progress : callable, optional
        ``progress(law, iteration, max_iterations, text)``.
    **options
        Further keyword arguments of :func:`rollerrig.calibrate.calibrate` (``roller_drive``,
        ``torque_noise``, ``search_width``, ...); not ``law``.

    Returns
    -------
    LawComparison
        The evidence per law (:func:`rollerrig.calibrate.compare.weigh`), the winner, by how
        much (:meth:`~rollerrig.calibrate.compare.ModelComparison.delta_bic`), each
        calibration with its advice.

    Raises
    ------
    CalibrationError
        ``law=`` given, fewer than two laws, a key of none of the laws (:func:`law_free_keys`),
        or what :func:`rollerrig.calibrate.calibrate` refuses.
    """
    from rollerrig.calibrate.fit import calibrate
    from rollerrig.recordings.recording import Recording
    from rollerrig.rig.parameters import default_rig

    if "law" in options:
        raise CalibrationError("compare_laws fits each of laws=...; give the laws there, not law=")
    started = _time.perf_counter()
    laws = _check_laws(laws)
    fit_keys, held = law_free_keys(free, laws, friction)
    if not isinstance(recording, Recording):
        from rollerrig.recordings.readers import read_recording

        recording = read_recording(recording, channel_map)
    rig = default_rig() if rig is None else rig
    calibrations = {}
    for lw in laws:

        def report(i, n, text, lw=lw):
            if progress is not None:
                progress(lw, i, n, text)

        calibrations[lw] = calibrate(
            recording,
            list(fit_keys[lw]),
            rig=rig,
            friction=friction,
            max_iterations=max_iterations,
            progress=report,
            law=lw,
            **options,
        )
    weighed = weigh(calibrations, recording, rig, models="creep laws", same_keys=_same_keys)
    weighed["calibrations"] = _advised(weighed)
    first = weighed["calibrations"][laws[0]]
    given = free.split(",") if isinstance(free, str) else list(free)
    return LawComparison(
        **weighed,
        wall_time=_time.perf_counter() - started,
        free=tuple(dict.fromkeys(str(k).strip() for k in given if str(k).strip())),
        keys=fit_keys,
        shape_keys_held=held,
        roller_drive=first.roller_drive,
    )


def _advised(weighed: dict[str, Any]) -> dict[str, Any]:
    """Each calibration with the comparison's advice in place of the generic one."""
    winner = weighed["winner"]
    bic = {lw: e["information_criteria"]["BIC"] for lw, e in weighed["evidence"].items()}
    out = {}
    for lw, cal in weighed["calibrations"].items():
        lost = lw != winner
        if not lost and not cal.conditional:
            out[lw] = cal  # white residuals and the law preferred: nothing to try
            continue
        advice = law_comparison_suggestion(
            lw, winner, bic[lw] - bic[winner], cal.roller_drive, lost=lost
        )
        old = cal.suggestion
        if old and any(old in w for w in cal.warnings):
            warnings = [w.replace(old, advice) for w in cal.warnings]
        else:
            warnings = [*cal.warnings, advice]
        out[lw] = dataclasses.replace(cal, suggestion=advice, warnings=warnings)
    return out
