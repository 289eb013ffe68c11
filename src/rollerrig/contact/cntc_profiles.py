"""Optional backend: a wheel profile on a tangent rail and on a roller, by CONTACT's module 1.

CONTACT (E.A.H. Vollebregt, Vtech CMCC; Apache-2.0; https://github.com/eve70a/CONTACT) solves
the wheel-rail contact from the wheel's and the rail's cross-section profiles (its module 1):
it locates the contact patches, solves the normal problem for a prescribed vertical force and
the tangential problem by Kalker's exact (half-space) theory, non-Hertzian. It also models a
roller rig (control digit ``C1 = 4``): the rail profile is then turned about the roller axle at
the nominal roller radius ``NOMRADR`` (CONTACT's user guide, "Roller rig configurations" and
"Track and roller geometry"). :func:`profile_creep_force` calls it, through the loading, units
and errors of :mod:`rollerrig.contact.cntc`, for one wheel profile on one rail profile, either
straight (tangent track) or as the running surface of a roller of radius ``roller_radius``;
:func:`profile_transfer_factor` does both at the same load and creepages and returns
F_rail/F_roller of the odd parts (F(ξ) - F(-ξ))/2, the factor that transfers a roller-rig
creep curve to the track (the spin of real profiles pushes F_x one way at either sign of ξ).

Setting (one left wheel, the right's is its mirror): standard-gauge placement by CONTACT's gauge
computation (gauge 1435 mm measured 14 mm below the track plane, flange-back distance 1360 mm,
flange back 70 mm inside the wheel profile's origin, as CONTACT's Manchester-benchmark example),
rail cant 0 (CONTACT ignores cant on rollers: the rail profile as given on both), elastic
half-spaces of one material, Coulomb friction, steady rolling (T = 3), the total vertical force
prescribed (N = 1), the potential contact found by CONTACT on a grid of square elements.

Creepage: module 1 takes the wheelset's velocities, not creepages. CONTACT defines the
longitudinal creepage as ξ = (V_w - V_r)/V_ref with V_ref = (V_w + V_r)/2, so the wheel's
angular velocity for a target ξ is ω = (V_r/r_w)(2 + ξ)/(2 - ξ); V_r/r_w (rolling radii at the
contact point) is measured from each solution and the case solved again until CONTACT's ξ is
within ``1e-3 |ξ| + 1e-8`` of the target (and its η within ``1e-3 |η| + 1e-8``, the lateral
creepage being set by the wheelset's lateral velocity, η = -v_y/V_ref). The spin follows from
the profiles (the contact angle) and is returned, not set.

Units: SI in and out; forces with the sign of the creepage (as the rest of the package),
CONTACT's (on the wheel, opposite) negated.
"""

from __future__ import annotations

import contextlib
import io
import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rollerrig._validation import ParameterError, require_finite, require_positive
from rollerrig.contact.cntc import _HOW, ContactNotAvailable, _library, _state, contact_dir

__all__ = [
    "EXAMPLE_RAIL",
    "EXAMPLE_WHEEL",
    "ProfileContact",
    "ProfileTransfer",
    "example_profile",
    "profile_creep_force",
    "profile_transfer_factor",
]

EXAMPLE_WHEEL = "MBench_S1002_v3.prw"  # S1002 wheel, CONTACT's examples/
EXAMPLE_RAIL = "MBench_UIC60_v3.prr"  # UIC60 rail, CONTACT's examples/
_IRE = 2  # CONTACT's result element for module 1 (cntc.exact_creep_force uses 1)
_GAUGE = (14.0, 0.0, 1435.0)  # GAUGHT, GAUGSQ, GAUGWD [mm]: standard gauge
_WHEELSET = (1360.0, -70.0)  # FBDIST, FBPOS [mm]
_MAX_SOLVES = 5
_NO_SOLUTION = -26  # CONTACT's ierror when its solver aborts (e.g. NaN in Brent's iteration)
_RETRIES = 2  # fresh starts of the result element after _NO_SOLUTION
_CREEP_RTOL, _CREEP_ATOL = 1e-3, 1e-8


