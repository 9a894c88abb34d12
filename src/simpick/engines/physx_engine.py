"""NVIDIA PhysX 5 (the physics of Isaac Sim and Isaac Lab) through SAPIEN 3 on the CPU.

- world: ``sapien.Scene([sapien.physx.PhysxCpuSystem()])``; the solver type (TGS/PGS) and gravity
  are scene-wide and SAPIEN reads them from its default scene config when the system is created,
  so :meth:`PhysxEngine.build` sets that config first. SAPIEN's CPU system runs PhysX on the
  calling thread (no worker threads), which keeps a run deterministic.
- robot: the scenario's URDF through SAPIEN's loader as a floating-base articulation
  (``fix_root_link = False``). The loader refuses a URDF with ``<visual>`` elements when no
  rendering device exists ("failed to find a rendering device"), so it reads a temporary copy with
  the visuals stripped (collision mesh paths made absolute). Everything else (wheel joints, base
  link, masses, inertias, collision shapes) comes from the URDF as it is. SAPIEN turns a URDF
  cylinder into a convex mesh. Any :class:`~simpick.inputs.robot.RobotSpec`: the driven wheels get drives
  in command order (their joint's own sign), casters and swivels are undriven articulation joints,
  a skid is a base shape with the robot's friction, and one robot's links never collide with each
  other (SAPIEN collision groups; PhysX itself excludes only a link and its parent).
- passive suspension (RobotSpec.suspension): limited articulation joints, the description's
  damping as an implicit velocity drive to 0, its friction as a joint force set before each step,
  and one fixed tendon per coupling (the URDF's <mimic> is stripped, so SAPIEN's loader makes none):
  :meth:`PhysxEngine._suspension`, :class:`PhysxWorld`.
- wheels: PhysX articulation velocity drives (stiffness 0, damping ``wheel_drive_damping``, force
  limit ``scenario.max_wheel_torque``): the implicit drive Isaac Lab's ``ImplicitActuatorCfg``
  configures for wheels (its Jetbot: stiffness 0, damping 1e5).
- friction: PhysX combines two materials' coefficients by their *average* (its default combine
  mode; SAPIEN 3.0.3 does not expose another). The robot's shapes get 0 and every ground or
  terrain shape twice its coefficient, so a wheel contact has exactly the terrain's (or the
  ground's) mu; robot-robot contacts are frictionless. Static = dynamic coefficient.
- IMU: none in PhysX; :func:`simpick.engines.kinematics.imu_from_kinematics` from base_link kinematics. PhysX
  reports a link's velocity at its centre of mass, converted here to base_link's origin.

Three corrections of ours: PhysX gives every articulation link 0.05 /s of linear
and angular damping by default (a robot coasting on frictionless ground lost 1.3 N of momentum),
set to 0 here; every articulation joint a friction coefficient of 0.05, which no URDF asks for (a
caster dragged: the diff-drive robot's locked-wheel slide +6.3 % against +3.0 % without), set to 0;
and the wheel cylinders become turned convex prisms (``PhysxSettings.wheel_prisms``).

Skid-steer turning. With the set-up Isaac Lab uses (TGS, 4 position / 0 velocity
iterations, implicit velocity drives) the Husky turns at a yaw-rate gain of 0.103 at (v, w) =
(0.5, 0.5) on mu 0.8, 0.191 in a spin and 0.081 at (0.5, 0.2), against the Coulomb 0.478 (the
validation cases, 6 s, second half); the same from headings 0 / 22.5 / 45 deg (0.103 / 0.102 /
0.102) and mirrored (w < 0: 0.091-0.094), so it is not world-aligned friction as in Bullet. A
spin at mu 0.2 does reach 0.477. Earlier variants, 4 s runs at 1 kHz with SAPIEN's cylinder and
the default link damping, yaw rate averaged after 1 s; nothing exposed moves the gain to Coulomb:
  variant                                              (0.5,0.5)   (0,0.5)
  SAPIEN defaults (TGS, 10/1 iterations, damping 1e3)  0.117       0.20
  PGS                                                  0.194       0.36-0.39
  TGS 50/10 iterations, PGS 50/10                      0.128 / 0.161
  drive damping 1e4 / 1e5                              0.116 / 0.112
  friction every iteration off; PCM off                0.117; 0.118
  torsional patch radius 0 / 5 cm                      0.117 / 0.117
  compliant contact 1e5 / 1e6 N/m (negative restitution)  0.123 / 0.167  0.20 / 0.20
  wheel as a sphere or a capsule (one contact per wheel)   0.114-0.116  0.20
The rigid contacts leave the four wheel loads indeterminate (at rest FL/FR/RL/RR 82/187/117/164 N
against the rigid-body 105/172/105/173; compliant 1e6 N/m: 104/157/104/156), but equalising them
does not restore the turn. The cause is PhysX's friction model: per friction anchor two rows,
each clamped on its own to mu N (a box, not a cone), along tangents built from the relative
*linear* velocity of the two bodies' centres (``computeFrictionTangents(b0.getLinVel() -
b1.getLinVel(), ...)`` in PhysX's ``DyContactPrep``), i.e. along the wheel centre's travel, not
the contact's slip. A box lets a skidding wheel carry full lateral *and* longitudinal friction at
once, which the cone does not (ODE's friction pyramid under-turned the same way, 0.03-0.21; DART's
Dantzig box 0.004 rad/s). PhysX's other friction types (one-/two-directional) and the friction
correlation distance are not reachable through SAPIEN 3.0.3 (its CPU system leaves PxSceneDesc's
frictionType and frictionCorrelationDistance at their defaults: patch friction, 0.025 m, the
values Isaac Lab's PhysxCfg also uses). So this is reported as PhysX's finding, as Bullet's is.

PGS with the tuned profile's iterations (64 position / 4 velocity, 4 prisms, 6 s cases, 2026-12-06) turns the
Husky one way only: gain 0.0038 at (0.5, 0.5) and 0.4759 at (0.5, -0.5) on mu 0.8 (1 velocity iteration:
0.0037 / 0.4765; 32 position: 0.0103 / 0.4964), where TGS turns it alike both ways (0.1116 / 0.1113). The
validation's mirrored cases fail it on the left turns; its right turns pass, which is how the tuning's "most
cases passed" chose it.
"""

