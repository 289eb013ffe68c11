"""Parametric studies of the rig on the digital twin (the seed's sections 4.5.1.7-4.5.1.8)."""

from rollerrig.studies.sweeps import (
    RELEASE_TEST,
    STUDIES,
    StudyResult,
    release_overshoots,
    run_study,
)

__all__ = ["RELEASE_TEST", "STUDIES", "StudyResult", "release_overshoots", "run_study"]