@dataclass(frozen=True)
class ProfileContact:
    """Result of :func:`profile_creep_force`; every array has one entry per case.

    Attributes
    ----------
    body : str
        ``"tangent_rail"`` or ``"roller"``.
    long_creep, lat_creep : ndarray
        ξ, η [-] of CONTACT's solution (within the stated tolerance of the request).
    spin : ndarray
        φ [1/m] of CONTACT's solution, from the contact angle (of the largest patch).
    fx, fy : ndarray
        Tangential forces [N] in the contact plane, summed over the patches, with the sign of
        the creepage.
    normal_force : ndarray
        F_n [N], summed over the patches (the prescribed vertical force over cos δ, about).
    n_patches : ndarray of int
        Number of contact patches.
    patch_length_x, patch_width_y : ndarray
        Extent of the largest patch along the rolling direction and across it [m], counted in
        whole elements of size ``element_size`` (its resolution).
    patch_area : ndarray
        Area of the largest patch [m²].
    contact_angle : ndarray
        δ [rad] of the largest patch: track z to the contact normal about x (right-hand rule).
    rail_y : ndarray
        Lateral position of the largest patch's reference point on the rail profile [m].
    solves : ndarray of int
        CONTACT solutions needed to hit the creepage.
    """

    body: str
    long_creep: np.ndarray
    lat_creep: np.ndarray
    spin: np.ndarray
    fx: np.ndarray
    fy: np.ndarray
    normal_force: np.ndarray
    n_patches: np.ndarray
    patch_length_x: np.ndarray
    patch_width_y: np.ndarray
    patch_area: np.ndarray
    contact_angle: np.ndarray
    rail_y: np.ndarray
    solves: np.ndarray

    def to_dict(self) -> dict:
        """JSON-ready, SI, units in the keys."""
        units = {
            "long_creep": "-", "lat_creep": "-", "spin": "1/m", "fx": "N", "fy": "N",
            "normal_force": "N", "n_patches": "-", "patch_length_x": "m", "patch_width_y": "m",
            "patch_area": "m^2", "contact_angle": "rad", "rail_y": "m", "solves": "-",
        }  # fmt: skip
        out = {"body": self.body}
        for name, unit in units.items():
            out[f"{name} [{unit}]"] = np.asarray(getattr(self, name)).tolist()
        return out


@dataclass(frozen=True)
class ProfileTransfer:
    """Result of :func:`profile_transfer_factor`.

    Attributes
    ----------
    rail, roller : ProfileContact
        The wheel on the tangent rail and on the roller at the same load and creepages +ξ.
    rail_reversed, roller_reversed : ProfileContact
        The same at -ξ.
    factor : ndarray
        F_x,rail / F_x,roller [-] at each creepage, of the odd parts
        ``(F_x(ξ) - F_x(-ξ)) / 2`` (see :func:`profile_transfer_factor`).
    """

    rail: ProfileContact
    roller: ProfileContact
    rail_reversed: ProfileContact
    roller_reversed: ProfileContact
    factor: np.ndarray

    @property
    def rail_fx_odd(self) -> np.ndarray:
        """The rail's F_x of the creepage, ``(F_x(ξ) - F_x(-ξ)) / 2`` [N]."""
        return (self.rail.fx - self.rail_reversed.fx) / 2.0

    @property
    def roller_fx_odd(self) -> np.ndarray:
        """The roller's F_x of the creepage, ``(F_x(ξ) - F_x(-ξ)) / 2`` [N]."""
        return (self.roller.fx - self.roller_reversed.fx) / 2.0


def example_profile(name: str) -> Path:
    """One of the profiles CONTACT's own examples ship, e.g. :data:`EXAMPLE_WHEEL` (S1002) or
    :data:`EXAMPLE_RAIL` (UIC60), read where CONTACT is, never copied into rollerrig.

    Looked for in ``$CONTACT_DIR/examples`` and then in ``$CONTACT_SOURCE/examples`` (the
    CONTACT checkout that ``tools/build_contact.sh`` built from).

    Raises
    ------
    ContactNotAvailable
        If neither folder holds ``name``.

    Examples
    --------
    >>> try:
    ...     example_profile(EXAMPLE_WHEEL).suffix
    ... except ContactNotAvailable:
    ...     '.prw'
    '.prw'
    """
    roots = [contact_dir(), os.environ.get("CONTACT_SOURCE", "").strip() or None]
    tried = []
    for root in roots:
        if root is None:
            continue
        path = Path(root).expanduser() / "examples" / name
        tried.append(str(path.parent))
        if path.is_file():
            return path
    where = f"looked in {', '.join(tried)}" if tried else "CONTACT_DIR and CONTACT_SOURCE unset"
    raise ContactNotAvailable(
        f"CONTACT's example profile {name} was not found ({where}); set CONTACT_SOURCE to the "
        f"CONTACT checkout (the folder holding examples/). {_HOW}"
    )