from __future__ import annotations

import importlib.metadata
import math
import tempfile
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import Field

from simpick.engines.base import FRICTION, BaseStates, EngineSettings, Scenario
from simpick.engines.kinematics import rotation_matrices
from simpick.engines.runner import Adapter
from simpick.errors import InputError

SPAWN_CLEARANCE = 0.002  # m above resting height, as for the other engines
# SAPIEN's plane collision has its normal along +x; this turns it onto +z (a -90 deg turn about y)
# sides of one convex prism standing in for a wheel cylinder: the most SAPIEN's convex cooking keeps
# (a 96-sided prism came back with 128 vertices)
PRISM_SIDES = 64
PLANE_UP = (math.sqrt(0.5), 0.0, -math.sqrt(0.5), 0.0)
# The fixed tendon coupling two suspension joints (RobotSpec.couplings), N m/rad and N m s/rad: PhysX
# solves a tendon's spring-damper implicitly inside the articulation, as it does a drive. SAPIEN's
# loader gives a <mimic> 1e5 N m/rad and no damping. Measured on the Warthog at 1 kHz, the coupling's
# residual q(right) + q(left) at rest (2 s) / after a 2 s spin at +-0.5 m/s rims: 1e5 and 0 (SAPIEN's)
# 4.0e-4 / 4.5e-4 rad, 1e5 and 1e4 5.2e-4 / 4.9e-4, 1e6 and 1e4 5.1e-5 / 6.2e-5 (chosen; the same
# chassis pitch at rest, -0.0015 deg, and spin gain, 0.14, within 0.015 deg and 0.003)
COUPLING_STIFFNESS = 1.0e6
COUPLING_DAMPING = 1.0e4
# Suspension joint friction (the description's <dynamics friction>, N m): SAPIEN's loader reads it and
# never applies it, and PhysX's joint friction is a coefficient on the force through the joint, not a
# torque. So it is a joint force set before every step, -friction x clip(speed / FRICTION_SPEED, -1, 1):
# Coulomb above FRICTION_SPEED, a steep viscous slope below it (friction / FRICTION_SPEED = 500 N m s/rad
# for the Warthog's 0.5 N m; explicit, and stable while slope x timestep is well under the joint's
# inertia, about 10 kg m^2 for a rocker: 0.05 at 1 kHz).
FRICTION_SPEED = 1.0e-3  # rad/s


