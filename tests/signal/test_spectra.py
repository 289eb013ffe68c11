"""Spectra with attribution, tested on synthetic signals with known lines and on the seed's tables.

Sources of the pinned numbers:
* Kayaalp (the seed dissertation), section 4.5.2.4: AM rotor 2.9343 Hz / electrical 14.6713 Hz at
  30 km/h, 0.487 Hz / 2.433 Hz at 5 km/h, 0.9728 Hz / 4.864 Hz at 10 km/h, the 1.333 Hz line at
  every speed; Table 3 (5 km/h harmonics), Table 4 (10 km/h harmonics); section 4.5.2.3: the
  displacement peaks 0.484 / 0.973 / 1.95 Hz at 5 / 10 / 20 km/h; section 4.5.1.5: roller radius
  452 mm, wheel radius 348 mm; Tables 1-2: 22 and 5 pole pairs.
* Closed forms: a sine of amplitude A has mean square A²/2; Parseval's theorem for the DFT; the
  coherence of a linear system with uncorrelated output noise (Bendat & Piersol 2010, eq. 6.37).
"""

from __future__ import annotations

import re

import matplotlib.pyplot as plt
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import signal as sps

from rollerrig._validation import ParameterError
from rollerrig.recordings.recording import Recording, RecordingError
from rollerrig.report.spectra import coherence_figure, order_map_figure, spectrum_figure
from rollerrig.signal.spectra import (
    ExplainedSpectrum,
    SpectralPeak,
    amplitude_spectrum,
    attribute_peaks,
    coherence,
    coherence_at,
    explain_spectrum,
    find_spectral_peaks,
    order_map,
    power_spectrum,
    speed_independent_lines,
)

FS_TORQUE = 250.0  # Kayaalp 4.5.2: torque sampled at 250 Hz
FS_LASER = 600.0  # laser displacement sensors at 600 Hz
R_ROLLER = 0.452  # [m], Kayaalp 4.5.1.5
R_WHEEL = 0.348  # [m]
NPERSEG = 16384  # Δf = 250 / 16384 = 0.0153 Hz: separates 1.333 Hz from 2 f_wheel = 1.27 Hz
FIXED_LINE = 1.333  # [Hz], Kayaalp 4.5.2.4


def roller_speed(v_kmh: float) -> float:
    """Roller angular speed [rad/s] at a surface speed [km/h]."""
    return v_kmh / 3.6 / R_ROLLER


def torque_recording(v_kmh: float, seed: int, duration: float = 240.0) -> Recording:
    """Synthetic roller-shaft torque with lines at f_AM, 2 f_AM, 4 f_r and 1.333 Hz plus noise."""
    w_r, w_w = roller_speed(v_kmh), v_kmh / 3.6 / R_WHEEL
    f_r = w_r / (2 * np.pi)
    f_am = 5 * f_r
    t = np.arange(int(duration * FS_TORQUE)) / FS_TORQUE
    rng = np.random.default_rng(seed)
    torque = (
        400.0
        + 5.0 * np.sin(2 * np.pi * f_am * t + 0.3)
        + 2.0 * np.sin(2 * np.pi * 2 * f_am * t + 1.1)
        + 1.5 * np.sin(2 * np.pi * 4 * f_r * t + 2.0)
        + 1.0 * np.sin(2 * np.pi * FIXED_LINE * t + 0.7)
        + 1.0 * rng.standard_normal(t.size)
    )
    return Recording(
        t,
        {
            "torque": torque,
            "roller_speed": w_r + 0.02 * rng.standard_normal(t.size),
            "wheel_speed": w_w + 0.02 * rng.standard_normal(t.size),
        },
        {"torque": "N.m", "roller_speed": "rad/s", "wheel_speed": "rad/s"},
    )


def expected_lines(v_kmh: float) -> dict[float, tuple[str, int]]:
    f_r = roller_speed(v_kmh) / (2 * np.pi)
    return {
        5 * f_r: ("am_electrical", 1),
        10 * f_r: ("am_electrical", 2),
        4 * f_r: ("roller_order", 4),
        FIXED_LINE: ("unexplained", 0),
    }