def _profile_file(name: str, value) -> str:
    try:
        path = Path(os.fspath(value)).expanduser().resolve()
    except TypeError:
        raise ParameterError(f"{name} must be a path to a profile file, got {value!r}") from None
    if not path.is_file():
        raise ParameterError(f"{name}: no such file {str(path)!r}")
    if not os.access(path, os.R_OK):
        raise ParameterError(f"{name}: cannot read {str(path)!r}")
    if len(str(path).encode()) > 250:
        raise ParameterError(
            f"{name}: CONTACT takes paths up to 250 bytes, {str(path)!r} is longer"
        )
    return str(path)


def _creep_array(name, value):
    arr = np.asarray(require_finite(name, value, "-"), dtype=float)
    if np.any(np.abs(arr) >= 0.5):
        raise ParameterError(f"{name} must lie in (-0.5, 0.5) [-], got {arr[np.abs(arr) >= 0.5]}")
    return arr


def _configure(cntc, ctab, *, roller_mm, wheel, rail, rw_mm, fz, mu, gg, nu, dx_mm, **_):
    keys = ("if_units", "ic_config", "ic_tang", "ic_pvtime", "ic_norm", "ic_discns",
            "if_wrtinp", "ic_matfil", "ic_output", "ic_flow", "ic_bound")  # fmt: skip
    values = (ctab["un_cntc"], 4 if roller_mm else 0, 3, 2, 1, 2, 0, 0, 0, 0, 0)
    cntc.setflags(_IRE, -1, np.array([ctab[k] for k in keys], np.intc), np.array(values, np.intc))
    cntc.setmaterialparameters(_IRE, -1, 0, [nu, nu, gg, gg])
    cntc.setfrictionmethod(_IRE, -1, 0, [mu, mu])
    cntc.setverticalforce(_IRE, fz)
    # element size along x and along the profile; CONTACT's defaults for separating patches
    cntc.setpotcontact(_IRE, -1, -1, [dx_mm, dx_mm, math.pi / 2, 8.0, 4.0])
    cntc.setrollingstepsize(_IRE, -1, 0.0, 1.0)
    # Z = 3: gauge placement, cant 0, NOMRAD (0 on track), no deviations
    cntc.settrackdimensions(_IRE, 3, [*_GAUGE, 0.0, roller_mm, 0, 0, 0, 0, 0, 0])
    cntc.setprofileinputfname(_IRE, rail, [0, 0, 0, 0, 1], [1.0, 0.0])
    cntc.setwheelsetdimensions(_IRE, 3, [*_WHEELSET, rw_mm])
    cntc.setprofileinputfname(_IRE, wheel, [1, 0, 0, 0, 1], [1.0, 0.0])
    cntc.setwheelsetflexibility(_IRE, 1, np.zeros(12))
    for itype, what, path in ((0, "rail_profile", rail), (1, "wheel_profile", wheel)):
        err = cntc.getprofilevalues(_IRE, -1, [itype, 0], [1.0])
        code = int(np.ravel(err)[0])
        if code != 0:
            raise ParameterError(f"{what}: CONTACT could not read or process {path!r} ({code})")


def _largest_patch(cntc, n):
    best, area = 1, -1.0
    for icp in range(1, n + 1):
        a = float(cntc.getcontactpatchareas(_IRE, icp)[0])
        if a > area:
            best, area = icp, a
    return best, area


_FIELDS = ("long_creep", "lat_creep", "spin", "fx", "fy", "normal_force", "n_patches",
           "patch_length_x", "patch_width_y", "patch_area", "contact_angle", "rail_y",
           "solves")  # fmt: skip
