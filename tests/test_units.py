"""The one unit registry: every accepted spelling of every quantity against reference factors.

References (independent of the code's arithmetic):
- NIST SP 811 (2008 ed.), Appendix B.9, factors "to convert from ... to": revolution per minute
  (rpm, r/min) -> rad/s 1.047198 E-01; bar -> Pa 1.0 E+05 (exact); kilometer per hour -> m/s
  2.777778 E-01.
- BIPM SI Brochure, 9th ed. (2019): Table 7 (prefixes k = 1e3, M = 1e6, G = 1e9, c = 1e-2,
  m = 1e-3, µ = 1e-6, n = 1e-9); a revolution is 2π rad, a minute 60 s; 1 Hz = 1 s^-1 (as a
  rotation speed in a DAQ file: 1 rev/s = 2π rad/s).
"""

from __future__ import annotations

import math
from decimal import Decimal, localcontext

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from rollerrig._validation import ParameterError
from rollerrig.units import (
    ALIASES,
    QUANTITIES,
    UNITS_BY_SI,
    UnitError,
    apply_factor,
    normalize_unit,
    quantity_factor,
    si_factor,
    to_si,
)

NIST_RPM = 1.047198e-1  # NIST SP 811 B.9, 7 significant digits
NIST_KMH = 2.777778e-1  # NIST SP 811 B.9, 7 significant digits
NIST_BAR = 1.0e5  # NIST SP 811 B.9, exact
NIST_PSI = 6.894757e3  # NIST SP 811 B.9, pound-force per square inch, 7 significant digits
SI_MINUTE, SI_HOUR = 60.0, 3600.0  # SI Brochure (9th ed.), Table 8, exact
NIST = 5e-7  # relative tolerance of a 7-digit NIST factor

TWO_PI = 2 * 3.14159265358979  # a revolution [rad], to 15 digits
KILO, MEGA, GIGA = 10.0**3, 10.0**6, 10.0**9  # SI Brochure, Table 7
CENTI, MILLI, MICRO, NANO = 10.0**-2, 10.0**-3, 10.0**-6, 10.0**-9

#: quantity -> ((unit, reference factor to SI), ...), in the registry's order. Every accepted
#: unit of every quantity has one (tested), so a unit added to the registry needs a reference.
REFERENCE_TABLE = {
    "length": (("m", 1), ("mm", MILLI), ("um", MICRO)),
    "area": (("m^2", 1), ("cm^2", CENTI**2), ("mm^2", MILLI**2)),
    "torsional_stiffness": (("N.m/rad", 1), ("kN.m/rad", KILO)),
    "torsional_damping": (("N.m.s/rad", 1),),
    "inertia": (("kg.m^2", 1),),
    "force": (("N", 1), ("kN", KILO)),
    "pressure": (
        ("Pa", 1),
        ("kPa", KILO),
        ("mbar", MILLI * NIST_BAR),
        ("bar", NIST_BAR),
        ("MPa", MEGA),
        ("GPa", GIGA),
        ("psi", NIST_PSI),
    ),
    "speed": (("m/s", 1), ("km/h", NIST_KMH)),
    "angular_speed": (("rad/s", 1), ("rpm", NIST_RPM), ("Hz", TWO_PI)),  # 1 rev/s = 2π rad/s
    "angular_frequency": (("rad/s", 1), ("Hz", TWO_PI)),
    "frequency": (("Hz", 1), ("kHz", KILO)),
    "rate": (("1/s", 1),),
    "voltage": (("V", 1), ("mV", MILLI), ("kV", KILO)),
    "current": (("A", 1), ("mA", MILLI)),
    "resistance": (("ohm", 1), ("mohm", MILLI)),
    "inductance": (("H", 1), ("mH", MILLI)),
    "flux_linkage": (("Wb", 1),),
    "power": (("W", 1), ("kW", KILO)),
    "torque": (("N.m", 1), ("kN.m", KILO)),
    "time": (
        ("s", 1),
        ("ms", MILLI),
        ("us", MICRO),
        ("ns", NANO),
        ("min", SI_MINUTE),
        ("h", SI_HOUR),
    ),
    "second_moment": (("m^4", 1), ("cm^4", CENTI**4), ("mm^4", MILLI**4)),
    "section_modulus": (("m^3", 1), ("cm^3", CENTI**3), ("mm^3", MILLI**3)),
    # 1 t = 1000 kg (SI Brochure Table 8, the tonne); g = 1e-3 kg
    "density": (("kg/m^3", 1), ("t/m^3", KILO), ("g/cm^3", MILLI / CENTI**3)),
    "mass": (("kg", 1), ("t", KILO)),
    "linear_stiffness": (("N/m", 1), ("N/mm", 1 / MILLI), ("kN/mm", KILO / MILLI), ("MN/m", MEGA)),
    "linear_damping": (("N.s/m", 1),),
    "dimensionless": (("1", 1),),
    "count": (("1", 1),),
}
REFERENCE = [(q, unit, factor) for q, rows in REFERENCE_TABLE.items() for unit, factor in rows]
#: Relative tolerance of a reference: 7 significant digits (NIST), 15 (2π), else rounding only.
TOLERANCE = {NIST_RPM: NIST, NIST_KMH: NIST, NIST_PSI: NIST, TWO_PI: 1e-14}

