"""Rebuild the CONTACT reference data of tests/contact/test_cntc.py from a live CONTACT.

    CONTACT_DIR=/path/to/contact python tools/contact_reference.py [--out tests/contact/data]

CONTACT (E.A.H. Vollebregt, Vtech CMCC; Apache-2.0; github.com/eve70a/CONTACT) is called through
rollerrig's backend :mod:`rollerrig.contact.cntc`; build it with ``tools/build_contact.sh``. Only
CONTACT's *outputs* are recorded, in SI units and with the package's sign (that of the
creepage). Two files:

``cntc_fastsim_rig.json``
    CONTACT's FASTSIM (M = 3, k0 = α∞ = 1, parabolic bound B = 3, Coulomb friction) on the
    default rig's wheel-on-roller ellipse, CONTACT's 48 x 44 grid: longitudinal, lateral, pure
    spin and lateral-with-spin sweeps.
``cntc_exact_rig.json``
    Kalker's exact theory (M = 0, B = 0, Coulomb friction) on the default rig's wheel-on-roller
    and wheel-on-tangent-rail ellipses at the same load (``rollerrig contact``'s defaults:
    10 kN, the rig's radii, the roller's crown for the rail), a longitudinal sweep on two grids
    (32 x 32 and 64 x 64 elements of the potential contact, scale 1.1) and their first-order
    extrapolation 2 F_64 - F_32: CONTACT's exact initial slope converges as 1/n (at 48 x 48 it
    is about 1.5 % below Kalker's C11), and the laws are compared with the extrapolated values.

Takes about 5 minutes on one core.
"""

from __future__ import annotations

import argparse
import datetime
import json
import re
import subprocess
from pathlib import Path

import numpy as np

from rollerrig.contact.cntc import contact_dir, contact_version, exact_creep_force
from rollerrig.contact.hertz import combined_elastic_constants, hertz_contact
from rollerrig.contact.laws import EUROSPRINTER_COULOMB
from rollerrig.rig.parameters import default_rig

HERE = Path(__file__).resolve().parent
LOAD = 10e3  # N, `rollerrig contact --load-kn` default
SPEED = 30 / 3.6  # m/s, `rollerrig contact --speed-kmh` default (steady rolling: no effect)
MU = EUROSPRINTER_COULOMB.static_friction  # Coulomb 0.33, as CONTACT's tractcurv.inp series 1
FASTSIM_GRID = (48, 44)
EXACT_GRIDS = ((32, 32), (64, 64))
SCALE = 1.1
# longitudinal creepage of the exact sweep: the creep curve through saturation (about 4e-3)
EXACT_CREEP = [1e-5, 2.5e-4, 5e-4, 7.5e-4, 1e-3, 1.5e-3, 2e-3, 2.5e-3, 3e-3, 4e-3, 6e-3, 1e-2]
SWEEP = [1e-5, 2e-4, 5e-4, 1e-3, 1.5e-3, 2e-3, 3e-3, 4e-3, 6e-3, 1e-2]
SPIN = [0.05, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0]  # 1/m


def provenance() -> dict:
    """Where the CONTACT results come from: commit, revision, interface version, build."""
    root = contact_dir()
    version = (root / "src" / "VERSION").read_text() if (root / "src" / "VERSION").is_file() else ""
    revision = re.search(r"\$Revision: (\d+) \$", version)
    commit_file = root / "contact_commit.txt"
    try:
        compiler = subprocess.run(
            ["gfortran", "--version"], capture_output=True, text=True, check=True
        ).stdout.splitlines()[0]
    except (OSError, subprocess.CalledProcessError):
        compiler = "unknown"
    return {
        "program": "CONTACT, E.A.H. Vollebregt (Vtech CMCC), Apache-2.0, github.com/eve70a/CONTACT",
        "commit": commit_file.read_text().strip() if commit_file.is_file() else "unknown",
        "revision": int(revision.group(1)) if revision else None,
        "interface_version": contact_version(),
        "build": f"tools/build_contact.sh ({compiler}, -O2, no MKL)",
        "called_through": "rollerrig.contact.cntc.exact_creep_force (CONTACT's python_intfc)",
    }


