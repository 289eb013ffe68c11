"""Signal processing: smoothing filters, filter scoring and tuning, spectra with attribution.

Smoothing and long recordings
    :mod:`~rollerrig.signal.smoothing` (the filters, MATLAB semantics, :func:`smooth`), each
    filter in its module: :mod:`~rollerrig.signal.averaging_filters` (moving average,
    Gaussian), :mod:`~rollerrig.signal.local_regression` (LOWESS/LOESS),
    :mod:`~rollerrig.signal.savitzky_golay_filter`, :mod:`~rollerrig.signal.butterworth_filter`;
    :mod:`~rollerrig.signal.chunked` (the filters over a stream of chunks),
    :mod:`~rollerrig.signal.decimate` (zero-phase anti-alias decimation, streamed),
    :mod:`~rollerrig.signal.channel_checks` (a channel that never changes refused).
The filter study (entry points in :mod:`~rollerrig.signal.scoring`)
    :mod:`~rollerrig.signal.filter_score` (the scores and their weights),
    :mod:`~rollerrig.signal.steady_transient` (the steady and transient parts scored),
    :mod:`~rollerrig.signal.filter_candidates` (the seed's filter grid, the tuning grid),
    :mod:`~rollerrig.signal.study_signal` (the signal at its analysis rate),
    :mod:`~rollerrig.signal.study_table` (the ranked result),
    :mod:`~rollerrig.signal.synthetic_torque` (a seed-like torque with known truth).
Spectra (public names gathered in :mod:`~rollerrig.signal.spectra`)
    :mod:`~rollerrig.signal.welch` (Welch spectra and coherence of arrays, the periodogram),
    :mod:`~rollerrig.signal.streamed_welch` (the same of a stream of chunks, bounded memory),
    :mod:`~rollerrig.signal.welch_settings` (their settings checked),
    :mod:`~rollerrig.signal.spectrum_results` (the spectra as results),
    :mod:`~rollerrig.signal.peaks` (peak finding), :mod:`~rollerrig.signal.attribution` (the
    source of each peak), :mod:`~rollerrig.signal.ordermap` (order maps),
    :mod:`~rollerrig.signal.workflow` (the one spectrum workflow: ``explain_recording``),
    :mod:`~rollerrig.signal.spectrum_settings` (settings chosen from the signal),
    :mod:`~rollerrig.signal.operating_point` (mean speeds and load),
    :mod:`~rollerrig.signal.recording_access` (a recording in memory or streamed, one interface),
    :mod:`~rollerrig.signal.explained_spectrum` (the results, their tables and summaries).
"""
