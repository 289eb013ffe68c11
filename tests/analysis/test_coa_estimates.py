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
