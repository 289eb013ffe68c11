"""Rebuild tests/contact/data/cntc_profiles_rig.json from a live CONTACT (module 1, profiles).

    CONTACT_DIR=/path/to/contact CONTACT_SOURCE=/path/to/CONTACT-checkout \\
        python tools/contact_profiles_reference.py [--out tests/contact/data]

CONTACT (E.A.H. Vollebregt, Vtech CMCC; Apache-2.0; github.com/eve70a/CONTACT), built by
``tools/build_contact.sh``, is called through :mod:`rollerrig.contact.cntc_profiles`. The wheel
and rail profiles are the ones CONTACT's own examples ship (S1002 wheel
``MBench_S1002_v3.prw``, UIC60 rail ``MBench_UIC60_v3.prr``), read from ``$CONTACT_DIR/examples``
or ``$CONTACT_SOURCE/examples``; only their names and SHA-256 are recorded, and CONTACT's
*outputs* (SI, the package's sign). Inputs: the default rig's wheel radius (348 mm) and roller
radius (452 mm), 10 kN vertical force, Coulomb μ = 0.33, the rig's material; the wheelset centred
(y_ws = 0).

Series:

``sweep``
    ξ from 1e-5 to 1e-2 on the tangent rail and on the roller, elements of 0.2 mm.
``slope``
    ξ = ±1e-4 on both, elements of 0.2 mm and 0.1 mm: the creep stiffness as the central
    difference (F(+ξ) - F(-ξ)) / 2ξ, which removes the force the spin makes on a patch that is
    not symmetric across the rolling direction, and its first-order extrapolation in the element
    size, 2 S(0.1 mm) - S(0.2 mm).
``lateral``
    ξ = 1e-3 at y_ws = 0, 3, 6 mm on both (patch count and position move with the wheelset).

Takes about 4 minutes on one core.
"""

from __future__ import annotations

import argparse
import datetime
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from contact_reference import provenance  # noqa: E402 (the same CONTACT provenance)

from rollerrig.contact.cntc_profiles import (  # noqa: E402
    EXAMPLE_RAIL,
    EXAMPLE_WHEEL,
    example_profile,
    profile_creep_force,
)
from rollerrig.contact.hertz import combined_elastic_constants  # noqa: E402
from rollerrig.output import file_sha256, write_json  # noqa: E402
from rollerrig.rig.parameters import default_rig  # noqa: E402

LOAD = 10e3  # N, `rollerrig contact --load-kn` default
MU = 0.33  # Coulomb, as tools/contact_reference.py
SPEED = 30 / 3.6  # m/s (steady rolling: no effect)
SWEEP = [1e-5, 2.5e-4, 5e-4, 1e-3, 1.5e-3, 2e-3, 3e-3, 4e-3, 6e-3, 1e-2]
SLOPE_CREEP = 1e-4
ELEMENTS = (0.2e-3, 0.1e-3)  # m
LATERAL = [0.0, 3e-3, 6e-3]  # m
LATERAL_CREEP = 1e-3


def inputs() -> dict:
    rig = default_rig()
    g, m = rig.geometry, rig.material
    el = combined_elastic_constants(m.youngs_modulus, m.poisson, m.youngs_modulus, m.poisson)
    wheel, rail = example_profile(EXAMPLE_WHEEL), example_profile(EXAMPLE_RAIL)
    return {
        "wheel_profile": EXAMPLE_WHEEL,
        "wheel_profile_sha256": file_sha256(wheel),
        "rail_profile": EXAMPLE_RAIL,
        "rail_profile_sha256": file_sha256(rail),
        "profiles_from": "CONTACT's examples/ (S1002 wheel, UIC60 rail), not copied",
        "normal_load_N": LOAD,
        "friction": MU,
        "rolling_speed_m_s": SPEED,
        "wheel_radius_m": g.wheel_radius_x,
        "roller_radius_m": g.roller_radius_x,
        "youngs_modulus_Pa": m.youngs_modulus,
        "poisson_material": m.poisson,
        "shear_modulus_Pa": float(el.shear_modulus),
        "poisson": float(el.poisson),
        "setting": (
            "left wheel, gauge 1435 mm at 14 mm, flange backs 1360 mm, FBPOS -70 mm, cant 0, "
            "Coulomb, steady rolling T=3, vertical force N=1, CONTACT's patch separation defaults"
        ),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=HERE.parent / "tests" / "contact" / "data")
    args = parser.parse_args()
    inp = inputs()
    common = dict(
        wheel_profile=example_profile(EXAMPLE_WHEEL),
        rail_profile=example_profile(EXAMPLE_RAIL),
        normal_load=LOAD,
        wheel_radius=inp["wheel_radius_m"],
        friction=MU,
        shear_modulus=inp["shear_modulus_Pa"],
        poisson=inp["poisson"],
        rolling_speed=SPEED,
    )
    bodies = {"tangent_rail": None, "roller": inp["roller_radius_m"]}
    record = {
        "contact": {
            **provenance(),
            "called_through": (
                "rollerrig.contact.cntc_profiles.profile_creep_force (CONTACT's python_intfc, "
                "module 1)"
            ),
        },
        "made_by": "tools/contact_profiles_reference.py",
        "date": datetime.date.today().isoformat(),
        "input": inp,
        "sweep": {"element_size_m": ELEMENTS[0], "long_creep": SWEEP},
        "slope": {"long_creep": [-SLOPE_CREEP, SLOPE_CREEP], "element_sizes_m": list(ELEMENTS)},
        "lateral": {"long_creep": LATERAL_CREEP, "lateral_position_m": LATERAL},
    }
    for body, rr in bodies.items():
        kw = dict(common, roller_radius=rr)
        record["sweep"][body] = profile_creep_force(SWEEP, **kw, element_size=ELEMENTS[0]).to_dict()
        slopes = []
        for h in ELEMENTS:
            r = profile_creep_force([-SLOPE_CREEP, SLOPE_CREEP], **kw, element_size=h)
            record["slope"][f"{body}_{h * 1e3:g}mm"] = r.to_dict()
            slopes.append(float((r.fx[1] - r.fx[0]) / (r.long_creep[1] - r.long_creep[0])))
        record["slope"][body] = {
            "creep_stiffness_N": slopes,
            "creep_stiffness_N_extrapolated": 2 * slopes[1] - slopes[0],
        }
        record["lateral"][body] = [
            profile_creep_force(LATERAL_CREEP, **kw, lateral_position=y).to_dict() for y in LATERAL
        ]
        print(f"{body}: done", flush=True)
    rail, roller = record["sweep"]["tangent_rail"], record["sweep"]["roller"]
    record["sweep"]["transfer_factor"] = (
        np.array(rail["fx [N]"]) / np.array(roller["fx [N]"])
    ).tolist()
    s = record["slope"]
    record["slope"]["transfer_factor_extrapolated"] = (
        s["tangent_rail"]["creep_stiffness_N_extrapolated"]
        / s["roller"]["creep_stiffness_N_extrapolated"]
    )
    path = write_json(args.out / "cntc_profiles_rig.json", record)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
