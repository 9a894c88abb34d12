"""Newton (NVIDIA, Google DeepMind, Disney; Linux Foundation), the physics library on Warp that
Isaac Lab 3 offers beside PhysX, with every rigid-body solver a user of it would pick.

The world: the robot's URDF through Newton's own importer (``ModelBuilder.add_urdf``, floating
base, no self-collision, as the other engines), the engine-neutral terrain as static boxes and
spheres on a ground plane, the driven wheels as Newton velocity drives (``JointTargetMode.VELOCITY``:
torque = ``wheel_drive_damping`` x speed error, clamped to the scenario's torque bound through the
joint's ``effort_limit``), the passive joints free. Newton runs on Warp's CPU device here.

Passive suspension (rockers), SolverMuJoCo only: the importer's revolute joints, free, with the spec's limits
(MuJoCo's solreflimit passed raw), damping and frictionloss; each coupling is the joint mimic the importer makes
from the <mimic> that :func:`simpick.engines.suspension.coupled_urdf` writes, which SolverMuJoCo passes as a
MuJoCo joint equality. Measured on the Warthog (1 kHz, mu 0.8, 500 N m): pitch -0.011 degrees at rest, base
1.5 mm low; uncoupled, on a rocker stop at 8.610 degrees; spin gain 0.578 (Coulomb 0.591). SolverSteel left
the limits unenforced (21.6 degrees uncoupled), so the adapter refuses a suspended robot on any other solver.

Solvers (setting ``solver``), measured on the validation's yaw-gain cases (Husky, mu 0.8, 1 kHz,
analytic Coulomb gain 0.478; left / right / left from 45 degrees):

* ``mujoco``: :class:`newton.solvers.SolverMuJoCo`, the set-up Isaac Lab validates its Newton
  backend with (MuJoCo's constraint solver on Newton's model). Why it turns at half the mechanics'
  rate out of the box (Newton's defaults: pyramidal cone, impratio 1, MuJoCo's default soft
  contact; measured 0.14 / 0.15 / 0.32 pyramidal, 0.24 / 0.27 / 0.25 elliptic): the mechanism
  simpick's MuJoCo adapter documents (:mod:`simpick.engines.mujoco_engine`): MuJoCo's soft contact
  turns a sliding contact's friction demand into extra normal force, so the sliding wheels of a
  skid-steer turn hop. Newton's model carries every MuJoCo setting the cure needs, as documented
  custom attributes: ``wheel_contact: pairs`` (the default) gives each wheel x ground shape a
  MuJoCo <pair> (``mujoco:pair_*``: solref, solreffriction, solimp, friction, condim 3, the MuJoCo
  adapter's values) and filters the wheel's automatic contact with that shape
  (``add_shape_collision_filter_pair``), with the solver's ``impratio``: 0.460 / 0.470 / 0.460 with
  Newton's joint drive, 0.4617 / 0.4724 / 0.4617 with the MuJoCo actuators (torque bound below), the
  MuJoCo adapter's 0.462 / 0.472 / 0.462, and its 1.5 mm resting sag. ``decoupled`` sets only
  the shape attributes (``mujoco:geom_solimp`` on wheels and ground, impratio), with which the
  friction rows keep the reference that solref implies (solreffriction exists only on pairs):
  0.44 / 0.45 / 0.44.
* ``xpbd``: :class:`~newton.solvers.SolverXPBD` (position-based). Its docstring says it does not
  support a joint's effort limit, so the drive is unbounded. Why the wheels lock (measured: at
  v 0.1 a wheel stops at 5.2 s = pi / 0.606 rad/s, i.e. after half a turn): its angular joint
  constraint (xpbd/kernels.py, the revolute / D6 branch) measures a joint's twist as
  ``2 asin(q_x)`` of the relative quaternion, after putting both quaternions in one hemisphere,
  and scales the twist's gradient by ``2 / |q_w|``. At half a turn q_w = 0: the gradient diverges,
  the hemisphere flip turns +pi into -pi, and the velocity drive's correction goes to zero, so a
  continuous joint cannot be driven past half a turn. A wheel is the one joint that must. The
  gain comes out with the wrong sign (-0.151 / 0.154 / -0.151). Shown as a finding.
* ``steel``: :class:`~newton.solvers.SolverSteel` (experimental: reduced coordinates, projected
  Gauss-Seidel). Needs ``articulation_constraint_max`` 128 for the Husky (its default 32 drops
  contact rows and the robot sits 4.5 cm low); on CPU only ``friction_mode`` "fixed_normal".
* ``kamino``: :class:`~newton.solvers.SolverKamino` (beta; NCP with hard frictional contact).
  25-29 steps/s on this CPU.

Every solver sees the same model; only ``solver`` and its own options change.

Torque bound (conformance test: servos saturated at 2 N m, rolling without slip, 0.768 m/s^2):
with Newton's joint velocity drive (``wheel_drive: joint``) SolverMuJoCo gives 0.123 and Steel 0.096.
Newton turns a joint's ``effort_limit`` into MuJoCo's joint-level ``actfrcrange`` (the drive's actuator
has no forcerange), and the implicit integrator keeps the velocity drive's derivative (kv 3000) while
the total is clamped: a saturated wheel is damped as if by 3000 N m s/rad (kv 50: 0.690). MuJoCo drops
that derivative for an *actuator* forcerange, so under SolverMuJoCo the wheels are driven, as in the
MuJoCo adapter, by MuJoCo <intvelocity> actuators through Newton's ``mujoco:actuator_*`` attributes
(``wheel_drive: intvelocity``, the default): 0.771, and the turning gains 0.4617 / 0.4724 / 0.4617,
the MuJoCo adapter's to four digits.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

import numpy as np
from pydantic import Field

from simpick.engines.base import FRICTION, BaseState, Calibratable, EngineSettings, Scenario
from simpick.engines.isolated import IsolatedAdapter
from simpick.engines.suspension import coupled_urdf

SPAWN_CLEARANCE = 0.002  # m above resting height, as for the other engines
SOLVERS = ("mujoco", "xpbd", "steel", "kamino")
# MuJoCo's default contact reference (solref timeconst 0.02 s) and largest default impedance (solimp dmax 0.95),
# from which the MuJoCo adapter derives its wheel pairs' friction reference; the same two MuJoCo defaults here,
# so that a Newton job holds no other adapter's code (tests/test_new_engines.py checks they agree)
MUJOCO_TIMECONST, MUJOCO_DMAX = 0.02, 0.95
# Newton's mujoco:solreflimit_mode for a raw MuJoCo solreflimit (newton/_src/solvers/mujoco/constants.py, 1.8.0)
SOLREF_MODE_RAW = 1


class NewtonSettings(EngineSettings):
    """config ``engines.newton``."""

    # Which of Newton's rigid-body solvers steps the world (module docstring: what each gave).
    solver: Literal["mujoco", "xpbd", "steel", "kamino"] = "mujoco"
    # SolverMuJoCo's backend: "c", MuJoCo's C library (use_mujoco_cpu=True), or "warp", mujoco-warp
    # (Isaac Lab's GPU path). Same physics (measured: gain 0.233 on C, 0.249 on warp, default
    # contact), 2 100 against 170-180 steps/s on this CPU, so "c" where Warp runs on the CPU.
    mujoco_backend: Literal["c", "warp"] = "c"
    # MuJoCo's friction cone; Newton's default is "pyramidal". "elliptic": the Coulomb cone, as the
    # MuJoCo adapter, and what MuJoCo's docs recommend against contact slip.
    mujoco_cone: Literal["elliptic", "pyramidal"] = "elliptic"
    # "decoupled": the wheel shapes get the MuJoCo adapter's contact impedance (solimp d 0.015)
    # and the solver its impratio (friction rows at impedance 0.98), see NewtonWorld._mujoco_attributes;
    # "default": Newton's conversion of its shape material to MuJoCo (the Isaac Lab set-up as shipped)
    # "pairs": the MuJoCo adapter's wheel x ground contact pairs exactly (solref, solreffriction, solimp),
    # as Newton's mujoco:pair_* attributes, the wheels' automatic ground contacts filtered out
    wheel_contact: Literal["pairs", "decoupled", "default"] = "pairs"
    # solimp d of the wheel shapes under "decoupled": the MuJoCo adapter's measured value
    wheel_contact_impedance: Annotated[float, Field(gt=0, lt=1)] = 0.015
    # impedance of the friction rows via impratio under "decoupled": the MuJoCo adapter's value
    wheel_friction_impedance: Annotated[float, Field(gt=0, lt=1)] = 0.98
    # N m s/rad, the velocity drive's gain (target_kd). 3000: measured on Steel, with which the
    # issue's table was taken; the drive is implicit in MuJoCo and Steel, so a stiff gain is stable
    # and the wheels track their command within the torque bound.
    wheel_drive_damping: Annotated[float, Field(gt=0, allow_inf_nan=False)] = 3000.0
    # SolverMuJoCo's wheel drive. "intvelocity": a MuJoCo <intvelocity> actuator per wheel (Newton's
    # mujoco:actuator_* attributes), the MuJoCo adapter's servo, bounded by the actuator's forcerange, whose
    # saturated velocity derivative MuJoCo drops from the implicit step: torque-bound acceleration 0.771 m/s^2
    # (analytic 0.768), gains 0.4617 / 0.4724 / 0.4617. "joint": Newton's joint velocity drive (what Isaac Lab
    # configures), bounded by the joint's effort limit, which Newton writes as MuJoCo's joint-level actfrcrange:
    # the implicit step keeps the drive's damping (wheel_drive_damping) while the total is clamped, so a
    # saturated wheel is braked as by 3000 N m s/rad: 0.123 m/s^2. The other solvers always use the joint drive.
    wheel_drive: Literal["intvelocity", "joint"] = "intvelocity"
    # N m/rad, stiffness of the "intvelocity" servo (critically damped on the wheel's inertia): the MuJoCo
    # adapter's wheel_servo_kp
    wheel_servo_kp: Annotated[float, Field(gt=0, allow_inf_nan=False)] = 1000.0
    # Constraint solver iterations: MuJoCo's 100 (None in Newton: MuJoCo's default), XPBD's 2,
    # Steel's 12, Kamino's own; 0 keeps each solver's own default.
    iterations: Annotated[int, Field(ge=0)] = 0
    # Steel: rows per articulation; 128 keeps every contact row of a four-wheel robot (32, the
    # default, drops rows: measured, the Husky sat 4.5 cm low).
    steel_constraint_max: Annotated[int, Field(ge=32)] = 128


def intvelocity_actuator(kp: float, bound: float) -> dict:
    """``newton.solvers.mujoco.add_actuator_general``'s keywords, its target aside, of a MuJoCo <intvelocity>
    actuator (its control: the speed, integrated into a position setpoint; biasprm[2] 1: MuJoCo's dampratio,
    critically damped), force within +-``bound``."""
    return {
        "dyntype": "integrator",
        "gaintype": "fixed",
        "biastype": "affine",
        "gainprm": (kp,),
        "biasprm": (0.0, -kp, 1.0),
        "actlimited": False,  # a continuous joint: no setpoint range
        "forcerange": (-bound, bound),
        "forcelimited": True,
    }


def _intvelocity(builder, joint: int, kp: float, bound: float) -> int:
    """A MuJoCo <intvelocity> actuator on ``joint`` (:func:`intvelocity_actuator`); its row index."""
    from newton.solvers import mujoco

    return mujoco.add_actuator_general(builder, mujoco.ActuatorTarget.joint(joint), **intvelocity_actuator(kp, bound))


def solver_mujoco_options(settings: NewtonSettings) -> dict:
    """SolverMuJoCo's keywords, its model aside, as the adapter passes them."""
    options: dict = {"use_mujoco_cpu": settings.mujoco_backend == "c", "cone": settings.mujoco_cone}
    options["integrator"] = "implicitfast"
    if settings.wheel_contact != "default":
        d, df = settings.wheel_contact_impedance, settings.wheel_friction_impedance
        options["impratio"] = ((1 - d) / d) / ((1 - df) / df)
    if settings.iterations != 0:
        options["iterations"] = settings.iterations
    return options


