"""Experiment protocols as data: TOML step lists and recorded torque-request replays.

A protocol compiles to piecewise-linear inputs in SI units (torque request, roller speed set
point, normal load) and friction-condition switches; the solvers integrate between its
breakpoints.
"""

from rollerrig.experiment.protocol import (
    DEFAULT_FAST_RAMP_DURATION,
    Protocol,
    ProtocolError,
    ProtocolEvent,
    bundled_protocols,
    load_protocol,
    protocol_from_csv,
    protocol_from_toml_string,
)

__all__ = [
    "DEFAULT_FAST_RAMP_DURATION",
    "Protocol",
    "ProtocolError",
    "ProtocolEvent",
    "bundled_protocols",
    "load_protocol",
    "protocol_from_csv",
    "protocol_from_toml_string",
]
