"""Does the frame matter? The seed's first hypothesis simulated instead of argued.

Kayaalp (section 4.3.1) first suspected the frame's longitudinal flexibility of causing the
torque oscillation after a release; a static FE model found a top deflection of about 0.04 mm
and the hypothesis was dropped (section 5.1.1) without a dynamic check. Here the frame is a
degree of freedom of the twin at the contact (:class:`rollerrig.rig.sections.FrameParameters`,
``DriveConfig(frame="flexible")``) with the stiffness and modal mass that the FE model of a frame
gives at the contact (:func:`rollerrig.frame.contact_dof`), and the release test runs on three
frames: rigid, that frame, and one ten times softer (same mass: its mode a factor √10 lower).

The verdict compares what the rig reports: the overshoot of T56/r_r after the release, the
ringing line of T56 (frequency and amplitude) and the T56 spectrum at the frame's frequency.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from rollerrig.experiment import load_protocol
from rollerrig.rig.model import DriveConfig
from rollerrig.rig.parameters import RigParameters, default_rig
from rollerrig.studies.metrics import RunChannels, compute_metrics, rest_spectrum

__all__ = ["MATTERS_THRESHOLD", "FrameCase", "FrameStudy", "frame_study"]

MATTERS_THRESHOLD = 0.05
"""The frame matters when it changes the release overshoot or the ringing line's amplitude by
more than this share of the rigid frame's value [-], or puts a line at its own frequency larger
than this share of the ringing line."""
METRICS = (
    "release_overshoot",
    "true_release_overshoot",
    "settling_time",
    "t56_line_frequency",
    "t56_line_amplitude",
    "coa_bias_rms",
)
SOFTER = 10.0
"""The soft variant: the frame's stiffness divided by this, its mass kept."""


@dataclass(frozen=True)
class FrameCase:
    """One frame of the study: its label, stiffness [N/m] (inf: rigid), modal mass [kg],
    frequency [Hz] (inf: rigid), the metrics of its run, the T56 rest spectrum (frequency [Hz],
    amplitude [N.m]) and the T56 line at the frame's frequency [N.m] (None: rigid)."""

    label: str
    stiffness: float
    modal_mass: float
    frequency: float
    metrics: dict[str, float]
    spectrum: tuple[np.ndarray, np.ndarray] = field(repr=False)
    line_at_frame_frequency: float | None = None

    def row(self) -> dict:
        """The case as JSON-ready values (None for a rigid frame's stiffness and frequency)."""
        finite = np.isfinite(self.stiffness)
        return {
            "frame": self.label,
            "longitudinal_stiffness [N/m]": self.stiffness if finite else None,
            "modal_mass [kg]": self.modal_mass if finite else None,
            "frequency [Hz]": self.frequency if finite else None,
            **{k: (v if np.isfinite(v) else None) for k, v in self.metrics.items()},
            "t56_line_at_frame_frequency [N.m]": self.line_at_frame_frequency,
        }


@dataclass(frozen=True)
class FrameStudy:
    """The outcome of :func:`frame_study`: the cases, the frame's FE numbers and the verdict."""

    cases: tuple[FrameCase, ...]
    experiment: str
    fe: dict
    matters: bool
    verdict: str

    def rows(self) -> list[dict]:
        """One JSON-ready row per case."""
        return [c.row() for c in self.cases]


def _line_near(spectrum, frequency: float, width: float = 0.05) -> float:
    """Amplitude of the largest spectral line (a local maximum) within ±``width`` (relative) of
    ``frequency`` [N.m]; 0 when there is none (only the flank of a line elsewhere)."""
    f, a = spectrum
    peak = np.zeros(a.size, dtype=bool)
    peak[1:-1] = (a[1:-1] > a[:-2]) & (a[1:-1] >= a[2:])
    near = peak & (np.abs(f - frequency) <= width * frequency)
    return float(a[near].max()) if near.any() else 0.0


