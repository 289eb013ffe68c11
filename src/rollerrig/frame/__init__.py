"""The rig frame: its description, static and modal FE analysis, and its reduction to the contact.

- :mod:`~rollerrig.frame.framefile` — the frame file (TOML): :func:`load_frame`,
  :func:`frame_from_dict`, :func:`default_frame` (the Pardubice rig's frame, every dimension a
  stated assumption); the frame it gives in :mod:`~rollerrig.frame.structure` (nodes, members,
  sections, supports, load points, lumped masses, strain gauges), what a file may hold in
  :mod:`~rollerrig.frame.limits`, its error in :mod:`~rollerrig.frame.errors`
  (:class:`FrameFileError`).
- :mod:`~rollerrig.frame.sections` — the sourced table of standard sections (IPE, HEB: EN 10365 /
  ArcelorMittal; SHS, RHS, CHS: EN 10219-2) and their formulas.
- :mod:`~rollerrig.frame.analysis` — static and modal analysis on PyNiteFEA
  (:func:`analyze_frame`): the FE model and its unit load cases (:mod:`~rollerrig.frame.femodel`),
  mechanisms and natural frequencies and mode shapes (:mod:`~rollerrig.frame.modes`), stresses at
  the gauges, largest von Mises stress and end forces (:mod:`~rollerrig.frame.stresses`), all in
  a :class:`FrameResult` (:mod:`~rollerrig.frame.results`) with the top deflection;
  :func:`contact_dof` (:mod:`~rollerrig.frame.reduction`), the frame as one longitudinal degree
  of freedom at the wheel-roller contact (stiffness and modal mass).
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

from rollerrig.frame.analysis import analyze_frame
from rollerrig.frame.errors import FrameFileError
from rollerrig.frame.framefile import default_frame, frame_from_dict, load_frame
from rollerrig.frame.gauges import GaugeInfluence, gauge_influence, gauge_signals
from rollerrig.frame.reduction import ContactDof, contact_dof
from rollerrig.frame.results import FrameResult
from rollerrig.frame.sections import SectionProperties, section_table, standard_section
from rollerrig.frame.stresses import GaugeStress, StressPeak
from rollerrig.frame.structure import Frame

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