class PhysxSettings(EngineSettings):
    """config ``engines.physx``; the measurements behind each choice are in the module docstring."""

    # PxSceneDesc solverType: "tgs" (Temporal Gauss-Seidel), Isaac Lab's default (PhysxCfg
    # solver_type=1, "recommended for articulated robots") and SAPIEN's; "pgs" turns the Husky more
    # (0.19 at (0.5, 0.5) for TGS's 0.11) but still far under the Coulomb 0.478
    solver: Literal["tgs", "pgs"] = "tgs"
    # per-articulation solver iterations: 4 position / 0 velocity, Isaac Lab's wheeled-robot asset
    # (isaaclab_assets JETBOT_CFG, ArticulationRootPropertiesCfg); 50 / 10 measured to change the
    # turning gain by < 0.02
    position_iterations: Annotated[int, Field(ge=1, le=255)] = 4
    velocity_iterations: Annotated[int, Field(ge=0, le=255)] = 0  # (see position_iterations)
    # N m s/rad, the wheels' implicit velocity drive (stiffness 0): Isaac Lab's Jetbot wheel
    # actuator (ImplicitActuatorCfg damping 1e5); 1e3 (SAPIEN examples) and 1e4 give the same gains
    wheel_drive_damping: Annotated[float, Field(gt=0, allow_inf_nan=False)] = 1.0e5
    # convex 64-sided prisms that together stand in for each URDF collision cylinder (a wheel), each
    # turned by 1/wheel_prisms of a side. SAPIEN's own cylinder is a coarse convex mesh and its
    # convex cooking keeps at most 128 vertices (64 sides). Each vertex landing is an inelastic
    # impact: with the wheel torque bound at 2 N m the Husky accelerates at 0.684 m/s^2 on SAPIEN's
    # cylinder, 0.726 / 0.748 / 0.752 / 0.757 on 1 / 2 / 4 / 8 prisms, for the analytic 0.768
    # (the conformance suite's 2 % tolerance needs >= 0.753)
    wheel_prisms: Annotated[int, Field(ge=1, le=16)] = 4
    # m, PxShape contactOffset of every shape: SAPIEN's default shape config (0.01 m), as in
    # Isaac Gym-style PhysX configs (contact_offset 0.01, rest_offset 0)
    contact_offset: Annotated[float, Field(gt=0, allow_inf_nan=False)] = 0.01
    # m/s, PxSceneDesc bounceThresholdVelocity: Isaac Lab 2.x PhysxCfg default (0.5); with
    # restitution 0 everywhere nothing bounces anyway
    bounce_threshold: Annotated[float, Field(gt=0, allow_inf_nan=False)] = 0.5


def _quiet_import():
    with warnings.catch_warnings():
        # SAPIEN warns at import that it falls back to its bundled libvulkan: the renderer is never used
        warnings.simplefilter("ignore")
        import sapien
        import sapien.physx
    return sapien


def cylinder_obj(radius: float, length: float, segments: int, phase: float = 0.0) -> str:
    """Wavefront OBJ text of a closed prism: ``segments`` sides around the z axis (the URDF
    cylinder's axis), vertices on the circle of ``radius``, from z = -length/2 to +length/2."""
    angles = 2 * np.pi * np.arange(segments) / segments + phase
    lines = []
    for z in (-length / 2, length / 2):
        lines += [f"v {radius * math.cos(a):.9f} {radius * math.sin(a):.9f} {z:.9f}" for a in angles]
    n = segments
    for i in range(n):  # sides (1-based OBJ indices), then the two caps
        j = (i + 1) % n
        lines.append(f"f {i + 1} {j + 1} {n + j + 1} {n + i + 1}")
    lines.append("f " + " ".join(str(i + 1) for i in reversed(range(n))))
    lines.append("f " + " ".join(str(n + i + 1) for i in range(n)))
    return "\n".join(lines) + "\n"