@pytest.fixture(scope="module")
def explained_by_speed() -> dict[float, ExplainedSpectrum]:
    return {
        v: explain_spectrum(torque_recording(v, seed=int(v)), nperseg=NPERSEG)
        for v in (5.0, 10.0, 20.0, 30.0)
    }


# ------------------------------------------------------------------------------------------
# Calibration and Parseval
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("method", ["welch", "periodogram"])
@pytest.mark.parametrize("window", ["hann", "blackmanharris", "boxcar"])
def test_bin_centred_sine_reads_a_squared_over_two(method, window):
    # Closed form: the mean square of A sin(2π f t) is A²/2; "spectrum" scaling shows it at the
    # peak bin when f is a bin centre.
    amplitude, nperseg = 3.0, 4096
    n = 8 * nperseg
    f0 = 300 * FS_TORQUE / nperseg  # bin centre for welch segments and for the full record
    t = np.arange(n) / FS_TORQUE
    x = amplitude * np.sin(2 * np.pi * f0 * t + 0.4) + 7.0
    s = power_spectrum(x, FS_TORQUE, method=method, nperseg=nperseg, window=window)
    k = int(np.argmax(s.power))
    assert s.frequency[k] == pytest.approx(f0)
    assert s.power[k] == pytest.approx(amplitude**2 / 2, rel=0.01)
    _, a = amplitude_spectrum(x, FS_TORQUE, method=method, nperseg=nperseg, window=window)
    assert a[k] == pytest.approx(amplitude, rel=0.01)
    (peak,) = find_spectral_peaks(s, min_frequency=1.0)
    assert peak.power == pytest.approx(amplitude**2 / 2, rel=0.01)


def test_displacement_amplitude_in_metres():
    # A 0.06 mm eccentricity at the 5 km/h roller rotation frequency, laser at 600 Hz.
    f_r = roller_speed(5.0) / (2 * np.pi)
    nperseg = 60_000
    t = np.arange(4 * nperseg) / FS_LASER
    x = 0.06e-3 * np.sin(2 * np.pi * f_r * t) + 2e-3
    s = power_spectrum(x, FS_LASER, nperseg=nperseg)
    (peak,) = find_spectral_peaks(s, min_frequency=0.1)
    assert np.sqrt(2 * peak.power) == pytest.approx(0.06e-3, rel=0.015)
    assert abs(peak.frequency - f_r) < 0.05 * s.resolution


@pytest.mark.parametrize("n", [4096, 4097])
def test_periodogram_parseval(n):
    # Parseval: for the one-sided periodogram density of the mean-removed record,
    # sum(PSD) Δf equals the variance exactly (boxcar window, DC and Nyquist counted once).
    rng = np.random.default_rng(n)
    x = rng.standard_normal(n) * 2.0 + np.sin(np.arange(n) * 0.3)
    s = power_spectrum(
        x, FS_TORQUE, method="periodogram", window="boxcar", detrend="constant", scaling="density"
    )
    assert np.sum(s.power) * s.resolution == pytest.approx(np.var(x), rel=1e-10)
    assert s.n_segments == 1 and s.nperseg == n


def test_welch_density_integrates_to_variance_of_white_noise():
    rng = np.random.default_rng(3)
    x = 0.5 * rng.standard_normal(2**18)
    s = power_spectrum(x, FS_TORQUE, nperseg=1024, scaling="density")
    # White noise variance σ² spreads evenly over 0..fs/2: density 2σ²/fs; average of 511 segments.
    assert np.sum(s.power) * s.resolution == pytest.approx(0.25, rel=0.01)
    assert s.enbw == pytest.approx(1.5 * s.resolution, rel=1e-3)  # Hann: 1.5 bins


