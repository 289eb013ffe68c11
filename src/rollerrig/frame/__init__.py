"""The rig frame: its description, static and modal FE analysis, and its reduction to the contact.

- :mod:`~rollerrig.frame.framefile` — the frame file (TOML): nodes, members, sections, supports,
  load points, lumped masses, strain gauges; :func:`load_frame`, :func:`default_frame` (the
  Pardubice rig's frame, every dimension a stated assumption); :class:`FrameFileError`.
- :mod:`~rollerrig.frame.sections` — the sourced table of standard sections (IPE, HEB: EN 10365 /
  ArcelorMittal; SHS, RHS, CHS: EN 10219-2) and their formulas.
- :mod:`~rollerrig.frame.analysis` — static and modal analysis on PyNiteFEA
  (:func:`analyze_frame`), stresses at the gauges, largest von Mises stress, top deflection,
  natural frequencies and mode shapes; :func:`contact_dof`, the frame as one longitudinal
  degree of freedom at the wheel-roller contact (stiffness and modal mass).
- :mod:`~rollerrig.frame.gauges` — virtual strain gauges: the stress at each gauge from the
  contact forces over an experiment.

The analysis needs PyNiteFEA (``pip install 'rollerrig[frame]'``); the frame file and the
section table do not.

Examples
--------
>>> frame = default_frame()
>>> result = analyze_frame(frame, normal_load=20e3, traction_force=2e3, n_modes=3)
>>> result.top_horizontal_deflection < 1e-4   # [m]
True
"""

from rollerrig.frame.analysis import (
    ContactDof,
    FrameResult,
    GaugeStress,
    StressPeak,
    analyze_frame,
    contact_dof,
)
from rollerrig.frame.framefile import (
    Frame,
    FrameFileError,
    default_frame,
    frame_from_dict,
    load_frame,
)
from rollerrig.frame.gauges import GaugeInfluence, gauge_influence, gauge_signals
from rollerrig.frame.sections import SectionProperties, section_table, standard_section

__all__ = [
    "ContactDof",
    "Frame",
    "FrameFileError",
    "FrameResult",
    "GaugeInfluence",
    "GaugeStress",
    "SectionProperties",
    "StressPeak",
    "analyze_frame",
    "contact_dof",
    "default_frame",
    "frame_from_dict",
    "gauge_influence",
    "gauge_signals",
    "load_frame",
    "section_table",
    "standard_section",
]
