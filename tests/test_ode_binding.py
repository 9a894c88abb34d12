"""The ctypes binding of ODE (simpick.engines._ode) against the installed library and headers.

Constants are checked against the header text under /usr/include/ode (libode-dev), struct
sizes and field offsets against a tiny C program compiled with gcc, and a few calls
against what they must do (a hinge velocity motor really turns its body: the bug of
Debian's python3-pyode, whose ParamFMax is 3 where ODE 0.16 has 5).
"""

import ctypes
import dataclasses
import math
import re
import shutil
import subprocess

import numpy as np
import pytest

from conftest import drive, flat_terrain, tile_terrain
from simpick.engines import _ode
from simpick.errors import InputError

try:
    LIB = _ode.load()
except _ode.OdeUnavailable as exc:  # pragma: no cover - depends on the machine
    pytest.skip(f"ODE not installed: {exc}", allow_module_level=True)

HEADERS = _ode.HEADER_DIR
needs_headers = pytest.mark.skipif(
    not (HEADERS / "common.h").is_file(), reason="ODE headers missing: apt-get install libode-dev"
)

STRUCTS = {
    "dMass": (_ode.dMass, ["mass", "c", "I"]),
    "dSurfaceParameters": (_ode.dSurfaceParameters, [f[0] for f in _ode.dSurfaceParameters._fields_]),
    "dContactGeom": (_ode.dContactGeom, [f[0] for f in _ode.dContactGeom._fields_]),
    "dContact": (_ode.dContact, ["surface", "geom", "fdir1"]),
}
ENUMS = [
    "dParamLoStop",
    "dParamHiStop",
    "dParamVel",
    "dParamLoVel",
    "dParamHiVel",
    "dParamFMax",
    "dParamFudgeFactor",
    "dParamBounce",
    "dParamCFM",
    "dParamStopERP",
    "dParamStopCFM",
    "dParamSuspensionERP",
    "dParamSuspensionCFM",
    "dParamERP",
    "dContactMu2",
    "dContactFDir1",
    "dContactBounce",
    "dContactSoftERP",
    "dContactSoftCFM",
    "dContactSlip1",
    "dContactSlip2",
    "dContactRolling",
    "dContactApprox0",
    "dContactApprox1_1",
    "dContactApprox1_2",
    "dContactApprox1_N",
    "dContactApprox1",
    "dSphereClass",
    "dBoxClass",
    "dCapsuleClass",
    "dCylinderClass",
    "dPlaneClass",
    "dJointTypeHinge",
    "dJointTypeContact",
]


def _enum_body(text: str, first_name: str) -> list[str]:
    """The comma-separated entries of the enum (or macro) that contains ``first_name``."""
    start = text.index(first_name)
    stop = text.index("}", start)
    body = re.sub(r"/\*.*?\*/", "", text[start:stop], flags=re.S)
    body = body.replace("\\\n", "\n")
    return [e.strip() for e in body.split(",") if e.strip()]


def _sequential(entries: list[str]) -> dict[str, int]:
    """C enum semantics: each entry is the previous + 1 unless given a number or an earlier name."""
    values, current = {}, -1
    for entry in entries:
        name, _, value = (p.strip() for p in entry.partition("="))
        if not value:
            current += 1
        elif value in values:
            current = values[value]
        elif re.fullmatch(r"0x[0-9a-fA-F]+|\d+", value):
            current = int(value, 0)
        else:  # an expression this test does not need; stop here rather than guess
            break
        values[name] = current
    return values


@needs_headers
def test_joint_parameter_numbers_match_common_h():
    text = (HEADERS / "common.h").read_text()
    macro = text[text.index("#define D_ALL_PARAM_NAMES(start)") :]
    macro = re.sub(r"/\*.*?\*/", "", macro[: macro.index("#define D_ALL_PARAM_NAMES_X")], flags=re.S)
    names = re.findall(r"\b(dParam\w+)\b", macro)
    assert names[0] == "dParamLoStop" and "dParamFMax" in names
    for index, name in enumerate(names):  # D_ALL_PARAM_NAMES(0): dParamLoStop = 0, then +1 each
        assert getattr(_ode, name) == index, name
    assert _ode.dParamVel == 2 and _ode.dParamFMax == 5