@settings(max_examples=25, deadline=None)
@given(offset=st.floats(0.0, 1.0), amplitude=st.floats(0.01, 100.0))
def test_interpolated_frequency_and_power_between_bins(offset, amplitude):
    nperseg = 2048
    df = FS_TORQUE / nperseg
    f0 = (200.0 + offset) * df
    t = np.arange(6 * nperseg) / FS_TORQUE
    s = power_spectrum(amplitude * np.sin(2 * np.pi * f0 * t), FS_TORQUE, nperseg=nperseg)
    peaks = find_spectral_peaks(s, min_frequency=1.0)
    best = max(peaks, key=lambda p: p.power)
    assert abs(best.frequency - f0) < 0.03 * df  # parabolic on log power, Hann: < 0.02 bin
    assert best.power == pytest.approx(amplitude**2 / 2, rel=0.02)
    # bare arrays: parabola vertex, at most +0.33 dB (Hann at half-bin offset)
    bare = max(find_spectral_peaks(*s, min_frequency=1.0), key=lambda p: p.power)
    assert 0.99 < bare.power / (amplitude**2 / 2) < 10 ** (0.34 / 10)


@pytest.mark.parametrize("seed", range(3))
def test_a_strong_line_near_the_low_edge_of_a_short_record_is_found(seed):
    """The ringing after a release, in a one-segment record: the largest peak lies 5 bins from
    0 Hz. The noise floor is the running median of the log spectrum; padded at the edge by
    repeating the 0 Hz bin (which holds the record's decaying remainder) 15 times, it stood
    level with the peak's shoulder and withheld the line (the demo's 0.81 Hz mode was missing
    from its quiet-phase table). Reflected padding counts each bin at most twice."""
    fs, n = 250.0, 1621
    t = np.arange(n) / fs
    rng = np.random.default_rng(seed)
    x = (
        30.0 * np.exp(-0.8 * t) * np.sin(2 * np.pi * 0.8 * t)
        + 20.0 * np.exp(-t / 1.5)
        + np.sin(2 * np.pi * 13.78 * t)
        + 0.05 * rng.standard_normal(n)
    )
    peaks = find_spectral_peaks(
        power_spectrum(x, fs, nperseg=n), min_frequency=2.5 * fs / n, min_snr=15.0
    )
    assert [round(p.frequency, 1) for p in peaks] == [0.8, 13.8]


def test_red_noise_in_one_segment_rarely_makes_a_false_peak():
    """The edge padding that finds the line above must not invent lines in noise: 100 records
    of a random walk (1/f² power, the shape of a quiet torque at low frequency), one segment
    each, give at most 3 false peaks in all (measured over 300 records: 0.010 per record with
    the reflected floor, 0.057 with the old padding)."""
    fs, n = 250.0, 1621
    false = 0
    for seed in range(100):
        x = 0.05 * np.cumsum(np.random.default_rng(seed).standard_normal(n))
        spectrum = power_spectrum(x, fs, nperseg=n)
        false += len(find_spectral_peaks(spectrum, min_frequency=2.5 * fs / n, min_snr=15.0))
    assert false <= 3


def test_pure_noise_gives_no_peaks():
    rng = np.random.default_rng(11)
    x = rng.standard_normal(60_000)
    assert find_spectral_peaks(power_spectrum(x, FS_TORQUE, nperseg=NPERSEG)) == []


# ------------------------------------------------------------------------------------------
# Synthetic torque at the seed's speeds
# ------------------------------------------------------------------------------------------


def test_30kmh_frequencies_match_the_seed():
    w_r = roller_speed(30.0)
    assert w_r == pytest.approx(18.44, abs=0.005)
    rows = attribute_peaks([14.6713], w_r, tolerance_hz=1e-3)
    assert rows[0].label == "AM electrical ×1 (14.67 Hz)"
    assert w_r / (2 * np.pi) == pytest.approx(2.9343, abs=1e-4)  # Kayaalp 4.5.2.4
    assert rows[0].delta_f == pytest.approx(0.0, abs=1e-4)


