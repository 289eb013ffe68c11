"""Small frames built as frame-file dictionaries, for the frame tests."""

from __future__ import annotations

import copy

import pytest

E = 210e9  # [Pa]
NU = 0.3
RHO = 7850.0  # [kg/m^3]

# A section given by its properties (IPE 200's values, ArcelorMittal): A [cm^2], I [cm^4].
IPE200 = {
    "area": {"value": 28.48, "unit": "cm^2", "source": "IPE 200"},
    "second_moment_strong": {"value": 1943.0, "unit": "cm^4", "source": "IPE 200"},
    "second_moment_weak": {"value": 142.4, "unit": "cm^4", "source": "IPE 200"},
    "torsion_constant": {"value": 6.98, "unit": "cm^4", "source": "IPE 200"},
    "depth": {"value": 200.0, "unit": "mm", "source": "IPE 200"},
    "width": {"value": 100.0, "unit": "mm", "source": "IPE 200"},
}


def node(x, y, z):
    return {"value": [float(x), float(y), float(z)], "unit": "m", "assumption": "test"}


def frame_dict(
    nodes,
    members,
    supports,
    load_points,
    *,
    sections=None,
    gauges=None,
    masses=None,
    density=RHO,
    output=None,
):
    """A frame file as a dict: nodes {name: (x, y, z)}, members {name: (start, end[, section,
    web])}, supports {node: kind}, load_points {name: (node, normal, traction)}."""
    data = {
        "meta": {"name": "test-frame", "description": "test"},
        "materials": {
            "steel": {
                "youngs_modulus": {"value": E, "unit": "Pa", "source": "test"},
                "poisson": {"value": NU, "unit": "1", "source": "test"},
                "density": {"value": density, "unit": "kg/m^3", "source": "test"},
            }
        },
        "sections": copy.deepcopy(sections) if sections else {"ipe": copy.deepcopy(IPE200)},
        "nodes": {n: node(*p) for n, p in nodes.items()},
        "members": {},
        "supports": dict(supports),
        "load_points": {},
    }
    first = next(iter(data["sections"]))
    for name, spec in members.items():
        start, end, *rest = spec
        m = {"nodes": [start, end], "section": rest[0] if rest and rest[0] else first}
        if len(rest) > 1:
            m["web"] = list(rest[1])
        data["members"][name] = m
    for name, (n, normal, traction) in load_points.items():
        data["load_points"][name] = {
            "node": n,
            "normal": list(normal),
            "traction": list(traction),
            "assumption": "test",
        }
    if gauges:
        data["strain_gauges"] = {
            name: {
                "member": m,
                "position": {"value": float(pos), "unit": "m", "assumption": "test"},
                "fibre": fibre,
                "assumption": "test",
            }
            for name, (m, pos, fibre) in gauges.items()
        }
    if masses:
        data["masses"] = {
            name: {"node": n, "mass": {"value": float(mass), "unit": "kg", "assumption": "test"}}
            for name, (n, mass) in masses.items()
        }
    if output:
        data["output"] = output
    return data


@pytest.fixture
def make_frame():
    from rollerrig.frame import frame_from_dict

    def make(*args, **kw):
        return frame_from_dict(frame_dict(*args, **kw), "test.toml")

    return make