#: The spellings the three former tables accepted (rig/parameters UNITS, measure/channels
#: UNIT_FACTORS/TIME_UNITS/_ALIASES, experiment/protocol _TIME_UNITS/_TORQUE_UNITS, which read
#: torque units in any letter case with '·', '⋅', '*' or a space as the product), by the
#: registry unit each means. All are still accepted.
FORMER = {
    "N.m": ("Nm", "N*m", "N·m", "N m", "n.m", "nm", "NM", "N.M", "N⋅m"),
    "kN.m": ("kNm", "kN*m", "kN·m", "kn.m", "knm", "KNM", "kN⋅m", "kN m", "KN*M"),
    "rad/s": ("rad/sec",),
    "rpm": ("1/min", "min^-1", "min-1", "U/min", "rev/min", "tr/min"),
    "Hz": ("rev/s",),
    "um": ("µm", "μm"),  # micro sign U+00B5, Greek mu U+03BC
    "us": ("µs", "μs"),
    "N": ("Newtons",),
    "1": ("counts", "count", "-"),
    "s": ("sec",),
}
FORMER_SPELLINGS = {
    **{u: u for table in QUANTITIES.values() for u in table.units},  # rig/parameters UNITS
    **{spelling: unit for unit, spellings in FORMER.items() for spelling in spellings},
}


def _quantities_of(unit: str) -> list[str]:
    return [q for q, spec in QUANTITIES.items() if unit in spec.units]


def test_every_accepted_unit_has_a_reference_factor():
    accepted = [(q, u) for q, spec in QUANTITIES.items() for u in spec.units]
    assert accepted == [(q, u) for q, u, _ in REFERENCE]


@pytest.mark.parametrize(("quantity", "unit", "factor"), REFERENCE)
def test_factor_matches_reference(quantity, unit, factor):
    rel = TOLERANCE.get(factor, 1e-15)
    assert quantity_factor(unit, quantity) == pytest.approx(factor, rel=rel, abs=0)
    si = QUANTITIES[quantity].si_unit
    assert si_factor(unit, si) == quantity_factor(unit, quantity)


def test_rpm_and_revolutions_follow_their_definitions_exactly():
    # 1 rpm = 2π rad / 60 s; 1 rev/s = 2π rad/s (a revolution is 2π rad).
    assert si_factor("rpm", "rad/s") == pytest.approx(2 * math.pi / 60, rel=1e-15)
    assert si_factor("rev/s", "rad/s") == pytest.approx(2 * math.pi, rel=1e-15)
    assert si_factor("km/h", "m/s") == pytest.approx(1 / 3.6, rel=1e-15)


@pytest.mark.parametrize(("spelling", "unit"), sorted(FORMER_SPELLINGS.items()))
def test_former_spellings_are_still_accepted(spelling, unit):
    assert normalize_unit(spelling) == unit
    assert normalize_unit(f"  {spelling} ") == unit
    quantities = _quantities_of(unit)
    assert quantities, spelling
    for q in quantities:
        assert quantity_factor(spelling, q) == QUANTITIES[q].units[unit]


@pytest.mark.parametrize(("alias", "unit"), sorted(ALIASES.items()))
def test_every_alias_names_an_accepted_unit(alias, unit):
    assert _quantities_of(unit), alias
    assert normalize_unit(alias) == unit


def test_si_unit_is_the_first_unit_with_factor_one():
    for quantity, spec in QUANTITIES.items():
        assert next(iter(spec.units)) == spec.si_unit, quantity
        assert spec.units[spec.si_unit] == 1.0, quantity


def test_quantities_sharing_an_si_unit_agree():
    # si_factor looks units up by SI unit: "Hz" is 2π rad/s for both angular quantities.
    for si, table in UNITS_BY_SI.items():
        for quantity, spec in QUANTITIES.items():
            if spec.si_unit == si:
                for unit, factor in spec.units.items():
                    assert table[unit] == factor, (quantity, unit)