@pytest.mark.parametrize("v_kmh", [5.0, 10.0, 20.0, 30.0])
def test_every_line_found_within_one_bin_and_attributed(explained_by_speed, v_kmh):
    e = explained_by_speed[v_kmh]
    df = e.spectrum.resolution
    expected = expected_lines(v_kmh)
    found = [p.frequency for p in e.peaks]
    assert len(found) == len(expected), e.format_table()
    for f_true, (source, order) in expected.items():
        k = int(np.argmin(np.abs(np.array(found) - f_true)))
        assert abs(found[k] - f_true) < df
        row = e.rows[k]
        assert (row.source, row.order) == (source, order), e.format_table()
    assert e.roller_frequency == pytest.approx(roller_speed(v_kmh) / (2 * np.pi), rel=1e-3)
    assert e.am_frequency == pytest.approx(5 * e.roller_frequency)
    assert e.pmsm_frequency == pytest.approx(22 * v_kmh / 3.6 / R_WHEEL / (2 * np.pi), rel=1e-3)


def test_am_line_also_listed_as_fifth_roller_order(explained_by_speed):
    e = explained_by_speed[30.0]
    row = next(r for r in e.rows if r.source == "am_electrical" and r.order == 1)
    assert row.label == "AM electrical ×1 (14.67 Hz)"
    assert [(m.source, m.order) for m in row.matches] == [
        ("am_electrical", 1),
        ("roller_order", 5),
    ]
    assert row.as_row()["also"] == "roller order ×5 (14.67 Hz)"


def test_fixed_line_is_speed_independent(explained_by_speed):
    lines = speed_independent_lines(list(explained_by_speed.values()))
    assert lines.shape == (1,)
    assert abs(lines[0] - FIXED_LINE) < NPERSEG**-1 * FS_TORQUE
    rows = attribute_peaks(
        explained_by_speed[20.0].peaks, roller_speed(20.0), speed_independent=lines
    )
    fixed = [r for r in rows if r.source == "speed_independent"]
    assert len(fixed) == 1 and fixed[0].label == f"speed-independent line ({lines[0]:.3f} Hz)"


def test_speed_independent_needs_distinct_speeds(explained_by_speed):
    e = explained_by_speed[20.0]
    # the same speed twice (and speeds within 20 %) do not make a fixed line
    assert speed_independent_lines([e, e]).size == 0
    near = [(roller_speed(20.0), e.peaks), (roller_speed(23.0), e.peaks)]
    assert speed_independent_lines(near).size == 0
    assert (
        speed_independent_lines([(roller_speed(20.0), e.peaks), (roller_speed(25.0), e.peaks)]).size
        == 1
    )


def test_coincident_order_is_not_a_fixed_line():
    # 2 f_r at 10 km/h and f_r at 20 km/h are both 1.956 Hz: speed-proportional, not fixed.
    f = roller_speed(20.0) / (2 * np.pi)
    spectra = [(roller_speed(10.0), [f]), (roller_speed(20.0), [f])]
    assert speed_independent_lines(spectra, tolerance_hz=0.02).size == 0
    spectra = [(roller_speed(10.0), [f, 1.333]), (roller_speed(20.0), [f, 1.334])]
    assert speed_independent_lines(spectra, tolerance_hz=0.02) == pytest.approx([1.3335])


# ------------------------------------------------------------------------------------------
# The seed's tables
# ------------------------------------------------------------------------------------------

TABLE_3 = [2.433, 4.897, 7.299, 9.792, 12.215, 14.645, 17.095, 19.56, 22.030, 24.460, 26.839,
           29.312]  # fmt: skip
TABLE_4 = [4.864, 9.732, 14.580, 29.162]
TABLE_4_ORDERS = [1, 2, 3, 6]


