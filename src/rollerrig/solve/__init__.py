"""Solving the rig model: reference and fast backends, labelled results, the `Simulation`.

- :class:`~rollerrig.solve.simulation.Simulation` — binds rig, protocol, drives and solver;
  a failed run raises :class:`~rollerrig.solve.simulation.SolverError`.
- :mod:`~rollerrig.solve.reference` — scipy Radau on the compiled model (the trusted solution).
- :mod:`~rollerrig.solve.fast` — the compiled backend: ETDRK4 (:mod:`~rollerrig.solve.etdrk4`)
  with ROS34PW2 as its fallback, single runs and batches on threads.
- :mod:`~rollerrig.solve.ros34pw` — the third-order W-method (Rang & Angermann 2005) on the
  generic W-method drivers (``_wdriver``: step control, output landing, Jacobian reuse,
  finite-difference Jacobians).
- :mod:`~rollerrig.solve.results` — the xarray dataset and its writers.

Importing this package does not import numba; the compiled backends load on first use, from
the on-disk cache of compiled code (:mod:`~rollerrig.solve._cache`).
"""

from rollerrig.solve.simulation import SOLVERS, Simulation, SolverError

__all__ = ["SOLVERS", "Simulation", "SolverError"]
