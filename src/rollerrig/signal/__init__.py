"""Signal processing: smoothing filters, filter scoring and tuning, spectra with attribution."""
