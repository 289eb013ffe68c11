"""Measurements: DAQ recordings, channel maps, physical quantities, test segmentation.

Reading a recording
    :mod:`~rollerrig.measure.recording` (the :class:`Recording` every reader returns),
    :mod:`~rollerrig.measure.readers` (:func:`read_recording`, format detection),
    :mod:`~rollerrig.measure.formats` (one reader per file format, text sniffing, timestamps),
    :mod:`~rollerrig.measure.channels` (channel maps), :mod:`~rollerrig.measure.translate`
    (columns through the map into SI channels), :mod:`~rollerrig.measure.timebase` (channels
    of several rates on one time base), :mod:`~rollerrig.measure.validate` (time, NaN/inf,
    gaps), :mod:`~rollerrig.measure.source` (long files read chunk by chunk).
Analysing an adhesion test
    :mod:`~rollerrig.measure.analysis` (:func:`analyze_test`, the orchestration),
    :mod:`~rollerrig.measure.checks` (what an analysis cannot compute with),
    :mod:`~rollerrig.measure.prepare` (uniform time base, analysis rate),
    :mod:`~rollerrig.measure.quantities` (normal force, encoder speeds, creep, CoA),
    :mod:`~rollerrig.measure.segmentation` (phases, branches, hysteresis),
    :mod:`~rollerrig.measure.correction` (CoA corrected for the rig's dynamics),
    :mod:`~rollerrig.measure.uncertainty` (its uncertainty, JCGM 100 law of propagation),
    :mod:`~rollerrig.measure.montecarlo` (JCGM 101 Monte Carlo and its validation),
    :mod:`~rollerrig.measure.filterweights` (the correction's filters as exact weights),
    :mod:`~rollerrig.measure.budget` (uncertainty budgets per phase and creep–CoA point),
    :mod:`~rollerrig.measure.estimator` (the contact torque estimated from T56 and the
    encoder by a Kalman filter, causal and online),
    :mod:`~rollerrig.measure.facts` (what is known about a recording, the twin's truth),
    :mod:`~rollerrig.measure.findings` (the result and its JSON summary).
Writing and generating
    :mod:`~rollerrig.measure.writers`, :mod:`~rollerrig.measure.synthetic`.
"""