def test_context_decides_what_hz_means():
    assert si_factor("Hz", "Hz") == 1.0  # a frequency
    assert si_factor("Hz", "rad/s") == pytest.approx(2 * math.pi, rel=1e-15)  # a rotation speed


def test_tables_are_read_only():
    with pytest.raises(TypeError):
        QUANTITIES["torque"].units["lbf.ft"] = 1.3558  # type: ignore[index]
    with pytest.raises(TypeError):
        ALIASES["x"] = "m"  # type: ignore[index]


def test_unknown_units_stay_as_written():
    assert normalize_unit(" degC ") == "degC"
    assert normalize_unit("Torque Roller") == "Torque Roller"


@pytest.mark.parametrize(
    ("unit", "si", "message"),
    [
        (
            "bar",
            "N.m",
            "unit not accepted for torque [N.m]; allowed 'N.m', 'kN.m' (also written 'Nm', "
            "'N-m', 'kNm'); got 'bar'",
        ),
        ("lbf", "N", "unit not accepted for force [N]; allowed 'N', 'kN'"),
        ("d", "s", "unit not accepted for time [s]; allowed 's', 'ms', 'us', 'ns', 'min', 'h'"),
        ("nm", "m", "unit not accepted for length [m]"),  # "nm" is read as N.m, never nanometre
        (3, "m", "got 3"),
    ],
)
def test_unit_not_accepted_is_one_clear_error(unit, si, message):
    with pytest.raises(UnitError) as info:
        si_factor(unit, si, what="map.toml: channels.x.unit: ")
    assert str(info.value).startswith("map.toml: channels.x.unit: ")
    assert message in str(info.value)
    assert isinstance(info.value, ParameterError)
    assert info.value.problem.got == unit


def test_unknown_si_unit_is_an_error():
    with pytest.raises(UnitError, match=r"no unit table for SI unit 'furlong'"):
        si_factor("m", "furlong")


def test_to_si_round_trip():
    values = np.array([0.0, 1.5, -3.25, 348.0, 1e6])
    for quantity, spec in QUANTITIES.items():
        for unit, factor in spec.units.items():
            si = to_si(values, unit, spec.si_unit)
            np.testing.assert_allclose(si / factor, values, rtol=1e-15, err_msg=quantity + unit)


def test_to_si_examples():
    np.testing.assert_allclose(
        to_si([0.0, 30.0, 60.0], "rpm", "rad/s"), [0.0, math.pi, 2 * math.pi], rtol=1e-15
    )
    assert to_si([1.5], "bar", "Pa").tolist() == [1.5e5]
    assert to_si([348.0, 291.0, 452.0, 1890.0], "mm", "m").tolist() == [0.348, 0.291, 0.452, 1.89]
    assert to_si([30.0], "km/h", "m/s").tolist() == [30.0 / 3.6]


@given(st.floats(allow_nan=False, allow_infinity=False, min_value=-1e300, max_value=1e300))
@example(1.1073078518241965e-307)  # x/1000 lies exactly halfway between two subnormals
def test_decimal_units_convert_correctly_rounded(x):
    # A factor with a short decimal inverse (mm, µs, ns) divides: the result is x/1000 etc.
    # rounded once, the float nearest to the exact quotient; km/h gives x / 3.6.
    with localcontext() as ctx:
        # Exact: a double has at most 767 significant decimal digits, and dividing by 10^k adds
        # none. 80 digits (before) broke an exact tie between two subnormals (x = 1.107e-307
        # over 1000), and the reference rounded the other way than IEEE's division.
        ctx.prec = 800
        for factor, inverse in ((1e-3, 1000), (1e-6, 1000000), (1e-9, 10**9)):
            exact = float(Decimal(x) / Decimal(inverse))
            assert apply_factor(x, factor) == exact
            assert apply_factor(np.array([x]), factor)[0] == exact
    assert apply_factor(x, 1 / 3.6) == x / 3.6


def test_apply_factor_keeps_scalars_and_arrays():
    assert isinstance(apply_factor(2, 1e3), float)
    assert apply_factor(np.array([2.0]), 1e3).tolist() == [2000.0]


def test_a_value_beyond_the_float_range_becomes_inf_without_a_numpy_warning():
    # 1e308 kN.m/rad: the validators refuse inf by name; numpy's overflow warning (an error
    # under this suite's filter) had been printed beside that message.
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert apply_factor(1e308, 1e3) == np.inf
        assert np.isinf(apply_factor(np.array([1e308]), 1e3)).all()
