"""The settings of a Welch estimate checked: the window's equivalent noise bandwidth."""

from __future__ import annotations

import re

import numpy as np
import pytest
from scipy import signal as sps

from rollerrig._validation import ParameterError
from rollerrig.signal.welch_settings import enbw


def test_enbw_of_known_windows():
    # rectangular: one bin f_s/n; Hann: 1.5 bins (Harris 1978, Table 1)
    assert enbw(np.ones(64), 250.0) == pytest.approx(250.0 / 64)
    assert enbw(sps.get_window("hann", 4096), 250.0) == pytest.approx(1.5 * 250.0 / 4096, 1e-3)


@pytest.mark.parametrize(
    ("window", "got"),
    [
        (np.zeros(8), "got Σw = 0 over 8 samples"),  # an all-zero window
        (np.array([1.0, -1.0]), "got Σw = 0 over 2 samples"),  # antisymmetric
        (np.array([0.1, 0.2, -0.3]), "over 3 samples"),  # zero to rounding (5.6e-17)
    ],
)
def test_enbw_refuses_a_window_that_sums_to_zero(window, got):
    with pytest.raises(ParameterError, match=r"window must not sum to zero \[-\].*" + got):
        enbw(window, 250.0)


def test_enbw_refuses_non_finite_windows_and_rates():
    with pytest.raises(ParameterError, match=re.escape("window must be finite [-], got [ 1. nan")):
        enbw(np.array([1.0, np.nan, 1.0]), 250.0)
    with pytest.raises(ParameterError, match=re.escape("sample_rate must be finite [Hz]")):
        enbw(np.ones(8), np.nan)
    with pytest.raises(ParameterError, match=re.escape("sample_rate must be > 0 [Hz], got -1")):
        enbw(np.ones(8), -1.0)
    with pytest.raises(ParameterError, match=re.escape("window must be a 1-D array")):
        enbw(np.array([]), 250.0)
