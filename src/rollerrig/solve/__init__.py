"""Solving the rig model: reference and fast backends, labelled results, the `Simulation`.

- :class:`~rollerrig.solve.simulation.Simulation` — binds rig, protocol, drives and solver.
- :mod:`~rollerrig.solve.reference` — scipy Radau on the compiled model (the trusted solution).
- :mod:`~rollerrig.solve.fast` — compiled ROS34PW2 W-method, single runs and parallel batches.
- :mod:`~rollerrig.solve.ros34pw` — the third-order W-method (Rang & Angermann 2005).
- :mod:`~rollerrig.solve.rosenbrock` — ROS2 and the LU routines; both methods share one driver
  (``_wdriver``: step control, output landing, Jacobian reuse, batches).
- :mod:`~rollerrig.solve.results` — the xarray dataset and its writers.

Importing this package does not import numba; the compiled backends load on first use.
"""

from rollerrig.solve.simulation import SOLVERS, Simulation

__all__ = ["SOLVERS", "Simulation"]