def test_table3_am_frequency_from_speed():
    # f_AM = 5 ω_r / 2π at 5 km/h is 2.445 Hz; the seed quotes 2.433 Hz = 5 × 0.4866 Hz (its
    # measured rotor frequency "0.487 Hz"), 0.5 % lower. A least-squares fit of the Table 3
    # harmonics (f = k f_AM) gives 2.444 Hz: they follow the nominal speed.
    # The package's prediction (attribute_peaks' first AM harmonic at the nominal 5 km/h roller
    # speed) must be that closed form, and the Table 3 harmonics must follow it.
    rows = attribute_peaks([2.4452], roller_speed(5.0), 5.0 / 3.6 / R_WHEEL, resolution=0.01)
    predicted = rows[0].matches[0].predicted_frequency
    assert (rows[0].source, rows[0].order) == ("am_electrical", 1)
    assert predicted == pytest.approx(5 * (5.0 / 3.6 / R_ROLLER) / (2 * np.pi), rel=1e-9)
    assert predicted == pytest.approx(2.4452, abs=1e-4)
    k = np.arange(1, 13)
    slope = float(np.sum(k * np.array(TABLE_3)) / np.sum(k * k))
    assert slope == pytest.approx(predicted, rel=0.001)


@pytest.mark.parametrize("rotor_hz", [roller_speed(5.0) / (2 * np.pi), 0.487])
def test_table3_harmonics_attributed(rotor_hz):
    # Δf = 0.01 Hz assumed for the seed's DFT (about 100 s of data at 5 km/h).
    rows = attribute_peaks(TABLE_3, 2 * np.pi * rotor_hz, 5.0 / 3.6 / R_WHEEL, resolution=0.01)
    for k, row in enumerate(rows, start=1):
        assert (row.source, row.order) == ("am_electrical", k), row
        assert abs(row.delta_f) <= row.matches[0].tolerance
        assert row.label.startswith(f"AM electrical ×{k} (")
        assert row.matches[0].predicted_frequency == pytest.approx(k * 5 * rotor_hz)


def test_table4_harmonics_attributed_with_measured_rotor_frequency():
    # Seed: "the mechanical frequency of the AM rotor is 0.9728 Hz which corresponds to 4.864 Hz"
    rows = attribute_peaks(TABLE_4, 2 * np.pi * 0.9728, resolution=0.01)
    assert [(r.source, r.order) for r in rows] == [("am_electrical", k) for k in TABLE_4_ORDERS]
    # At the nominal 10 km/h (f_AM = 4.89 Hz) the 3rd and 6th harmonics lie 0.6 % off: beyond
    # the 0.5 % speed allowance, they stay unexplained.
    nominal = attribute_peaks(TABLE_4, roller_speed(10.0), resolution=0.01)
    assert [r.source for r in nominal][2:] == ["unexplained", "unexplained"]


@pytest.mark.parametrize(("v_kmh", "measured"), [(5.0, 0.484), (10.0, 0.973), (20.0, 1.95)])
def test_displacement_peaks_are_roller_rotation(v_kmh, measured):
    (row,) = attribute_peaks([measured], roller_speed(v_kmh), resolution=0.01)
    assert (row.source, row.order) == ("roller_order", 1)


# ------------------------------------------------------------------------------------------
# Coherence
# ------------------------------------------------------------------------------------------


def test_coherence_matches_linear_system_closed_form():
    # y = h * x + n, x and n white and independent:
    # γ² = |H|² σx² / (|H|² σx² + σn²)  (Bendat & Piersol 2010, eq. 6.37)
    rng = np.random.default_rng(5)
    n, sx, sn = 2**18, 1.0, 0.4
    x = sx * rng.standard_normal(n)
    b, a = sps.butter(2, 25.0, fs=FS_TORQUE)
    y = sps.lfilter(b, a, x) + sn * rng.standard_normal(n)
    coh = coherence(x, y, FS_TORQUE, nperseg=512)
    probe = np.array([5.0, 20.0, 30.0, 45.0, 80.0])
    _, h = sps.freqz(b, a, worN=probe, fs=FS_TORQUE)
    expected = np.abs(h) ** 2 * sx**2 / (np.abs(h) ** 2 * sx**2 + sn**2)
    measured = np.interp(probe, coh.frequency, coh.coherence)
    assert measured == pytest.approx(expected, abs=0.03)
    assert expected.min() < 0.2 and expected.max() > 0.8  # the probe spans the range
    assert coh.n_segments == 1023