def frame_study(
    rig: RigParameters | None = None,
    frame=None,
    *,
    experiment: str = "release-test",
    output_rate: float = 1000.0,
    progress: Callable[[str], None] | None = None,
) -> FrameStudy:
    """Simulate the release test with a rigid frame, the FE frame and one ten times softer.

    Parameters
    ----------
    rig : RigParameters, optional
        The rig; default the bundled one.
    frame : Frame, optional
        The frame (:func:`rollerrig.frame.load_frame`); its static and modal FE analysis gives
        the contact's stiffness and modal mass. Default: the rig's ``[frame]`` values (those of
        the bundled default frame).
    experiment : str
        Bundled experiment or file with a sudden release (default: the release test).
    output_rate : float
        Sampling of the runs [Hz]: 1 kHz resolves the frame's mode (tens of Hz).
    progress : callable, optional
        Called as ``progress(step)`` as each step starts ("simulating: rigid frame (1 of 3)").

    Returns
    -------
    FrameStudy
    """
    from rollerrig.solve.simulation import Simulation

    rig = rig or default_rig()
    fe: dict = {"source": "the rig file's [frame] values"}
    if frame is not None:
        from rollerrig.frame import analyze_frame, contact_dof

        if progress is not None:
            progress(f"FE of frame {frame.name!r}")
        result = analyze_frame(frame)
        dof = contact_dof(result)
        rig = rig.with_overrides(
            {
                "frame.longitudinal_stiffness": dof.stiffness,
                "frame.modal_mass": dof.equivalent_mass,
            }
        )
        fe = {
            "source": f"FE of frame {frame.name!r}",
            "top_horizontal_deflection [m]": result.top_horizontal_deflection,
            "contact_mode_frequency [Hz]": dof.frequency,
            "contact_mode_share_of_flexibility": dof.participation,
        }
    k, m = rig.frame.longitudinal_stiffness, rig.frame.modal_mass
    fe.update({"longitudinal_stiffness [N/m]": k, "modal_mass [kg]": m})
    protocol = load_protocol(experiment)
    variants = [
        ("rigid frame", rig, "rigid", np.inf, np.nan),
        ("frame (FE)", rig, "flexible", k, m),
        (
            f"frame {SOFTER:g}x softer",
            rig.with_overrides({"frame.longitudinal_stiffness": k / SOFTER}),
            "flexible",
            k / SOFTER,
            m,
        ),
    ]
    cases = []
    for i, (label, r, mode, stiffness, mass) in enumerate(variants):
        if progress is not None:
            progress(f"simulating {protocol.name}: {label} ({i + 1} of {len(variants)})")
        sim = Simulation(r, protocol, DriveConfig(frame=mode), output_rate=output_rate)
        ds = sim.run()
        run = RunChannels.from_dataset(ds, r.geometry.roller_radius_x)
        values = compute_metrics(run, protocol, METRICS)
        spectrum = rest_spectrum(run, protocol)
        freq = np.sqrt(stiffness / mass) / (2 * np.pi) if np.isfinite(stiffness) else np.inf
        at_frame = _line_near(spectrum, freq) if np.isfinite(freq) else None
        cases.append(FrameCase(label, stiffness, mass, freq, values, spectrum, at_frame))
    matters, verdict = _verdict(cases)
    return FrameStudy(tuple(cases), protocol.name, fe, matters, verdict)


def _verdict(cases: list[FrameCase]) -> tuple[bool, str]:
    rigid, fe, soft = cases
    parts = []
    matters = soft_big = False
    for case in (fe, soft):
        d_over = case.metrics["release_overshoot"] - rigid.metrics["release_overshoot"]
        rel_over = d_over / rigid.metrics["release_overshoot"]
        d_amp = case.metrics["t56_line_amplitude"] - rigid.metrics["t56_line_amplitude"]
        rel_amp = d_amp / rigid.metrics["t56_line_amplitude"]
        share = case.line_at_frame_frequency / rigid.metrics["t56_line_amplitude"]
        big = max(abs(rel_over), abs(rel_amp), share) > MATTERS_THRESHOLD
        if case is fe:
            matters = big
        else:  # the sensitivity case: would a much softer frame matter?
            soft_big = big
        parts.append(
            f"{case.label} ({case.frequency:.1f} Hz): release overshoot "
            f"{case.metrics['release_overshoot']:.2%} against "
            f"{rigid.metrics['release_overshoot']:.2%} "
            f"rigid (relative {rel_over:+.2%}); ringing line "
            f"{case.metrics['t56_line_frequency']:.2f} Hz, "
            f"{case.metrics['t56_line_amplitude']:.2f} N.m ({rel_amp:+.2%}); T56 at the frame's "
            f"frequency {case.line_at_frame_frequency:.3g} N.m ({share:.2%} of the ringing line)"
        )
    head = (
        f"The frame matters: it changes what the rig reports by more than {MATTERS_THRESHOLD:.0%}."
        if matters
        else "The frame does not explain the oscillation: the rig's frame changes what the rig "
        f"reports by less than {MATTERS_THRESHOLD:.0%} (Kayaalp 5.1.1's conclusion, now "
        "simulated)"
        + (
            f"; a frame ten times softer would change it by more than {MATTERS_THRESHOLD:.0%}, "
            "so the verdict rests on the frame's stiffness."
            if soft_big
            else "."
        )
    )
    return matters, " ".join([head, *(p + "." for p in parts)])
