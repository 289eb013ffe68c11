"""rollerrig: turn a wheel-roller adhesion test rig into a trustworthy measuring instrument.

Packages, one per concern:

- :mod:`rollerrig.contact` — Hertz contact, Kalker coefficients, creep laws (Polach, Kalker linear),
  creep kinematics, roller versus tangent rail.
- :mod:`rollerrig.rig` — rig parameter sets, the torsional chain and its modes.
- :mod:`rollerrig.drives` — PMSM, induction motor, ideal sources, speed-controlled roller drive.
- :mod:`rollerrig.experiment` — experiment protocols as data.
- :mod:`rollerrig.solve` — reference and fast solvers, labelled results.
- :mod:`rollerrig.report` — figures and reports.
- :mod:`rollerrig.cli` — the ``rollerrig`` command.

All quantities are SI inside the package; conversions (km/h, mm, rpm) happen only at the edges.
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("rollerrig")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0+unknown"

__all__ = ["__version__"]
