"""A minimal ``ctypes`` binding of the Open Dynamics Engine (ODE 0.16, Debian's ``libode8``).

Only the calls :mod:`simpick.engines.ode_engine` needs are bound. Why a binding of our own:
PyPI ``pyode`` does not build on Python 3.11, Debian's ``python3-pyode`` carries joint
parameter numbers from an older ODE (its ``ParamFMax`` is 3, ODE 0.16's ``dParamFMax`` is 5,
so velocity motors silently do nothing) and PyPI ``ode-python`` installs stray top-level
packages. The constants and struct layouts below are checked against the installed
headers by ``tests/test_ode_binding.py``.

Every function pointer is bound once with its ``argtypes``/``restype``; handles (world,
space, body, geom, joint) are plain ``int`` addresses (``c_void_p``), which is the cheapest
thing ctypes can pass, and matters in a stepping loop that runs 10 000+ times in Python.
"""

from __future__ import annotations

import collections
import ctypes
import ctypes.util
import os
import re
import subprocess
from ctypes import POINTER, Structure, c_char_p, c_double, c_int, c_uint, c_ulong, c_void_p
from pathlib import Path
from types import SimpleNamespace

INSTALL_HINT = (
    "install ODE's shared library: `sudo apt-get install -y libode8` on Debian/Ubuntu "
    "(libode-dev as well to run tests/test_ode_binding.py), or set SIMPICK_LIBODE to "
    "the path of a libode.so built with double precision"
)
LIBRARY_NAMES = ("libode.so.8", "libode.so")  # ODE 0.16.x has soname 8
HEADER_DIR = Path("/usr/include/ode")


class OdeUnavailable(RuntimeError):
    """ODE's shared library is missing or unusable; the message says what to install."""


# --- types ------------------------------------------------------------------------------
# dReal is double in Debian's build (dGetConfiguration says "ODE_double_precision");
# load() refuses a single-precision library rather than silently mis-reading memory.
dReal = c_double
dVector3 = dReal * 4  # x, y, z and one pad
dVector4 = dReal * 4
dQuaternion = dReal * 4  # w, x, y, z
dMatrix3 = dReal * 12  # 3 rows of 4 (the 4th column is padding)


class dMass(Structure):
    _fields_ = [("mass", dReal), ("c", dVector3), ("I", dMatrix3)]


class dSurfaceParameters(Structure):
    _fields_ = [
        ("mode", c_int),
        ("mu", dReal),
        ("mu2", dReal),
        ("rho", dReal),
        ("rho2", dReal),
        ("rhoN", dReal),
        ("bounce", dReal),
        ("bounce_vel", dReal),
        ("soft_erp", dReal),
        ("soft_cfm", dReal),
        ("motion1", dReal),
        ("motion2", dReal),
        ("motionN", dReal),
        ("slip1", dReal),
        ("slip2", dReal),
    ]


class dContactGeom(Structure):
    _fields_ = [
        ("pos", dVector3),
        ("normal", dVector3),
        ("depth", dReal),
        ("g1", c_void_p),
        ("g2", c_void_p),
        ("side1", c_int),
        ("side2", c_int),
    ]


class dContact(Structure):
    _fields_ = [("surface", dSurfaceParameters), ("geom", dContactGeom), ("fdir1", dVector3)]


# void dNearCallback(void *data, dGeomID o1, dGeomID o2)
dNearCallback = ctypes.CFUNCTYPE(None, c_void_p, c_void_p, c_void_p)
# void dMessageFunction(int errnum, const char *msg, va_list ap): msg is a printf format
dMessageFunction = ctypes.CFUNCTYPE(None, c_int, c_char_p, c_void_p)

# --- constants (values from ODE 0.16's headers; checked by tests/test_ode_binding.py) ----
# common.h: enum { D_ALL_PARAM_NAMES(0) ... } -- joint parameters of the first axis
dParamLoStop, dParamHiStop, dParamVel, dParamLoVel, dParamHiVel, dParamFMax = 0, 1, 2, 3, 4, 5
dParamFudgeFactor, dParamBounce, dParamCFM, dParamStopERP, dParamStopCFM = 6, 7, 8, 9, 10
dParamSuspensionERP, dParamSuspensionCFM, dParamERP = 11, 12, 13
# contact.h: surface mode flags
dContactMu2 = 0x001
dContactFDir1 = 0x002
dContactBounce = 0x004
dContactSoftERP = 0x008
dContactSoftCFM = 0x010
dContactSlip1 = 0x100
dContactSlip2 = 0x200
dContactRolling = 0x400
dContactApprox0 = 0x0000
dContactApprox1_1 = 0x1000
dContactApprox1_2 = 0x2000
dContactApprox1_N = 0x4000
dContactApprox1 = 0x7000
# collision.h: geometry classes
dSphereClass, dBoxClass, dCapsuleClass, dCylinderClass, dPlaneClass = 0, 1, 2, 3, 4
# odeinit.h
dAllocateMaskAll = 0xFFFFFFFF  # ~0 as unsigned int
# objects.h / common.h
dJointTypeHinge, dJointTypeContact = 2, 4

