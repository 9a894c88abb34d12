"""Isaac Lab (PhysX), Isaac Lab 3 (Newton) and Genesis: Python configuration blocks, and their reader."""

from __future__ import annotations

import ast
from collections.abc import Mapping

from simpick.engines.simulator_files.common import GROUND_MU, _header, _meanings, _num
from simpick.engines.simulator_files.mjcf import MUJOCO_DMAX, MUJOCO_TIMECONST

# Each block is Python a user runs: the configuration classes' keyword arguments as dicts, named after the
# class they go to, with the import that gives the class. The names are checked against each simulator's
# own classes where they install here (Newton, Genesis: tests/test_simulator_files.py in their venvs) and
# against simpick.engines.simulator_names.NAMES (quoted from the source) where they do not (Isaac Lab).

PHYSX_SOLVER = {"tgs": 1, "pgs": 0}


def _isaaclab(settings: Mapping) -> list[tuple[str, str, dict]]:
    """(import, class, {keyword: value}) of an Isaac Lab (PhysX) profile."""
    return [
        (
            "from isaaclab.sim import PhysxCfg",
            "PhysxCfg",
            {
                "solver_type": PHYSX_SOLVER[settings["solver"]],
                "bounce_threshold_velocity": settings["bounce_threshold"],
            },
        ),
        (
            "from isaaclab.sim.schemas import ArticulationRootPropertiesCfg",
            "ArticulationRootPropertiesCfg",
            {
                "solver_position_iteration_count": int(settings["position_iterations"]),
                "solver_velocity_iteration_count": int(settings["velocity_iterations"]),
            },
        ),
        (
            "from isaaclab.actuators import ImplicitActuatorCfg",
            "ImplicitActuatorCfg",
            {"stiffness": 0.0, "damping": settings["wheel_drive_damping"]},
        ),
    ]


def _newton(settings: Mapping, ground_mu: float) -> list[tuple[str, str, dict]]:
    """(import, class or call, {keyword: value}) of an Isaac Lab 3 (Newton) profile: SolverMuJoCo's keywords
    (Isaac Lab's MJWarpSolverCfg fields of the same names) and, with the tuned wheel contact, the MuJoCo pair
    attributes SolverMuJoCo registers on a ModelBuilder (ModelBuilder.add_custom_values, one call per wheel and
    ground shape, geom1 the ground's shape index, geom2 the wheel's)."""
    solver = {"cone": settings["mujoco_cone"]}
    blocks = []
    if settings["wheel_contact"] != "default":
        d, df = settings["wheel_contact_impedance"], settings["wheel_friction_impedance"]
        solver["impratio"] = float(_num(((1 - d) / d) / ((1 - df) / df)))
    blocks.append(("from newton.solvers import SolverMuJoCo", "SolverMuJoCo", solver))
    if settings["wheel_contact"] == "pairs":
        d = settings["wheel_contact_impedance"]
        blocks.append(
            (
                "import newton  # SolverMuJoCo.register_custom_attributes(builder) first",
                "newton.ModelBuilder.add_custom_values",
                {
                    "mujoco:pair_condim": 3,
                    "mujoco:pair_friction": (ground_mu, ground_mu, 0.0, 0.0, 0.0),
                    "mujoco:pair_solref": (MUJOCO_TIMECONST, 1.0),
                    "mujoco:pair_solreffriction": (float(_num(MUJOCO_TIMECONST * MUJOCO_DMAX / d)), 1.0),
                    "mujoco:pair_solimp": (d, d, 0.001, 0.5, 2.0),
                },
            )
        )
    return blocks


def _genesis(settings: Mapping) -> list[tuple[str, str, dict]]:
    """(import, class, {keyword: value}) of a Genesis profile; friction_cone takes Genesis's enum
    (gs.friction_cone), not its name (the options are strict: genesis/options/solvers.py RigidOptions)."""
    return [
        (
            "import genesis as gs",
            "gs.options.RigidOptions",
            {"friction_cone": _Code(f"gs.friction_cone.{settings['friction_cone']}")},
        ),
        ("import genesis as gs", "gs.morphs.URDF", {"default_armature": settings.get("default_armature")}),
    ]


