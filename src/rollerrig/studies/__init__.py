"""Studies on the twin: any grid, sampled design or set of cases, run at scale.

- :mod:`~rollerrig.studies.studyfile` — the study file (TOML) and the bundled studies; the
  keys a study may vary (:mod:`~rollerrig.studies.varied_keys`), its design tables read
  (:mod:`~rollerrig.studies.design_tables`), the study in memory
  (:mod:`~rollerrig.studies.spec`);
- :mod:`~rollerrig.studies.design` — its points, and what each point simulates;
- :mod:`~rollerrig.studies.metrics` — the metrics of one run, by name;
- :mod:`~rollerrig.studies.runner` — running the points in this process or on dask;
- :mod:`~rollerrig.studies.store` — the resumable store (zarr), one entry per point;
- :mod:`~rollerrig.studies.summary` and :mod:`~rollerrig.studies.sensitivity` — tables and
  sensitivity indices of a finished study.
"""

from rollerrig.studies.metrics import METRICS, release_overshoots
from rollerrig.studies.runner import Progress, StudyRun, run_study
from rollerrig.studies.sensitivity import (
    MainEffects,
    RankCorrelations,
    SobolIndices,
    main_effects,
    rank_correlations,
    sobol_indices,
)
from rollerrig.studies.spec import StudySpec
from rollerrig.studies.store import open_study
from rollerrig.studies.studyfile import StudyFileError, bundled_studies, load_study
from rollerrig.studies.summary import failures, metric_summary, metric_table

__all__ = [
    "METRICS",
    "MainEffects",
    "Progress",
    "RankCorrelations",
    "SobolIndices",
    "StudyFileError",
    "StudyRun",
    "StudySpec",
    "bundled_studies",
    "failures",
    "load_study",
    "main_effects",
    "metric_summary",
    "metric_table",
    "open_study",
    "rank_correlations",
    "release_overshoots",
    "run_study",
    "sobol_indices",
]
