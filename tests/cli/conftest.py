"""Fixtures of the command-line tests: a runner and hand-built recordings.

``adhesion_csv(path, ...)``: an adhesion test of 10 s at 100 Hz built by hand (CSV);
``fast_test(path, ...)``: the same test at 19.2 kHz with an inverter line, written by the
package's writer (format from the suffix).
"""

import numpy as np
import pytest
from typer.testing import CliRunner

HEADER = "time [s],torque [N.m],torque_request [N.m],wheel_speed [rad/s],roller_speed [rad/s]"


@pytest.fixture
def runner():
    return CliRunner()


def _adhesion_csv(path, fs=100.0, duration=10.0, torque=None, nan_at=(), drop=()):
    """A hand-built adhesion test: ramp 2-5 s to 600 N.m, hold, sudden release; creep rising
    with the CoA; 30 km/h, 4.3 kN; ``torque`` replaces the measured torque if given; NaN at
    the samples ``nan_at``; the rows ``drop`` left out (a gap)."""
    rng = np.random.default_rng(0)
    t = np.arange(int(duration * fs)) / fs
    request = np.interp(t, [0, 2, 5, 5.5, 5.52, duration], [0, 0, 600, 600, 0, 0])
    # The induction motor's line (5 pole pairs x roller rotation at 30 km/h: 14.67 Hz) and noise.
    line = 3.0 * np.sin(2 * np.pi * 5 * (30 / 3.6) / (2 * np.pi * 0.452) * t)
    measured = request + line + rng.standard_normal(t.size) if torque is None else torque(t)
    rr, rw, load = 0.452, 0.348, 4300.0
    coa = np.clip(request / (rr * load), 0, None)
    creep = 0.02 * np.tan(np.clip(coa / 0.45, 0, 0.9) * np.pi / 2) / np.tan(0.45 * np.pi)
    omega_r = np.full(t.size, 30 / 3.6 / rr)
    omega_w = omega_r * rr * (1 + creep + 1e-4 * coa) / rw
    measured = np.array(measured, dtype=float)
    measured[list(nan_at)] = np.nan
    rows = [HEADER + ",normal_load [N]"]
    skip = set(drop)
    rows += [
        f"{a:.6f},{b!r},{c:.6f},{d:.9f},{e:.9f},{load}"
        for i, (a, b, c, d, e) in enumerate(
            zip(t, measured.tolist(), request, omega_w, omega_r, strict=True)
        )
        if i not in skip
    ]
    path.write_text("\n".join(rows) + "\n")
    return path


@pytest.fixture
def adhesion_csv():
    return _adhesion_csv


def _fast_test(path, fs=19_200.0, duration=8.0):
    """The hand-built adhesion test of ``adhesion_csv`` at the QuantumX rate (19.2 kHz), with
    an inverter line at 2.35 kHz (far above the analysis band: decimation must not alias it),
    written with the package's writer (format from the suffix); returns the path and the true
    CoA on the file's time axis."""
    from rollerrig.recordings.recording import Recording
    from rollerrig.recordings.writers import write_recording

    rng = np.random.default_rng(1)
    t = np.arange(int(duration * fs)) / fs
    request = np.interp(t, [0, 2, 5, 5.5, 5.52, duration], [0, 0, 600, 600, 0, 0])
    line = 3.0 * np.sin(2 * np.pi * 14.67 * t) + 2.0 * np.sin(2 * np.pi * 2350.0 * t)
    rr, rw, load = 0.452, 0.348, 4300.0
    coa = np.clip(request / (rr * load), 0, None)
    creep = 0.02 * np.tan(np.clip(coa / 0.45, 0, 0.9) * np.pi / 2) / np.tan(0.45 * np.pi)
    omega_r = np.full(t.size, 30 / 3.6 / rr)
    channels = {
        "torque": request + line + rng.standard_normal(t.size),
        "torque_request": request,
        "wheel_speed": omega_r * rr * (1 + creep + 1e-4 * coa) / rw,
        "roller_speed": omega_r,
        "normal_load": np.full(t.size, load),
    }
    units = {"torque": "N.m", "torque_request": "N.m", "wheel_speed": "rad/s"}
    units |= {"roller_speed": "rad/s", "normal_load": "N"}
    write_recording(Recording(t, channels, units), path)
    return path, t, coa


@pytest.fixture
def fast_test():
    return _fast_test
