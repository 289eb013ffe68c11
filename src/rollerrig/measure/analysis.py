"""Analysis of one adhesion test: from a recording to phases, corrected CoA, branches and fits.

The thin orchestration layer over :mod:`rollerrig.measure` (quantities, segmentation,
correction), :mod:`rollerrig.signal` (Savitzky-Golay tuning, filter study, spectra) and
:mod:`rollerrig.fit` (Polach). Each step is a public function of those modules; this module only
chains them in the order an analyst would and keeps what each step found.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from rollerrig.fit.polach import PolachFit, creep_stiffness_for_rig, fit_polach
from rollerrig.measure.correction import corrected_adhesion
from rollerrig.measure.quantities import derive_quantities
from rollerrig.measure.recording import Recording
from rollerrig.measure.segmentation import (
    Branches,
    Hysteresis,
    Phase,
    adhesion_branches,
    hysteresis,
    segment_test,
)
from rollerrig.signal.scoring import StudyRow, filter_study, tune_savitzky_golay
from rollerrig.signal.smoothing import savitzky_golay
from rollerrig.signal.spectra import ExplainedSpectrum, explain_spectrum

__all__ = ["TestAnalysis", "analyze_test", "quiet_phase"]


@dataclass
class TestAnalysis:
    """What :func:`analyze_test` found. Arrays on the recording's time axis, SI units."""

    recording: Recording  # raw, derived, smoothed and corrected channels
    rig_name: str
    phases: list[Phase]
    smoothing_order: int
    smoothing_window: int  # [samples]
    smoothing_table: list[StudyRow]
    branches: list[Branches]
    hysteresis: list[Hysteresis | None]
    fit: PolachFit | None  # to the dynamics-corrected CoA
    fit_rig_coa: PolachFit | None  # to the CoA as the rig reports it, T56 / (r_r N)
    fit_points: np.ndarray  # indices of the samples both fits used
    spectrum: ExplainedSpectrum | None
    spectrum_window: tuple[float, float] | None  # [s]
    study: list[StudyRow]
    notes: list[str] = field(default_factory=list)
    truth_errors: dict = field(default_factory=dict)

    def summary(self) -> dict:
        """A JSON-ready summary of every result, with units in the keys."""
        return {
            "rig": self.rig_name,
            "phases": [
                {"name": ph.name, "start [s]": ph.start, "end [s]": ph.end, "cycle": ph.cycle}
                for ph in self.phases
            ],
            "smoothing": {
                "method": "Savitzky-Golay",
                "order": self.smoothing_order,
                "window [samples]": self.smoothing_window,
                "window [s]": self.smoothing_window / self.recording.sample_rate,
            },
            "hysteresis": [
                _hysteresis_dict(b, h) for b, h in zip(self.branches, self.hysteresis, strict=True)
            ],
            "polach_fit_corrected_coa": _fit_dict(self.fit, self.fit_points.size),
            "polach_fit_rig_coa": _fit_dict(self.fit_rig_coa, self.fit_points.size),
            "spectrum": None
            if self.spectrum is None
            else {"window [s]": self.spectrum_window, "peaks": list(self.spectrum.table())},
            "filter_study_top10": [row.as_dict() for row in self.study[:10]],
            "truth_errors": self.truth_errors,
            "notes": self.notes,
        }


def _fit_dict(fit: PolachFit | None, n_points: int) -> dict | None:
    if fit is None:
        return None
    p = fit.parameters
    return {
        "mu0": p.static_friction,
        "A": p.limit_ratio,
        "B [s/m]": p.friction_decay,
        "kA": p.k_adhesion,
        "kS": p.k_slip,
        "stderr": {k: float(v) for k, v in fit.stderr.items()},
        "rmse [-]": float(fit.rmse),
        "points": int(n_points),
        "identifiable": bool(fit.identifiable),
    }


def _hysteresis_dict(branch: Branches, h: Hysteresis | None) -> dict | None:
    if h is None:
        return None
    return {
        "cycle": branch.cycle,
        "area [-]": h.area,
        "abs_area [-]": h.abs_area,
        "max_difference [-]": h.max_difference,
        "creep_at_max_difference [-]": h.creep_at_max_difference,
    }


def _odd(n: float) -> int:
    k = max(round(n), 7)
    return k if k % 2 else k + 1


def quiet_phase(phases: list[Phase]) -> tuple[float, float] | None:
    """The longest phase without torque activity (free rolling or rest) [s], for spectra."""
    quiet = [ph for ph in phases if ph.name in ("free_rolling", "rest")]
    if not quiet:
        return None
    best = max(quiet, key=lambda ph: ph.end - ph.start)
    return best.start, best.end


