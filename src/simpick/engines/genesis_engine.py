"""Genesis (genesis-world) on its CPU backend, its rigid solver (MuJoCo-style soft constraints solved on
Genesis's own kernels).

The world: the robot's URDF as a ``gs.morphs.URDF`` entity (floating base, fixed links merged,
the base link kept so its pose is the record's), the engine-neutral terrain as fixed boxes and
spheres on a ``gs.morphs.Plane``, each with a ``gs.materials.Rigid`` friction; the driven wheels
velocity-controlled (``control_dofs_velocity``: torque = kv x speed error within a force range of
the scenario's torque bound), the passive joints free.

Passive suspension (rockers): the parser's revolute joints with no gains, the spec's limits, damping and
frictionloss; each coupling is the joint equality constraint Genesis's URDF parser makes from the <mimic> that
:func:`simpick.engines.suspension.coupled_urdf` writes. Measured on the Warthog (1 kHz, mu 0.8, 500 N m): pitch
-0.002 degrees at rest, base at 0.4100 m; uncoupled, on a rocker stop at 8.597 degrees; spin gain 0.566 (Coulomb
0.591).

Settings, each against what Genesis gives out of the box (Husky, mu 0.8, 1 kHz, yaw gain
left / right / left from 45 degrees; mechanics 0.478):

* out of the box (pyramidal cone, armature 0.1 kg m^2 on every revolute joint): 0.174 / 0.194 /
  0.349, i.e. turning at a third of the mechanics' rate and depending on the world heading
  (the pyramid's faces lie along the world axes);
* ``friction_cone: elliptic``: the Coulomb cone, isotropic. Genesis then resolves contacts
  with "signorini" (its docs: friction bounded by the normal force the contact has developed,
  "so sliding never inflates it"), the cure for the normal-force inflation of MuJoCo's convex
  contact that simpick's MuJoCo adapter needed contact pairs for;
* ``constraint_solver: Newton``: Genesis's default and MuJoCo's, the solver the elliptic cone
  is meant for;
* ``default_armature: None``: Genesis adds 0.1 kg m^2 of rotor inertia to every revolute joint
  the URDF leaves without one, about twice a Husky wheel's own inertia; the real wheel has no
  such rotor, and the URDF is loaded as it is in every other engine;
* ``wheel_kv`` 3000 N m s/rad: the velocity gain with which the issue measured 0.468 / 0.477 /
  0.468 at 2 470 steps/s; Genesis's velocity control is implicit in the integrator
  (approximate_implicitfast), so a stiff gain is stable.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

import numpy as np
from pydantic import Field

from simpick.engines.base import FRICTION, BaseState, Calibratable, EngineSettings, Scenario
from simpick.engines.isolated import IsolatedAdapter
from simpick.engines.suspension import coupled_urdf
from simpick.inputs.terrain import Terrain

SPAWN_CLEARANCE = 0.002  # m above resting height, as for the other engines
# Genesis takes a contact's friction as the larger of its two materials', never below 0.01, and refuses a
# material below 0.01 (collider/contact.py, options): the robot gets that floor, so every ground contact
# has the surface's coefficient (a terrain patch's, not the robot's); a frictionless surface becomes 0.01.
MIN_FRICTION = 0.01


class GenesisSettings(EngineSettings):
    """config ``engines.genesis``."""

    # the Coulomb cone, isotropic (pyramidal, Genesis's default: gains 0.17-0.35, heading-dependent)
    friction_cone: Literal["elliptic", "pyramidal"] = "elliptic"
    # Genesis's default and MuJoCo's constraint solver
    constraint_solver: Literal["Newton", "CG"] = "Newton"
    # kg m^2 rotor inertia Genesis adds to joints without one; None: the URDF's inertia only (Genesis's
    # default 0.1 is twice the wheel's own)
    default_armature: Annotated[float, Field(ge=0)] | None = None
    # N m s/rad, gain of the wheels' velocity control (measured: gains 0.468 / 0.477 / 0.468)
    wheel_kv: Annotated[float, Field(gt=0, allow_inf_nan=False)] = 3000.0
    # constraint solver iterations (Genesis's default 25)
    iterations: Annotated[int, Field(ge=1)] = 25


# gs.init's keywords beside the CPU backend
INIT_OPTIONS = {"precision": "64", "logging_level": "warning", "seed": 0}
# the RigidOptions keywords whose value is a member of a Genesis enum, and that enum's name in genesis
ENUM_OPTIONS = {"constraint_solver": "constraint_solver", "friction_cone": "friction_cone"}


def rigid_options(settings: GenesisSettings) -> dict:
    """``gs.options.RigidOptions``' keywords as the adapter passes them, an enum's member by its name
    (:data:`ENUM_OPTIONS`)."""
    return {
        "constraint_solver": settings.constraint_solver,
        "friction_cone": settings.friction_cone,
        "iterations": settings.iterations,
        "enable_self_collision": False,
    }


def _quat_wxyz(yaw: float) -> tuple[float, float, float, float]:
    return (math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2))


_INITIALISED = False


def _terrain_mjcf(terrain: Terrain):
    """The terrain's boxes and spheres as the static geoms of an MJCF worldbody, in a temporary file."""
    import tempfile

    geoms = []
    for x, y, z, yaw, sx, sy, sz in terrain.boxes:
        geoms.append(
            f'<geom type="box" size="{sx / 2} {sy / 2} {sz / 2}" pos="{x} {y} {z}" '
            f'quat="{" ".join(str(q) for q in _quat_wxyz(yaw))}"/>'
        )
    for x, y, z, r in terrain.spheres:
        geoms.append(f'<geom type="sphere" size="{r}" pos="{x} {y} {z}"/>')
    f = tempfile.NamedTemporaryFile("w", suffix=".xml", prefix="simpick-terrain-")
    f.write('<mujoco model="terrain"><worldbody>' + "".join(geoms) + "</worldbody></mujoco>")
    f.flush()
    return f