def collision_only_urdf(urdf: Path, folder: Path, prisms: int) -> Path:
    """A copy of ``urdf`` in ``folder`` without ``<visual>`` or ``<mimic>`` elements, mesh paths made
    absolute, and each collision cylinder replaced by ``prisms`` convex 64-sided prisms, each turned by
    1/``prisms`` of a side against the previous one: together a 64 x ``prisms``-sided wheel.

    ``<mimic>`` goes because SAPIEN's loader would turn it into a fixed tendon of its own (stiffness
    1e5, and for a multiplier other than -1 or 1 the wrong linear combination: it builds
    ``-m q(follower) + q(leader)``); the adapter couples the joints itself from RobotSpec.couplings."""
    try:
        tree = ET.parse(urdf)
    except (OSError, ET.ParseError) as exc:
        raise InputError(str(urdf), f"cannot read the robot description: {exc}") from None
    root = tree.getroot()
    for joint in root.iter("joint"):
        for mimic in joint.findall("mimic"):
            joint.remove(mimic)
    for link in root.iter("link"):
        for visual in link.findall("visual"):
            link.remove(visual)
    for mesh in root.iter("mesh"):
        name = mesh.get("filename", "")
        if name and "://" not in name and not Path(name).is_absolute():
            mesh.set("filename", str((urdf.parent / name).resolve()))
    k = 0
    for link in root.iter("link"):
        for collision in link.findall("collision"):
            cylinder = collision.find("geometry/cylinder")
            if cylinder is None:
                continue
            try:
                radius, length = float(cylinder.get("radius")), float(cylinder.get("length"))
            except (TypeError, ValueError):
                raise InputError(
                    str(urdf), f"a collision cylinder needs a numeric radius and length, got {cylinder.attrib}"
                ) from None
            link.remove(collision)
            for p in range(prisms):
                obj = folder / f"cylinder{k}_{p}.obj"
                obj.write_text(cylinder_obj(radius, length, PRISM_SIDES, 2 * math.pi * p / (PRISM_SIDES * prisms)))
                copy = ET.SubElement(link, "collision")
                if collision.find("origin") is not None:
                    copy.append(collision.find("origin"))
                ET.SubElement(ET.SubElement(copy, "geometry"), "mesh", {"filename": str(obj)})
            k += 1
    out = folder / urdf.name
    tree.write(out)
    return out


def _yaw_quat(yaw: float) -> list[float]:
    return [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]


