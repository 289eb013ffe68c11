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

from importlib import import_module

# The names below are imported on first use (PEP 562): ``rollerrig simulate`` imports
# ``rollerrig.studies.metrics`` for the release overshoots, and an eager package imported the
# runner, the store, the summaries and the sensitivity analysis with it (27 ms of a fresh
# process, 2026-12-01).
_EXPORTS: dict[str, str] = {
    "METRICS": "metrics",
    "release_overshoots": "metrics",
    "Progress": "runner",
    "StudyRun": "runner",
    "run_study": "runner",
    "MainEffects": "sensitivity",
    "RankCorrelations": "sensitivity",
    "SobolIndices": "sensitivity",
    "main_effects": "sensitivity",
    "rank_correlations": "sensitivity",
    "sobol_indices": "sensitivity",
    "StudySpec": "spec",
    "open_study": "store",
    "StudyFileError": "studyfile",
    "bundled_studies": "bundled",
    "load_study": "studyfile",
    "failures": "summary",
    "metric_summary": "summary",
    "metric_table": "summary",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'rollerrig.studies' has no attribute {name!r}")
    value = getattr(import_module(f"rollerrig.studies.{module}"), name)
    globals()[name] = value  # later lookups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
