"""The one output layer: every file rollerrig writes goes through here.

- :func:`atomic_write` — the only atomic writer (temporary file in the target folder, mode from
  the umask, one :func:`os.replace`; nothing partial is ever left, not even on Ctrl-C).
- :func:`write_json`, :func:`write_text` — JSON (NaN policy below; provenance added) and text.
- :func:`save_figure` — PNG, SVG or PDF with the provenance embedded.
- :func:`write_table` — the one results writer, keyed by format (csv, parquet, tdms, mf4, mat,
  nc), one convention per format with units on every column; :func:`write_dataset` writes an
  xarray Dataset through it (NetCDF: any dimensions, CF-1.10 attributes).
- :class:`~rollerrig.output.labelled.LabelledData` — a Dataset's content (variables along
  named dimensions, attributes) without xarray: what :func:`write_dataset` takes besides an
  xarray Dataset, and what ``rollerrig simulate`` writes and draws without importing xarray.
- :func:`storable_names` — the one mapping of column names to what NetCDF and MAT store
  (``oil temp/bearing`` -> ``oil_temp_bearing``, the given name kept as ``original_name``).
- :func:`provenance`, :func:`run_context` — what made a file: package version and commit,
  command, inputs with their SHA-256, rig parameter set hash, channel map.
- :class:`OutputError` — every output-side fault, naming the path.

This package is the bottom of the layering: it imports only the standard library, numpy,
:mod:`rollerrig._validation`, :mod:`rollerrig._optional` and ``rollerrig.__version__``; optional
packages (pandas, pyarrow, nptdms, asammdf, scipy, h5py, xarray, matplotlib) are imported when a
format needs them.

NaN policy
----------
- JSON has no NaN or inf: a number that cannot be given is written as ``null`` with the reason
  beside it; a non-finite float that still reaches :func:`write_json` is written as ``null`` and
  listed under the top-level key ``"null_values"`` (where, what it was, why).
- Tables (CSV, Parquet, TDMS, MDF, MAT, NetCDF) keep NaN only in channels whose attributes state
  why (``nan_meaning``, e.g. "creep undefined at standstill: roller encoder speed 0"); a
  non-finite sample in any other column is refused (``ParameterError``).
"""

from rollerrig.output.atomic import OutputError, atomic_write, new_file_mode
from rollerrig.output.figures import figure_provenance, save_figure
from rollerrig.output.jsonfile import NULL_VALUES_KEY, json_text, write_json, write_text
from rollerrig.output.provenance import (
    file_sha256,
    package_commit,
    provenance,
    rig_sha256,
    run_context,
)
from rollerrig.output.tables import TABLE_FORMATS, TableColumn, write_dataset, write_table
from rollerrig.output.varnames import ORIGINAL_NAME, storable_names

__all__ = [
    "NULL_VALUES_KEY",
    "ORIGINAL_NAME",
    "TABLE_FORMATS",
    "OutputError",
    "TableColumn",
    "atomic_write",
    "figure_provenance",
    "file_sha256",
    "json_text",
    "new_file_mode",
    "package_commit",
    "provenance",
    "rig_sha256",
    "run_context",
    "save_figure",
    "storable_names",
    "write_dataset",
    "write_json",
    "write_table",
    "write_text",
]