def rig_input() -> dict:
    """The default rig's two ellipses at LOAD and the combined elastic constants."""
    rig = default_rig()
    g, m = rig.geometry, rig.material
    el = combined_elastic_constants(m.youngs_modulus, m.poisson, m.youngs_modulus, m.poisson)
    out = {
        "normal_load_N": LOAD,
        "rolling_speed_m_s": SPEED,
        "friction": MU,
        "youngs_modulus_Pa": m.youngs_modulus,
        "poisson_material": m.poisson,
        "shear_modulus_Pa": float(el.shear_modulus),
        "poisson": float(el.poisson),
        "wheel_radius_x_m": g.wheel_radius_x,
        "wheel_radius_y_m": g.wheel_radius_y,
        "roller_radius_x_m": g.roller_radius_x,
        "roller_radius_y_m": g.roller_radius_y,
        "contacts": {},
    }
    for where, rx in (("roller", g.roller_radius_x), ("tangent_rail", np.inf)):
        c = hertz_contact(
            LOAD,
            g.wheel_radius_x,
            g.wheel_radius_y,
            rx,
            g.roller_radius_y,
            youngs_modulus=m.youngs_modulus,
            poisson=m.poisson,
        )
        out["contacts"][where] = {
            "semi_axis_x_m": float(c.semi_axis_x),
            "semi_axis_y_m": float(c.semi_axis_y),
        }
    return out


def _common(inp: dict, where: str) -> dict:
    c = inp["contacts"][where]
    return dict(
        semi_axis_x=c["semi_axis_x_m"],
        semi_axis_y=c["semi_axis_y_m"],
        normal_load=inp["normal_load_N"],
        shear_modulus=inp["shear_modulus_Pa"],
        poisson=inp["poisson"],
        friction=inp["friction"],
        rolling_speed=inp["rolling_speed_m_s"],
        scale=SCALE,
    )


def fastsim_reference(inp: dict) -> dict:
    """CONTACT's FASTSIM on the roller's ellipse, four sweeps."""
    kw = _common(inp, "roller")
    zero = [0.0] * len(SWEEP)
    sweeps = {
        "longitudinal": (SWEEP, zero, zero),
        "lateral": (zero, SWEEP, zero),
        "spin": ([0.0] * len(SPIN), [0.0] * len(SPIN), SPIN),
        "lateral_with_spin": (zero, SWEEP, [2.0] * len(SWEEP)),
    }
    series = {}
    for name, (xi, eta, phi) in sweeps.items():
        fx, fy, mz = exact_creep_force(xi, eta, phi, **kw, grid=FASTSIM_GRID, theory="fastsim")
        series[name] = {
            "long_creep": list(xi),
            "lat_creep": list(eta),
            "spin_1_m": list(phi),
            "fx_N": fx.tolist(),
            "fy_N": fy.tolist(),
            "mz_N_m": mz.tolist(),
        }
    return {
        "input": {**inp, "contact": "roller", "grid_mx_my": FASTSIM_GRID, "scale": SCALE},
        "theory": "CONTACT's FASTSIM: M=3 (k0=alpha_inf=beta=1), B=3 parabolic bound, Coulomb",
        "series": series,
    }


def exact_reference(inp: dict) -> dict:
    """Kalker's exact theory on both ellipses, two grids and their extrapolation."""
    out = {}
    for where in ("roller", "tangent_rail"):
        kw = _common(inp, where)
        got = {}
        for grid in EXACT_GRIDS:
            fx, _, _ = exact_creep_force(EXACT_CREEP, **kw, grid=grid)
            got[f"fx_N_{grid[0]}x{grid[1]}"] = fx.tolist()
        coarse, fine = (np.array(v) for v in got.values())
        out[where] = {**got, "fx_N_extrapolated": (2.0 * fine - coarse).tolist()}
    return {
        "input": {**inp, "grids_mx_my": EXACT_GRIDS, "scale": SCALE},
        "theory": "Kalker's exact theory: M=0, B=0, steady rolling T=3, Coulomb (L=0)",
        "extrapolation": "F = 2 F(64x64) - F(32x32) (first order in the element size)",
        "long_creep": EXACT_CREEP,
        "contacts": out,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=HERE.parent / "tests" / "contact" / "data")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    inp = rig_input()
    made = {
        "contact": provenance(),
        "made_by": "tools/contact_reference.py",
        "date": datetime.date.today().isoformat(),
    }
    builders = {"cntc_fastsim_rig": fastsim_reference, "cntc_exact_rig": exact_reference}
    for name, build in builders.items():
        record = {**made, **build(inp)}
        path = args.out / f"{name}.json"
        path.write_text(json.dumps(record, indent=1) + "\n")
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
