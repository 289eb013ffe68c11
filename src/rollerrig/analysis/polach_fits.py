"""The Polach fits of an adhesion test's analysis, and the creep–CoA points they use.

Steps of :func:`rollerrig.analysis.adhesion.analyze_test`: the ascending-branch points a fit
takes (thinned above a cap, stated), under one friction condition only (a recording of several
is fitted on the condition with the most points, noted; one that does not say its condition
gets a note when its cycles' initial slopes differ as a change of friction makes them), the
fits to the corrected and to the rig's CoA (:func:`rollerrig.fit.polach.fit_polach`, their
warnings noted), and a note where a fit misses the twin's true set.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from rollerrig.analysis.findings import TRUTH_SIGMA
from rollerrig.fit.polach import PolachFit, creep_stiffness_for_rig, fit_polach
from rollerrig.measure.segmentation import Branches
from rollerrig.recordings.recording import Recording

__all__ = ["FRICTION_SLOPE_RATIO"]

_SYMBOLS = {
    "static_friction": "μ0",
    "limit_ratio": "A",
    "friction_decay": "B [s/m]",
    "k_adhesion": "kA",
    "k_slip": "kS",
}


def _fit_points(
    branches: list[Branches], creep: np.ndarray, coa: np.ndarray, cap: int, notes: list[str]
) -> tuple[np.ndarray, int, int]:
    """Indices of the ascending-branch samples the fits use, how many were available, the step.

    Samples with creep above 1e-4 and CoA above 0.01; above ``cap`` every k-th (noted).
    """
    points = np.array([], dtype=int)
    if branches:
        points = np.concatenate([br.ascending for br in branches])
        points = points[(creep[points] > 1e-4) & (coa[points] > 0.01)]
    available, step = int(points.size), max(1, math.ceil(points.size / cap))
    if step > 1:
        points = points[::step]
        notes.append(
            f"Polach fits on one in {step} of the {available} ascending-branch points "
            f"({points.size} used; a fit uses at most {cap} points, MAX_FIT_POINTS): the "
            "points are consecutive samples of smooth branches, so the thinned set spans the "
            "same creep and slip-velocity range"
        )
    return points, available, step


FRICTION_SLOPE_RATIO = 1.6
"""Cycles whose initial creep-CoA slopes (normalised by the rig's creep stiffness) differ by
more than this factor are noted as a probable change of friction (a dry and a wet branch of
Polach's sets differ by 2.4-2.9; the cycles of one condition by at most 1.2)."""


def _one_friction_condition(
    t: np.ndarray, points: np.ndarray, schedule, notes: list[str]
) -> tuple[np.ndarray, str | None]:
    """The fit points under one friction condition, and that condition.

    A recording the twin made with several friction conditions (``schedule``:
    :func:`~rollerrig.measure.facts.friction_schedule`) is fitted on the condition with the
    most ascending-branch points only, noted: one law is never fitted across two conditions.
    Without a schedule, or with one condition, ``points`` as they are.
    """
    if not schedule or points.size == 0:
        return points, None
    starts = np.array([start for start, _ in schedule])
    names = np.array([name for _, name in schedule])
    which = names[np.clip(np.searchsorted(starts, t[points], side="right") - 1, 0, None)]
    counts = {str(c): int(np.sum(which == c)) for c in dict.fromkeys(which.tolist())}
    if len(counts) == 1:
        return points, next(iter(counts))
    chosen = max(counts, key=counts.get)
    kept = points[which == chosen]
    when = ", ".join(f"{name} from {start:g} s" for start, name in schedule)
    left = ", ".join(f"{n} under {c!r}" for c, n in counts.items() if c != chosen)
    notes.append(
        f"the test changes friction ({when}): the Polach fits use the {kept.size} "
        f"ascending-branch points under {chosen!r} only and leave out {left}, another law "
        "(one law is never fitted across two friction conditions; analyse the other "
        "condition's cycles on their own, Recording.select, to fit it)"
    )
    return kept, chosen


def _note_friction_change(
    branches: list[Branches],
    creep: np.ndarray,
    coa: np.ndarray,
    normal_load: np.ndarray,
    rig,
    notes: list[str],
) -> None:
    """A note when the cycles' initial creep-CoA slopes differ as a change of friction makes
    them (Polach's kA), for a recording that does not say its friction condition: the fits
    then take every cycle as one law, and the note says so."""
    slopes = {}
    for br in branches:
        a = br.ascending
        c, m = creep[a], coa[a]
        ok = (c > 1e-4) & (m > 0.01)
        if np.count_nonzero(ok) < 5:
            continue
        c, m, q = c[ok], m[ok], normal_load[a][ok]
        low = m <= 0.5 * float(np.max(m))  # the initial, nearly linear part
        if np.count_nonzero(low) < 3:
            continue
        q_med = float(np.median(q[low]))
        stiffness = creep_stiffness_for_rig(q_med, rig) / q_med  # slope of Kalker's line [-]
        slopes[br.cycle] = float(np.median(m[low] / c[low])) / stiffness
    if len(slopes) < 2:
        return
    low_c, high_c = min(slopes, key=slopes.get), max(slopes, key=slopes.get)
    ratio = slopes[high_c] / slopes[low_c]
    if ratio > FRICTION_SLOPE_RATIO:
        notes.append(
            f"the cycles' initial creep-CoA slopes differ by x{ratio:.2g} (cycle {high_c}: "
            f"{slopes[high_c]:.2g}, cycle {low_c}: {slopes[low_c]:.2g} of Kalker's slope): the "
            "friction condition probably changed during the test (water or contamination "
            "lowers Polach's kA), yet the Polach fits take every cycle as one law; analyse "
            "each condition's cycles on their own (Recording.select) if it did"
        )


def _polach_fits(
    rec: Recording, rig, points: np.ndarray, notes: list[str]
) -> tuple[PolachFit | None, PolachFit | None]:
    """Polach fits to the corrected and to the rig's smoothed CoA at ``points`` (warnings noted)."""
    if points.size < 10:
        notes.append("too few ascending-branch points for a Polach fit")
        return None, None
    creep_s, slip_s = rec["creep_smoothed"], rec["slip_velocity_smoothed"]
    spring = rec["normal_load"][points]
    corrected = rec["coa_corrected"][points]
    # The corrected CoA is on the contact's load N = S + W_d + κ μ N (the swinging arm), the
    # rig's on the air-spring force S it measures.
    arm = rig.arm
    contact_load = (spring + arm.dead_weight) / (1.0 - arm.transfer_ratio * corrected)
    fits = []
    for label, coa_points, load in (
        ("corrected CoA", corrected, contact_load),
        ("rig CoA", rec["coa_smoothed"][points], spring),
    ):
        # Kalker's stiffness scales with N^(2/3) (Hertz at a fixed a/b): per point, as the twin.
        q_med = float(np.median(load))
        stiffness = creep_stiffness_for_rig(q_med, rig) * np.cbrt((load / q_med) ** 2)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            fits.append(
                fit_polach(
                    creep_s[points], coa_points, load, stiffness, slip_velocity=slip_s[points]
                )
            )
            notes.extend(
                f"fit to the {label}: {m}" for m in dict.fromkeys(str(w.message) for w in caught)
            )
    return fits[0], fits[1]


def _with_systematic_errors(fit: PolachFit | None, budget, points: np.ndarray, notes: list[str]):
    """The fit to the corrected CoA with the CoA's systematic errors in its standard errors.

    The fit's own standard errors come from the points' scatter; the errors every point
    shares (the sensors' classes, the air spring's area, the roller's radius, J5, the bearing
    loss, the arm; :class:`~rollerrig.estimation.coa_uncertainty.CoaUncertainty`) move the
    whole curve. On the bundled test the scatter's alone had put the twin's true μ0 9 standard
    errors away, A 52, kA 10 (a review, 2026-12-03). The fit to the rig's CoA keeps the
    scatter's: it is the uncorrected quantity, shown for comparison.
    """
    if fit is None or budget is None:
        return fit
    unc = budget.uncertainty
    if fit.data_gain is None or points.size == 0 or int(np.max(points)) >= unc.value.size:
        return fit  # not on the uncertainty's samples: the scatter's errors as they are
    errors = unc.systematic_errors(points)
    if not errors:
        return fit
    out = fit.with_systematic(errors)
    ratios = [
        out.stderr[k] / out.stderr_statistical[k]
        for k in ("static_friction", "k_adhesion", "k_slip")
        if np.isfinite(out.stderr_statistical[k]) and out.stderr_statistical[k] > 0
    ]
    grown = f"; up to x{max(ratios):.3g} the scatter's alone for μ0, kA, kS" if ratios else ""
    notes.append(
        "the Polach fit to the corrected CoA states standard errors with the CoA's systematic "
        "errors (sensor classes, air-spring area, radius, J5, bearing loss, arm)"
        + grown
        + "; the results give both (stderr, stderr_statistical); the fit to the rig's CoA "
        "states the scatter's alone"
    )
    return out


def _note_truth_distance(
    fits: dict[str, PolachFit | None], true_params: dict, notes: list[str]
) -> None:
    """A note for each fit that misses the twin's true Polach set by more than TRUTH_SIGMA."""
    for label, f in fits.items():
        if f is None:
            continue
        far = {
            name: row
            for name, row in f.truth_distance(true_params, TRUTH_SIGMA).items()
            if row["beyond_warn_sigma"]
        }
        if far:
            notes.append(
                f"fit to the {label} misses the twin's true Polach set by more than "
                f"{TRUTH_SIGMA:g} standard errors: "
                + ", ".join(
                    f"{_SYMBOLS[n]} {r['fitted']:.4g} ± {r['stderr']:.2g} against "
                    f"{r['true']:.4g} ({r['sigma']:.1f} σ)"
                    for n, r in far.items()
                )
                + "; the standard errors cover the noise, not the systematic errors of the "
                "data (smoothing, the dynamics correction, unidentifiable A and B)"
            )