def wheel_solimp(settings: NewtonSettings) -> tuple:
    """The MuJoCo solimp of the wheels' contacts under ``wheel_contact`` "decoupled" or "pairs": impedance
    ``wheel_contact_impedance``, constant with depth."""
    d = settings.wheel_contact_impedance
    return (d, d, 0.001, 0.5, 2.0)


def pair_values(settings: NewtonSettings, mu: float) -> dict:
    """The ``mujoco:pair_*`` values, its two shapes aside, of a wheel x ground shape pair of friction ``mu``
    (``wheel_contact`` "pairs": the MuJoCo adapter's pairs)."""
    d = settings.wheel_contact_impedance
    return {
        "mujoco:pair_condim": 3,
        "mujoco:pair_friction": (mu, mu, 0.0, 0.0, 0.0),
        "mujoco:pair_solref": (MUJOCO_TIMECONST, 1.0),
        "mujoco:pair_solreffriction": (MUJOCO_TIMECONST * MUJOCO_DMAX / d, 1.0),
        "mujoco:pair_solimp": wheel_solimp(settings),
        "mujoco:pair_margin": 0.0,
        "mujoco:pair_gap": 0.0,
    }


def robot_shape(mu: float) -> dict:
    """The robot shapes' ``ModelBuilder.ShapeConfig`` keywords: the ground's coefficient ``mu`` (on flat ground every
    solver's combination rule, MuJoCo: the larger, unless priority; XPBD and Steel: the mean, then gives mu itself)
    and no restitution."""
    return {"mu": mu, "restitution": 0.0}


