"""The studies bundled with rollerrig: their names, from the package's data folder.

Apart from :mod:`rollerrig.studies.studyfile` (which reads them) so that the command line can
list them in ``study run --help`` without importing the study reader and numpy.
"""

from __future__ import annotations

from importlib import resources

__all__ = ["bundled_studies"]


def data_dir():
    """The folder of the bundled study files (``studies/data``)."""
    return resources.files("rollerrig.studies").joinpath("data")


def bundled_studies() -> tuple[str, ...]:
    """Names of the studies bundled with rollerrig (``studies/data/*.toml``), sorted.

    Examples
    --------
    >>> {"arm", "stiffness", "lag", "drives"} <= set(bundled_studies())
    True
    """
    return tuple(
        sorted(f.name[: -len(".toml")] for f in data_dir().iterdir() if f.name.endswith(".toml"))
    )
