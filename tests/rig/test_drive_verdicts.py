"""Tests of the drive-dynamics study's verdicts (rollerrig.rig.drive_verdicts).

References used below:
- The definition of the damping ratio: ζ < 0 is a growing oscillation (an unstable mode), never
  a lightly damped one.
- A reduced model of slip compensation written here from its equations, independent of the
  twin: the whole rotating assembly J (J5 + J6 + the wheel side through (r_r/r_w)²) on the
  machine's small-slip torque T = (c/p)(ω_s − pΩ) lagged by the transient rotor time constant
  τ'_r, the slip estimate p T/c through the first-order slip filter τ_f, and ω_s = ω* + k ŝ:
      J Ω' = T,  τ_f ŝ' = p T/c − ŝ,  τ'_r T' = (c/p)(k ŝ − pΩ) − T.
  c is the rig's Thevenin slope 3V²/(R2' ω_syn²) reduced by the flux the stator resistance
  takes under V ∝ f, 1/(1 + (R_s/(ω_s(L_σ + L_M)))²). Its complex pair must give the twin's
  electromechanical mode to ~12 % in frequency, and the same trends: a shorter slip filter and
  a lighter J5 raise the frequency, more gain lowers the damping, 150 % with 0.05 s is unstable.
"""

from __future__ import annotations

import numpy as np
import pytest

from rollerrig.rig import drive_dynamics as dd
from rollerrig.rig import drive_verdicts as dv
from rollerrig.rig.parameters import default_rig

RIG = default_rig()


def _row(speed, modes, unstable=()):
    return {
        "speed [km/h]": speed,
        "normal_load [kN]": 4.3,
        "modes below 20 Hz": [{"frequency [Hz]": f, "damping_ratio [-]": z} for f, z in modes],
        "unstable": list(unstable),
    }


def test_an_unstable_mode_is_its_own_class():
    assert dv.mode_class(-0.016) == "unstable"
    assert dv.mode_class(0.0) == "lightly damped"
    assert dv.mode_class(0.299) == "lightly damped"
    assert dv.mode_class(0.3) == "damped"
    # the table row of a growing 1.55 Hz mode: unstable, not lightly damped
    row = _row(10.0, [(1.55, -0.016), (4.5, 0.21)], unstable=[(0.15, 1.55)])
    assert dv.band_class(row, (1.0, 1.7)) == "unstable"
    rows = [row, _row(5.0, [(1.45, 0.002)])]
    v = dv.band_verdict(rows)
    assert v["kind"] == "unstable" and v["speeds [km/h]"] == [10.0]
    # only the unstable row is quoted: the 5 km/h mode (ζ 0.002) is not what it names
    assert v["damping_ratio [-]"] == [-0.016, -0.016]
    assert v["text"] == "unstable at 10 km/h (1.55-1.55 Hz, ζ -0.016 to -0.016)"


def test_the_twins_rows_never_count_an_unstable_mode_as_lightly_damped():
    # 150 % slip compensation with a 0.05 s filter grows at 20 km/h (ζ ≈ −0.01)
    drive = dd.default_dq_drive(RIG, slip_compensation=1.5, slip_filter_time=0.05)
    (row,) = dd.eigen_table(RIG, [drive], [20 / 3.6], [4.3e3])
    growing = [md for md in row["modes below 20 Hz"] if md["damping_ratio [-]"] < 0.0]
    assert growing and all(md["class"] == "unstable" for md in growing)
    assert row["unstable"]
    assert row["class in 1-1.7 Hz"] == "unstable"
    assert not row["lightly damped in 1-1.7 Hz"]  # only modes with 0 <= ζ < 0.3 count


