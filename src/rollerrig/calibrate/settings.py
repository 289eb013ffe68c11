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
    "FD_STEP_TABULATED",
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

FD_STEP_TABULATED = 3e-4
"""Finite-difference step in z of the ``fastsim.*`` keys (the FASTSIM family, whose force comes
from a table, :mod:`rollerrig.contact.table`) [-]. The table's Hermite interpolant is smooth
(C1) in its parameters, and no noise shows: on the 7.5 s test of the calibration tests (modified
FASTSIM, k0 = 0.6, μ0 = 0.52) the central-difference columns of k0 at steps from 3e-3 to 3e-5
agree to 2e-5 (relative), as Polach's k_A's do. But the discrete FASTSIM's last kink (full
slip) is smoothed over one node spacing only (2e-3 of ε there), and a central difference of
±1e-3 spans it: the μ0 column at 1e-3 differs by 3.4e-3 from those at 3e-4 to 3e-6, which
agree to 3e-4 among themselves (Polach's μ0 column: 2e-5). A step of 3e-4 resolves the
interpolant; below 1e-4 the fast backend's own error (1e-5 of the column) begins to show."""

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
"""Values per free parameter in the coarse search [-]."""
