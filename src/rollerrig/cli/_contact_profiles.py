"""``rollerrig contact --wheel-profile F --rail-profile F``: the non-Hertzian part of the command.

CONTACT (optional, never shipped: :mod:`rollerrig.contact.cntc_profiles`) solves the wheel
profile on the rail profile straight (tangent track) and turned into the rig's roller, at the
command's load, by Kalker's exact theory; this module runs it at a few creepages with progress,
prints the table beside the Hertzian factor of the command's creep law, and writes the JSON and
the figure.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from rich.table import Table

from rollerrig.cli._boundary import UserError
from rollerrig.cli._console import console, steps

__all__ = ["PROFILE_CREEPAGES", "profile_files", "run_profiles"]

PROFILE_CREEPAGES = (1e-4, 5e-4, 1e-3, 2e-3, 3e-3, 6e-3)
"""Kalker creepages ξ [-] of the profile comparison: the linear part, the transition, the
saturation. Each is solved at +ξ and -ξ on both bodies (four CONTACT solutions of 1-3 s at
0.2 mm elements): the spin of a conical profile pushes F_x one way whatever the sign of ξ (about
250 N at 10 kN on S1002/UIC60), so the force of the creepage is the odd part
(F(ξ) - F(-ξ))/2; a single ratio at +1e-4 would read 1.16 where the odd parts give 1.47 (μ 0.33)."""

EXAMPLE = "example"
"""``--wheel-profile example`` (``--rail-profile example``): CONTACT's own S1002 wheel (UIC60
rail) from its examples folder (:func:`rollerrig.contact.cntc_profiles.example_profile`)."""


def profile_files(wheel: str | None, rail: str | None) -> tuple[Path, Path] | None:
    """The two profile files, or None when neither option is given; one error line otherwise."""
    if wheel is None and rail is None:
        return None
    if wheel is None or rail is None:
        raise UserError(
            "--wheel-profile and --rail-profile go together: the wheel's cross-section and the "
            "rail's (the roller's running surface is the rail profile turned about its axle); "
            f"'{EXAMPLE}' takes CONTACT's own S1002 and UIC60"
        )
    from rollerrig.contact.cntc import ContactNotAvailable
    from rollerrig.contact.cntc_profiles import EXAMPLE_RAIL, EXAMPLE_WHEEL, example_profile

    try:
        w = example_profile(EXAMPLE_WHEEL) if wheel == EXAMPLE else Path(wheel)
        r = example_profile(EXAMPLE_RAIL) if rail == EXAMPLE else Path(rail)
    except ContactNotAvailable as exc:
        raise UserError(str(exc)) from None
    for option, path in (("--wheel-profile", w), ("--rail-profile", r)):
        if not path.is_file():
            raise UserError(f"{option}: no such file {str(path)!r}")
    return w, r


def run_profiles(
    files: tuple[Path, Path],
    *,
    load: float,
    wheel_radius: float,
    roller_radius: float,
    friction: float,
    shear_modulus: float,
    poisson: float,
    hertz_factor,
) -> dict:
    """Solve both bodies at :data:`PROFILE_CREEPAGES`, print the table, return the summary.

    ``hertz_factor(xi)`` gives the command's Hertzian factor F_rail/F_roller at Kalker
    creepages ``xi`` (same load, the chosen creep law), for the comparison.
    """
    from rollerrig._validation import ParameterError
    from rollerrig.contact.cntc import ContactNotAvailable
    from rollerrig.contact.cntc_profiles import profile_transfer_factor

    xi = np.asarray(PROFILE_CREEPAGES, dtype=float)
    common = dict(
        wheel_profile=files[0],
        rail_profile=files[1],
        normal_load=load,
        wheel_radius=wheel_radius,
        friction=friction,
        shear_modulus=shear_modulus,
        poisson=poisson,
    )
    solved = []
    try:
        with steps("CONTACT on the profiles") as say:
            for k, x in enumerate(xi):
                say(f"xi = ±{x:g} ({k + 1} of {xi.size}): tangent rail and roller")
                solved.append(profile_transfer_factor([x], roller_radius=roller_radius, **common))
    except ContactNotAvailable as exc:
        raise UserError(str(exc)) from None
    except (ParameterError, RuntimeError) as exc:
        raise UserError(f"CONTACT on the profiles: {exc}") from None

    def first(values) -> float:
        return float(np.ravel(values)[0])

    rail = np.array([first(t.rail_fx_odd) for t in solved])
    roller = np.array([first(t.roller_fx_odd) for t in solved])
    # the normal force is even in ξ: the mean of the two solutions
    n_rail = np.array([(first(t.rail.normal_force) + first(t.rail_reversed.normal_force)) / 2
                       for t in solved])  # fmt: skip
    n_roller = np.array([(first(t.roller.normal_force) + first(t.roller_reversed.normal_force))
                         / 2 for t in solved])  # fmt: skip
    factor = np.array([first(t.factor) for t in solved])
    hertz = np.asarray(hertz_factor(xi), dtype=float)
    table = Table(
        title=f"Wheel and rail profiles by CONTACT (exact theory, μ {friction:g}, "
        f"{load / 1e3:g} kN): {files[0].name} on {files[1].name}",
        title_justify="left",
    )
    heads = ("ξ [-]", "F/(μN) rail", "F/(μN) roller", "factor rail/roller", "Hertz, rig radii")
    for head in heads:
        table.add_column(head, justify="right")
    for row in zip(xi, rail / (friction * n_rail), roller / (friction * n_roller), factor, hertz,
                   strict=True):  # fmt: skip
        table.add_row(*(f"{v:.4g}" for v in row))
    console.print(table)
    return {
        "what": "a wheel profile on a rail profile, straight and as the rig's roller, by "
        "CONTACT's module 1 (Kalker's exact theory, non-Hertzian, Coulomb friction)",
        "wheel_profile": str(files[0]),
        "rail_profile": str(files[1]),
        "friction [-]": friction,
        "long_creep [-]": xi.tolist(),
        "fx_odd_part": "F_x(xi) - F_x(-xi), halved: the force of the creepage without the "
        "spin's push, which does not change sign with xi",
        "fx_rail [N]": rail.tolist(),
        "fx_roller [N]": roller.tolist(),
        "factor_rail_over_roller [-]": factor.tolist(),
        "hertz_factor_rail_over_roller [-]": hertz.tolist(),
        "hertz_note": "the Hertzian factor of the command's creep law on the rig file's radii "
        "(not the profiles' curvatures): a comparison, not a check",
        "tangent_rail": [[t.rail.to_dict(), t.rail_reversed.to_dict()] for t in solved],
        "roller": [[t.roller.to_dict(), t.roller_reversed.to_dict()] for t in solved],
    }