class _Code(str):
    """A keyword's value written as code (an enum member), not as a literal."""

    def __repr__(self) -> str:
        return str(self)


PYTHON_BLOCKS = {"isaaclab": _isaaclab, "newton": _newton, "genesis": _genesis}
# Why an Isaac Lab 3 (Newton) file has no lateral/longitudinal friction ratio, as the calibration's search space
# says it (tests/test_simulator_files.py holds the two to the same words): the adapter has no such setting, so
# neither the tuned nor the calibrated profile carries one, and the pairs' two tangential frictions are equal
NEWTON_NO_RATIO = (
    "no friction ratio (both tangential frictions the ground's): resources/simulators/calibration.yaml, "
    "isaac_lab_newton, if_unbound: simpick's Newton adapter writes the pairs' friction isotropic (no friction_ratio "
    "setting), so no calibrated setting can be run; its calibrated row is its tuned profile"
)
# the adapter setting behind each keyword, for the reader (keyword -> setting)
PYTHON_KEYS = {
    "isaaclab": {
        "solver_type": "solver",
        "bounce_threshold_velocity": "bounce_threshold",
        "solver_position_iteration_count": "position_iterations",
        "solver_velocity_iteration_count": "velocity_iterations",
        "damping": "wheel_drive_damping",
    },
    "newton": {"cone": "mujoco_cone"},
    "genesis": {"friction_cone": "friction_cone", "default_armature": "default_armature"},
}


def python_blocks(fmt: str, settings: Mapping, ground_mu: float = GROUND_MU) -> list[tuple[str, str, dict]]:
    """(import, class, {keyword: value}) of a Python-configured simulator's profile."""
    if fmt == "newton":
        return _newton(settings, ground_mu)
    return PYTHON_BLOCKS[fmt](settings)


def _variable(call: str) -> str:
    """The dict's name in the file: the class or call's own name, lower case (PhysxCfg -> physxcfg_kwargs)."""
    return call.split(".")[-1].lower() + "_kwargs"


def write_python(
    fmt: str, settings: Mapping, entries: Mapping | None, title: list[str], ground_mu: float = GROUND_MU
) -> dict:
    lines: list[str] = []
    for imp, call, kwargs in python_blocks(fmt, settings, ground_mu):
        if imp not in lines:
            lines.append(imp)
        body = ", ".join(f"{k!r}: {v!r}" for k, v in kwargs.items())
        lines.append(f"{_variable(call)} = {{{body}}}  # {call}(**{_variable(call)})")
    notes = _meanings(entries, PYTHON_KEYS[fmt].values(), settings)
    if fmt == "newton" and settings.get("wheel_contact") == "pairs":
        notes.append(
            f"pair values: one add_custom_values call per wheel shape and ground shape, with 'mujoco:pair_geom1' "
            f"(the ground's shape) and 'mujoco:pair_geom2' (the wheel's); friction: the ground's ({ground_mu:g} here)"
        )
    if fmt == "newton":
        notes.append(NEWTON_NO_RATIO)
    return {"py": _header("#", [*title, *notes]) + "\n".join(lines) + "\n"}


def read_python(fmt: str, text: str) -> dict:
    out: dict = {}
    keys = PYTHON_KEYS[fmt]
    for node in ast.parse(text).body:
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Dict):
            for k, v in zip(node.value.keys, node.value.values, strict=True):
                key = ast.literal_eval(k)
                if key not in keys:
                    continue
                if isinstance(v, ast.Attribute):  # an enum member: its name
                    value = v.attr
                else:
                    value = ast.literal_eval(v)
                if fmt == "isaaclab" and key == "solver_type":
                    value = {n: s for s, n in PHYSX_SOLVER.items()}[value]
                out[keys[key]] = value
    if fmt == "newton":
        out["wheel_contact"] = (
            "pairs" if "mujoco:pair_solref" in text else ("decoupled" if "'impratio'" in text else "default")
        )
    return out