def test_coherence_at_peak_frequencies():
    rng = np.random.default_rng(8)
    t = np.arange(2**16) / FS_TORQUE
    common = np.sin(2 * np.pi * 14.67 * t)
    x = common + rng.standard_normal(t.size)
    y = 0.5 * common + np.sin(2 * np.pi * 1.333 * t) + rng.standard_normal(t.size)
    coh = coherence(x, y, FS_TORQUE, nperseg=2048)
    g = coherence_at(coh, [14.67, 1.333, 500.0])
    assert g[0] > 0.9 and g[1] < 0.2 and np.isnan(g[2])


# ------------------------------------------------------------------------------------------
# Recording interface, order map, figures, validation
# ------------------------------------------------------------------------------------------


def test_explain_spectrum_speeds_from_channels_or_given():
    rec = torque_recording(30.0, seed=1, duration=60.0)
    e = explain_spectrum(rec, nperseg=4096)
    assert e.roller_speed == pytest.approx(roller_speed(30.0), rel=1e-3)
    assert e.wheel_speed == pytest.approx(30.0 / 3.6 / R_WHEEL, rel=1e-3)
    given_speed = explain_spectrum(rec, roller_speed=20.0, wheel_speed=None, nperseg=4096)
    assert given_speed.roller_speed == 20.0
    table = e.table()
    assert {"frequency_hz", "power", "label", "order", "source", "delta_f_hz"} <= set(table[0])
    assert "AM electrical ×1" in e.format_table()
    no_speed = Recording(rec.time, {"torque": rec["torque"]}, {"torque": "N.m"})
    with pytest.raises(RecordingError, match="roller_speed"):
        explain_spectrum(no_speed)
    e2 = explain_spectrum(no_speed, roller_speed=roller_speed(30.0), nperseg=4096)
    assert e2.wheel_speed is None and e2.pmsm_frequency is None


def test_order_map_lines_and_points(explained_by_speed):
    m = order_map(list(explained_by_speed.values()), speed_independent=[FIXED_LINE])
    assert m.wheel_to_roller == pytest.approx(R_ROLLER / R_WHEEL, rel=1e-3)
    am1 = next(line for line in m.lines if line.label == "AM electrical ×1")
    assert am1.frequency == pytest.approx(5 * m.speed_grid / (2 * np.pi))
    wheel1 = next(line for line in m.lines if line.label == "wheel order ×1")
    assert wheel1.frequency == pytest.approx(m.wheel_to_roller * m.speed_grid / (2 * np.pi))
    assert m.frequency.size == 16 and set(m.source) == {
        "am_electrical",
        "roller_order",
        "unexplained",
    }
    # every AM point lies on an AM line
    for w, f, s in zip(m.speed, m.frequency, m.source, strict=True):
        if s == "am_electrical":
            k = f / (5 * w / (2 * np.pi))
            assert abs(k - round(k)) < 0.01
    bare = order_map([(roller_speed(5.0), [2.445]), (roller_speed(30.0), [14.67])])
    assert bare.wheel_to_roller is None and list(bare.source) == ["", ""]
    assert all(line.source in {"am_electrical", "roller_order"} for line in bare.lines)


def test_figures(explained_by_speed, tmp_path):
    e = explained_by_speed[30.0]
    fig = spectrum_figure(e)
    assert len(fig.axes[0].texts) == len(e.rows) + 1  # the labels and the settings line
    assert any("AM electrical ×2" in t.get_text() for t in fig.axes[0].texts)
    fig.savefig(tmp_path / "spectrum.png")
    rng = np.random.default_rng(2)
    x = rng.standard_normal(20_000)
    coh = coherence(x, x + rng.standard_normal(x.size), FS_TORQUE, nperseg=512)
    fig2 = coherence_figure(coh, [10.0, 20.0], ["a", "b"], names=("torque", "laser"))
    assert len(fig2.axes[0].texts) == 2
    m = order_map(list(explained_by_speed.values()), speed_independent=[FIXED_LINE])
    fig3 = order_map_figure(m, roller_radius=R_ROLLER)
    assert fig3.axes[0].get_xlabel() == "speed [km/h]"
    assert fig3.axes[0].get_xlim()[1] == pytest.approx(1.1 * 30.0, rel=1e-3)
    for f in (fig, fig2, fig3):
        plt.close(f)