class PhysxEngine(Adapter):
    # SAPIEN 3.0.3 exposes one contact parameter that matters here, the friction coefficient
    # (no material damping, so no tunable compliant contact)
    calibratable = {"friction": FRICTION}
    name = "physx"
    settings_model = PhysxSettings
    simulates_suspension = True  # limits, damping, friction and couplings: PhysxEngine._suspension, PhysxWorld.step

    def version(self) -> str:
        sapien = _quiet_import()
        return f"{importlib.metadata.version('sapien')} ({sapien.physx.version()})"

    def build(self, scenario: Scenario) -> PhysxWorld:
        """The scene, and per robot (articulation, its driven wheel joints in simpick's order)."""
        sapien = _quiet_import()
        px = sapien.physx
        settings = PhysxSettings.of(scenario.settings, self.name)

        config = px.PhysxSceneConfig()
        config.gravity = list(scenario.gravity)
        config.enable_tgs = settings.solver == "tgs"
        config.bounce_threshold = settings.bounce_threshold
        px.set_scene_config(config)  # read by the system's constructor
        shapes = px.get_shape_config()
        shapes.contact_offset = settings.contact_offset
        shapes.rest_offset = 0.0
        px.set_shape_config(shapes)
        system = px.PhysxCpuSystem()
        system.set_timestep(scenario.timestep)
        scene = sapien.Scene([system])

        def material(mu: float):  # averaged with the robot's 0: the contact gets mu
            # SAPIEN 3.0.3's PhysxMaterial has static, dynamic friction and restitution only: no
            # anisotropic (lateral/longitudinal) friction to set
            return px.PhysxMaterial(2 * mu, 2 * mu, 0.0)

        terrain = scenario.terrain
        ground = scene.create_actor_builder()
        ground.add_plane_collision(sapien.Pose(q=list(PLANE_UP)), material=material(scenario.ground_friction))
        shape_material = material(float(terrain.friction))
        for x, y, z, yaw, sx, sy, sz in terrain.boxes:
            ground.add_box_collision(
                sapien.Pose([x, y, z], _yaw_quat(yaw)), half_size=[sx / 2, sy / 2, sz / 2], material=shape_material
            )
        for x, y, z, r in terrain.spheres:
            ground.add_sphere_collision(sapien.Pose([x, y, z]), radius=r, material=shape_material)
        ground.build_static(name="terrain")

        robot = scenario.robot
        robots = []
        with tempfile.TemporaryDirectory(prefix="simpick-physx-") as folder:
            urdf = collision_only_urdf(Path(robot.urdf), Path(folder), settings.wheel_prisms)
            loader = scene.create_urdf_loader()
            loader.fix_root_link = False
            loader.set_material(0.0, 0.0, 0.0)  # see the module docstring: the terrain carries mu
            for i, (x, y, yaw) in enumerate(scenario.starts):
                try:
                    art = loader.load(str(urdf))
                except Exception as exc:  # SAPIEN raises RuntimeError with its parser's message
                    raise InputError(str(robot.urdf), f"SAPIEN's URDF loader could not read the robot: {exc}") from None
                art.name = f"robot{i}"
                art.set_root_pose(sapien.Pose([x, y, robot.base_height + SPAWN_CLEARANCE], _yaw_quat(yaw)))
                art.set_solver_position_iterations(settings.position_iterations)
                art.set_solver_velocity_iterations(settings.velocity_iterations)
                for link in art.links:  # PhysX gives articulation links 0.05 /s damping by default
                    link.linear_damping = 0.0
                    link.angular_damping = 0.0
                    # a robot's own links never touch each other, as in the other engines: PhysX
                    # filters only parent and child links, and the diff-drive robot's caster wheel
                    # (the chassis's grandchild) pushed on the chassis (impulses up to 0.28 N s a
                    # step in a spin). Shapes sharing SAPIEN's "id group" (g3) and an "ignore
                    # group" bit (g2) never collide; other robots and the terrain (g3 0) still do.
                    for shape in link.collision_shapes:
                        g0, g1, g2, _ = shape.get_collision_groups()
                        shape.set_collision_groups([g0, g1, g2 | 1 << 31, i + 1])
                for joint in art.active_joints:
                    # PhysX gives every articulation joint a friction coefficient of 0.05 (a
                    # resisting torque in proportion to the force through the joint); the URDF
                    # gives none (SAPIEN's loader reads <dynamics friction> but never applies it, and
                    # its N m have no counterpart in the coefficient). At 0.05 the diff-drive robot's
                    # caster dragged: locked-wheel slide 2.449 m/s^2 for the analytic 2.303 (+6.3 %),
                    # at 0 2.373 (+3.0 %); the Husky's torque-bound acceleration 0.7523 -> 0.7522
                    joint.friction = 0.0
                joints = {j.name: j for j in art.active_joints}
                missing = [n for n in robot.wheel_joints if n not in joints]
                if missing:
                    raise InputError(
                        str(robot.urdf), f"wheel joints {missing} are not movable joints of the articulation"
                    )
                wheels = [joints[n] for n in robot.wheel_joints]
                for joint in wheels:
                    joint.set_drive_properties(0.0, settings.wheel_drive_damping, scenario.max_wheel_torque, "force")
                    joint.set_drive_velocity_target(0.0)
                self._suspension(art, joints, robot)
                robots.append((art, wheels))
        return PhysxWorld(scene, robots, scenario)

    @staticmethod
    def _suspension(art, joints: dict, robot) -> None:
        """The robot's passive suspension joints: limits, damping (friction: PhysxWorld.step) and couplings."""
        for sus in robot.suspension:
            joint = joints[sus.joint]
            joint.limit = [[sus.lower, sus.upper]]  # as SAPIEN's loader reads them; PhysX enforces them
            # the description's viscous damping: an implicit velocity drive to 0 with damping only and no
            # force bound, what SAPIEN's loader makes of <dynamics damping> (stated here, not left to it)
            joint.set_drive_properties(0.0, sus.damping, 3.4e38, "force")
            joint.set_drive_velocity_target(0.0)
        links = {j.name: j.child_link for j in art.joints if j.name}
        for c in robot.couplings:
            follower, leader = joints[c.joint], joints[c.leader]
            if follower.parent_link is not leader.parent_link:  # a fixed tendon spans joints on one parent here
                raise InputError(
                    f"robot couplings ({c.source})",
                    f"{c.joint!r} and {c.leader!r} hang on different links: the PhysX adapter couples "
                    "suspension joints only on the same parent link",
                )
            # tendon length = q(follower) - multiplier q(leader), held at the offset (rest length)
            art.create_fixed_tendon(
                [follower.parent_link, links[c.joint], links[c.leader]],
                [0.0, 1.0, -c.multiplier],
                [0.0, 1.0, -1.0 / c.multiplier],
                rest_length=c.offset,
                stiffness=COUPLING_STIFFNESS,
                damping=COUPLING_DAMPING,
            )


