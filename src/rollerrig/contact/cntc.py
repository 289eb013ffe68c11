"""Optional backend: Kalker's exact theory through CONTACT's own Python interface.

CONTACT (E.A.H. Vollebregt, Vtech CMCC; Apache-2.0; https://github.com/eve70a/CONTACT) solves
the rolling contact problem by Kalker's exact (half-space) theory, also for non-Hertzian
profiles. rollerrig never ships it: a user who has built it points ``CONTACT_DIR`` (or
``CONTACTDIR``, the name CONTACT's own examples read) at the installation folder, the one that
holds ``python_intfc/`` and ``bin/`` with the compiled library, and rollerrig calls the library
through that package. Without it, :func:`load_contact` raises :class:`ContactNotAvailable` with
one message saying how to get it.

Units: rollerrig is SI; CONTACT's default convention is mm, N, N/mm², and forces on body 1
(the wheel), opposite in sign to the creepage. :func:`exact_creep_force` converts both ways and
returns forces with the sign of the creepage, as the rest of the package.

How it was checked: against CONTACT commit d431cdb (2025-07-23, revision 2707, interface
version 2520) built with gfortran 12 by ``tools/build_contact.sh`` of rollerrig's source
repository; that build reproduces the total forces of CONTACT's own ``examples/*.ref_out`` to the
printed digits, and ``tools/contact_reference.py`` records, through this module, the CONTACT
results that ``tests/contact/test_cntc.py`` checks the package's laws against.
"""

from __future__ import annotations

import contextlib
import importlib
import io
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

from rollerrig._validation import (
    ParameterError,
    require_finite,
    require_in_range,
    require_positive,
)

__all__ = [
    "ContactNotAvailable",
    "contact_dir",
    "contact_version",
    "exact_creep_force",
    "load_contact",
]

_ENV = ("CONTACT_DIR", "CONTACTDIR")
_HOW = (
    "CONTACT (Vollebregt's implementation of Kalker's exact theory, Apache-2.0) is not "
    "available. rollerrig does not ship it: build it from https://github.com/eve70a/CONTACT "
    "(with gfortran: tools/build_contact.sh in rollerrig's source repository), then set "
    "CONTACT_DIR to the folder that holds its python_intfc/ and bin/ (e.g. export "
    "CONTACT_DIR=$HOME/contact). The built-in laws need nothing: --law fastsim, "
    "modified-fastsim, fastrip or polach."
)
_LIBRARY = "contact_addon_linux64.so" if sys.platform.startswith("linux") else "contact_addon_*"
_THEORIES = ("exact", "fastsim")
_state: dict = {}


class ContactNotAvailable(RuntimeError):
    """CONTACT is not installed where ``CONTACT_DIR`` points (or that variable is unset)."""


def contact_dir() -> Path | None:
    """The CONTACT installation folder named by ``CONTACT_DIR`` (or ``CONTACTDIR``), if any.

    Examples
    --------
    >>> isinstance(contact_dir(), (Path, type(None)))
    True
    """
    for name in _ENV:
        value = os.environ.get(name, "").strip()
        if value:
            return Path(value).expanduser()
    return None


