"""Experiment protocols: step objects in Python, TOML files, recorded torque-request replays.

A protocol compiles to piecewise-linear inputs in SI units (torque request, roller speed set
point, normal load) and friction-condition switches; the solvers integrate between its
breakpoints.

- :mod:`~rollerrig.experiment.protocol` — :class:`Protocol`, the compiled protocol.
- :mod:`~rollerrig.experiment.steps` — the step objects (:class:`Hold`, :class:`RampTorque`,
  ...) and their compilation (:meth:`Protocol.from_steps`).
- :mod:`~rollerrig.experiment.tomlfile` — the TOML format and the bundled protocols
  (:func:`load_protocol`).
- :mod:`~rollerrig.experiment.replay` — a recorded torque request (:meth:`Protocol.replay`).

Examples
--------
>>> from rollerrig.experiment import Hold, Protocol, RampTorque, ReleaseTorque
>>> p = Protocol.from_steps("pulse", [Hold(1.0), RampTorque(600.0, 2.0), ReleaseTorque()],
...                         normal_load=4300.0, roller_speed=30 / 3.6)
>>> p.duration, p.events[-1].action
(3.02, 'release_torque')
"""

from rollerrig.experiment import protocol, replay, steps, tomlfile
from rollerrig.experiment.protocol import *  # noqa: F403
from rollerrig.experiment.replay import *  # noqa: F403
from rollerrig.experiment.steps import *  # noqa: F403
from rollerrig.experiment.tomlfile import *  # noqa: F403

__all__ = [*protocol.__all__, *steps.__all__, *tomlfile.__all__, *replay.__all__]
