"""Shared inputs of the uncertainty tests: an adhesion test in closed form, no twin needed.

:func:`coa_recording` builds what the rig's DAQ records (torque with white noise, quantised
encoder counts of wheel and roller, air-spring pressure with noise) around a known contact CoA,
so that the dynamics correction's exact answer is known: T56 = μ r_r N − J5 α5 − R05.

The wheel hangs on the rig's swinging arm: the air spring's force S is what the DAQ sees, the
contact carries N = S + W_d + κ μ N, written here in closed form in μ,
N = (S + W_d) / (1 − κ μ) (κ = σ h/l), independently of the correction's form, which solves
for F_x.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rollerrig.measure.quantities import derive_quantities
from rollerrig.recordings.recording import Recording
from rollerrig.rig.parameters import default_rig


def coa_recording(rig=None, *, seconds=12.0, fs=250.0, seed=0, torque_noise=1.0,
                  pressure_noise=100.0, peak=0.3):  # fmt: skip
    """(derived Recording, true contact CoA, release (start, end) [s]) of a closed-form test.

    Roller at 30 km/h with a 0.3 Hz speed swing (α5 up to ±1 rad/s²); the CoA ramps from 0 to
    ``peak`` over 2-6 s, holds to 7 s, drops to 0 in 20 ms; creep follows the CoA (2 % at the
    peak); load 4.3 kN. Encoder counts are floor(θ·CPR/2π) of the exact angles.
    """
    rig = rig or default_rig()
    rng = np.random.default_rng(seed)
    t = np.arange(round(seconds * fs)) / fs
    rr, rw = rig.geometry.roller_radius_x, rig.geometry.wheel_radius_x
    j5, area = rig.inertia.roller, rig.sensors.air_spring_effective_area
    b, cpr = rig.bearing, rig.sensors.encoder_counts_per_revolution
    w0, dw, f = 30 / 3.6 / rr, 0.5, 0.3
    omega = w0 + dw * np.sin(2 * math.pi * f * t)
    alpha = dw * 2 * math.pi * f * np.cos(2 * math.pi * f * t)
    theta_r = w0 * t + dw / (2 * math.pi * f) * (1 - np.cos(2 * math.pi * f * t)) + 0.37
    mu = np.interp(t, [0, 2, 6, 7, 7.02, seconds], [0, 0, peak, peak, 0, 0])
    creep = mu / peak * 0.02
    # wheel angle: ω_w r_w = (1 + s) ω_r r_r, integrated (trapezoid on a 10x finer grid)
    fine = np.linspace(0, t[-1], 10 * t.size - 9)
    w_w = (1 + np.interp(fine, t, creep)) * np.interp(fine, t, omega) * rr / rw
    steps = np.diff(fine) * 0.5 * (w_w[1:] + w_w[:-1])
    theta_w = np.interp(t, fine, np.concatenate([[0.0], np.cumsum(steps)])) + 0.11
    spring = 4300.0  # the air spring's force S [N]
    arm = rig.arm
    kappa = (1.0 if arm.pivot_side == "rear" else -1.0) * arm.pivot_height / arm.arm_length
    load = (spring + arm.dead_weight) / (1.0 - kappa * mu)  # at the contact
    bearing = b.friction_coefficient * b.roller_bearing_radius * (b.roller_subsystem_weight + load)
    t56 = mu * rr * load - j5 * alpha - bearing * np.tanh(omega / b.regularisation_speed)
    channels = {
        "torque": t56 + torque_noise * rng.standard_normal(t.size),
        "roller_encoder_counts": np.floor(theta_r * cpr / (2 * math.pi)),
        "wheel_encoder_counts": np.floor(theta_w * cpr / (2 * math.pi)),
        "air_spring_pressure": spring / area + pressure_noise * rng.standard_normal(t.size),
    }
    units = {"torque": "N.m", "roller_encoder_counts": "1", "wheel_encoder_counts": "1",
             "air_spring_pressure": "Pa"}  # fmt: skip
    rec = derive_quantities(Recording(t, channels, units, {"source": "closed-form"}), rig)
    return rec, mu, (7.0, 7.02)


@pytest.fixture(scope="session")
def closed_form_test():
    """:func:`coa_recording` with the default rig and seed 0."""
    return coa_recording()


NO_ARM = {
    "arm.pivot_height": 0.0,
    "arm.pivot_height_tolerance": 0.0,
    "arm.arm_length_tolerance": 0.0,
    "arm.dead_weight_uncertainty": 0.0,
}
"""Rig overrides of a contact that carries exactly the air-spring force (no arm transfer, known
exactly): the rig the GUM and Monte Carlo machinery tests were derived for, where the sensors'
own inputs dominate."""


def no_arm_rig():
    """The default rig with :data:`NO_ARM`."""
    return default_rig().with_overrides(NO_ARM)


@pytest.fixture(scope="session")
def closed_form_no_arm():
    """:func:`coa_recording` on :func:`no_arm_rig`, seed 0: ``(rig, recording, μ, release)``."""
    rig = no_arm_rig()
    return (rig, *coa_recording(rig))


@pytest.fixture(scope="session")
def make_coa_recording():
    """:func:`coa_recording` itself, for tests that need another seed, rig or noise."""
    return coa_recording