_FRESH_PROCESSES = 2  # fresh processes tried for a case that has no solution in this one


class _NoSolution(Exception):
    """CONTACT aborted a case (ierror -26) in this process, also after fresh starts."""


def _place(cntc, settings, xt, et, omega, v_ref_r):
    """Set the wheelset's position and velocities for creepages ``(xt, et)``; solve."""
    v, rr = settings["v"], settings["roller_mm"]
    vy = -et * v_ref_r * 2 / (2 - xt)
    cntc.setwheelsetposition(_IRE, 2, [0.0, settings["y_ws"], 0.0, 0.0, 0.0, 0.0])
    first = v / rr if rr else v  # roller: its angular velocity [rad/s]
    cntc.setwheelsetvelocity(_IRE, 2, [first, vy, 0.0, 0.0, 0.0, -omega])
    return cntc.calculate(_IRE)


def _solve_case(cntc, ctab, settings, xt, et, warm):
    """One case: the wheel's angular velocity solved until CONTACT's creepages are ``(xt,
    et)``; the row of :class:`ProfileContact`. ``warm`` ([ω/ξ factor, V_ref]) starts from the
    previous case and is updated. Raises :class:`_NoSolution` when CONTACT aborts the case
    also after :data:`_RETRIES` fresh starts of its result element."""
    body = "roller" if settings["roller_mm"] else "tangent_rail"
    for attempt in range(1, _MAX_SOLVES + 1):
        solves = attempt
        omega = warm[0] * (2 + xt) / (2 - xt)
        ierror = _place(cntc, settings, xt, et, omega, warm[1])
        for _ in range(_RETRIES):
            if ierror != _NO_SOLUTION:
                break
            # The gfortran build's normal solver sometimes ends in NaN for a case it solves
            # in another process (state left by earlier cases): start the result element
            # afresh and solve the same case again.
            cntc.finalize(_IRE)
            cntc.initialize(_IRE, 1, _state["outdir"], 0)
            _configure(cntc, ctab, **settings)
            ierror = _place(cntc, settings, xt, et, omega, warm[1])
        if ierror == _NO_SOLUTION:
            raise _NoSolution
        n = int(cntc.getnumcontactpatches(_IRE)) if ierror == 0 else 0
        if ierror or n < 1:
            raise RuntimeError(
                f"CONTACT found no solution for the wheel on the {body} (ierror = {ierror}, "
                f"{n} contact patches) at y_ws = {settings['y_ws'] * 1e-3:g} m, creepages "
                f"({xt:g}, {et:g}); see {_state['outdir']}contact_addon.out"
            )
        icp, area = _largest_patch(cntc, n)
        xa, ea, pa = (float(c) for c in cntc.getcreepages(_IRE, icp))
        vref = float(cntc.getreferencevelocity(_IRE, icp))
        warm[0] = omega * (2 - xa) / (2 + xa)
        warm[1] = vref * (2 - xa) / 2
        if (
            abs(xa - xt) <= _CREEP_RTOL * abs(xt) + _CREEP_ATOL
            and abs(ea - et) <= _CREEP_RTOL * abs(et) + _CREEP_ATOL
        ):
            break
    else:
        raise RuntimeError(
            f"CONTACT's creepage ({xa:g}, {ea:g}) did not reach ({xt:g}, {et:g}) in "
            f"{_MAX_SOLVES} solutions on the {body}"
        )
    fn = fx = fy = 0.0
    for p in range(1, n + 1):
        f = cntc.getcontactforces(_IRE, p)
        fn, fx, fy = fn + f[0], fx - f[1], fy - f[2]  # on the wheel -> creepage sign
    pn = np.asarray(cntc.gettractions(_IRE, icp)[0])  # (my, mx)
    ddx, ddy = (float(d) for d in cntc.getgriddiscretization(_IRE, icp))
    loaded = pn > 0
    loc = cntc.getcontactlocation(_IRE, icp)
    return dict(
        long_creep=xa, lat_creep=ea, spin=pa * 1e3, fx=fx, fy=fy, normal_force=fn, n_patches=n,
        patch_length_x=loaded.any(axis=0).sum() * ddx * 1e-3,
        patch_width_y=loaded.any(axis=1).sum() * ddy * 1e-3, patch_area=area * 1e-6,
        contact_angle=float(loc[3]), rail_y=float(loc[5]) * 1e-3, solves=solves,
    )  # fmt: skip


