"""Spectrum settings chosen from the signal: resolution from the line spacing, averages, band."""

from __future__ import annotations

import numpy as np
import pytest

from rollerrig.signal.spectrum_settings import (
    SpectrumSettings,
    choose_settings,
    line_spacing,
    segment_count,
)

R_ROLLER, R_WHEEL = 0.452, 0.348  # [m], the default rig (Kayaalp 4.5.1.5)


def test_settings_from_the_signal():
    spacing = line_spacing(30 / 3.6 / R_ROLLER / (2 * np.pi), 30 / 3.6 / R_WHEEL / (2 * np.pi))
    assert spacing == pytest.approx(3.811 - 2.934, abs=2e-3)  # |f_w - f_r| at 30 km/h
    long = choose_settings(250 * 600, 250.0, spacing)  # 10 min at 250 Hz: wanted resolution
    assert long.resolution(250.0) == pytest.approx(spacing / 6, rel=1e-3)
    assert long.segments(250 * 600) >= 8 and long.min_snr == 10.0
    medium = choose_settings(12_000, 600.0, spacing)  # 20 s at 600 Hz: 8 averages
    assert medium.segments(12_000) == 8 and medium.resolution(600.0) < spacing / 3
    short = choose_settings(1620, 250.0, spacing)  # a 6.5 s quiet phase: the whole record
    assert short.nperseg == 1620 and short.segments(1620) == 1 and short.min_snr == 15.0
    assert "whole record" in short.reason
    assert segment_count(100, 200, 100) == 0
    with pytest.raises(ValueError, match="16 samples"):
        choose_settings(10, 250.0, 1.0)


def test_settings_state_the_band_they_search():
    s = SpectrumSettings(1000, 500, min_frequency=0.625)
    assert s.band() == "0.625–Nyquist" and "in 0.625–Nyquist;" in s.describe(250.0, 10_000)
    assert SpectrumSettings(1000, 500, max_frequency=40.0).band() == "0.1–40 Hz"


def test_line_spacing_and_segment_count_refuse_what_has_no_spacing_or_count():
    """A negative line spacing, a NaN wheel frequency ignored, -16 segments and a division by
    zero had come back."""
    from rollerrig._validation import ParameterError

    with pytest.raises(ParameterError, match="roller_frequency must be > 0"):
        line_spacing(-1.0)
    with pytest.raises(ParameterError, match="wheel_frequency must be finite"):
        line_spacing(1.0, float("nan"))
    with pytest.raises(ParameterError, match="wheel_frequency must be > 0"):
        line_spacing(1.0, -2.0)
    for noverlap in (300, 256, -1):
        with pytest.raises(ParameterError, match=r"noverlap must lie in \[0, nperseg\)"):
            segment_count(1000, 256, noverlap)
    assert segment_count(1000, 256, 128) == 6