_P = POINTER(dReal)
_SIGNATURES: dict[str, tuple] = {
    # init and configuration
    "dInitODE2": (c_int, [c_uint]),
    "dAllocateODEDataForThread": (c_int, [c_uint]),
    "dGetConfiguration": (c_char_p, []),
    "dCheckConfiguration": (c_int, [c_char_p]),
    "dRandSetSeed": (None, [c_ulong]),
    "dSetMessageHandler": (None, [dMessageFunction]),
    # world
    "dWorldCreate": (c_void_p, []),
    "dWorldDestroy": (None, [c_void_p]),
    "dWorldSetGravity": (None, [c_void_p, dReal, dReal, dReal]),
    "dWorldSetERP": (None, [c_void_p, dReal]),
    "dWorldSetCFM": (None, [c_void_p, dReal]),
    "dWorldStep": (c_int, [c_void_p, dReal]),
    "dWorldQuickStep": (c_int, [c_void_p, dReal]),
    "dWorldSetQuickStepNumIterations": (None, [c_void_p, c_int]),
    "dWorldSetQuickStepW": (None, [c_void_p, dReal]),
    "dWorldSetContactMaxCorrectingVel": (None, [c_void_p, dReal]),
    "dWorldSetContactSurfaceLayer": (None, [c_void_p, dReal]),
    "dWorldSetAutoDisableFlag": (None, [c_void_p, c_int]),
    # bodies
    "dBodyCreate": (c_void_p, [c_void_p]),
    "dBodySetMass": (None, [c_void_p, POINTER(dMass)]),
    "dBodySetPosition": (None, [c_void_p, dReal, dReal, dReal]),
    "dBodySetQuaternion": (None, [c_void_p, _P]),
    "dBodyGetPosition": (c_void_p, [c_void_p]),
    "dBodyGetRotation": (c_void_p, [c_void_p]),
    "dBodyGetQuaternion": (c_void_p, [c_void_p]),
    "dBodyGetLinearVel": (c_void_p, [c_void_p]),
    "dBodyGetAngularVel": (c_void_p, [c_void_p]),
    # mass
    "dMassSetZero": (None, [POINTER(dMass)]),
    "dMassSetParameters": (None, [POINTER(dMass)] + [dReal] * 10),
    "dMassSetBoxTotal": (None, [POINTER(dMass), dReal, dReal, dReal, dReal]),
    "dMassSetCylinderTotal": (None, [POINTER(dMass), dReal, c_int, dReal, dReal]),
    "dMassTranslate": (None, [POINTER(dMass), dReal, dReal, dReal]),
    "dMassRotate": (None, [POINTER(dMass), _P]),
    "dMassCheck": (c_int, [POINTER(dMass)]),
    # joints
    "dJointCreateHinge": (c_void_p, [c_void_p, c_void_p]),
    "dJointCreateContact": (c_void_p, [c_void_p, c_void_p, c_void_p]),
    "dJointAttach": (None, [c_void_p, c_void_p, c_void_p]),
    "dJointGetType": (c_int, [c_void_p]),
    "dJointSetHingeAnchor": (None, [c_void_p, dReal, dReal, dReal]),
    "dJointSetHingeAxis": (None, [c_void_p, dReal, dReal, dReal]),
    "dJointSetHingeParam": (None, [c_void_p, c_int, dReal]),
    "dJointGetHingeParam": (dReal, [c_void_p, c_int]),
    "dJointGetHingeAngleRate": (dReal, [c_void_p]),
    "dJointGetHingeAngle": (dReal, [c_void_p]),
    "dJointAddHingeTorque": (None, [c_void_p, dReal]),
    "dJointGroupCreate": (c_void_p, [c_int]),
    "dJointGroupDestroy": (None, [c_void_p]),
    "dJointGroupEmpty": (None, [c_void_p]),
    # spaces
    "dSimpleSpaceCreate": (c_void_p, [c_void_p]),
    "dHashSpaceCreate": (c_void_p, [c_void_p]),
    "dHashSpaceSetLevels": (None, [c_void_p, c_int, c_int]),
    "dQuadTreeSpaceCreate": (c_void_p, [c_void_p, _P, _P, c_int]),
    "dSpaceDestroy": (None, [c_void_p]),
    "dSpaceCollide": (None, [c_void_p, c_void_p, dNearCallback]),
    "dSpaceCollide2": (None, [c_void_p, c_void_p, c_void_p, dNearCallback]),
    # geoms
    "dCreatePlane": (c_void_p, [c_void_p, dReal, dReal, dReal, dReal]),
    "dCreateBox": (c_void_p, [c_void_p, dReal, dReal, dReal]),
    "dCreateSphere": (c_void_p, [c_void_p, dReal]),
    "dCreateCylinder": (c_void_p, [c_void_p, dReal, dReal]),
    "dGeomSetBody": (None, [c_void_p, c_void_p]),
    "dGeomGetBody": (c_void_p, [c_void_p]),
    "dGeomSetPosition": (None, [c_void_p, dReal, dReal, dReal]),
    "dGeomSetQuaternion": (None, [c_void_p, _P]),
    "dGeomSetOffsetPosition": (None, [c_void_p, dReal, dReal, dReal]),
    "dGeomSetOffsetQuaternion": (None, [c_void_p, _P]),
    "dGeomSetCategoryBits": (None, [c_void_p, c_ulong]),
    "dGeomSetCollideBits": (None, [c_void_p, c_ulong]),
    "dGeomGetClass": (c_int, [c_void_p]),
    "dGeomGetAABB": (None, [c_void_p, _P]),
    "dCollide": (c_int, [c_void_p, c_void_p, c_int, c_void_p, c_int]),
}