@needs_headers
def test_contact_mode_flags_match_contact_h():
    text = (HEADERS / "contact.h").read_text()
    header = {m.group(1): int(m.group(2), 16) for m in re.finditer(r"\b(dContact\w+)\s*=\s*(0x[0-9a-fA-F]+)", text)}
    for name in [n for n in ENUMS if n.startswith("dContact")]:
        assert header[name] == getattr(_ode, name), name


@needs_headers
def test_geom_classes_and_joint_types_match_headers():
    classes = _sequential(_enum_body((HEADERS / "collision.h").read_text(), "dSphereClass = 0"))
    for name in ("dSphereClass", "dBoxClass", "dCapsuleClass", "dCylinderClass", "dPlaneClass"):
        assert classes[name] == getattr(_ode, name), name
    joints = _sequential(_enum_body((HEADERS / "common.h").read_text(), "dJointTypeNone = 0"))
    assert joints["dJointTypeHinge"] == _ode.dJointTypeHinge
    assert joints["dJointTypeContact"] == _ode.dJointTypeContact
    init = (HEADERS / "odeinit.h").read_text()
    assert re.search(r"dAllocateMaskAll\s*=\s*~0", init) and _ode.dAllocateMaskAll == ctypes.c_uint(~0).value


@needs_headers
def test_struct_fields_follow_the_header_order():
    contact = (HEADERS / "contact.h").read_text()
    surface = contact[contact.index("typedef struct dSurfaceParameters") :]
    surface = re.sub(r"/\*.*?\*/", "", surface[: surface.index("} dSurfaceParameters;")], flags=re.S)
    declared = [n for decl in re.findall(r"(?:int|dReal)\s+([^;]+);", surface) for n in re.split(r"\s*,\s*", decl)]
    assert declared == STRUCTS["dSurfaceParameters"][1]
    assert "dReal mass;" in (HEADERS / "mass.h").read_text()


def test_library_is_double_precision_like_the_binding():
    assert LIB.dCheckConfiguration(b"ODE_double_precision") == 1
    assert ctypes.sizeof(_ode.dReal) == 8