def test_validation_messages():
    x = np.zeros(100)
    with pytest.raises(ParameterError, match="method"):
        power_spectrum(x, 250.0, method="fft")
    with pytest.raises(ParameterError, match="sample_rate"):
        power_spectrum(x, -1.0)
    with pytest.raises(ParameterError, match="tolerance"):
        attribute_peaks([1.0], 10.0)
    with pytest.raises(ParameterError, match="roller_speed"):
        attribute_peaks([1.0], 0.0, tolerance_hz=0.1)
    with pytest.raises(ParameterError, match="tolerance_hz"):
        speed_independent_lines([(10.0, [1.0]), (20.0, [1.0])])
    with pytest.raises(ParameterError, match="scaling"):
        amplitude_spectrum(x, 250.0, scaling="density")
    with pytest.raises(ParameterError, match="equally spaced"):
        find_spectral_peaks([0.0, 1.0, 3.0], [1.0, 2.0, 1.0])


def test_unexplained_and_tolerance_rule():
    peak = SpectralPeak(7.0, 1.0, 20.0, 20.0, 100, 0.01)
    (row,) = attribute_peaks([peak], roller_speed(30.0))
    assert row.source == "unexplained" and row.delta_f is None and row.matches == ()
    assert "nearest" in row.reason and row.as_row()["delta_f_hz"] is None
    # tolerance = 1.5 Δf + 0.5 % f_c: accepted just inside, rejected just outside
    f_am = 5 * roller_speed(30.0) / (2 * np.pi)
    tol = 1.5 * 0.01 + 0.005 * f_am
    inside = SpectralPeak(f_am + 0.99 * tol, 1.0, 20.0, 20.0, 100, 0.01)
    outside = SpectralPeak(f_am + 1.01 * tol, 1.0, 20.0, 20.0, 100, 0.01)
    r_in, r_out = attribute_peaks([inside, outside], roller_speed(30.0))
    assert r_in.source == "am_electrical" and r_in.matches[0].tolerance == pytest.approx(tol)
    assert r_out.source == "unexplained"


def test_window_sidelobe_is_leakage_not_a_line():
    # Hann: first sidelobe -31.5 dB at 2.5 bins (Harris 1978, Table 1); a "peak" there at
    # -32 dB is leakage, one at -20 dB is a line.
    from rollerrig.signal.peaks import _leakage, _leakage_envelope

    env = _leakage_envelope(sps.get_window("hann", 1024))
    assert 10 * np.log10(env[round(2.5 * 16)]) == pytest.approx(-31.5, abs=0.2)
    position = np.array([100.0, 102.5, 97.5, 130.0])
    height = np.array([0.0, -32.0, -20.0, -60.0])
    assert _leakage(position, height, env).tolist() == [False, True, False, False]


def test_rig_torsional_mode_is_a_source():
    # The roller-shaft mode of the default rig: 13.84 Hz (two-inertia closed form, J5-k56-J6).
    from rollerrig.signal.spectra import attribute_peaks

    rows = attribute_peaks([13.80, 20.0], roller_speed=18.44, resolution=0.1, rig_modes=[13.84])
    assert rows[0].source == "rig_mode" and "13.84 Hz" in rows[0].label
    assert rows[1].source == "unexplained"


def test_only_damped_twin_modes_that_can_ring_label_peaks():
    # The coupled twin at 30 km/h, 4.3 kN (rollerrig.rig.linear): the roller-shaft mode rings at
    # 13.78 Hz (ζ 0.004); the free chain's 19.02 Hz (am_mount, ζ 12) and 64.97 Hz (pmsm_mount,
    # ζ 41) are overdamped, and the wheel-rubber mode (47.86 Hz free) sits near 38.5 Hz with
    # ζ 0.37: none of those may label a line.
    from rollerrig.rig.linear import coupled_modes
    from rollerrig.rig.parameters import default_rig

    modes = coupled_modes(default_rig(), 30 / 3.6, 4.3e3)
    peaks = [13.78, 19.02, 38.47, 47.86, 64.97]
    rows = attribute_peaks(peaks, None, resolution=0.05, rig_modes=modes.modes)
    assert rows[0].source == "rig_mode" and "roller_shaft" in rows[0].label
    assert [r.source for r in rows[1:]] == ["unexplained"] * 4
    assert all(r.as_row()["delta_f_hz"] is None for r in rows[1:])


