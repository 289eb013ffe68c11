"""The calibration's error type (apart from the problem and the measurement, which both raise
it)."""

from __future__ import annotations

from rollerrig._validation import ParameterError

__all__ = ["CalibrationError"]


class CalibrationError(ParameterError):
    """A calibration cannot run as asked: the message names the key, channel or file and what
    to change."""