@needs_headers
@pytest.mark.skipif(shutil.which("gcc") is None, reason="no gcc to compile the layout probe")
def test_struct_layouts_and_enums_match_a_compiled_probe(tmp_path):
    lines = ["#include <stdio.h>", "#include <stddef.h>", "#include <ode/ode.h>", "int main(void) {"]
    for struct, (_, fields) in STRUCTS.items():
        lines.append(f'printf("sizeof {struct} %zu\\n", sizeof({struct}));')
        for f in fields:
            lines.append(f'printf("offsetof {struct}.{f} %zu\\n", offsetof({struct}, {f}));')
    for name in ENUMS:
        lines.append(f'printf("enum {name} %ld\\n", (long){name});')
    lines.append('printf("sizeof dReal %zu\\n", sizeof(dReal));')
    lines += ["return 0;", "}"]
    source = tmp_path / "probe.c"
    source.write_text("\n".join(lines))
    exe = tmp_path / "probe"
    build = subprocess.run(["gcc", str(source), "-o", str(exe)], capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    out = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout
    c = {}
    for line in out.splitlines():
        kind, name, value = line.split()
        c[(kind, name)] = int(value)
    assert c[("sizeof", "dReal")] == ctypes.sizeof(_ode.dReal)
    for struct, (cls, fields) in STRUCTS.items():
        assert c[("sizeof", struct)] == ctypes.sizeof(cls), struct
        for f in fields:
            assert c[("offsetof", f"{struct}.{f}")] == getattr(cls, f).offset, f"{struct}.{f}"
    for name in ENUMS:
        assert c[("enum", name)] == getattr(_ode, name), name


def test_mass_helpers_give_the_textbook_inertia():
    m = _ode.dMass()
    LIB.dMassSetBoxTotal(ctypes.byref(m), 12.0, 1.0, 2.0, 3.0)
    assert m.mass == 12.0
    assert np.allclose([m.I[0], m.I[5], m.I[10]], [2 * 2 + 3 * 3, 1 + 9, 1 + 4])
    LIB.dMassSetCylinderTotal(ctypes.byref(m), 2.637, 3, 0.1651, 0.1143)  # axis z
    assert math.isclose(m.I[10], 0.5 * 2.637 * 0.1651**2)
    assert math.isclose(m.I[0], 2.637 * (3 * 0.1651**2 + 0.1143**2) / 12)
    LIB.dMassSetParameters(ctypes.byref(m), 3.0, 0, 0, 0, 1.0, 2.0, 3.0, 0.1, 0.2, 0.3)
    assert m.I[1] == 0.1 and m.I[4] == 0.1 and m.I[2] == 0.2 and m.I[6] == 0.3 and LIB.dMassCheck(ctypes.byref(m))


def test_hinge_velocity_motor_turns_the_body_with_bounded_torque():
    LIB.dAllocateODEDataForThread(_ode.dAllocateMaskAll)
    world = LIB.dWorldCreate()
    try:
        LIB.dWorldSetGravity(world, 0, 0, 0)
        body = LIB.dBodyCreate(world)
        m = _ode.dMass()
        LIB.dMassSetParameters(ctypes.byref(m), 1.0, 0, 0, 0, 1.0, 1.0, 1.0, 0, 0, 0)
        LIB.dBodySetMass(body, ctypes.byref(m))
        hinge = LIB.dJointCreateHinge(world, None)
        LIB.dJointAttach(hinge, body, None)
        assert LIB.dJointGetType(hinge) == _ode.dJointTypeHinge
        LIB.dJointSetHingeAnchor(hinge, 0, 0, 0)
        LIB.dJointSetHingeAxis(hinge, 0, 1, 0)
        LIB.dJointSetHingeParam(hinge, _ode.dParamVel, 3.0)
        LIB.dJointSetHingeParam(hinge, _ode.dParamFMax, 2.0)
        assert LIB.dJointGetHingeParam(hinge, _ode.dParamFMax) == 2.0
        LIB.dWorldStep(world, 0.1)  # torque-limited: 2 N m on 1 kg m^2 for 0.1 s -> 0.2 rad/s
        assert math.isclose(LIB.dJointGetHingeAngleRate(hinge), 0.2, rel_tol=1e-6)
        for _ in range(20):
            LIB.dWorldStep(world, 0.1)
        assert math.isclose(LIB.dJointGetHingeAngleRate(hinge), 3.0, rel_tol=1e-6)
        omega = _ode.vector_view(LIB.dBodyGetAngularVel(body))
        assert np.allclose(omega, [0, 3.0, 0])
    finally:
        LIB.dWorldDestroy(world)


def test_collide_fills_contacts_in_place_and_sphere_rests_on_plane():
    LIB.dAllocateODEDataForThread(_ode.dAllocateMaskAll)
    space = LIB.dHashSpaceCreate(None)
    try:
        plane = LIB.dCreatePlane(space, 0, 0, 1, 0)
        sphere = LIB.dCreateSphere(space, 0.5)
        LIB.dGeomSetPosition(sphere, 1.0, 2.0, 0.4)
        assert LIB.dGeomGetClass(sphere) == _ode.dSphereClass and LIB.dGeomGetClass(plane) == _ode.dPlaneClass
        contacts = (_ode.dContact * 4)()
        n = LIB.dCollide(
            sphere, plane, 4, ctypes.addressof(contacts) + _ode.dContact.geom.offset, ctypes.sizeof(_ode.dContact)
        )
        assert n == 1
        geom = contacts[0].geom
        assert math.isclose(geom.depth, 0.1) and list(geom.normal)[:3] == [0, 0, 1]
        assert geom.g1 == sphere and geom.g2 == plane
        assert np.allclose(list(geom.pos)[:2], [1.0, 2.0])
    finally:
        LIB.dSpaceDestroy(space)


def test_version_names_ode_016_double():
    assert _ode.version().startswith("0.16") and "double" in _ode.version()


def test_missing_library_says_what_to_install(monkeypatch):
    monkeypatch.setattr(_ode, "LIBRARY_NAMES", ("libode-not-here.so.99",))
    monkeypatch.setattr(_ode.ctypes.util, "find_library", lambda name: None)
    monkeypatch.delenv("SIMPICK_LIBODE", raising=False)
    with pytest.raises(_ode.OdeUnavailable, match="apt-get install -y libode8"):
        _ode._find_library()


# --- the adapter built on the binding ---------------------------------------------------

DT = 0.001


def _simulate(robot, **kwargs):
    return drive("ode", robot, **kwargs)


def _speed(record, t: float) -> float:
    return float(np.linalg.norm(record.linear_velocity[int(t / DT) - 1, :2]))


def test_the_loader_folds_the_imu_into_the_chassis(robot):
    model = robot.rigid  # the loader's rigid bodies, which the ODE adapter builds
    chassis = model.chassis
    assert math.isclose(chassis.mass, 46.034 + 0.018)
    com = (46.034 * np.array([-0.00065, -0.085, 0.062]) + 0.018 * np.array([0.19, 0.0, 0.149])) / chassis.mass
    assert np.allclose(chassis.com, com)
    # about the combined COM: both inertias moved by the parallel-axis theorem, off-diagonals kept
    base = np.array([[0.6022, -0.02364, -0.1197], [-0.02364, 1.7386, -0.001544], [-0.1197, -0.001544, 2.0296]])
    expected = base + 2e-6 * np.eye(3)
    for m, c in ((46.034, [-0.00065, -0.085, 0.062]), (0.018, [0.19, 0.0, 0.149])):
        d = np.asarray(c) - com
        expected += m * (d @ d * np.eye(3) - np.outer(d, d))
    assert np.allclose(chassis.inertia, expected, rtol=1e-12, atol=1e-12)
    assert abs(chassis.inertia[0, 1] - -0.02364) < 5e-4  # the IMU hardly moves it
    assert [s[0] for s in chassis.shapes] == ["box", "box"]
    assert len(model.wheels) == 4
    for _xyz, _rot, axis, wheel in model.wheels:
        assert np.allclose(axis, [0, 1, 0]) and math.isclose(wheel.mass, 2.637)
        kind, (radius, length), _, shape_rot = wheel.shapes[0]
        assert kind == "cylinder" and radius == 0.1651 and length == 0.1143
        assert np.allclose(np.abs(shape_rot @ [0, 0, 1]), [0, 1, 0])  # cylinder axis along y


def test_terrain_friction_not_the_robot_s_decides_the_contact(robot):
    raised = dataclasses.replace(robot, base_height=robot.base_height + 0.01)  # spawn on the tile
    assert _speed(_simulate(raised, terrain=tile_terrain(0.1), ground=0.95), 0.25) < 0.3
    assert _speed(_simulate(raised, terrain=tile_terrain(0.95), ground=0.1), 0.25) > 0.45
    assert _speed(_simulate(robot, terrain=flat_terrain(0.95), ground=0.1), 0.25) < 0.3


def test_wheel_torque_bound_limits_the_acceleration(robot):
    record = _simulate(robot, terrain=flat_terrain(), torque=1.0, duration=0.5)
    assert _speed(record, 0.5) < 0.25  # 4 x 1 N m / 0.1651 m on 57 kg: 0.21 m/s after 0.5 s


def test_robots_collide_with_each_other(robot):
    record = _simulate(robot, terrain=flat_terrain(), starts=((0.0, 0.0, 0.0), (1.6, 0.0, math.pi)), duration=2.5)
    assert record.position[:, 0].max() < 1.6 / 2 - 0.3


@pytest.mark.parametrize("space", ["hash", "simple"])
def test_space_kind_does_not_change_the_physics(robot, space):
    terrain = tile_terrain(0.5)
    terrain["spheres"] = [[0.6, 0.28, 0.0, 0.05], [0.9, -0.28, 0.0, 0.04]]
    raised = dataclasses.replace(robot, base_height=robot.base_height + 0.01)
    a = _simulate(raised, terrain=terrain, duration=1.5)
    b = _simulate(raised, terrain=terrain, duration=1.5, settings={"space": space})
    # the spaces hand the contacts to the solver in another order: round-off only (measured
    # 4.7e-9 m with the stick/slip switch of friction_direction "coulomb", 0 without it)
    np.testing.assert_allclose(a.position, b.position, atol=1e-7)


def test_unknown_settings_are_refused(robot):
    with pytest.raises(InputError, match=r"engines\.ode: unknown setting\(s\) \['solver'\]"):
        _simulate(robot, terrain=flat_terrain(), settings={"solver": "x"})
    with pytest.raises(InputError, match=r"engines\.ode\.stepper: Input should be 'world' or 'quick' \(got 'rk4'\)"):
        _simulate(robot, terrain=flat_terrain(), settings={"stepper": "rk4"})
