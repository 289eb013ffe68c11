"""Old import paths of modules that moved to another package, kept working for one release.

A module that moved is found under its old name by :class:`MovedModuleFinder` (on
``sys.meta_path`` from ``import rollerrig``): importing the old name imports the new module, warns
once with a :class:`DeprecationWarning` that names the new path, and binds the old name to the
same module object (so classes keep one identity, and ``mock.patch`` of an old dotted name
patches the module that runs). No file is left at the old path.

Examples
--------
>>> import warnings
>>> with warnings.catch_warnings(record=True) as caught:
...     warnings.simplefilter("always")
...     import rollerrig.measure.recording as old
>>> import rollerrig.recordings.recording as new
>>> old is new, caught[0].category.__name__
(True, 'DeprecationWarning')
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys
import warnings

__all__ = ["MOVED", "MovedModuleFinder", "install"]

MOVED: dict[str, str] = {
    # recordings: what acquisition software writes, read, mapped, checked and written
    "rollerrig.measure.formats": "rollerrig.recordings.formats",
    "rollerrig.measure.readers": "rollerrig.recordings.readers",
    "rollerrig.measure.source": "rollerrig.recordings.source",
    "rollerrig.measure.timebase": "rollerrig.recordings.timebase",
    "rollerrig.measure.channels": "rollerrig.recordings.channels",
    "rollerrig.measure.mapfile": "rollerrig.recordings.mapfile",
    "rollerrig.measure.translate": "rollerrig.recordings.translate",
    "rollerrig.measure.validate": "rollerrig.recordings.validate",
    "rollerrig.measure.writers": "rollerrig.recordings.writers",
    "rollerrig.measure.recording": "rollerrig.recordings.recording",
    "rollerrig.measure.synthetic": "rollerrig.recordings.synthetic",
    # estimation: estimators of the contact and the uncertainty of the corrected CoA
    "rollerrig.measure.estimator": "rollerrig.estimation.estimator",
    "rollerrig.measure.uncertainty": "rollerrig.estimation.uncertainty",
    "rollerrig.measure.montecarlo": "rollerrig.estimation.montecarlo",
    "rollerrig.measure.budget": "rollerrig.estimation.budget",
    "rollerrig.measure.filterweights": "rollerrig.estimation.filterweights",
    # analysis: the orchestration of an adhesion test's analysis
    "rollerrig.measure.analysis": "rollerrig.analysis.adhesion",
    "rollerrig.measure.findings": "rollerrig.analysis.findings",
    # the roller-to-track transfer reads analyses and fits laws: above contact mechanics
    "rollerrig.contact.transfer": "rollerrig.analysis.transfer",
    # the dq drive coupled with the rig, its modes and study: the rig's layer
    "rollerrig.drives.drive_dynamics": "rollerrig.rig.drive_dynamics",
    "rollerrig.drives.drive_verdicts": "rollerrig.rig.drive_verdicts",
}
"""Old module name -> new module name (a package's submodules follow it)."""

_PREFIXES = tuple({old.rsplit(".", 1)[0] + "." for old in MOVED})
"""The packages that held a moved module (``rollerrig.measure.`` ...)."""


def _new_name(fullname: str) -> str | None:
    if not fullname.startswith(_PREFIXES):  # every other import asks too: answer at once
        return None
    for old, new in MOVED.items():
        if fullname == old or fullname.startswith(old + "."):
            return new + fullname[len(old) :]
    return None


class MovedModuleFinder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds a moved module under its old name and loads it as the new module (warning)."""

    def find_spec(self, fullname, path=None, target=None):
        new = _new_name(fullname)
        if new is None:
            return None
        target_spec = importlib.util.find_spec(new)
        if target_spec is None:
            return None
        package = target_spec.submodule_search_locations is not None
        return importlib.util.spec_from_loader(fullname, self, is_package=package)

    def create_module(self, spec):
        new = _new_name(spec.name)
        warnings.warn(
            f"{spec.name} moved to {new}; the old import path will be removed in the next release",
            DeprecationWarning,
            stacklevel=2,
        )
        return importlib.import_module(new)

    def exec_module(self, module) -> None:
        """Nothing to run: the new module ran when it was imported."""


def install() -> None:
    """Put the finder first on ``sys.meta_path`` (once)."""
    if not any(isinstance(f, MovedModuleFinder) for f in sys.meta_path):
        sys.meta_path.insert(0, MovedModuleFinder())