def test_explain_spectrum_names_the_channel_of_a_constant_signal():
    t = np.arange(5000) / FS_TORQUE
    rec = Recording(
        t,
        {"torque": np.zeros(t.size), "roller_speed": np.full(t.size, 18.4)},
        {"torque": "N.m", "roller_speed": "rad/s"},
        {"source": "run.csv"},
    )
    with pytest.raises(RecordingError, match=r"run.csv: channel 'torque' is constant"):
        explain_spectrum(rec)


@pytest.mark.parametrize(
    ("setting", "message"),
    [
        ({"min_frequency": np.nan}, "min_frequency must be finite"),
        ({"min_snr": np.nan}, "min_snr must be finite"),
        ({"min_prominence": np.nan}, "min_prominence must be finite"),
        ({"floor_bins": 0}, r"floor_bins must lie in \[3, inf\)"),
        ({"min_frequency": 20.0, "max_frequency": 10.0}, "max_frequency must be above"),
    ],
)
def test_peak_settings_that_would_drop_every_peak_are_refused(setting, message):
    """Each of these had returned no peak at all from a spectrum with a clear line."""
    f = np.linspace(0.0, 50.0, 501)
    p = 1e-4 + np.exp(-0.5 * ((f - 10.0) / 0.2) ** 2)
    assert [round(pk.frequency) for pk in find_spectral_peaks(f, p)] == [10]
    with pytest.raises(ParameterError, match=message):
        find_spectral_peaks(f, p, **setting)


@pytest.mark.parametrize(
    ("entries", "options", "message"),
    [
        ([(np.nan, [2.0])], {}, "roller_speed must be finite [rad/s], got nan"),
        ([(3.0, np.inf, [2.0])], {}, "wheel_speed must be finite [rad/s], got inf"),
        ([(3.0, [-2.0])], {}, "peaks must be >= 0 [Hz]"),
        ([(3.0, [2.0])], {"n_grid": 1}, "n_grid must be a whole number in [2, 1000000]"),
        ([(3.0, [2.0])], {"am_pole_pairs": 0}, "am_pole_pairs must be a whole number >= 1"),
        ([(3.0, [2.0])], {"pmsm_pole_pairs": 2.5}, "pmsm_pole_pairs must be a whole number"),
        ([(3.0, [2.0])], {"am_harmonics": (1, 1.5)}, "am_harmonics[1] must be a whole number"),
        ([(3.0, [2.0])], {"wheel_orders": (0,)}, "wheel_orders[0] must be a whole number >= 1"),
        ([(3.0, [2.0])], {"wheel_to_roller": np.nan}, "wheel_to_roller must be finite"),
        ([(3.0, [2.0])], {"wheel_to_roller": -1.3}, "wheel_to_roller must be > 0"),
    ],
)  # fmt: skip
def test_order_map_refuses_what_would_draw_a_wrong_map(entries, options, message):
    # Each of these had been accepted: a NaN speed put the peak off every line, a harmonic
    # 1.5 or a pole-pair count 0 drew a line of no source, n_grid 1 a line of one point.
    with pytest.raises(ParameterError, match=re.escape(message)):
        order_map(entries, **options)


def test_order_map_takes_a_recording_at_rest_without_a_speed_ratio():
    # Roller and wheel both at rest: no speed ratio (it had divided by zero).
    m = order_map([(0.0, 0.0, [2.0]), (10.0, 13.0, [5.0])])
    assert m.wheel_to_roller == pytest.approx(1.3)
    assert m.speed.tolist() == [0.0, 10.0]
