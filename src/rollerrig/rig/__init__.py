"""The rig: validated parameter sets, the torsional chain and its modes, the coupled model.

- :mod:`~rollerrig.rig.parameters` — validated parameter sets (:class:`RigParameters`): load,
  override, save; the bundled default rig.
- :mod:`~rollerrig.rig.sections` — the parameter sections (SI values, quantities, ranges).
- :mod:`~rollerrig.rig.rigfile` — the TOML file form: entries with value, unit and provenance.
- :mod:`~rollerrig.rig.chain` — mass, stiffness and damping matrices; modal analysis.
- :mod:`~rollerrig.rig.model` — the coupled nonlinear model (chain, contact, drives).
- :mod:`~rollerrig.rig.assemble` — numeric solver inputs from rig, drives and protocol.
- :mod:`~rollerrig.rig.drive_dynamics` — the study of the dq V/f roller drive coupled with the
  rig; its parts in :mod:`~rollerrig.rig.dq_drive` (machine and controller),
  :mod:`~rollerrig.rig.dq_twin` (the coupled twin), :mod:`~rollerrig.rig.drive_mode_tables`
  (mode tables) and :mod:`~rollerrig.rig.lag_in_rig` (the lag it amounts to).
"""

from rollerrig.rig.chain import (
    BODY_NAMES,
    CHAIN_ELEMENTS,
    ModalResult,
    ModalRow,
    assemble_chain,
    chain_matrices,
    contact_damping_matrix,
    format_modal_table,
    modal_analysis,
    modal_table,
)
from rollerrig.rig.parameters import (
    RigFileError,
    RigParameters,
    default_rig,
    load_rig,
    save_rig,
)

__all__ = [
    "BODY_NAMES",
    "CHAIN_ELEMENTS",
    "ModalResult",
    "ModalRow",
    "RigFileError",
    "RigParameters",
    "assemble_chain",
    "chain_matrices",
    "contact_damping_matrix",
    "default_rig",
    "format_modal_table",
    "load_rig",
    "modal_analysis",
    "modal_table",
    "save_rig",
]