def load_contact():
    """Import CONTACT's ``python_intfc`` package from ``CONTACT_DIR``.

    CONTACT's package prints on import, reads ``LD_LIBRARY_PATH`` (failing when it is unset)
    and exits the interpreter when its library is missing; here its prints are captured, the
    variable is set to empty for the import only when absent, ``CONTACT_DIR`` is on
    ``sys.path`` for the import only, and every failure becomes :class:`ContactNotAvailable`.
    One process loads one CONTACT.

    Returns
    -------
    module
        CONTACT's ``python_intfc`` (which loads the compiled library on import).

    Raises
    ------
    ContactNotAvailable
        If ``CONTACT_DIR`` is unset, or holds no ``python_intfc/`` or no library in ``bin/``,
        or the library does not load; the message says how to get CONTACT.
    """
    root = contact_dir()
    if root is None:
        raise ContactNotAvailable(f"CONTACT_DIR is not set. {_HOW}")
    if not (root / "python_intfc" / "__init__.py").is_file():
        raise ContactNotAvailable(f"CONTACT_DIR={root} holds no python_intfc/. {_HOW}")
    if not any((root / "bin").glob(_LIBRARY)):
        raise ContactNotAvailable(f"CONTACT_DIR={root} holds no compiled library in bin/. {_HOW}")
    loaded = sys.modules.get("python_intfc")
    if loaded is not None:
        if Path(loaded.__file__).resolve().parent.parent == root.resolve():
            return loaded
        raise ContactNotAvailable(
            f"CONTACT was loaded from {Path(loaded.__file__).parent.parent} in this process; "
            f"it cannot be reloaded from CONTACT_DIR={root}. {_HOW}"
        )
    unset = "LD_LIBRARY_PATH" not in os.environ
    printed = io.StringIO()
    sys.path.insert(0, str(root))  # for the import only: its package imports itself by name
    try:
        if unset:
            os.environ["LD_LIBRARY_PATH"] = ""
        with contextlib.redirect_stdout(printed):
            return importlib.import_module("python_intfc")
    except (ImportError, OSError, SystemExit, KeyError, AttributeError) as exc:
        for name in [n for n in sys.modules if n.split(".")[0] == "python_intfc"]:
            if str(getattr(sys.modules[name], "__file__", "")).startswith(str(root)):
                del sys.modules[name]  # this failed import's, not another CONTACT's
        said = " ".join(printed.getvalue().split())
        raise ContactNotAvailable(
            f"CONTACT at {root} could not be loaded ({exc!r}; it said: {said or 'nothing'}). {_HOW}"
        ) from exc
    finally:
        sys.path.remove(str(root))
        if unset:
            os.environ.pop("LD_LIBRARY_PATH", None)


def _library():
    """CONTACT's package and its magic numbers, the library initialised once per process.

    CONTACT writes its log ``contact_addon.out`` into a temporary folder of its own.
    """
    cntc = load_contact()
    if _state.get("module") is not cntc:
        outdir = tempfile.mkdtemp(prefix="rollerrig-contact-") + os.sep
        with contextlib.redirect_stdout(io.StringIO()):
            table, version, ierror = cntc.initlibrary(" ", outdir, " ", 0)
        if ierror:
            raise ContactNotAvailable(f"CONTACT's initlibrary failed (ierror = {ierror}). {_HOW}")
        # One thread per contact patch: with OpenMP threads the gfortran build's module-1 solver
        # returned NaN (Brent's iteration aborted, ierror -26) in some processes and not in
        # others, for the same case; sequential it is deterministic (CONTACT's own test_memory
        # and test_caddon set the same).
        cntc.setglobalflags([table["if_idebug"], table["if_openmp"]], [0, 1])
        _state.update(module=cntc, table=table, version=version, outdir=outdir)
    return cntc, _state["table"]


def contact_version() -> int:
    """The interface version of the CONTACT library loaded (e.g. 2520 for CONTACT 25.2).

    Raises
    ------
    ContactNotAvailable
        Without CONTACT (see :func:`load_contact`).
    """
    _library()
    return int(_state["version"])