def test_a_verdict_quotes_only_the_modes_of_the_rows_it_names():
    """Review: "dq slip comp 1.0, 0.1 s: lightly damped mode in 1-1.7 Hz at 5 km/h only (1.39-1.50
    Hz, ζ 0.200 to 0.339)": the least damped mode of every row was quoted, the damped ones at
    10-30 km/h (ζ 0.307-0.339) too, above the 0.3 the class stops at."""
    rows = [
        _row(5.0, [(1.50, 0.200), (1.63, 0.541)]),
        _row(10.0, [(1.48, 0.963), (1.48, 0.307)]),
        _row(30.0, [(1.39, 0.339)]),
    ]
    v = dv.band_verdict(rows)
    assert v["kind"] == "some speeds" and v["speeds [km/h]"] == [5.0]
    assert v["damping_ratio [-]"] == [0.200, 0.200] and v["frequency [Hz]"] == [1.50, 1.50]
    assert v["text"].endswith("at 5 km/h only (1.50-1.50 Hz, ζ 0.200 to 0.200)")
    # none lightly damped: every row's least damped mode in the band, all damped
    v = dv.band_verdict(rows[1:])
    assert v["kind"] == "none" and v["damping_ratio [-]"] == [0.307, 0.339]
    # an instability above 20 Hz (not in the modes listed) is quoted from its eigenvalue
    sigma, f = 2.0, 35.0
    growing = _row(20.0, [(1.4, 0.15)], unstable=[(sigma, f)])
    v = dv.band_verdict([growing, rows[0]])
    zeta = -sigma / np.hypot(sigma, 2 * np.pi * f)
    assert v["kind"] == "unstable" and v["speeds [km/h]"] == [20.0]
    assert v["frequency [Hz]"] == [f, f] and v["damping_ratio [-]"] == [zeta, zeta]
    # the study's R_s check quoted "ζ 0.201 to 0.300" for a lightly damped 0.29996
    v = dv.band_verdict([_row(5.0, [(1.5, 0.201)]), _row(10.0, [(1.49, 0.29996)])])
    assert v["kind"] == "every speed" and v["text"].endswith("ζ 0.201 to 0.29996)")


@pytest.mark.parametrize(
    ("kinds", "expected"),
    [
        (["lightly damped", "lightly damped"], "every speed"),
        (["lightly damped", "damped"], "some speeds"),
        (["damped", "none"], "none"),
    ],
)
def test_band_verdict_kinds(kinds, expected):
    modes = {"lightly damped": [(1.4, 0.15)], "damped": [(1.4, 0.5)], "none": [(3.0, 0.1)]}
    rows = [_row(v, modes[k]) for v, k in zip((5.0, 30.0), kinds, strict=True)]
    assert dv.band_verdict(rows)["kind"] == expected


def test_robustness_names_the_assumption_and_the_values_where_it_flips():
    # A fake table: lightly damped everywhere unless the slip filter is 0.05 s (unstable) or
    # J5 is above 45 kg.m^2 (damped). R_s, the current filter and the estimate change nothing.
    def rows_for(rig, settings):
        if settings.get("slip_filter_time") == 0.05:
            return [_row(v, [(1.5, -0.01)], unstable=[(0.1, 1.5)]) for v in (5.0, 30.0)]
        zeta = 0.5 if rig.inertia.roller > 45.0 + 1e-9 else 0.15
        return [_row(v, [(1.4, zeta)]) for v in (5.0, 30.0)]

    settings = {"slip_compensation": 1.0, "slip_filter_time": 0.1}
    nominal = dv.band_verdict(rows_for(RIG, settings))
    out = dv.robustness(RIG, settings, rows_for, nominal)
    assert not out["holds"]
    by = {a["label"]: a for a in out["assumptions"]}
    assert by["slip filter"]["flips"] == [0.05]
    assert by["J5"]["flips"] == [pytest.approx(49.5)]
    assert by["R_s"]["holds"] and by["rotor-resistance estimate"]["holds"]
    assert out["text"].startswith("depends on J5")
    assert "unstable at 5, 30 km/h" in out["text"] and "at 0.05" in out["text"]
    # R_s is checked at 1.5 and 2 % of the base impedance of a delta phase (4.949 ohm)
    assert by["R_s"]["values"][0]["value"] == pytest.approx(
        0.015 * 380 / (133 / np.sqrt(3)), abs=1e-4
    )
    # without slip compensation the slip filter and the estimate act on nothing
    out0 = dv.robustness(RIG, {}, rows_for, nominal)
    unused = {a["label"] for a in out0["assumptions"] if "unused" in a}
    assert unused == {"slip filter", "current filter", "rotor-resistance estimate"}


