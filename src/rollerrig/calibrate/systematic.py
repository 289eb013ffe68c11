"""The systematic errors of the fitted channels that the rig file states, carried into the
calibration's standard errors (JCGM 100 type B).

The statistical standard errors of a fit (:mod:`rollerrig.calibrate.stats`) cover the noise
of the channels, not an error every sample of a channel shares. The rig file states such
errors for the channels the calibration fits, in its ``[sensors]`` section, with the same
inputs and the same conversion to a standard uncertainty as the corrected CoA's budget
(:mod:`rollerrig.estimation.uncertainty`; names, symbols and table of
:mod:`rollerrig.estimation.gum_inputs`):

=====================  ===  ===========  ============  =========================================
input                  δ    channel      distribution  standard uncertainty u (rig ``sensors``)
=====================  ===  ===========  ============  =========================================
``torque_class``       δT   torque       rectangular   torque_sensor_accuracy × range / √3
``torque_gain``        g_T  torque       rectangular   torque_sensor_accuracy / √3 (relative),
                                                       acting as δT = g_T T
``pressure_class``     δp   normal load  rectangular   pressure_sensor_accuracy × range / √3,
                                                       acting as δN = A δp
``air_spring_area``    A    normal load  normal        air_spring_area_uncertainty × A,
                                                       acting as δN = N δA/A
=====================  ===  ===========  ============  =========================================

The encoders state no class: their counts are exact but for the quantisation, a random error
the fit's weights carry. A torque offset matters most: at one load and speed the roller
bearing's loss is a constant torque, and a zero offset of the torque sensor within its class
(±3 N.m on the bundled rig) moved ``bearing.friction_coefficient`` by 49-77 statistical
standard errors on the twin's own recordings (0.0055 fitted as 0.004464 ± 1.35e-5 with
+1.0 N.m; 2026-12-03), with white residuals: the fit cannot see it.

The class bounds the sensor's error at every reading (abs(δT) <= class × range at every abs(T)
<= range), and so admits a sensitivity (gain) error up to the class as a fraction of the
reading as well as a zero offset: the two are carried as two inputs, each with the whole class,
which overstates their sum by at most √2 where both reach their bounds (conservative; a
datasheet's separate zero and sensitivity tolerances would split it). A gain moves other keys
than an offset does: the torque's swings scale with it, and with them the roller's inertia and
the motor's lag. On the calibration tests' recording (the twin with values the fit is not told)
a gain of +0.1 % (inside the bundled rig's 0.1 % class) had put
``induction_motor.response_lag_clp`` 3.6 and ``inertia.roller`` 2.1 standard errors off, +0.2 %
5.0 and 3.1, with the offset alone carried (2026-12-03); with the gain carried, within 2.

Each input's effect is linearised at the optimum (:func:`parameter_shifts`): an error of one
standard uncertainty u changes the weighted residuals by Δr (the channel's change, its torque
lines projected out as the fit projects them, over the channel's σ), and moves the parameters
by the Gauss–Newton step

.. math:: \\Delta z = (A^T A)^{-1} A^T \\Delta r,

A the fit's weighted central-difference Jacobian; the delta method takes Δz to the values.
The inputs are independent: each adds Δθ Δθᵀ to the covariance (JCGM 100 §5.1.2, as
:meth:`rollerrig.fit.polach.PolachFit.with_systematic` does for the Polach fit of a curve).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rollerrig.estimation.gum_inputs import InputQuantity

__all__ = [
    "SENSOR_INPUTS",
    "SYSTEMATIC_MEANING",
    "SensorInput",
    "parameter_shifts",
    "sensor_inputs",
]

SENSOR_INPUTS = ("torque_class", "torque_gain", "pressure_class", "air_spring_area")
"""The systematic inputs of the fitted channels, in this order (names of
:data:`rollerrig.estimation.gum_inputs.INPUT_NAMES`)."""

SYSTEMATIC_MEANING = (
    "standard_error = sqrt(standard_error_statistical^2 + standard_error_systematic^2): the "
    "statistical part from the fit's residuals (Newey-West), the systematic part from the "
    "errors every sample of a channel shares that the rig file states (systematic_inputs: the "
    "torque sensor's and the pressure sensor's accuracy classes, rectangular, class x range/"
    "sqrt(3); the air spring's effective area, normal; as rollerrig analyze's CoA budget "
    "converts them; the torque class also as a gain error, class/sqrt(3) of the reading, "
    "since it bounds the error at every reading). systematic: each input's shift of the value "
    "for an error of one standard uncertainty, linearised at the optimum: (A^T A)^-1 A^T dr "
    "with A the fit's weighted Jacobian and dr the weighted residuals' change (JCGM 100 "
    "type B, the inputs independent); "
    "standard_error_systematic is the root sum of their squares. The standard errors hold "
    "conditional on the stated classes: an error beyond them is not covered"
)
"""What the split of ``standard_error`` in ``calibration.json`` means."""


@dataclass(frozen=True)
class SensorInput:
    """One systematic input of a fitted channel.

    Attributes
    ----------
    quantity : InputQuantity
        Name, symbol, distribution, standard uncertainty u [its unit] and basis, as the
        corrected CoA's budget states the same input.
    channel : str
        The fitted channel it acts on (``"torque"`` or ``"normal_load"``).
    change : ndarray
        The channel's change at each sample for an error of one standard uncertainty [N.m or
        N]: the same in every sample (an offset) or proportional to the reading (a gain).
    """

    quantity: InputQuantity
    channel: str
    change: np.ndarray

    def as_dict(self) -> dict:
        """JSON-ready: the input's table row, the channel, how it acts."""
        mean = float(np.mean(self.change))
        return self.quantity.as_dict() | {
            "channel": self.channel,
            "channel_change_mean": mean,
            "channel_change_unit": "N.m" if self.channel == "torque" else "N",
        }