def exact_creep_force(
    long_creep,
    lat_creep=0.0,
    spin=0.0,
    *,
    semi_axis_x,
    semi_axis_y,
    normal_load,
    shear_modulus,
    poisson,
    friction,
    rolling_speed=10.0,
    grid=(48, 44),
    scale=1.1,
    theory="exact",
):
    """Creep forces by Kalker's exact theory, computed by CONTACT (steady rolling, Hertzian).

    CONTACT's module 3 (basic contact): a Hertzian ellipse with prescribed semi-axes
    (``IPOTCN = -3``) and normal force (N = 1), steady rolling (T = 3), Coulomb friction
    (L = 0, μ_stat = μ_kin = μ), elastic half-spaces of one material (M = 0). With
    ``theory="fastsim"`` CONTACT's own FASTSIM instead (M = 3 with k0 = α∞ = β = 1, i.e. not
    modified; parabolic traction bound B = 3; CONTACT blends the three flexibilities towards one
    at larger creepage, see :func:`rollerrig.contact.fastsim.blended_flexibilities`).

    Parameters
    ----------
    long_creep, lat_creep : array_like
        ξ, η [-], broadcast.
    spin : array_like
        φ [1/m].
    semi_axis_x, semi_axis_y : float
        a (rolling direction), b [m].
    normal_load : float
        N [N].
    shear_modulus : float
        G [Pa].
    poisson : float
        ν [-], in [0, 0.5].
    friction : float
        Coulomb μ [-].
    rolling_speed : float
        V [m/s] (steady rolling: the forces do not depend on it).
    grid : (int, int)
        CONTACT's MX, MY: elements of the potential contact along x and y.
    scale : float
        Potential contact / ellipse [-].
    theory : {"exact", "fastsim"}
        Kalker's exact theory, or CONTACT's FASTSIM on the same grid.

    Returns
    -------
    tuple of ndarray
        (F_x [N], F_y [N], M_z [N m]), sign of the creepage; M_z = ∫(x p_y - y p_x) dA.

    Raises
    ------
    ContactNotAvailable
        Without CONTACT (see :func:`load_contact`).
    ParameterError
        For a non-physical input, or an unknown ``theory``.
    RuntimeError
        If CONTACT reports an error for a case.
    """
    if theory not in _THEORIES:
        raise ParameterError(f"theory must be one of {_THEORIES}, got {theory!r}")
    xi, eta, phi = np.broadcast_arrays(
        require_finite("long_creep", long_creep, "-"),
        require_finite("lat_creep", lat_creep, "-"),
        require_finite("spin", spin, "1/m"),
    )
    a = require_positive("semi_axis_x", semi_axis_x, "m", single=True) * 1e3  # mm
    b = require_positive("semi_axis_y", semi_axis_y, "m", single=True) * 1e3
    fn = require_positive("normal_load", normal_load, "N", single=True)
    gg = require_positive("shear_modulus", shear_modulus, "Pa", single=True) * 1e-6  # N/mm²
    # [0, 0.5] as hertz_contact and kalker_coefficients (ν = 0 had been refused as not > 0,
    # and ν > 0.5, a negative bulk modulus, passed on to CONTACT).
    nu = require_in_range(
        "poisson", poisson, 0.0, 0.5, "-", low_inclusive=True, high_inclusive=True, single=True
    )
    mu = require_positive("friction", friction, "-", single=True)
    veloc = require_positive("rolling_speed", rolling_speed, "m/s", single=True) * 1e3  # mm/s
    mx, my = (int(require_positive("grid", n, "-")) for n in grid)
    s = require_positive("scale", scale, "-", single=True)
    cntc, ctab = _library()
    ire, icp = 1, 1
    cntc.initialize(ire, 3, _state["outdir"], 0)  # module 3: basic contact
    try:
        keys = ("if_units", "if_wrtinp", "ic_matfil", "ic_output", "ic_flow", "ic_norm",
                "ic_tang", "ic_pvtime", "ic_bound")  # fmt: skip
        values = (ctab["un_cntc"], 0, 0, 0, 0, 1, 3, 2, 3 if theory == "fastsim" else 0)
        cntc.setflags(
            ire, icp, np.array([ctab[k] for k in keys], np.intc), np.array(values, np.intc)
        )
        if theory == "fastsim":
            cntc.setmaterialparameters(ire, icp, 3, [nu, nu, gg, gg, 1.0, 1.0, 1.0])
        else:
            cntc.setmaterialparameters(ire, icp, 0, [nu, nu, gg, gg])
        cntc.sethertzcontact(ire, icp, -3, [mx, my, a, b, s])
        cntc.setreferencevelocity(ire, icp, veloc)
        cntc.setnormalforce(ire, icp, fn)
        cntc.setfrictionmethod(ire, icp, 0, [mu, mu])
        out = np.zeros((xi.size, 3))
        for i, (x, e, p) in enumerate(zip(xi.ravel(), eta.ravel(), phi.ravel(), strict=True)):
            cntc.setcreepages(ire, icp, float(x), float(e), float(p) * 1e-3)  # rad/mm
            ierror = cntc.calculate(ire, icp, 0)
            if ierror:
                raise RuntimeError(
                    f"CONTACT's calculate failed (ierror = {ierror}) at creepages "
                    f"({x:g}, {e:g}, {p:g} 1/m)"
                )
            _, fx, fy, mz = cntc.getcontactforces(ire, icp)
            out[i] = (-fx, -fy, -mz * 1e-3)  # on body 1, N mm -> sign of the creepage, N m
    finally:
        cntc.finalize(ire)
    shape = xi.shape
    return tuple(out[:, k].reshape(shape) for k in range(3))