_lib: SimpleNamespace | None = None

# ODE's non-fatal messages (e.g. "LCP internal error, s <= 0" from dWorldStep's solver,
# which then carries on) are counted here instead of being printed to stderr; the
# adapter clears the counter before a run and logs what it holds after.
messages: collections.Counter = collections.Counter()


def _on_message(number: int, text: bytes | None, _args) -> None:
    messages[(number, (text or b"").decode(errors="replace"))] += 1


_message_handler = dMessageFunction(_on_message)


def _find_library() -> tuple[ctypes.CDLL, str]:
    candidates = []
    if os.environ.get("SIMPICK_LIBODE"):
        candidates.append(os.environ["SIMPICK_LIBODE"])
    candidates += list(LIBRARY_NAMES)
    found = ctypes.util.find_library("ode")
    if found:
        candidates.append(found)
    errors = []
    for name in candidates:
        try:
            return ctypes.CDLL(name), name
        except OSError as exc:
            errors.append(f"{name}: {exc}")
    raise OdeUnavailable(
        "ODE (Open Dynamics Engine) shared library not found (tried " + "; ".join(errors) + "); " + INSTALL_HINT
    )


def load() -> SimpleNamespace:
    """The bound library (loaded and initialised once per process).

    Raises :class:`OdeUnavailable`, saying what to install, when libode cannot be loaded
    or is not a double-precision build.
    """
    global _lib
    if _lib is not None:
        return _lib
    cdll, name = _find_library()
    lib = SimpleNamespace(cdll=cdll, name=name)
    for fname, (restype, argtypes) in _SIGNATURES.items():
        try:
            fn = getattr(cdll, fname)
        except AttributeError:
            raise OdeUnavailable(f"{name} has no function {fname}: not ODE 0.16 ({INSTALL_HINT})") from None
        fn.restype, fn.argtypes = restype, argtypes
        setattr(lib, fname, fn)
    if not lib.dCheckConfiguration(b"ODE_double_precision"):
        raise OdeUnavailable(
            f"{name} is a single-precision ODE build "
            f"({lib.dGetConfiguration().decode()}); simpick's binding needs dReal = double "
            f"({INSTALL_HINT})"
        )
    if not lib.dInitODE2(0):
        raise OdeUnavailable(f"dInitODE2 failed in {name}")
    lib.configuration = lib.dGetConfiguration().decode()
    lib.dSetMessageHandler(_message_handler)
    _lib = lib
    return lib


def version() -> str:
    """ODE's version: the library has no version call, so read it from the header, the
    Debian package or the library's file name, in that order."""
    lib = load()
    text = None
    header = HEADER_DIR / "version.h"
    if header.is_file():
        match = re.search(r'#define\s+dODE_VERSION\s+"([^"]+)"', header.read_text())
        if match:
            text = match.group(1)
    if text is None:
        try:
            out = subprocess.run(
                ["dpkg-query", "-W", "-f=${Version}", "libode8"], capture_output=True, text=True, timeout=10
            )
            if out.returncode == 0 and out.stdout.strip():
                text = out.stdout.strip().split(":")[-1].split("-")[0]
        except (OSError, subprocess.SubprocessError):
            pass
    if text is None:
        real = os.path.realpath(ctypes.util.find_library("ode") or lib.name)
        text = f"unknown (library {os.path.basename(real)})"
    precision = "double" if "ODE_double_precision" in lib.configuration else "single"
    return f"{text} ({precision} precision)"


def vector_view(address: int, n: int = 3):
    """A numpy view (no copy) of ``n`` dReals at ``address``, e.g. a body's position."""
    import numpy as np

    return np.ctypeslib.as_array((dReal * n).from_address(address))