def analyze_test(
    recording: Recording,
    rig=None,
    *,
    truth=None,
    smoothing: tuple[int, int] | None = None,
    run_study: bool = True,
) -> TestAnalysis:
    """Analyse one adhesion test.

    Steps: the physical quantities the rig derives (normal force from pressure, speeds from the
    encoders, creep, CoA = T/(r_r N)); the phases of the test; a Savitzky-Golay order and window
    tuned on the torque (or given); smoothed torque and speeds, and the creep and CoA from them;
    the CoA corrected for the roller's inertia and bearing loss
    (:func:`rollerrig.measure.correction.corrected_adhesion`); ascending and descending branches
    per cycle and their hysteresis; Polach fits to the ascending branches of the corrected and
    of the rig's CoA; the spectrum of the longest quiet phase with every peak explained (the
    rig's torsional modes among the candidates); the seed's filter study, ranked.

    Parameters
    ----------
    recording : Recording
        Needs ``torque``, speeds or encoder counts, and the normal load or air-spring pressure.
    rig : RigParameters, optional
        The rig the test ran on (geometry, inertia, bearings, sensors); default the bundled rig.
    truth : xarray.Dataset, optional
        For synthetic recordings, the twin's truth on the same time axis: adds the errors of the
        rig's and the corrected CoA against the true contact CoA.
    smoothing : (order, window), optional
        Fix the Savitzky-Golay filter instead of tuning it.
    run_study : bool
        Run the full filter study.

    Returns
    -------
    TestAnalysis
    """
    from rollerrig.rig.chain import modal_table
    from rollerrig.rig.parameters import default_rig

    notes: list[str] = []
    if rig is None:
        rig = default_rig()
        notes.append("no rig given: the bundled default rig's parameters were used")
    rec = derive_quantities(recording, rig)
    rec.require("torque", "creep", "coa", "normal_load", "roller_speed", "wheel_speed")
    t, fs = rec.time, rec.sample_rate

    phases = segment_test(rec)
    if smoothing is None:
        order, window, table = tune_savitzky_golay(t, rec["torque"])
    else:
        (order, window), table = smoothing, []
    torque_s = savitzky_golay(rec["torque"], window, order)
    wheel_s = savitzky_golay(rec["wheel_speed"], window, order)
    roller_s = savitzky_golay(rec["roller_speed"], window, order)
    rw, rr = rig.geometry.wheel_radius_x, rig.geometry.roller_radius_x
    v_roller = roller_s * rr
    slip_s = wheel_s * rw - v_roller
    creep_s = np.divide(slip_s, v_roller, out=np.zeros_like(slip_s), where=np.abs(v_roller) > 1e-3)
    coa_s = torque_s / (rr * rec["normal_load"])
    b = rig.bearing
    coa_c, alpha = corrected_adhesion(
        rec["torque"],
        rec["roller_speed"],
        rec["normal_load"],
        fs,
        roller_radius=rr,
        roller_inertia=rig.inertia.roller,
        bearing_friction=b.friction_coefficient,
        bearing_radius=b.roller_bearing_radius,
        roller_weight=b.roller_subsystem_weight,
        regularisation_speed=b.regularisation_speed,
        # The acceleration needs less smoothing than the noise does: a 0.2 s quartic SG keeps
        # the transients (measured: CoA error 0.009 vs 0.019 with a 0.8 s quadratic one).
        window=_odd(0.2 * fs),
        order=4,
    )
    rec = rec.with_channels(
        torque_smoothed=torque_s,
        creep_smoothed=creep_s,
        slip_velocity_smoothed=slip_s,
        coa_smoothed=coa_s,
        coa_corrected=coa_c,
        roller_acceleration=alpha,
    )

    branches = adhesion_branches(t, creep_s, phases)
    hyst: list[Hysteresis | None] = []
    for br in branches:
        try:
            hyst.append(
                hysteresis(
                    creep_s[br.ascending],
                    coa_s[br.ascending],
                    creep_s[br.descending],
                    coa_s[br.descending],
                )
            )
        except ValueError as exc:  # branches that do not overlap in creep
            hyst.append(None)
            notes.append(f"cycle {br.cycle}: no hysteresis ({exc})")

    fit = fit_rig = None
    points = np.array([], dtype=int)
    if branches:
        points = np.concatenate([br.ascending for br in branches])
        points = points[(creep_s[points] > 1e-4) & (coa_s[points] > 0.01)]
    if points.size >= 10:
        load = rec["normal_load"][points]
        stiffness = creep_stiffness_for_rig(float(np.median(load)), rig)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            fit = fit_polach(
                creep_s[points], coa_c[points], load, stiffness, slip_velocity=slip_s[points]
            )
            fit_rig = fit_polach(
                creep_s[points], coa_s[points], load, stiffness, slip_velocity=slip_s[points]
            )
        notes.extend(sorted({str(w.message) for w in caught}))
    else:
        notes.append("too few ascending-branch points for a Polach fit")

    spectrum, window_s = None, quiet_phase(phases)
    if window_s is not None and (window_s[1] - window_s[0]) * fs >= 256:
        quiet = rec.select(*window_s)
        modes = [row.frequency for row in modal_table(rig) if row.frequency > 0]
        # One Hann segment over the whole quiet phase: the finest resolution it allows.
        spectrum = explain_spectrum(
            quiet, "torque", nperseg=quiet.time.size, rig_modes=modes, min_frequency=0.5
        )
    else:
        notes.append("no quiet phase of at least 256 samples: spectrum skipped")

    study = filter_study(t, rec["torque"]) if run_study else []

    errors = {}
    if truth is not None:
        true_coa = np.asarray(truth["coa"].values)

        def rms(x):
            return float(np.sqrt(np.mean((x - true_coa) ** 2)))

        errors = {
            "rig_coa_vs_true_rms [-]": rms(rec["coa"]),
            "smoothed_rig_coa_vs_true_rms [-]": rms(coa_s),
            "corrected_coa_vs_true_rms [-]": rms(coa_c),
            "corrected_coa_vs_true_max [-]": float(np.max(np.abs(coa_c - true_coa))),
        }
    return TestAnalysis(
        recording=rec,
        rig_name=rig.meta.name,
        phases=phases,
        smoothing_order=int(order),
        smoothing_window=int(window),
        smoothing_table=table,
        branches=branches,
        hysteresis=hyst,
        fit=fit,
        fit_rig_coa=fit_rig,
        fit_points=points,
        spectrum=spectrum,
        spectrum_window=window_s,
        study=study,
        notes=notes,
        truth_errors=errors,
    )
