"""Coverage of the stated standard errors over independent synthetic recordings.

Each seed draws its own true parameters (the bundled rig's values altered by 5-35 %, each
scaled again by up to ±3 %, so that the encoders' quantisation pattern differs too) and its
own noise and line phases; the calibration is told none of it. For honest standard errors,
(fitted − true)/standard error is standard normal: about 68 % within 1 and 95 % within 2.
The recordings have no sensor offsets, so this holds for the statistical part of the standard
error; the stated total adds the sensors' classes (test_systematic.py) and can only cover more.
"""

import numpy as np
import pytest

from rollerrig.calibrate import calibrate

SEEDS = range(10)


@pytest.mark.slow
def test_standard_errors_cover_the_truth_at_the_stated_rate(recording_maker, truth_drawer):
    z, z_total = [], []
    for seed in SEEDS:
        truth = truth_drawer(np.random.default_rng(100 + seed))
        rec, _ = recording_maker(truth=truth, seed=seed)
        result = calibrate(rec, list(truth))
        for key, true in truth.items():
            p = result.parameters[key]
            assert p.identified, (seed, key)
            z.append((p.value - true) / p.standard_error_statistical)
            z_total.append((p.value - true) / p.standard_error)
    z, z_total = np.abs(np.array(z)), np.abs(np.array(z_total))
    assert np.all(z_total <= z) and z_total.max() < 2.0, z_total
    # 40 values: a stated error too small by 1.5x would put 18 % outside 2 standard errors and
    # give an RMS of 1.5. Measured on these seeds: 95 % within 2, RMS 1.0; on 30 seeds of this
    # test 71 % within 1 and 96 % within 2, and on 10 seeds of the bundled 30 s test 82 % and
    # 98 % (RMS 0.85).
    assert np.mean(z < 2.0) >= 0.85, z
    assert np.mean(z < 1.0) >= 0.5, z
    assert float(np.sqrt(np.mean(z**2))) < 1.35, z
    assert z.max() < 4.0, z