# MuJoCo takes the friction (and every contact parameter) of the higher-priority geom: the ground's
GROUND_ATTRIBUTES = {"mujoco:geom_priority": 1}


def _yaw_quat_xyzw(yaw: float) -> tuple[float, float, float, float]:
    return (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))


class NewtonWorld:
    """One built Newton world: set_wheel_targets / step / read (see simpick.engines.base)."""

    def __init__(self, scenario: Scenario, settings: NewtonSettings):
        import warp as wp

        wp.config.quiet = True
        import newton

        self.scenario, self.settings = scenario, settings
        self.dt = scenario.timestep
        solver = settings.solver
        builder = newton.ModelBuilder(gravity=tuple(scenario.gravity))
        if solver == "mujoco":
            newton.solvers.SolverMuJoCo.register_custom_attributes(builder)
        elif solver == "kamino":
            newton.solvers.SolverKamino.register_custom_attributes(builder)
        ShapeConfig = newton.ModelBuilder.ShapeConfig
        robot_cfg = ShapeConfig(**robot_shape(scenario.ground_friction))
        builder.default_shape_cfg = robot_cfg
        ground_attrs = dict(GROUND_ATTRIBUTES) if solver == "mujoco" else None
        self.ground_shapes = [builder.shape_count]
        builder.add_shape_plane(
            cfg=ShapeConfig(mu=scenario.ground_friction), width=0.0, length=0.0, custom_attributes=ground_attrs
        )
        terrain = scenario.terrain
        for x, y, z, yaw, sx, sy, sz in terrain.boxes:
            self.ground_shapes.append(builder.shape_count)
            builder.add_shape_box(
                -1,
                xform=wp.transform((x, y, z), _yaw_quat_xyzw(yaw)),
                hx=sx / 2,
                hy=sy / 2,
                hz=sz / 2,
                cfg=ShapeConfig(mu=terrain.friction),
                custom_attributes=ground_attrs,
            )
        for x, y, z, r in terrain.spheres:
            self.ground_shapes.append(builder.shape_count)
            builder.add_shape_sphere(
                -1,
                xform=wp.transform((x, y, z), wp.quat_identity()),
                radius=r,
                cfg=ShapeConfig(mu=terrain.friction),
                custom_attributes=ground_attrs,
            )

        robot = scenario.robot
        self.base_bodies, wheel_dofs, wheel_shapes = [], [], []
        self.actuators = []
        # the robot's file with its <mimic> elements exactly the spec's couplings: Newton's importer turns each
        # into a joint-owned mimic (ModelBuilder.set_joint_mimic), checked in _suspend
        urdf = coupled_urdf(robot)
        for x, y, yaw in scenario.starts:
            joints0, bodies0 = builder.joint_count, builder.body_count
            builder.add_urdf(
                str(urdf),
                xform=wp.transform((x, y, robot.base_height + SPAWN_CLEARANCE), _yaw_quat_xyzw(yaw)),
                floating=True,
                enable_self_collisions=False,
            )
            labels = {builder.joint_label[j].rsplit("/", 1)[-1]: j for j in range(joints0, builder.joint_count)}
            bodies = {builder.body_label[b].rsplit("/", 1)[-1]: b for b in range(bodies0, builder.body_count)}
            self.base_bodies.append(bodies[robot.base_link])
            dofs = []
            for name in robot.wheel_joints:
                j = labels[name]
                dof = builder.joint_qd_start[j]
                if solver == "mujoco" and settings.wheel_drive == "intvelocity":
                    builder.joint_target_mode[dof] = int(newton.JointTargetMode.NONE)
                    builder.joint_target_ke[dof] = builder.joint_target_kd[dof] = 0.0
                    self.actuators.append(_intvelocity(builder, j, settings.wheel_servo_kp, scenario.max_wheel_torque))
                else:
                    builder.joint_target_mode[dof] = int(newton.JointTargetMode.VELOCITY)
                    builder.joint_target_ke[dof] = 0.0
                    builder.joint_target_kd[dof] = settings.wheel_drive_damping
                    builder.joint_effort_limit[dof] = scenario.max_wheel_torque
                dofs.append(dof)
                child = builder.joint_child[j]
                wheel_shapes += [s for s in range(builder.shape_count) if builder.shape_body[s] == child]
            for name in robot.passive_joints:
                j = labels[name]
                for dof in range(builder.joint_qd_start[j], builder.joint_qd_start[j] + builder.joint_dof_dim[j][1]):
                    builder.joint_target_mode[dof] = int(newton.JointTargetMode.NONE)
                    builder.joint_target_kd[dof] = builder.joint_target_ke[dof] = 0.0
            self._suspend(builder, labels)
            wheel_dofs.append(dofs)
        if solver == "mujoco" and settings.wheel_contact == "decoupled":
            self._mujoco_attributes(builder, wheel_shapes)
        elif solver == "mujoco" and settings.wheel_contact == "pairs":
            self._mujoco_pairs(builder, wheel_shapes)
        self.model = model = builder.finalize(device="cpu")
        self.wheel_dofs = np.asarray(wheel_dofs)
        self.base_com = model.body_com.numpy()[self.base_bodies[scenario.recorded_robot]].astype(float)
        self.state_0, self.state_1 = model.state(), model.state()
        self.control = model.control()
        newton.eval_fk(model, model.joint_q, model.joint_qd, self.state_0)
        self.target = np.zeros(model.joint_dof_count, dtype=np.float32)
        self.contacts, self.pipeline = None, None
        self.solver = self._solver(newton, model)
        if self.pipeline is None and solver != "mujoco":
            self.pipeline = newton.CollisionPipeline(model)
            self.contacts = self.pipeline.contacts()

    def _suspend(self, builder, labels: dict[str, int]) -> None:
        """One robot's passive suspension joints (``labels``: joint name -> index): free but for the
        spec's limits, damping and friction, and its couplings as Newton joint mimics."""
        import newton

        robot = self.scenario.robot
        for sus in robot.suspension:
            j = labels[sus.joint]
            dof = builder.joint_qd_start[j]
            builder.joint_target_mode[dof] = int(newton.JointTargetMode.NONE)
            builder.joint_target_kd[dof] = builder.joint_target_ke[dof] = 0.0
            # The importer reads <limit> and <dynamics>; set from the spec all the same. SolverMuJoCo writes
            # them as the MuJoCo joint's range (limited: a limit constraint), damping (integrated implicitly
            # by implicitfast) and frictionloss (a friction constraint row bounded by +-friction).
            builder.joint_limit_lower[dof], builder.joint_limit_upper[dof] = sus.lower, sus.upper
            builder.joint_damping[dof] = sus.damping
            builder.joint_friction[dof] = sus.friction
            if self.settings.solver == "mujoco":
                # MuJoCo's own limit reference, solreflimit (0.02 s, 1), as the MuJoCo adapter's joints have,
                # passed raw: Newton's default writes its force-space limit gains (ke 1e4 N m/rad, kd 10), and
                # with them the uncoupled Warthog's chassis sank through the 0.15 rad (8.59 deg) stops to
                # 9.26 deg at rest (peak 10.57)
                for name, value in (
                    ("mujoco:solreflimit", (MUJOCO_TIMECONST, 1.0)),
                    ("mujoco:solreflimit_mode", SOLREF_MODE_RAW),
                ):
                    attribute = builder.custom_attributes[name]
                    if attribute.values is None:
                        attribute.values = {}
                    attribute.values[dof] = value
        # Each coupling once: the importer's mimic (SolverMuJoCo: a MuJoCo joint equality with polycoef
        # (offset, multiplier), acting on both joints, with MuJoCo's default solref 0.02 s / 1 and solimp
        # 0.9 / 0.95: read back from the solver's MuJoCo model)
        for c in robot.couplings:
            follower, leader = labels[c.joint], labels[c.leader]
            if builder.joint_mimic_joint[follower] != leader:
                raise RuntimeError(f"newton: the importer did not make {c.joint} follow {c.leader}")
            if not np.allclose(builder.joint_mimic_coeffs[follower], (c.offset, c.multiplier)):
                raise RuntimeError(f"newton: {c.joint} follows {c.leader} by {builder.joint_mimic_coeffs[follower]}")

    def _mujoco_attributes(self, builder, wheel_shapes: list[int]) -> None:
        """The MuJoCo adapter's wheel contact, through the attributes Newton passes to MuJoCo.

        On the wheel shapes: solimp d = ``wheel_contact_impedance`` (constant with depth), so
        a sliding contact's friction demand no longer lifts the wheel (the mechanism in
        :mod:`simpick.engines.mujoco_engine`); the solver's impratio makes the friction rows' impedance
        ``wheel_friction_impedance``. What Newton's model cannot carry: ``solreffriction`` exists
        only on explicit contact pairs (``mujoco:pair_*``), which SolverMuJoCo passes as MuJoCo
        <pair> elements; the shape-level attributes used here leave the friction rows' reference
        at MuJoCo's rule (it follows solref)."""
        solimp = builder.custom_attributes["mujoco:geom_solimp"]
        if solimp.values is None:
            solimp.values = {}
        # the ground shapes too: they have priority (their friction is the contact's), and MuJoCo
        # then takes every contact parameter from the higher-priority geom
        for s in wheel_shapes + self.ground_shapes:
            solimp.values[s] = wheel_solimp(self.settings)

    def _mujoco_pairs(self, builder, wheel_shapes: list[int]) -> None:
        """The MuJoCo adapter's contact pairs (simpick.engines.mujoco_engine.MujocoEngine._wheel_pairs) through
        Newton's ``mujoco:pair_*`` attributes, which SolverMuJoCo writes as MuJoCo <pair> elements; each
        wheel's automatic contact with each ground shape is filtered out, so every contact is counted once."""
        mu = builder.shape_material_mu
        for wheel in wheel_shapes:
            for ground in self.ground_shapes:
                builder.add_shape_collision_filter_pair(ground, wheel)
                builder.add_custom_values(
                    **{
                        "mujoco:pair_geom1": ground,
                        "mujoco:pair_geom2": wheel,
                        **pair_values(self.settings, mu[ground]),
                    }
                )

    def _solver(self, newton, model):
        s = self.settings
        its = {} if s.iterations == 0 else {"iterations": s.iterations}
        if s.solver == "mujoco":
            return newton.solvers.SolverMuJoCo(model, **solver_mujoco_options(s))
        if s.solver == "xpbd":
            return newton.solvers.SolverXPBD(model, **its)
        if s.solver == "steel":
            return newton.solvers.SolverSteel(
                model, articulation_constraint_max=s.steel_constraint_max, friction_mode="fixed_normal", **its
            )
        config = newton.solvers.SolverKamino.Config.from_model(model)
        config.use_collision_detector = True
        self.pipeline = False  # Kamino detects its own contacts
        return newton.solvers.SolverKamino(model, config=config)

    def set_wheel_targets(self, speeds: np.ndarray) -> None:
        if self.actuators:  # MuJoCo actuators: their controls, in the order they were added
            ctrl = self.control.mujoco.ctrl.numpy()
            ctrl[self.actuators] = np.asarray(speeds, dtype=np.float32).reshape(-1)
            self.control.mujoco.ctrl.assign(ctrl)
            return
        self.target[self.wheel_dofs.reshape(-1)] = np.asarray(speeds, dtype=np.float32).reshape(-1)
        self.control.joint_target_qd.assign(self.target)

    def step(self, n: int = 1) -> None:
        for _ in range(n):
            self.state_0.clear_forces()
            if self.pipeline:
                self.pipeline.collide(self.state_0, self.contacts)
            self.solver.step(self.state_0, self.state_1, self.control, self.contacts, self.dt)
            self.state_0, self.state_1 = self.state_1, self.state_0

    def read(self) -> BaseState:
        """The recorded robot's base_link pose and twist (world frame, at the link origin) and wheel speeds."""
        i = self.scenario.recorded_robot
        q = self.state_0.body_q.numpy()[self.base_bodies[i]].astype(float)
        qd = self.state_0.body_qd.numpy()[self.base_bodies[i]].astype(float)
        position, xyzw = q[:3], q[3:]
        quaternion = np.array([xyzw[3], xyzw[0], xyzw[1], xyzw[2]])
        angular = qd[3:]
        # body_qd's linear part is the centre of mass's velocity; the link origin's is v - w x (R com)
        lever = _rotate(quaternion, self.base_com)
        linear = qd[:3] - np.cross(angular, lever)
        wheel = self.state_0.joint_qd.numpy()[self.wheel_dofs[i]].astype(float)
        return BaseState(position, quaternion, linear, angular, wheel)


