"""The analysis of an adhesion test: the orchestration over recordings, measurement and
estimation.

- :mod:`~rollerrig.analysis.adhesion`: :func:`analyze_test` (phases, corrected CoA and its
  uncertainty, creep–CoA branches, Polach fits, spectrum, filter study); its steps in
  :mod:`~rollerrig.analysis.smoothed_channels` (smoothing, the corrected CoA),
  :mod:`~rollerrig.analysis.polach_fits` (the fit points and the fits) and
  :mod:`~rollerrig.analysis.coa_estimates` (the corrected CoA's uncertainty, the model-based
  estimates);
- :mod:`~rollerrig.analysis.findings`: the result (:class:`TestAnalysis`) and its JSON summary;
- :mod:`~rollerrig.analysis.transfer`: a creep curve measured on the roller predicted on the
  rail (the elastic part by contact mechanics, the surface's part carried over as measured);
  its inputs in :mod:`~rollerrig.analysis.measured_curve` (the points, from an analysis or a
  CSV) and :mod:`~rollerrig.analysis.transfer_geometry` (wheel, roller, rail, the Hertz
  ellipse on each side), its output in :mod:`~rollerrig.analysis.transfer_result`.
"""
