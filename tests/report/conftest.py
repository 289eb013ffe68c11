"""Shared inputs of the report tests: one analysed adhesion test, built without the twin.

The recording is made in closed form (three ramp-hold-release cycles at 30 km/h on the
bundled rig's radii, CoA from a Polach-shaped curve, a motor line and noise on the torque), so
the analysis runs in well under a second and the report tests need no simulation.
"""

from __future__ import annotations

import numpy as np
import pytest

from rollerrig.measure.analysis import analyze_test
from rollerrig.measure.recording import Recording
from rollerrig.rig.parameters import default_rig

FS = 250.0  # [Hz]


def adhesion_test_recording(seed: int = 0) -> Recording:
    """24 s at 250 Hz: three cycles of creep 0 -> 4 % (3 s), hold 0.5 s, release (50 ms)."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(24 * FS)) / FS
    rr, rw, load, v = 0.452, 0.348, 4300.0, 30 / 3.6  # m, m, N, m/s
    creep = np.zeros_like(t)
    for t0 in (2.0, 10.0, 18.0):
        up = (t >= t0) & (t < t0 + 3.0)
        creep[up] = 0.04 * (t[up] - t0) / 3.0
        creep[(t >= t0 + 3.0) & (t < t0 + 3.5)] = 0.04
        rel = (t >= t0 + 3.5) & (t < t0 + 4.0)
        creep[rel] = 0.04 * np.exp(-(t[rel] - t0 - 3.5) / 0.05)
    eps = 40.0 * creep  # Polach's gradient of tangential stress, here in closed form
    coa = 2 * 0.45 / np.pi * (0.6 * eps / (1 + (0.6 * eps) ** 2) + np.arctan(0.3 * eps))
    torque = (
        coa * load * rr + 3.0 * np.sin(2 * np.pi * 14.67 * t) + 2.0 * rng.standard_normal(t.size)
    )
    return Recording(
        t,
        {
            "torque": torque,
            "torque_request": coa * load * rw,
            "wheel_speed": v * (1 + creep) / rw,
            "roller_speed": np.full(t.size, v / rr),
            "normal_load": np.full(t.size, load),
        },
        {
            "torque": "N.m",
            "torque_request": "N.m",
            "wheel_speed": "rad/s",
            "roller_speed": "rad/s",
            "normal_load": "N",
        },
        {"source": "synthetic-test.csv"},
    )


@pytest.fixture(scope="session")
def analysed():
    """:class:`rollerrig.measure.analysis.TestAnalysis` of :func:`adhesion_test_recording`."""
    return analyze_test(adhesion_test_recording(), default_rig())


@pytest.fixture(scope="session")
def written(analysed, tmp_path_factory):
    """The files :func:`rollerrig.report.analysis.write_analysis` writes: json, nc, html."""
    from rollerrig.report.analysis import write_analysis

    out = tmp_path_factory.mktemp("analysis")
    return write_analysis(analysed, out, "synthetic", source="synthetic-test.csv")
