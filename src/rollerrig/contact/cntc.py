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
"""

from __future__ import annotations

import importlib
import os
import sys
from pathlib import Path

import numpy as np

from rollerrig._validation import require_finite, require_positive

__all__ = ["ContactNotAvailable", "contact_dir", "exact_creep_force", "load_contact"]

_ENV = ("CONTACT_DIR", "CONTACTDIR")
_HOW = (
    "CONTACT (Vollebregt's implementation of Kalker's exact theory, Apache-2.0) is not "
    "available. rollerrig does not ship it: build it from https://github.com/eve70a/CONTACT "
    "(gfortran; see its doc/getting-started.pdf), then set CONTACT_DIR to the folder that "
    "holds its python_intfc/ and bin/ (e.g. export CONTACT_DIR=$HOME/contact). The built-in "
    "laws need nothing: --law fastsim, modified-fastsim, fastrip or polach."
)


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

    Returns
    -------
    module
        CONTACT's ``python_intfc`` (which loads the compiled library on import).

    Raises
    ------
    ContactNotAvailable
        If ``CONTACT_DIR`` is unset, or holds no ``python_intfc/`` or no library in ``bin/``;
        the message says how to get CONTACT.
    """
    root = contact_dir()
    if root is None:
        raise ContactNotAvailable(f"CONTACT_DIR is not set. {_HOW}")
    if not (root / "python_intfc" / "__init__.py").is_file():
        raise ContactNotAvailable(f"CONTACT_DIR={root} holds no python_intfc/. {_HOW}")
    if not any((root / "bin").glob("contact_addon*")):
        raise ContactNotAvailable(f"CONTACT_DIR={root} holds no compiled library in bin/. {_HOW}")
    if str(root) not in sys.path:
        sys.path.append(str(root))
    try:
        return importlib.import_module("python_intfc")
    except (ImportError, OSError, SystemExit) as exc:
        raise ContactNotAvailable(f"CONTACT at {root} could not be loaded ({exc}). {_HOW}") from exc


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
):
    """Creep forces by Kalker's exact theory, computed by CONTACT (steady rolling, Hertzian).

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
        ν [-].
    friction : float
        Coulomb μ [-].
    rolling_speed : float
        V [m/s].
    grid : (int, int)
        CONTACT's MX, MY.
    scale : float
        Potential contact / ellipse [-].

    Returns
    -------
    tuple of ndarray
        (F_x [N], F_y [N], M_z [N m]), sign of the creepage.

    Raises
    ------
    ContactNotAvailable
        Without CONTACT (see :func:`load_contact`).
    """
    xi, eta, phi = np.broadcast_arrays(
        require_finite("long_creep", long_creep, "-"),
        require_finite("lat_creep", lat_creep, "-"),
        require_finite("spin", spin, "1/m"),
    )
    a = float(require_positive("semi_axis_x", semi_axis_x, "m")) * 1e3
    b = float(require_positive("semi_axis_y", semi_axis_y, "m")) * 1e3
    fn = float(require_positive("normal_load", normal_load, "N"))
    gg = float(require_positive("shear_modulus", shear_modulus, "Pa")) * 1e-6
    mu = float(require_positive("friction", friction, "-"))
    veloc = float(require_positive("rolling_speed", rolling_speed, "m/s")) * 1e3
    cntc = load_contact()
    ctab, _, ierror = cntc.initlibrary(" ", " ", " ", 0)
    if ierror:
        raise ContactNotAvailable(f"CONTACT's initlibrary failed (ierror = {ierror}). {_HOW}")
    ire, icp = 1, 1
    cntc.initialize(ire, 3)  # module 3: basic contact
    keys = ("if_units", "if_wrtinp", "ic_matfil", "ic_output", "ic_norm", "ic_tang", "ic_pvtime")
    flags = np.array([ctab[k] for k in keys], dtype=np.intc)
    values = np.array([ctab["un_cntc"], 0, 0, 0, 1, 3, 2], dtype=np.intc)
    cntc.setflags(ire, icp, flags, values)
    cntc.setmaterialparameters(ire, icp, 0, [poisson, poisson, gg, gg])
    cntc.sethertzcontact(ire, icp, -3, [grid[0], grid[1], a, b, scale])
    cntc.setreferencevelocity(ire, icp, veloc)
    cntc.setnormalforce(ire, icp, fn)
    cntc.setfrictionmethod(ire, icp, 0, [mu, mu])
    out = np.zeros((xi.size, 3))
    try:
        for i, (x, e, p) in enumerate(zip(xi.ravel(), eta.ravel(), phi.ravel(), strict=True)):
            cntc.setcreepages(ire, icp, float(x), float(e), float(p) * 1e-3)
            ierror = cntc.calculate(ire, icp)
            if ierror:
                raise RuntimeError(f"CONTACT's calculate failed (ierror = {ierror})")
            _, fx, fy, mz = cntc.getcontactforces(ire, icp)
            out[i] = (-fx, -fy, -mz * 1e-3)  # body 1, N mm -> sign of the creepage, N m
    finally:
        cntc.finalize(ire)
    shape = xi.shape
    return tuple(out[:, k].reshape(shape) for k in range(3))
