"""Measurement: the rig's physical quantities from its channels.

- :mod:`~rollerrig.measure.quantities` (normal force, encoder speeds, creep, CoA),
- :mod:`~rollerrig.measure.segmentation` (the test's phases, branches, hysteresis),
- :mod:`~rollerrig.measure.correction` (the CoA corrected for the rig's dynamics),
- :mod:`~rollerrig.measure.prepare` (uniform time base, analysis rate),
- :mod:`~rollerrig.measure.checks` (what an analysis cannot compute with),
- :mod:`~rollerrig.measure.facts` (what is known about a recording, the twin's truth).

Reading recordings moved to :mod:`rollerrig.recordings`, the estimators and the uncertainty to
:mod:`rollerrig.estimation`, the test analysis to :mod:`rollerrig.analysis`; their old paths
(``rollerrig.measure.readers`` and the others) still import, with a DeprecationWarning, for one
release (:mod:`rollerrig._moved`).
"""
