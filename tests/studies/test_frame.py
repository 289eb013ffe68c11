"""The frame study: rigid, the FE frame, ten times softer (Kayaalp 4.3.1 simulated)."""

import numpy as np
import pytest

from rollerrig.studies.frame import MATTERS_THRESHOLD, SOFTER, frame_study


@pytest.fixture(scope="module")
def study():
    return frame_study()  # the rig's [frame] values: the bundled default frame's FE


def test_three_frames_with_their_frequencies(study):
    rigid, fe, soft = study.cases
    assert np.isinf(rigid.frequency) and rigid.line_at_frame_frequency is None
    # sqrt(k/m)/2π of the rig's [frame]: 1.006e8 N/m, 1101 kg -> 48.1 Hz; softer by sqrt(10).
    assert fe.frequency == pytest.approx(np.sqrt(1.006e8 / 1101.0) / (2 * np.pi), rel=1e-9)
    assert soft.frequency == pytest.approx(fe.frequency / np.sqrt(SOFTER), rel=1e-9)


def test_the_default_frame_does_not_matter_and_the_verdict_says_so(study):
    rigid, fe, _ = study.cases
    change = abs(fe.metrics["release_overshoot"] / rigid.metrics["release_overshoot"] - 1)
    assert change < MATTERS_THRESHOLD / 10  # measured 0.05 %
    assert not study.matters and "does not explain" in study.verdict
    # the overshoot in %, as simulate prints it, its change relative
    assert f"against {rigid.metrics['release_overshoot']:.2%} rigid (relative " in study.verdict
    # ... and says what it rests on: the 10x softer frame's ringing line changes by -10.7 %
    # and its own line is 13 % of it (above the threshold), so the stiffness matters.
    assert "ten times softer would change it" in study.verdict
    # The ringing is the roller-shaft mode whatever the frame (13.8 Hz).
    assert fe.metrics["t56_line_frequency"] == pytest.approx(13.8, abs=0.1)


def test_a_frame_near_the_shaft_mode_shows_in_t56(study):
    # 10x softer: the frame's mode (15.2 Hz) sits beside the 13.8 Hz shaft mode and puts a
    # line of its own into T56 (measured 4.5 N.m, 13 % of the ringing line).
    rigid, fe, soft = study.cases
    assert soft.line_at_frame_frequency > 100 * fe.line_at_frame_frequency
    assert soft.line_at_frame_frequency > 0.05 * rigid.metrics["t56_line_amplitude"]


def test_rows_are_json_ready(study):
    import json

    text = json.dumps(study.rows(), allow_nan=False, default=float)
    assert '"frame": "rigid frame"' in text