class GenesisWorld:
    """One built Genesis scene: set_wheel_targets / step / read (see simpick.engines.base)."""

    def __init__(self, scenario: Scenario, settings: GenesisSettings):
        global _INITIALISED
        import genesis as gs

        if not _INITIALISED:
            gs.init(backend=gs.cpu, **INIT_OPTIONS)
            _INITIALISED = True
        self.scenario, self.settings = scenario, settings
        rigid = gs.options.RigidOptions(
            **{
                k: getattr(getattr(gs, ENUM_OPTIONS[k]), v) if k in ENUM_OPTIONS else v
                for k, v in rigid_options(settings).items()
            }
        )
        scene = gs.Scene(
            sim_options=gs.options.SimOptions(dt=scenario.timestep, gravity=tuple(scenario.gravity)),
            rigid_options=rigid,
            show_viewer=False,
        )
        scene.add_entity(
            gs.morphs.Plane(), material=gs.materials.Rigid(friction=max(scenario.ground_friction, MIN_FRICTION))
        )
        terrain = scenario.terrain
        if terrain.boxes or terrain.spheres:
            # one fixed entity holding every shape (an MJCF worldbody): as one entity per shape, Genesis took
            # 285 s to build the gravel strip's 480 stones (measured, loaded machine)
            self._terrain_file = _terrain_mjcf(terrain)
            scene.add_entity(
                gs.morphs.MJCF(file=self._terrain_file.name),
                material=gs.materials.Rigid(friction=max(terrain.friction, MIN_FRICTION)),
            )
        robot = scenario.robot
        self.robots = []
        # the robot's file with its <mimic> elements exactly the spec's couplings: Genesis's URDF parser turns
        # each into a joint equality constraint (checked in _suspend)
        urdf = coupled_urdf(robot)
        for x, y, yaw in scenario.starts:
            self.robots.append(
                scene.add_entity(
                    gs.morphs.URDF(
                        file=str(urdf),
                        pos=(x, y, robot.base_height + SPAWN_CLEARANCE),
                        quat=_quat_wxyz(yaw),
                        default_armature=settings.default_armature,
                        links_to_keep=[robot.base_link],
                    ),
                    material=gs.materials.Rigid(friction=MIN_FRICTION),
                )
            )
        scene.build()
        self.scene = scene
        self.dofs = [
            [entity.get_joint(name).dofs_idx_local[0] for name in robot.wheel_joints] for entity in self.robots
        ]
        for entity, dofs in zip(self.robots, self.dofs):
            entity.set_dofs_kp(np.zeros(len(dofs)), dofs)
            entity.set_dofs_kv(np.full(len(dofs), settings.wheel_kv), dofs)
            bound = scenario.max_wheel_torque
            entity.set_dofs_force_range(np.full(len(dofs), -bound), np.full(len(dofs), bound), dofs)
            self._suspend(gs, entity)

    def _suspend(self, gs, entity) -> None:
        """One robot's passive suspension joints: free (no gains) but for the spec's limits, damping and
        friction, and its couplings as the parser's joint equality constraints."""
        robot = self.scenario.robot
        for sus in robot.suspension:
            dof = [entity.get_joint(sus.joint).dofs_idx_local[0]]
            # Genesis reads <limit> and <dynamics> through MuJoCo's URDF parser; set from the spec all the
            # same. Its rigid solver treats them as MuJoCo does: the range as a limit constraint, damping
            # as a joint force -c qdot integrated implicitly, friction as frictionloss (a constraint row
            # bounded by +-friction).
            entity.set_dofs_limit(np.array([sus.lower]), np.array([sus.upper]), dof)
            entity.set_dofs_damping(np.array([sus.damping]), dof)
            entity.set_dofs_frictionloss(np.array([sus.friction]), dof)
            entity.set_dofs_kp(np.zeros(1), dof)
            entity.set_dofs_kv(np.zeros(1), dof)
        # each coupling once: the parser's joint equality (q1 = offset + multiplier q0, a MuJoCo-style soft
        # equality row acting on both joints, with Genesis's default reference: read back, timeconst 0.01 s,
        # damping ratio 1, solimp 0.9 / 0.95)
        found = {(int(e.eq_obj1id), int(e.eq_obj2id)) for e in entity.equalities if e.type == gs.EQUALITY_TYPE.JOINT}
        wanted = {(entity.get_joint(c.joint).idx, entity.get_joint(c.leader).idx) for c in robot.couplings}
        if found != wanted:
            raise RuntimeError(f"genesis: joint equalities {sorted(found)} for the couplings {sorted(wanted)}")

    def set_wheel_targets(self, speeds: np.ndarray) -> None:
        speeds = np.asarray(speeds, dtype=float).reshape(len(self.robots), -1)
        for entity, dofs, row in zip(self.robots, self.dofs, speeds):
            entity.control_dofs_velocity(row, dofs)

    def step(self, n: int = 1) -> None:
        for _ in range(n):
            self.scene.step()

    def read(self) -> BaseState:
        """The recorded robot's base_link pose and twist (world frame, at the link origin) and wheel speeds."""
        i = self.scenario.recorded_robot
        entity = self.robots[i]

        def arr(t) -> np.ndarray:
            return np.asarray(t.cpu().numpy() if hasattr(t, "cpu") else t, dtype=float).reshape(-1)

        return BaseState(
            arr(entity.get_pos()),
            arr(entity.get_quat()),
            arr(entity.get_vel()),
            arr(entity.get_ang()),
            arr(entity.get_dofs_velocity(self.dofs[i])),
        )


class GenesisEngine(IsolatedAdapter):
    """Genesis as an engine adapter; its world runs where genesis-world is installed (simpick.engines.isolated)."""

    name = "genesis"
    settings_model = GenesisSettings
    simulates_suspension = True
    distribution = "genesis-world"
    calibratable = {
        "friction": FRICTION,
        # the velocity gain: from 300 (a tenth) to 30 000 (ten times the measured 3000)
        "wheel_kv": Calibratable(300.0, 30000.0, log=True, why="a tenth to ten times the measured 3000"),
    }

    def build_here(self, scenario: Scenario) -> GenesisWorld:
        return GenesisWorld(scenario, GenesisSettings.of(scenario.settings, self.name))
