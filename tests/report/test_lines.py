"""Envelopes of long lines in report figures (src/rollerrig/report/lines.py)."""

import numpy as np

from rollerrig.report.lines import envelope


def test_envelope_keeps_every_excursion_within_the_point_budget():
    rng = np.random.default_rng(0)
    t = np.arange(1_000_003) / 1000.0
    y = rng.standard_normal(t.size)
    y[123_457], y[987_654] = 40.0, -40.0  # single-sample spikes
    xs, ys = envelope(t, y, 2000)
    assert ys.size <= 2004 and np.all(np.diff(xs) > 0)  # time order, no duplicates
    assert ys.max() == 40.0 and ys.min() == -40.0
    assert xs[0] == t[0] and xs[-1] == t[-1]  # spans the whole signal
    short = np.arange(10.0)
    assert envelope(short, short, 2000)[1] is short  # short lines drawn as they are


def test_x_and_y_of_different_lengths_are_refused_not_paired_wrongly():
    import re

    import pytest

    from rollerrig._validation import ParameterError

    with pytest.raises(ParameterError, match=re.escape("must be 1-D arrays of the same length")):
        envelope(np.arange(200.0), np.arange(100.0), 10)
    with pytest.raises(ParameterError, match=re.escape("max_points must be a whole number")):
        envelope(np.arange(100.0), np.arange(100.0), float("nan"))