def _solve_in_this_process(settings, xt, et):
    """:func:`_solve_case` on a CONTACT loaded afresh (run in a new process)."""
    cntc, ctab = _library()
    cntc.initialize(_IRE, 1, _state["outdir"], 0)
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            _configure(cntc, ctab, **settings)
            return _solve_case(cntc, ctab, settings, xt, et, [settings["v"] / settings["rw_mm"],
                                                              settings["v"]])  # fmt: skip
    finally:
        cntc.finalize(_IRE)


_NO_SOLUTION_EXIT = 3  # exit status of the fresh process when CONTACT aborts there too


def _fresh_main() -> None:
    """Entry of the fresh process of :func:`_solve_fresh`: the case as JSON on stdin, the row
    as JSON on stdout."""
    import json
    import sys

    case = json.loads(sys.stdin.read())
    try:
        row = _solve_in_this_process(case["settings"], case["xt"], case["et"])
    except _NoSolution:
        sys.exit(_NO_SOLUTION_EXIT)
    except RuntimeError as exc:
        print(exc, file=sys.stderr)
        sys.exit(1)
    sys.stdout.write(json.dumps({k: float(v) for k, v in row.items()}))


def _solve_fresh(settings, xt, et):
    """A case CONTACT aborted here, solved in a new Python process: the gfortran build's normal
    solver sometimes ends in NaN (ierror -26) after many cases in one process, also after the
    result element starts afresh, and solves the same case in a process of its own. A plain
    interpreter (not multiprocessing, which would import the caller's script again)."""
    import json
    import subprocess
    import sys

    body = "roller" if settings["roller_mm"] else "tangent_rail"
    case = json.dumps({"settings": settings, "xt": xt, "et": et})
    code = "from rollerrig.contact.cntc_profiles import _fresh_main; _fresh_main()"
    for _ in range(_FRESH_PROCESSES):
        run = subprocess.run([sys.executable, "-c", code], input=case, capture_output=True,
                             text=True, check=False)  # fmt: skip
        if run.returncode == 0:
            return json.loads(run.stdout)
        if run.returncode != _NO_SOLUTION_EXIT:
            raise RuntimeError((run.stderr.strip().splitlines() or ["CONTACT failed"])[-1])
    raise RuntimeError(
        f"CONTACT found no solution for the wheel on the {body} (ierror = {_NO_SOLUTION}, its "
        f"solver aborted, also in {_FRESH_PROCESSES} fresh processes) at y_ws = "
        f"{settings['y_ws'] * 1e-3:g} m, creepages ({xt:g}, {et:g}); see "
        f"{_state['outdir']}contact_addon.out"
    )