def _reduced_mode(rig, kmh, k, tau_f, j_scale=1.0):
    """(f [Hz], ζ) of the reduced slip-compensation model (module docstring)."""
    g, inertia, am = rig.geometry, rig.inertia, rig.induction_motor
    machine = dd.default_dq_drive(rig).machine
    p = machine.pole_pairs
    circuit = am.circuit()
    c = 3.0 * circuit.voltage**2 / (circuit.rotor_resistance * am.synchronous_speed**2)
    w_s = p * kmh / 3.6 / g.roller_radius_x
    b = machine.stator_resistance / (
        w_s * (machine.leakage_inductance + machine.magnetising_inductance)
    )
    c /= 1.0 + b * b
    j = (
        j_scale * inertia.roller
        + inertia.am_rotor
        + (inertia.pmsm_rotor + inertia.wheel_disc + inertia.wheel_tyre)
        * (g.roller_radius_x / g.wheel_radius_x) ** 2
    )
    tr = machine.transient_rotor_time_constant
    a = np.array(
        [
            [0.0, 0.0, 1.0 / j],
            [0.0, -1.0 / tau_f, p / (c * tau_f)],
            [-c / tr, c * k / (p * tr), -1 / tr],
        ]
    )
    lam = np.linalg.eigvals(a)
    lam = lam[lam.imag > 0.0][0]
    return lam.imag / (2 * np.pi), -lam.real / abs(lam)


def _twin_mode(rig, kmh, k, tau_f):
    drive = dd.default_dq_drive(rig, slip_compensation=k, slip_filter_time=tau_f)
    modes = dd.DqTwin.at(rig, kmh / 3.6, 4.3e3, drive).modes()
    slow = [md for md in modes if md.kind == "oscillatory" and 0.8 < md.frequency < 2.5]
    md = min(slow, key=lambda m: m.damping_ratio)
    return md.frequency, md.damping_ratio


def test_the_electromechanical_mode_against_the_reduced_slip_filter_model():
    cases = [(1.0, 0.1), (1.0, 0.05), (1.5, 0.1), (1.5, 0.05)]
    twin = {c: _twin_mode(RIG, 30.0, *c) for c in cases}
    red = {c: _reduced_mode(RIG, 30.0, *c) for c in cases}
    for c in cases:
        assert twin[c][0] == pytest.approx(red[c][0], rel=0.12)
    for model in (twin, red):
        assert model[(1.0, 0.05)][0] > model[(1.0, 0.1)][0]  # the filter sets the frequency
        assert model[(1.5, 0.1)][1] < model[(1.0, 0.1)][1]  # more gain, less damping
        assert model[(1.5, 0.05)][1] < 0.0 < model[(1.0, 0.05)][1]  # 150 % with 0.05 s grows
    # J5 + 10 %: both lower the frequency by the same factor (to 2 %)
    heavy = RIG.with_overrides({"inertia.roller": 1.1 * RIG.inertia.roller})
    ratio_twin = _twin_mode(heavy, 30.0, 1.5, 0.1)[0] / twin[(1.5, 0.1)][0]
    ratio_red = _reduced_mode(RIG, 30.0, 1.5, 0.1, j_scale=1.1)[0] / red[(1.5, 0.1)][0]
    assert ratio_twin < 1.0
    assert ratio_twin == pytest.approx(ratio_red, rel=0.02)


def test_mode_class_refuses_a_nan_damping_ratio_and_a_bad_threshold():
    import re

    from rollerrig._validation import ParameterError

    with pytest.raises(ParameterError, match=re.escape("damping_ratio must be finite [-]")):
        dv.mode_class(float("nan"))
    with pytest.raises(ParameterError, match=re.escape("damping_threshold must lie in (0, 1)")):
        dv.mode_class(0.1, -1.0)


def test_band_verdict_refuses_a_reversed_band_and_no_rows():
    import re

    from rollerrig._validation import ParameterError

    row = {
        "speed [km/h]": 10.0,
        "unstable": [],
        "modes below 20 Hz": [{"frequency [Hz]": 1.55, "damping_ratio [-]": 0.01}],
    }
    for band in ((1.7, 1.0), (float("nan"), 1.7)):
        with pytest.raises(ParameterError, match=re.escape("band must")):
            dv.band_verdict([row], band)
    with pytest.raises(ParameterError, match=re.escape("band must be (low, high) [Hz]")):
        dv.band_verdict([row], (1.0, 1.5, 2.0))
    with pytest.raises(ParameterError, match=re.escape("rows must hold at least one row")):
        dv.band_verdict([])
