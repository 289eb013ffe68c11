"""Notes of the corrected CoA's analysis step (analysis/coa_estimates.py)."""

import numpy as np

from rollerrig.analysis.coa_estimates import _note_wheel_drive_voltage
from rollerrig.recordings.recording import Recording
from rollerrig.rig.parameters import default_rig, load_rig


def _recording(omega, request=None):
    t = np.arange(omega.size) / 250.0
    channels = {"wheel_speed": omega}
    units = {"wheel_speed": "rad/s"}
    if request is not None:
        channels["torque_request"] = request
        units["torque_request"] = "N.m"
    return Recording(t, channels, units)


def test_a_wheel_at_its_pmsms_voltage_limit_is_noted_where_the_band_fails():
    """The quarter-scale rig's wheel at 72.9 rad/s (30 km/h): the back-EMF is 98 % of the
    inverter's voltage, where on the twin the wheel torque collapsed and the corrected CoA
    missed by up to 4 U. The Pardubice wheel at 23.9 rad/s (30 km/h) is far from it."""
    n = 2500
    omega = np.full(n, 72.9)
    omega[:500] = 40.0  # 2 s below the limit first
    request = np.linspace(0.0, 900.0, n)
    notes: list[str] = []
    _note_wheel_drive_voltage(_recording(omega, request), load_rig("vt-fra-quarter-scale"), notes)
    assert len(notes) == 1, notes
    note = notes[0]
    assert note.startswith("wheel drive at its voltage limit")
    assert "for 8 s of the test from t = 2.00 s" in note
    assert "from the torque request and measured wheel speed" in note
    assert "the corrected CoA's band is not valid" in note
    notes = []
    _note_wheel_drive_voltage(_recording(np.full(n, 23.9), request), default_rig(), notes)
    assert notes == []


def test_without_a_torque_request_the_back_emf_alone_decides_and_nan_is_skipped():
    omega = np.full(1000, 72.9)
    omega[::7] = np.nan  # samples a reader left as NaN are not read as a speed
    notes: list[str] = []
    _note_wheel_drive_voltage(_recording(omega), load_rig("vt-fra-quarter-scale"), notes)
    assert len(notes) == 1 and "no torque request recorded: the back-EMF alone" in notes[0]
    assert "up to 98.3 %" in notes[0]
    notes = []
    _note_wheel_drive_voltage(
        _recording(np.full(1000, 60.0)), load_rig("vt-fra-quarter-scale"), notes
    )
    assert notes == []  # 81 %: below the limit's 95 %


def test_a_release_from_deep_slip_is_named():
    # Runaways to 75-96 % creep had broken the corrected CoA's band by up to 3 U with nothing
    # said (a review, 2026-12-03); the release residual is stated up to 30 % creep.
    from types import SimpleNamespace

    from rollerrig.analysis.coa_estimates import _note_release_creep
    from rollerrig.measure.segmentation import Phase

    t = np.arange(0.0, 10.0, 0.01)
    creep = np.where((t > 4.0) & (t < 5.0), 0.9, 0.02)

    class Rec(SimpleNamespace):
        def __contains__(self, name):
            return name == "creep_smoothed"

        def __getitem__(self, name):
            return creep

    phases = [Phase("traction", 1.0, 5.0, 0), Phase("release", 5.0, 6.0, 0)]
    notes = []
    _note_release_creep(Rec(time=t), phases, notes)
    assert len(notes) == 1 and "90 % at t = 5.00 s" in notes[0] and "not validated" in notes[0]
    creep = np.full_like(t, 0.05)  # an ordinary release: nothing to say
    notes = []
    _note_release_creep(Rec(time=t), phases, notes)
    assert notes == []


def test_a_phase_mean_coa_above_one_is_called_implausible_with_its_likely_causes():
    # A recording analysed with the wrong rig had printed a hold's CoA of 2.37 without a word.
    from types import SimpleNamespace

    from rollerrig.analysis.coa_estimates import _implausible_coa

    def row(name, cycle, rig_coa, corrected):
        return {"name": name, "cycle": cycle, "start [s]": 5.0, "end [s]": 5.5,
                "rig_coa_mean [-]": rig_coa, "corrected_coa_mean [-]": corrected}  # fmt: skip

    rig = default_rig()
    plausible = SimpleNamespace(phases=[row("hold", 0, 0.45, 0.46), row("rest", 0, -0.02, 0.0)])
    assert _implausible_coa(plausible, rig) is None
    assert _implausible_coa(None, rig) is None
    phases = [row("hold", 0, 2.3724, 2.2888), row("hold", 1, 2.3721, 0.9)]
    budget = SimpleNamespace(phases=[*phases, row("rest", 0, -1.2, None)])
    text = _implausible_coa(budget, rig)
    assert text.startswith("implausible CoA: the rig CoA's mean is 2.372 in phase hold 1")
    assert "above 1.0 in 2 other phase(s)" in text  # a negative mean counts too
    assert "wrong rig file" in text and "pardubice" in text
    assert "wrong units or channel map" in text and "air-spring area" in text
    assert "sensors.air_spring_effective_area = 0.05 m²" in text
