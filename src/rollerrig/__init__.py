"""rollerrig: turn a wheel-roller adhesion test rig into a trustworthy measuring instrument.

Packages, one per concern:

- :mod:`rollerrig.contact` — Hertz contact, Kalker coefficients, creep laws (Polach, Kalker linear),
  creep kinematics, roller versus tangent rail.
- :mod:`rollerrig.rig` — rig parameter sets, the torsional chain and its modes.
- :mod:`rollerrig.drives` — PMSM, induction motor, ideal sources, speed-controlled roller drive.
- :mod:`rollerrig.experiment` — experiment protocols, from step objects or TOML files.
- :mod:`rollerrig.solve` — reference and fast solvers, labelled results.
- :mod:`rollerrig.recordings` — what acquisition software writes: readers, channel maps, time
  bases, checks, writers, the :class:`Recording` type, synthetic recordings of the twin.
- :mod:`rollerrig.measure` — physical quantities from channels: normal force, speeds, creep,
  CoA, the test's phases, the dynamics correction.
- :mod:`rollerrig.estimation` — the contact estimated from the sensors (Kalman filter, RTS
  smoothers) and the corrected CoA's uncertainty (JCGM 100, JCGM 101, budgets).
- :mod:`rollerrig.analysis` — the analysis of an adhesion test (:func:`analyze_test`).
- :mod:`rollerrig.signal` — spectra, peak attribution, smoothing filters and their study.
- :mod:`rollerrig.fit` — Polach fits and their honesty checks.
- :mod:`rollerrig.calibrate` — the twin fitted to a recording: parameters with their errors.
- :mod:`rollerrig.studies` — studies at scale: grids, samples and cases on dask, a resumable
  store, sensitivity indices.
- :mod:`rollerrig.output` — the one output layer: atomic files, provenance, JSON, tables.
- :mod:`rollerrig.report` — figures and reports.
- :mod:`rollerrig.cli` — the ``rollerrig`` command.

All quantities are SI inside the package; conversions (km/h, mm, rpm) happen only at the edges.

The names a notebook needs are importable from the top level (loaded on first use, so that
``import rollerrig`` stays fast and works without the optional extras):

>>> import rollerrig
>>> rig = rollerrig.default_rig()
>>> protocol = rollerrig.Protocol.from_steps(
...     "short", [rollerrig.Hold(1.0), rollerrig.RampTorque(300.0, 2.0), rollerrig.ReleaseTorque()],
...     normal_load=4300.0, roller_speed=30 / 3.6)
>>> round(protocol.duration, 2)
3.02

Top-level names (``help(rollerrig.NAME)`` for each; ``help(rollerrig)`` lists them without
importing them, so it stays fast):

- the twin: ``Simulation``, ``SolverError``, ``DriveConfig``;
- experiments: ``Protocol``, ``Hold``, ``RampTorque``, ``StepTorque``, ``ReleaseTorque``,
  ``SetRollerSpeed``, ``SetNormalLoad``, ``SetFriction``, ``Repeat``, ``load_protocol``;
- the rig: ``RigParameters``, ``default_rig``, ``load_rig``;
- recordings and their analysis: ``Recording``, ``read_recording``, ``write_recording``,
  ``synthetic_recording``, ``analyze``, ``explain_recording``, ``write_analysis``;
- studies: ``run_study``, ``load_study``, ``open_study``;
- errors and warnings: ``ParameterError``, ``DomainWarning``.
"""

import sys
from importlib import import_module
from importlib.metadata import PackageNotFoundError, version

from rollerrig._moved import install as _install_moved

_install_moved()  # modules that moved stay importable under their old names for one release

try:
    __version__ = version("rollerrig")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0+unknown"

#: Top-level name -> module that defines it (imported lazily by :func:`__getattr__`).
_EXPORTS: dict[str, str] = {
    # the twin
    "Simulation": "rollerrig.solve.simulation",
    "SolverError": "rollerrig.solve.simulation",
    "DriveConfig": "rollerrig.rig.model",
    # experiments
    "Protocol": "rollerrig.experiment",
    "Hold": "rollerrig.experiment",
    "RampTorque": "rollerrig.experiment",
    "StepTorque": "rollerrig.experiment",
    "ReleaseTorque": "rollerrig.experiment",
    "SetRollerSpeed": "rollerrig.experiment",
    "SetNormalLoad": "rollerrig.experiment",
    "SetFriction": "rollerrig.experiment",
    "Repeat": "rollerrig.experiment",
    "load_protocol": "rollerrig.experiment",
    # the rig
    "RigParameters": "rollerrig.rig.parameters",
    "default_rig": "rollerrig.rig.parameters",
    "load_rig": "rollerrig.rig.parameters",
    # recordings and their analysis
    "Recording": "rollerrig.recordings.recording",
    "read_recording": "rollerrig.recordings.readers",
    "write_recording": "rollerrig.recordings.writers",
    "synthetic_recording": "rollerrig.recordings.synthetic",
    "analyze": "rollerrig._api",
    # studies
    "run_study": "rollerrig.studies",
    "load_study": "rollerrig.studies",
    "open_study": "rollerrig.studies",
    "write_analysis": "rollerrig.report.analysis",
    "explain_recording": "rollerrig._api",
    # errors and warnings
    "ParameterError": "rollerrig._validation",
    "DomainWarning": "rollerrig._warnings",
}

__all__ = ["__version__", *_EXPORTS]


def _listed_by_pydoc() -> bool:
    """Whether the attribute is looked up by ``help(rollerrig)`` listing the module's members
    (:func:`inspect.getmembers` called from :mod:`pydoc`): the lazy names are then left out
    rather than imported (every subpackage, seconds), and the docstring lists them."""
    frame = sys._getframe(2)  # the caller of __getattr__'s caller: getattr is builtin
    if frame.f_globals.get("__name__") != "inspect":
        return False
    for _ in range(8):
        frame = frame.f_back
        if frame is None:
            return False
        if frame.f_globals.get("__name__") == "pydoc":
            return True
    return False


def __getattr__(name: str):
    module = _EXPORTS.get(name)
    if module is None or _listed_by_pydoc():
        raise AttributeError(f"module 'rollerrig' has no attribute {name!r}")
    value = getattr(import_module(module), name)
    globals()[name] = value  # later lookups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(__all__)