def profile_creep_force(
    long_creep,
    lat_creep=0.0,
    *,
    wheel_profile,
    rail_profile,
    normal_load,
    wheel_radius,
    roller_radius=None,
    lateral_position=0.0,
    friction,
    shear_modulus,
    poisson,
    rolling_speed=10.0,
    element_size=0.2e-3,
) -> ProfileContact:
    """Creep forces of a wheel profile on a rail profile, straight or as a roller, by CONTACT.

    CONTACT's module 1 (wheel-rail contact from profiles, Kalker's exact theory, non-Hertzian):
    see the module's docstring for the setting. ``roller_radius=None`` is a tangent rail;
    a radius puts the rail profile on a roller of that nominal radius (CONTACT's roller rig,
    ``C1 = 4``, ``NOMRADR``): the wheel then meets a surface curved along the rolling direction
    too, which shortens the patch along x (Hertz: a ∝ (1/R_w + 1/R_roller)^(-1/3) when the
    lateral curvatures dominate) and lowers the creep stiffness.

    Parameters
    ----------
    long_creep, lat_creep : array_like
        Target ξ, η [-] (broadcast), |·| < 0.5.
    wheel_profile, rail_profile : path-like
        Profile files CONTACT reads (e.g. ``.prw`` Simpack wheel, ``.prr`` rail, Miniprof
        ``.ban``/``.whl``), coordinates in mm; e.g. :func:`example_profile`.
    normal_load : float
        Prescribed total vertical force F_z [N] (CONTACT's N = 1).
    wheel_radius : float
        Nominal wheel radius r_nom,w [m]: the wheel profile's origin to the axle.
    roller_radius : float or None
        Nominal roller radius r_nom,r [m] (the rail profile's z = 0 at this radius), or None
        for a tangent rail.
    lateral_position : float
        Lateral wheelset position y_ws [m] in CONTACT's track coordinates (0: centred; with
        CONTACT's S1002 and UIC60 examples +6 mm moves the patch from 8.7 to 2.7 mm on the
        rail profile, one patch throughout).
    friction : float
        Coulomb μ [-].
    shear_modulus : float
        G [Pa] of both bodies.
    poisson : float
        ν [-] of both bodies.
    rolling_speed : float
        V [m/s] (steady rolling: the forces do not depend on it).
    element_size : float
        Size of CONTACT's square elements [m], along x and along the profile (default 0.2 mm;
        the creep stiffness converges as the element size, about 1.5 % low at 30 elements
        along the patch).

    Returns
    -------
    ProfileContact
        Creepages reached, forces [N] (sign of the creepage), patch data [m, m²], spin [1/m].

    Raises
    ------
    ContactNotAvailable
        Without CONTACT (see :func:`rollerrig.contact.cntc.load_contact`).
    ParameterError
        For a non-physical input, a missing or unreadable profile file.
    RuntimeError
        If CONTACT finds no contact or reports an error, or the creepage is not reached.

    Examples
    --------
    >>> try:  # doctest: +SKIP
    ...     r = profile_creep_force(1e-3, wheel_profile=example_profile(EXAMPLE_WHEEL),
    ...         rail_profile=example_profile(EXAMPLE_RAIL), normal_load=10e3,
    ...         wheel_radius=0.348, roller_radius=0.452, friction=0.33,
    ...         shear_modulus=80.8e9, poisson=0.3)
    ... except ContactNotAvailable:
    ...     pass
    """
    xi_t, eta_t = np.broadcast_arrays(
        _creep_array("long_creep", long_creep), _creep_array("lat_creep", lat_creep)
    )
    wheel = _profile_file("wheel_profile", wheel_profile)
    rail = _profile_file("rail_profile", rail_profile)
    fz = require_positive("normal_load", normal_load, "N", single=True)
    rw = require_positive("wheel_radius", wheel_radius, "m", single=True) * 1e3  # mm
    rr = 0.0
    if roller_radius is not None:
        rr = require_positive("roller_radius", roller_radius, "m", single=True) * 1e3
    y_ws = require_finite("lateral_position", lateral_position, "m", single=True) * 1e3
    if abs(y_ws) > 50.0:
        raise ParameterError(f"lateral_position must lie within ±0.05 m, got {y_ws * 1e-3!r}")
    mu = require_positive("friction", friction, "-", single=True)
    gg = require_positive("shear_modulus", shear_modulus, "Pa", single=True) * 1e-6  # N/mm²
    nu = require_positive("poisson", poisson, "-", single=True)
    if nu >= 0.5:
        raise ParameterError(f"poisson must lie in (0, 0.5) [-], got {nu!r}")
    v = require_positive("rolling_speed", rolling_speed, "m/s", single=True) * 1e3  # mm/s
    dx = require_positive("element_size", element_size, "m", single=True) * 1e3
    if not 0.01 <= dx <= 2.0:
        raise ParameterError(f"element_size must lie in [1e-5, 2e-3] m, got {dx * 1e-3!r}")

    body = "roller" if rr else "tangent_rail"
    settings = dict(roller_mm=rr, wheel=wheel, rail=rail, rw_mm=rw, fz=fz, mu=mu, gg=gg, nu=nu,
                    dx_mm=dx, y_ws=y_ws, v=v)  # fmt: skip
    out = {k: np.zeros(xi_t.size) for k in _FIELDS}
    pending = []  # cases CONTACT gave up on in this process (see _solve_fresh)
    cntc, ctab = _library()
    cntc.initialize(_IRE, 1, _state["outdir"], 0)  # module 1: wheel-rail contact
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            _configure(cntc, ctab, **settings)
            # V_r/r_w [rad/s]: the wheel's free-rolling angular velocity, refined by each solve
            warm = [v / rw, v]
            for i, (xt, et) in enumerate(zip(xi_t.ravel(), eta_t.ravel(), strict=True)):
                try:
                    row = _solve_case(cntc, ctab, settings, xt, et, warm)
                except _NoSolution:
                    pending.append(i)
                    continue
                for k, val in row.items():
                    out[k][i] = val
    finally:
        cntc.finalize(_IRE)
    for i in pending:
        row = _solve_fresh(settings, float(xi_t.ravel()[i]), float(eta_t.ravel()[i]))
        for k, val in row.items():
            out[k][i] = val
    shape = xi_t.shape
    arrays = {k: out[k].reshape(shape) for k in _FIELDS}
    for k in ("n_patches", "solves"):
        arrays[k] = arrays[k].astype(int)
    return ProfileContact(body=body, **arrays)