def sensor_inputs(measurement, rig) -> tuple[SensorInput, ...]:
    """The systematic inputs the rig file states for the channels a calibration fits.

    Parameters
    ----------
    measurement : Measurement
        The prepared recording (:func:`rollerrig.calibrate.measurement.prepare_measurement`):
        its normal-load channel [N] and where it came from.
    rig : RigParameters
        Its ``sensors`` section: the classes, ranges and the air spring's area.

    Returns
    -------
    tuple of SensorInput
        In the order of :data:`SENSOR_INPUTS`; an input whose standard uncertainty is 0 is
        left out.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> from rollerrig.rig.parameters import default_rig
    >>> m = SimpleNamespace(time=np.arange(3.0), values={"normal_load": np.full(3, 4300.0),
    ...                     "torque": np.full(3, 600.0)}, load_source="air_spring_pressure")
    >>> torque, gain, pressure, area = sensor_inputs(m, default_rig())
    >>> round(torque.quantity.standard_uncertainty, 4)  # 0.1 % of 3000 N.m over sqrt(3)
    1.7321
    >>> round(float(gain.change[0]), 4)  # 0.1 % over sqrt(3) of a 600 N.m reading
    0.3464
    >>> round(float(pressure.change[0]), 2)  # 0.35 % of 10 bar over sqrt(3), on 0.05 m^2
    101.04
    >>> round(float(area.change[0]), 1)  # 2 % of the 4300 N the spring carries
    86.0
    """
    s = rig.sensors
    n = measurement.time.size
    area = float(s.air_spring_effective_area)
    load = np.asarray(measurement.values["normal_load"], dtype=float)
    via = (
        ""
        if getattr(measurement, "load_source", "air_spring_pressure") == "air_spring_pressure"
        else "; the recording gives the load, taken as measured by the air spring (p = N/A), "
        "as rollerrig analyze takes it"
    )
    u_t = s.torque_sensor_accuracy * s.torque_sensor_range / math.sqrt(3.0)
    u_g = s.torque_sensor_accuracy / math.sqrt(3.0)
    torque = np.asarray(measurement.values["torque"], dtype=float)
    u_p = s.pressure_sensor_accuracy * s.pressure_sensor_range / math.sqrt(3.0)
    u_a = s.air_spring_area_uncertainty * area
    out = [
        SensorInput(
            InputQuantity(
                "torque_class",
                "δT",
                "systematic",
                "rectangular",
                0.0,
                u_t,
                "N.m",
                f"accuracy class {s.torque_sensor_accuracy:g} of {s.torque_sensor_range:g} "
                "N.m (sensors.torque_sensor_accuracy): a zero offset of the torque channel, "
                "the same in every sample",
                "sensors.torque_sensor_accuracy",
            ),
            "torque",
            np.full(n, u_t),
        ),
        SensorInput(
            InputQuantity(
                "torque_gain",
                "g_T",
                "systematic",
                "rectangular",
                0.0,
                u_g,
                "1",
                f"accuracy class {s.torque_sensor_accuracy:g} (sensors.torque_sensor_accuracy) "
                "as a sensitivity error: the class bounds the error at every reading, so a "
                "gain of up to the class is inside it, δT = g_T T in every sample",
                "sensors.torque_sensor_accuracy",
            ),
            "torque",
            torque * u_g,
        ),
        SensorInput(
            InputQuantity(
                "pressure_class",
                "δp",
                "systematic",
                "rectangular",
                0.0,
                u_p,
                "Pa",
                f"accuracy class {s.pressure_sensor_accuracy:g} of "
                f"{s.pressure_sensor_range:g} Pa (sensors.pressure_sensor_accuracy): an offset "
                f"of the normal load by A δp{via}",
                "sensors.pressure_sensor_accuracy",
            ),
            "normal_load",
            np.full(n, area * u_p),
        ),
        SensorInput(
            InputQuantity(
                "air_spring_area",
                "A",
                "systematic",
                "normal",
                area,
                u_a,
                "m^2",
                f"{s.air_spring_area_uncertainty:g} relative "
                "(sensors.air_spring_area_uncertainty): a gain error of the normal load, "
                f"N δA/A{via}",
                "sensors.air_spring_effective_area",
            ),
            "normal_load",
            load * s.air_spring_area_uncertainty,
        ),
    ]
    return tuple(i for i in out if i.quantity.standard_uncertainty > 0.0)


def parameter_shifts(jacobian: np.ndarray, changes: dict[str, np.ndarray]) -> dict:
    """The linearised shift of the fitted z for each input's change of the weighted residuals.

    Parameters
    ----------
    jacobian : ndarray, shape (n, p)
        The fit's weighted Jacobian of the stacked channels with respect to the active z at
        the optimum [-].
    changes : dict of str to ndarray, shape (n,)
        Input name -> the weighted residuals' change Δr for an error of one standard
        uncertainty [-].

    Returns
    -------
    dict of str to ndarray, shape (p,)
        Input name -> Δz = (AᵀA)⁻¹AᵀΔr [-] (least squares, as the Gauss–Newton step).

    Examples
    --------
    A straight line fitted to data that all read 0.5 high: the intercept moves by 0.5.

    >>> a = np.column_stack([np.ones(5), np.arange(5.0)])
    >>> d = parameter_shifts(a, {"offset": np.full(5, 0.5)})["offset"]
    >>> [round(float(x), 12) + 0.0 for x in d]  # + 0.0: no negative zero
    [0.5, 0.0]
    """
    return {
        name: np.linalg.lstsq(jacobian, np.asarray(dr, dtype=float), rcond=None)[0]
        for name, dr in changes.items()
    }
