"""Recordings: what acquisition software writes, read, mapped, checked and written.

- :mod:`~rollerrig.recordings.recording`: the :class:`Recording` every reader returns, and
  :class:`RecordingError`;
- :mod:`~rollerrig.recordings.readers` (:func:`read_recording`, format detection) over one
  reader per format in :mod:`~rollerrig.recordings.formats` (CSV and text dialects, LabVIEW
  .lvm, Parquet, NI TDMS, ASAM MDF4, MATLAB .mat; text sniffing, timestamps);
  :mod:`~rollerrig.recordings.source` (long files read chunk by chunk);
- :mod:`~rollerrig.recordings.channels` and :mod:`~rollerrig.recordings.mapfile` (channel
  maps), :mod:`~rollerrig.recordings.translate` (columns through the map into SI channels),
  :mod:`~rollerrig.recordings.timebase` (channels of several rates on one time base),
  :mod:`~rollerrig.recordings.validate` (time, NaN/inf, gaps);
- :mod:`~rollerrig.recordings.writers` (every format the readers read);
- :mod:`~rollerrig.recordings.synthetic`: what the rig's DAQ would record of a twin run.

This package imports nothing of the measurement, estimation or analysis above it.
"""