class PhysxWorld:
    """One SAPIEN scene (simpick.engines.base.World). PhysX gives the centre of mass's velocity;
    base_link's origin moves at v - w x (R c)."""

    def __init__(self, scene, robots: list, scenario: Scenario):
        self.scene, self.robots = scene, robots
        art, wheels = robots[scenario.recorded_robot]
        self.art, self.base = art, art.find_link_by_name(scenario.robot.base_link)
        if self.base is None:
            raise InputError(str(scenario.robot.urdf), f"no link {scenario.robot.base_link!r} in the articulation")
        order = [j.name for j in art.active_joints]
        self.wheel_dofs = [order.index(j.name) for j in wheels]
        self.com = np.asarray(self.base.cmass_local_pose.p, dtype=float)  # centre of mass in base_link
        # suspension joint friction (see FRICTION_SPEED): per robot its articulation, the suspension dofs
        # and their friction torques; None when no joint has friction
        robot = scenario.robot
        dofs = [order.index(s.joint) for s in robot.suspension if s.friction > 0]
        torques = np.array([s.friction for s in robot.suspension if s.friction > 0])
        self.friction = [(a, dofs, torques, np.zeros(len(order))) for a, _ in robots] if dofs else None

    def set_wheel_targets(self, speeds: np.ndarray) -> None:
        for (_, wheels), robot_speeds in zip(self.robots, speeds):
            for joint, w in zip(wheels, robot_speeds.tolist()):
                joint.set_drive_velocity_target(w)

    def step(self, n: int = 1) -> None:
        step = self.scene.step
        if self.friction is None:
            for _ in range(n):
                step()
            return
        clip = np.clip
        for _ in range(n):
            for art, dofs, torques, qf in self.friction:
                qf[dofs] = -torques * clip(art.qvel[dofs] / FRICTION_SPEED, -1.0, 1.0)
                art.qf = qf
            step()

    def read(self) -> tuple:
        pose, base = self.base.entity_pose, self.base
        # every joint speed, the wheels' picked out once in states (indexing here cost 0.7 us a step)
        return pose.p, pose.q, base.linear_velocity, base.angular_velocity, self.art.qvel

    def states(self, samples: list) -> BaseStates:
        position, quat, v_com, omega, qvel = (
            np.array([s[i] for s in samples], dtype=float).reshape(len(samples), -1) for i in range(5)
        )
        wheel_speed = qvel[:, self.wheel_dofs]
        quat /= np.linalg.norm(quat, axis=1, keepdims=True)
        quat *= np.where(quat[:, :1] < 0, -1.0, 1.0)
        velocity = v_com - np.cross(omega, rotation_matrices(quat) @ self.com)
        return BaseStates(
            position=position,
            quaternion=quat,
            linear_velocity=velocity,
            angular_velocity=omega,
            wheel_speed=wheel_speed,
        )
