"""Virtual strain gauges: the stress at each gauge of the frame from the contact forces.

The frame is linear, so the axial stress at a gauge is a fixed combination of the two test
loads (influence coefficients from the unit load cases of :func:`rollerrig.frame.analysis.
analyze_frame`)::

    σ_g(t) = a_g N(t) + b_g F_x(t)          [Pa],  ε_g(t) = σ_g(t) / E

with N the normal load (air-spring force) and F_x the longitudinal contact force (> 0 in
traction), e.g. the twin's truth channels ``normal_load`` and ``contact_force``. A measured
strain channel of a recording can be compared with ``ε_g``; a gauge zeroed on the unloaded
frame reads it as it is, one zeroed under the normal load reads ``ε_g − a_g N_0 / E``.

The combination is quasi-static: it holds for forces that change slowly against the frame's
first natural frequency (:attr:`GaugeInfluence.first_frequency`); the frame's own vibration
above it is not in it.

Examples
--------
>>> import numpy as np
>>> from rollerrig.frame import default_frame, analyze_frame
>>> influence = gauge_influence(analyze_frame(default_frame(), n_modes=1))
>>> s = influence.stresses(np.array([0.0, 20e3]), np.array([0.0, 2e3]))
>>> float(s["top_beam"][0]), float(s["top_beam"][1]) > 0.0
(0.0, True)
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from rollerrig._validation import ParameterError, require_broadcastable, require_finite
from rollerrig.frame.analysis import FrameResult

__all__ = ["GaugeInfluence", "gauge_influence", "gauge_signals"]


@dataclass(frozen=True)
class GaugeInfluence:
    """Influence coefficients of the frame's strain gauges.

    Attributes
    ----------
    names : tuple of str
        The gauges, in the frame file's order.
    normal : ndarray
        Stress per newton of normal load, a_g [Pa/N].
    traction : ndarray
        Stress per newton of traction force, b_g [Pa/N].
    youngs_modulus : ndarray
        E of each gauge's member [Pa].
    first_frequency : float
        The frame's first natural frequency [Hz] (the quasi-static limit), NaN if not computed.
    """

    names: tuple[str, ...]
    normal: np.ndarray
    traction: np.ndarray
    youngs_modulus: np.ndarray
    first_frequency: float = float("nan")

    def stresses(self, normal_load, traction_force) -> dict[str, np.ndarray]:
        """Axial stress at each gauge [Pa] (> 0 tension).

        Parameters
        ----------
        normal_load : array_like
            Normal load N [N].
        traction_force : array_like
            Longitudinal contact force F_x [N], > 0 in traction; broadcast with N.
        """
        n = require_finite("normal_load", normal_load, "N")
        f = require_finite("traction_force", traction_force, "N")
        n, f = require_broadcastable(normal_load=n, traction_force=f)
        return {
            name: a * n + b * f
            for name, a, b in zip(self.names, self.normal, self.traction, strict=True)
        }

    def strains(self, normal_load, traction_force) -> dict[str, np.ndarray]:
        """Axial strain at each gauge [-] (σ / E)."""
        stresses = self.stresses(normal_load, traction_force)
        return {
            name: stresses[name] / e
            for name, e in zip(self.names, self.youngs_modulus, strict=True)
        }


def gauge_influence(result: FrameResult) -> GaugeInfluence:
    """The influence coefficients of a frame's gauges from its analysis."""
    frame = result.frame
    names = tuple(result.gauges)
    return GaugeInfluence(
        names=names,
        normal=np.array([result.gauges[n].normal for n in names]),
        traction=np.array([result.gauges[n].traction for n in names]),
        youngs_modulus=np.array(
            [
                frame.materials[frame.members[frame.gauges[n].member].material].youngs_modulus
                for n in names
            ]
        ),
        first_frequency=float(result.frequencies[0]) if len(result.frequencies) else float("nan"),
    )


def gauge_signals(
    source: Mapping,
    influence: GaugeInfluence,
    *,
    normal: str = "normal_load",
    traction: str = "contact_force",
) -> dict[str, np.ndarray]:
    """The stress at each gauge over an experiment [Pa], from its force channels.

    Parameters
    ----------
    source : mapping
        Anything indexable by channel name giving arrays: the twin's results
        (:class:`xarray.Dataset` from :class:`rollerrig.Simulation`), a dict of arrays.
    influence : GaugeInfluence
    normal, traction : str
        The channels of the normal load N [N] and the contact force F_x [N].

    Raises
    ------
    ParameterError
        A channel is missing (named), or not finite.
    """
    if not isinstance(influence, GaugeInfluence):
        raise ParameterError(
            f"influence must be a GaugeInfluence (gauge_influence), got {type(influence).__name__}"
        )
    if isinstance(source, str | bytes) or not hasattr(source, "__getitem__"):
        raise ParameterError(
            "source must be a mapping of channel name -> array (the twin's results, a dict), "
            f"got {type(source).__name__}"
        )
    arrays = []
    for channel in (normal, traction):
        try:
            values = source[channel]
        except (KeyError, IndexError, TypeError):  # a list or an array indexed by a name
            raise ParameterError(
                f"the results have no channel {channel!r} (needed for the virtual strain "
                "gauges: normal load N [N] and contact force F_x [N]); name the channels with "
                "normal=..., traction=..."
            ) from None
        arrays.append(require_finite(f"channel {channel!r}", getattr(values, "values", values)))
    n, f = require_broadcastable(
        **{f"channel {normal!r}": arrays[0], f"channel {traction!r}": arrays[1]}
    )
    return influence.stresses(n, f)