def _rotate(q_wxyz: np.ndarray, v: np.ndarray) -> np.ndarray:
    w, u = q_wxyz[0], q_wxyz[1:]
    return v + 2.0 * np.cross(u, np.cross(u, v) + w * v)


class NewtonEngine(IsolatedAdapter):
    """Newton as an engine adapter; its world runs where newton is installed (simpick.engines.isolated)."""

    name = "newton"
    settings_model = NewtonSettings
    simulates_suspension = True
    distribution = "newton"
    calibratable = {
        "friction": FRICTION,
        # The velocity drive's gain: from 300, the MuJoCo adapter's former velocity servo, to 30 000;
        # a skid-steer turn's wheels slip against the drive, so its stiffness may move the turning.
        "wheel_drive_damping": Calibratable(
            300.0, 30000.0, log=True, why="the MuJoCo adapter's former kv 300 to 10x the measured 3000"
        ),
    }

    def check(self, scenario: Scenario) -> None:
        settings = NewtonSettings.of(scenario.settings, self.name)
        if scenario.robot.suspension and settings.solver != "mujoco":
            from simpick.errors import InputError

            # measured (Warthog, rockers uncoupled, 2 s at rest): SolverSteel leaves the rocker limits unenforced,
            # the chassis tipping 21.6 degrees through the 8.6-degree stops; the others were not checked
            raise InputError(
                f"engines.{self.name}.solver",
                f"{settings.solver!r} is not checked with passive suspension ({scenario.robot.name} has "
                f"{[s.joint for s in scenario.robot.suspension]}): only 'mujoco' is",
                "use solver: mujoco for this robot",
            )

    def build_here(self, scenario: Scenario) -> NewtonWorld:
        self.check(scenario)
        return NewtonWorld(scenario, NewtonSettings.of(scenario.settings, self.name))


__all__ = ["NewtonEngine", "NewtonSettings", "NewtonWorld", "SOLVERS"]
