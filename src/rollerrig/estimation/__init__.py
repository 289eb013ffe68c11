"""Estimation: the contact estimated from the sensors, and the corrected CoA's uncertainty.

- :mod:`~rollerrig.estimation.estimator`: the contact torque from T56 and the encoders, by a
  causal Kalman filter (online, one sample at a time) and by Rauch-Tung-Striebel smoothers of
  the roller alone or of the roller-shaft-rotor-drive chain, which choose their model by the
  evidence of their innovations (the causal filter in :mod:`~rollerrig.estimation.kalman`, its
  model and gains in :mod:`~rollerrig.estimation.kalman_design`, its steady recursion in
  :mod:`~rollerrig.estimation.schur_recursion`; what filter and smoothers share: the estimate
  in :mod:`~rollerrig.estimation.contact_estimate`, the models, default noises and checked
  parameters in :mod:`~rollerrig.estimation.estimator_parameters`, the checked samples and
  the bearing loss in :mod:`~rollerrig.estimation.estimator_inputs`; the smoother in
  :mod:`~rollerrig.estimation.smoother`, its model and gains in
  :mod:`~rollerrig.estimation.smoother_model`, its passes in
  :mod:`~rollerrig.estimation.smoother_passes`, the torque's order lines in
  :mod:`~rollerrig.estimation.order_lines`, its innovations and the drive noise by maximum
  likelihood in :mod:`~rollerrig.estimation.smoother_likelihood`);
- :mod:`~rollerrig.estimation.uncertainty` (JCGM 100 law of propagation, per sample) with its
  inputs (:mod:`~rollerrig.estimation.gum_inputs`), the calibrated ones' covariance
  (:mod:`~rollerrig.estimation.calibrated_inputs`), the stated release residual
  (:mod:`~rollerrig.estimation.release_residual`) and its result
  (:mod:`~rollerrig.estimation.coa_uncertainty`),
  :mod:`~rollerrig.estimation.montecarlo` (JCGM 101 and its validation),
  :mod:`~rollerrig.estimation.budget` (per phase and creep–CoA point),
  :mod:`~rollerrig.estimation.filterweights` (the correction's filters as exact weights).
"""
