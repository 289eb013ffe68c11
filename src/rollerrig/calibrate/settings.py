"""The calibration's settings: finite-difference step, covariance window, identification and
correlation limits, the coarse search.

They live apart from the fit so that the result, the file checks and the fit read the same
numbers without importing one another.
"""

from __future__ import annotations

import math

__all__ = [
    "DROP_AT_START",
    "FD_STEP",
    "HAC_WINDOW",
    "MAX_CORRELATION",
    "MAX_RELATIVE_SE",
    "SEARCH_POINTS",
    "SEARCH_WIDTH",
]

FD_STEP = 1e-3
"""Finite-difference step in z = ln(p − p_low) [-]: 0.1 % of the value. The fast backend's
outputs are smooth in the parameters at this step (its error is set by its largest step, the
same for every variant); the roller-shaft stiffness moves the phase of the shaft oscillation,
and its Jacobian changes by 0.5 % between steps of 1e-3 and 1e-4."""

HAC_WINDOW: float | None = None
"""Lag window L of the Newey–West covariance [s]; None: Andrews' (1991) AR(1) plug-in from the
scores (:func:`rollerrig.calibrate.stats.andrews_lag_window`). Measured on 30 synthetic 7.5 s
tests (seeds and true parameters drawn at random, the torque's lines modelled): the RMS of
(fitted − true)/standard error was 0.92, 1.22, 0.81, 0.83 for the roller shaft's stiffness, the
bearing friction, c_lp and J5 (71 % of the 120 within one standard error, 96 % within two);
with a fixed 0.4 s window it was 1.15, 1.31, 1.27, 1.17, and about twice too large (1.8) when
the normal load was held at the mean of the pressure instead of being fitted."""

MAX_RELATIVE_SE = 0.5
"""A parameter is identified when its standard error is at most this fraction of its value."""

DROP_AT_START = 5.0
"""A parameter whose starting Jacobian column alone gives a standard error of z above this
(a factor e⁵ ≈ 150 on the value) does not act on the fitted channels: fixed before the fit."""

MAX_CORRELATION = 0.98
"""|correlation| above which a pair of fitted parameters gets a warning."""

SEARCH_WIDTH = math.log(1.5)
"""Half-width of the coarse search of each free parameter in z [-]: values from 1/1.5 to 1.5
times the start (spaced by :data:`SEARCH_POINTS`: 1.7 %, finer than the basin of the roller
shaft's stiffness, about ±2.5 % wide on a 7.5 s test)."""

SEARCH_POINTS = 49
"""Values per free parameter in the coarse search [1]."""