def profile_transfer_factor(long_creep, *, roller_radius, **kwargs) -> ProfileTransfer:
    """F_x on the tangent rail over F_x on the roller, one wheel profile, equal creepage and load.

    The non-Hertzian counterpart of the Hertzian transfer factor (Kalker's linear theory:
    (a b C11)_rail / (a b C11)_roller at small creepage, :mod:`rollerrig.analysis.transfer`):
    both sides solved by :func:`profile_creep_force` with the same ``kwargs`` (profiles, load,
    wheel radius, lateral position, friction, material, element size), the rail profile
    straight and as a roller of ``roller_radius`` [m], each at +ξ and at -ξ.

    The factor is the ratio of the odd parts ``(F_x(ξ) - F_x(-ξ)) / 2``, the force of the
    creepage. On real profiles the contact angle brings spin, and spin pushes F_x one way
    whatever the sign of ξ (about 300 N at 10 kN on S1002/UIC60, CONTACT's examples): a plain
    ratio at ξ = 1e-4 reads 1.16 where the odd parts give 1.47, and at 1e-5 it is 0.96. Towards
    saturation both forces reach μ F_n and the factor tends to the ratio of the normal forces
    (about 1).

    Parameters
    ----------
    long_creep : array_like
        ξ [-], non-zero (each is also solved at -ξ).
    roller_radius : float
        Nominal roller radius [m].
    **kwargs
        Every other argument of :func:`profile_creep_force` (keywords).

    Returns
    -------
    ProfileTransfer
        The four results and the factor F_x,rail / F_x,roller of the odd parts [-].

    Raises
    ------
    ContactNotAvailable, ParameterError, RuntimeError
        As :func:`profile_creep_force`; RuntimeError also when an odd part is zero or the
        two odd parts have opposite signs.
    """
    if "roller_radius" in kwargs or roller_radius is None:
        raise ParameterError("roller_radius [m] is required once, as a number")
    xi = _creep_array("long_creep", long_creep)
    if np.any(xi == 0):
        raise ParameterError("long_creep must be non-zero for a transfer factor (0/0 at ξ = 0)")
    rail = profile_creep_force(xi, **kwargs)
    rail_reversed = profile_creep_force(-xi, **kwargs)
    roller = profile_creep_force(xi, roller_radius=roller_radius, **kwargs)
    roller_reversed = profile_creep_force(-xi, roller_radius=roller_radius, **kwargs)
    result = ProfileTransfer(rail, roller, rail_reversed, roller_reversed, np.empty(0))
    on_rail, on_roller = result.rail_fx_odd, result.roller_fx_odd
    if np.any(on_roller == 0) or np.any(np.sign(on_rail) != np.sign(on_roller)):
        raise RuntimeError(
            "CONTACT gave an odd part of F_x that is zero, or of opposite signs on the rail and "
            f"the roller, at some creepage {xi.tolist()}: no transfer factor"
        )
    return ProfileTransfer(rail, roller, rail_reversed, roller_reversed, on_rail / on_roller)
