"""The corrected CoA's stated uncertainty on recordings from models the analysis does not share
(issue 25): an independently written swinging arm whose geometry the analysis is not told, and
the dq induction machine under V/f settings it is not told (its rig keeps the lag model).

Targets of the issue: |corrected − true| <= U (k = 2) at >= 90 % of the samples in the holds,
>= 80 % overall, >= 70 % in the second after each release; the corrected CoA's RMS error at
most 1/4 of the rig's raw error when the arm is the one stated (within its tolerance).
Recordings: tests/untold_models.py.
"""

import functools

import numpy as np
import pytest

from rollerrig.analysis.adhesion import analyze_test
from rollerrig.rig.parameters import default_rig
from untold_models import ArmGeometry, arm_recording, coverage, dq_recording

CASES = {
    # pivot 0.30 m above the contact, 0.80 m behind (h/l 0.375, the default assumes 0.497),
    # 300 N of weight outside the spring's calibration at 0.40 m from the pivot (W_d 150 N):
    # the seed's level then drives the wheel to 30 % creep before each release.
    "lower, longer arm with a dead weight": lambda: arm_recording(
        ArmGeometry(pivot=(-0.80, 0.30), spring_x=0.0, weight=300.0, weight_x=-0.40)
    ),
    # pivot 0.45 m above, 0.60 m behind (h/l 0.75), the spring calibrated 200 N high.
    "higher, shorter arm": lambda: arm_recording(
        ArmGeometry(pivot=(-0.60, 0.45), spring_x=0.0, weight=-200.0, weight_x=0.0)
    ),
    # The dq machine with 100 % slip compensation and 0.1 s filters (the rig: lag model).
    "dq drive, slip compensation": lambda: dq_recording(
        {"slip_compensation": 1.0, "current_filter_time": 0.1, "slip_filter_time": 0.1}
    ),
}


@functools.cache
def _recording(case):
    return CASES[case]()


@pytest.mark.slow
@pytest.mark.parametrize("case", list(CASES))
def test_the_band_covers_the_truth_of_a_model_the_analysis_does_not_share(case):
    rec, truth, protocol = _recording(case)
    result = analyze_test(rec, default_rig(), truth=truth, run_study=False)
    got = coverage(result, truth, protocol)
    assert got["holds at the level"] >= 0.90, got
    assert got["rest holds"] >= 0.90, got
    assert got["second after each release"] >= 0.70, got
    assert got["overall"] >= 0.80, got
    assert got["rms error corrected"] <= 0.25 * got["rms error rig"], got


def test_the_independent_arm_is_the_packages_arm_in_other_words():
    """The moment balance written from coordinates gives the package's N = S + W_d + σ(h/l)F_x
    (h = z_pivot, l = −x_pivot, W_d = W (x_g − x_p)/(−x_p)) for a spring above the wheel."""
    geometry = ArmGeometry(pivot=(-0.80, 0.30), spring_x=0.0, weight=300.0, weight_x=-0.40)
    rig = default_rig().with_overrides(
        {"arm.pivot_height": 0.30, "arm.arm_length": 0.80, "arm.dead_weight": 150.0}
    )
    for s, f in ((4300.0, 0.0), (4300.0, 1800.0), (10e3, -500.0)):
        assert geometry.contact_load(s, f) == pytest.approx(rig.arm.contact_load(s, f), rel=1e-12)


@pytest.mark.slow
def test_the_chain_smoother_fits_its_drive_noise_to_a_drive_it_does_not_model():
    """On the dq drive's recording the chain (lag model of the drive) at its fixed default
    noise is worse than the roller alone (measured 0.0097 against 0.0044); with the noise by
    maximum likelihood it is better (0.0039) and says that the drive is not the lag model."""
    from rollerrig.estimation.estimator import smooth_from_recording
    from rollerrig.measure.facts import truth_coa

    rec, truth, _ = _recording("dq drive, slip compensation")
    rig = default_rig()
    t_true, coa_true = truth_coa(truth, rec)
    true = np.interp(rec.time, t_true, coa_true)
    edge = (rec.time > rec.time[0] + 0.5) & (rec.time < rec.time[-1] - 0.5)

    def rms(est):
        return float(np.sqrt(np.mean((est.coa - true)[edge] ** 2)))

    alone = smooth_from_recording(rec, rig, chain=None)
    fixed = smooth_from_recording(rec, rig, chain="induction")
    chosen = smooth_from_recording(rec, rig, shaft_calibrated=True)
    assert rms(fixed) > rms(alone)
    assert rms(chosen) < rms(alone) < rms(fixed)
    assert chosen.drive_noise > 1e3 * 1e2  # 10^3 times the default or more
    assert "not the lag model" in chosen.choice
