"""MuJoCo (DeepMind) through its official Python bindings.

The world is assembled with ``MjSpec``: the same URDF the other engines load (MuJoCo
gives a URDF no free joint, so one is added), the engine-neutral terrain as primitive
geoms, wheel servos with a torque bound, and MuJoCo's own accelerometer
and gyro at the IMU mount (they already follow REP-145). The whole run is stepped in C by
``mujoco.rollout`` with the sensors recorded there, so no Python runs per step.

Passive suspension (RobotSpec.suspension): MuJoCo's URDF importer makes each rocker a limited hinge
with the description's damping and frictionloss; the couplings are RobotSpec's joint equalities (the
importer's own, from <mimic>, are dropped so that each is applied once), see :meth:`MujocoEngine.spec`.

Friction: MuJoCo combines two geoms' friction by taking the maximum unless one has higher
``priority``; terrain and floor get priority 1 so their coefficient is the contact's.

Wheel contacts. With MuJoCo's default soft contact the Husky turned at 0.18-0.25 of
the commanded yaw rate against the quasi-static Coulomb 0.478: the contacts of every *sliding*
wheel hop. MuJoCo's contact force is the solution of a convex problem (docs, Computation > Dual
problem); for one steadily sliding contact it reduces to
``N = (N0 + mu b_t v_slip / R_n) / (1 + mu^2 / impratio)`` (N0: the force of the normal
spring-damper alone, R: the regulariser, b_t: the friction rows' velocity decay rate): the
friction demand ``b_t v_slip`` is projected onto the elliptic cone in the metric of R and, with
the default ``R_n`` (impedance 0.9-0.95), it *raises the normal force* instead of capping the
friction (the docs: "if we push it sideways, we would expect it to move up a bit as it starts
sliding"). For this robot that inflation (b_t / R_n = 16 800 N s/m per contact, times mu)
exceeds the 50-90 N loads above 6 mm/s of slip, so in a turn the wheels lift, land and lift
(35 Hz, loads 0-300 N, 5.4 of 8 contacts in contact). impratio does not help (it shrinks R_t but
raises the demand b_t v / R_t by the same factor), nor do noslip, the integrator (implicit, RK4,
Euler), the solver (Newton, CG, PGS; 200 iterations, tolerance 1e-10), condim 4 or 6, or a servo
that tracks exactly; a 4x finer step only reaches 0.37. The coupling grows with mu: at mu 0.05
the default contact gives 0.479. The cure keeps MuJoCo's contact *dynamics* and friction law and
removes only the coupling, with documented contact-pair attributes (``wheel_contact:
decoupled``, see :meth:`MujocoEngine._wheel_pairs`).
"""

from __future__ import annotations

import importlib.metadata
import math
from typing import Annotated, Literal

import numpy as np
from pydantic import Field, model_validator

from simpick.engines.base import FRICTION, FRICTION_RATIO, BaseState, BaseStates, Calibratable, EngineSettings, Scenario
from simpick.engines.runner import Adapter

SPAWN_CLEARANCE = 0.002  # m above resting height, as for the other engines


class MujocoSettings(EngineSettings):
    """config ``engines.mujoco``."""

    # mjOption integrator; implicitfast: implicit in velocity, so the stiff wheel servos stay
    # stable at 1 kHz (config.yaml)
    integrator: Literal["implicitfast", "implicit", "euler", "rk4"] = "implicitfast"
    # mjOption cone; elliptic: the true Coulomb cone rather than the pyramid approximation
    cone: Literal["elliptic", "pyramidal"] = "elliptic"
    # mjOption iterations, the constraint solver's cap per step (MuJoCo's default: 100). 50 since
    # the first adapter, as PyBullet's; no measurement is recorded for it.
    solver_iterations: Annotated[int, Field(ge=1)] = 50
    # "intvelocity": position servo on the integrated speed command (MuJoCo's <intvelocity>; the
    # docs: "in real robotic systems this integrated-velocity actuator is the most common
    # implementation of actuators with velocity semantics"), no steady speed error; "velocity":
    # torque = wheel_servo_gain x speed error, the former servo. Measured: the velocity servo lags
    # 5 % in a spin and leaves 11 % of the differential at (v, w) = (0.5, 0.2); and MuJoCo drops a
    # saturated actuator's velocity derivative from the implicit step (engine_derivative.c,
    # mjd_actuator_vel: "skip if force is clamped by forcerange"), so with kv > 2 I / h = 88 N m s/rad
    # a wheel that is not held by stiff stick friction (in the air, on ice, sliding) locks into a
    # +-100 N m bang-bang cycle (2.27 rad/s per step). With the decoupled contact below, a spin at
    # mu 0.2 then gives rear rim speeds 0.198 / 0.074 m/s for 0.139 commanded and a gain of 0.80
    # (0.05 at mu 0.05). The integrated servo has no such cycle (same cases: 0.467 / 0.467).
    wheel_servo: Literal["intvelocity", "velocity"] = "intvelocity"
    # N m/rad, intvelocity stiffness (critically damped on the wheel's inertia); 5000 gives the
    # same gains to 3 digits
    wheel_servo_kp: Annotated[float, Field(gt=0, allow_inf_nan=False)] = 1000.0
    # N m s/rad, kv of the "velocity" servo only (above 88 it bang-bangs when saturated, see wheel_servo)
    wheel_servo_gain: Annotated[float, Field(gt=0, allow_inf_nan=False)] = 300.0
    # "decoupled": wheel x terrain contact pairs as described in _wheel_pairs; "default": MuJoCo's
    # default geom contact (the Husky then turns at 0.18-0.25 of w, see the module docstring).
    wheel_contact: Literal["decoupled", "default"] = "decoupled"
    # solimp d of the wheel pairs, see _wheel_pairs: 0.015 gives a 1.5 mm resting sag; 0.005-0.1
    # measured to give the same gains, 0.2 fails at 2 rad/s. An impedance, so below 1, and
    # R_n = (1 - d) / d needs it above 0.
    wheel_contact_impedance: Annotated[float, Field(gt=0, lt=1)] = 0.015
    # impedance the wheel pairs' friction rows get via impratio, see _wheel_pairs: parked creep at
    # 0.8 atan(mu) 0.27 mm/s at 0.98, 0.71 at 0.95, 1.6 at 0.90 (MuJoCo's default contact: 6.6)
    wheel_friction_impedance: Annotated[float, Field(gt=0, lt=1)] = 0.98
    # Lateral / longitudinal friction ratio of the driven wheels' ground pairs (1: the
    # default, isotropic, unchanged). A pair's friction[0] and [1] act along its contact frame's two
    # tangents; MuJoCo orients them for a capsule on a plane along the capsule's axis, but fixes
    # them to the world for a cylinder (measured, MuJoCo 4.0.0; google-deepmind/mujoco#67). So with
    # r != 1 each driven wheel collides as a capsule of the wheel's radius whose segment spans the
    # tyre's width (on flat ground the same two contacts at the tyre's edges as the cylinder; on
    # terrain its rounded ends reach one radius beyond the tyre's sides), with friction
    # [r mu (along the axle), mu (rolling)] under the elliptic cone: the elliptic Coulomb law in
    # the wheel's frame. Needs wheel_contact "decoupled" and cone "elliptic". Measured (mu 0.8, 6 s,
    # (0, 0.5) / (0.5, 0.5) / (0.5, -0.5), anisotropic Coulomb in brackets): r 0.9999 (capsule, nearly
    # isotropic) 0.467 / 0.462 / 0.473 (0.478; the cylinder: the same), 0.8 0.584 / 0.581 / 0.589
    # (0.601), 0.63 0.682 / 0.681 / 0.686 (0.705), 0.5 0.751 / 0.753 / 0.756 (0.781); the same from
    # start headings 112.5 and -135 degrees.
    friction_ratio: Annotated[float, Field(gt=0, le=2, allow_inf_nan=False)] = 1.0

    @model_validator(mode="after")
    def _ratio_needs_pairs(self):
        if self.friction_ratio != 1.0 and (self.wheel_contact != "decoupled" or self.cone != "elliptic"):
            raise ValueError(
                f"friction_ratio {self.friction_ratio} needs wheel_contact 'decoupled' and cone "
                f"'elliptic' (got {self.wheel_contact!r}, {self.cone!r}): anisotropy lives on the "
                "wheels' ground pairs, and only the elliptic cone gives the friction ellipse"
            )
        return self


# MuJoCo's default contact reference (solref timeconst 0.02 s, dampratio 1) and the largest default
# impedance (solimp dmax 0.95): the friction rows' velocity decay rate is 2 / (dmax timeconst).
MUJOCO_TIMECONST, MUJOCO_DMAX = 0.02, 0.95
# Sensor layout of the recorded robot (Scenario.recorded_robot), in the order the sensors are added: name -> width.
# "wheels": one joint speed per driven wheel (RobotSpec.wheel_joints).
SENSORS = (("accel", 3), ("gyro", 3), ("pos", 3), ("quat", 4), ("linvel", 3), ("angvel", 3), ("wheels", None))


def _yaw_quat(yaw: float) -> list[float]:
    return [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]


class MujocoEngine(Adapter):
    calibratable = {
        "friction": FRICTION,
        # Contact softness (solimp d of the wheel pairs): 0.005-0.1 is the range the adapter was
        # measured over when it was set up (config comment: same gains); 0.015 gives 1.5 mm resting sag.
        "wheel_contact_impedance": Calibratable(
            0.005, 0.1, log=True, why="the range measured when the adapter was set up (MujocoSettings comment)"
        ),
        # Friction softness (impedance of the friction rows via impratio): from 0.8, softer friction
        # rows that let a sticking contact creep more, to 0.995, stiffer than the 0.98 chosen in
        # the adapter's set-up (config comment: parked creep 0.27 against 6.6 for MuJoCo's default contact).
        "wheel_friction_impedance": Calibratable(
            0.8, 0.995, why="from MuJoCo-default-like creep (0.8) to near-rigid 0.995"
        ),
        # the turning parameter: base.FRICTION_RATIO, the adapter's friction_ratio
        "friction_ratio": FRICTION_RATIO,
    }
    name = "mujoco"
    settings_model = MujocoSettings
    simulates_suspension = True  # rockers: the importer's limits, damping and frictionloss; couplings in spec()

    def version(self) -> str:
        return importlib.metadata.version("mujoco")

    def build(self, scenario: Scenario) -> MujocoWorld:
        return MujocoWorld(self.compile(scenario), len(scenario.robot.wheel_joints))

    def compile(self, scenario: Scenario):
        """The compiled MjModel of the scenario's world."""
        return self.spec(scenario).compile()

    def spec(self, scenario: Scenario):
        """The scenario's world as an uncompiled ``mujoco.MjSpec``: what :meth:`compile` compiles, and what
        :mod:`simpick.engines.simulator_models.mujoco` writes out as a model a user opens (``to_xml``)."""
        import mujoco

        settings = MujocoSettings.of(scenario.settings, self.name)
        spec = mujoco.MjSpec()
        spec.option.timestep = scenario.timestep
        spec.option.gravity = list(scenario.gravity)
        spec.option.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{settings.integrator.upper()}")
        spec.option.cone = getattr(mujoco.mjtCone, f"mjCONE_{settings.cone.upper()}")
        spec.option.iterations = settings.solver_iterations
        world = spec.worldbody

        grounds = []  # (geom, friction) of the floor and every terrain shape

        def surface(geom, friction: float) -> None:
            geom.friction = [friction, 0.0, 0.0]
            geom.priority = 1
            geom.condim = 3
            geom.name = f"ground{len(grounds)}"
            grounds.append((geom, friction))

        floor = world.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 1])
        surface(floor, scenario.ground_friction)
        terrain = scenario.terrain
        for x, y, z, yaw, sx, sy, sz in terrain.boxes:
            surface(
                world.add_geom(
                    type=mujoco.mjtGeom.mjGEOM_BOX, size=[sx / 2, sy / 2, sz / 2], pos=[x, y, z], quat=_yaw_quat(yaw)
                ),
                terrain.friction,
            )
        for x, y, z, r in terrain.spheres:
            surface(world.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[r, 0, 0], pos=[x, y, z]), terrain.friction)

        robot = scenario.robot
        for i, (x, y, yaw) in enumerate(scenario.starts):
            child = mujoco.MjSpec.from_file(str(robot.urdf))
            # MuJoCo's URDF importer reads each <dynamics> into the joint's damping (implicit in the
            # integrator) and frictionloss (a dry-friction constraint row), each <limit> into a
            # limited range (a limit constraint), and each <mimic> into a joint equality (measured,
            # MuJoCo 4.0.0 on the Warthog: damping 100, frictionloss 0.5, range +-0.15, one mjEQ_JOINT
            # with polycoef (0, -1)). The couplings are RobotSpec's (a <mimic> or the config's
            # robot.couplings): the importer's equalities are dropped and each coupling added once below.
            for equality in list(child.equalities):
                child.delete(equality)
            frame = world.add_frame(pos=[x, y, robot.base_height + SPAWN_CLEARANCE], quat=_yaw_quat(yaw))
            prefix = f"r{i}/"
            spec.attach(child, prefix=prefix, frame=frame)
            base = spec.body(prefix + robot.base_link)
            base.add_freejoint()
            # A robot's own links never touch each other, as in the other engines (PyBullet, DART:
            # no self-collision by default; ODE: kept apart here): MuJoCo only filters parent and
            # child, so a caster wheel under the chassis (its grandparent) would rub on it (measured on
            # the diff-drive robot: a locked-wheel slide braked at mu g, the caster jammed). Robot i's
            # geoms get their own contype bit and collide with the ground's (1) and other robots'.
            own = 1 << (1 + i % 30)
            others = sum(1 << (1 + k % 30) for k in range(len(scenario.starts))) & ~own
            for geom in base.find_all(mujoco.mjtObj.mjOBJ_GEOM):
                if geom.contype or geom.conaffinity:
                    geom.contype, geom.conaffinity = own, 1 | others
            for coupling in robot.couplings:
                # q(joint) = offset + multiplier q(leader): MJCF <equality><joint polycoef="offset
                # multiplier 0 0 0">, with MuJoCo's default solref (0.02 s, critically damped) and solimp
                equality = spec.add_equality(
                    type=mujoco.mjtEq.mjEQ_JOINT, name1=prefix + coupling.joint, name2=prefix + coupling.leader
                )
                data = list(equality.data)
                data[:5] = [coupling.offset, coupling.multiplier, 0.0, 0.0, 0.0]
                equality.data = data
            for joint in robot.wheel_joints:
                act = spec.add_actuator(
                    name=prefix + joint + "/servo", target=prefix + joint, trntype=mujoco.mjtTrn.mjTRN_JOINT
                )
                if settings.wheel_servo == "intvelocity":
                    act.set_to_intvelocity(kp=settings.wheel_servo_kp, dampratio=1.0)
                    act.actlimited = mujoco.mjtLimited.mjLIMITED_FALSE  # a continuous joint: no setpoint range
                else:  # "velocity"
                    act.set_to_velocity(kv=settings.wheel_servo_gain)
                act.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
                act.forcerange = [-scenario.max_wheel_torque, scenario.max_wheel_torque]
            if settings.wheel_contact == "decoupled":  # else "default": MuJoCo's geom contacts, as they are
                # the driven wheels: a caster keeps MuJoCo's default contact (the pairs' soft normal,
                # set for a Husky wheel, let the diff-drive robot's 50 g caster sink 7.7 mm)
                self._wheel_pairs(
                    spec, settings, [spec.joint(prefix + j).parent for j in robot.wheel_joints], grounds, prefix
                )
            if i == scenario.recorded_robot:  # its sensors: the record
                base.add_site(name="imu", pos=list(robot.imu_mount))
                S, O = mujoco.mjtSensor, mujoco.mjtObj
                spec.add_sensor(type=S.mjSENS_ACCELEROMETER, objtype=O.mjOBJ_SITE, objname="imu")
                spec.add_sensor(type=S.mjSENS_GYRO, objtype=O.mjOBJ_SITE, objname="imu")
                for kind in (S.mjSENS_FRAMEPOS, S.mjSENS_FRAMEQUAT, S.mjSENS_FRAMELINVEL, S.mjSENS_FRAMEANGVEL):
                    spec.add_sensor(type=kind, objtype=O.mjOBJ_XBODY, objname=prefix + robot.base_link)
                for joint in robot.wheel_joints:
                    spec.add_sensor(type=S.mjSENS_JOINTVEL, objtype=O.mjOBJ_JOINT, objname=prefix + joint)
        return spec

    @staticmethod
    def _wheel_pairs(spec, settings: MujocoSettings, wheels, grounds, prefix: str) -> None:
        """Wheel x ground contact pairs whose sliding friction does not lift the wheel.

        From the per-contact problem above, the normal-force inflation of a sliding contact is
        ``mu b_t v / R_n`` with ``R_n = (1 - d) / d * A`` (A: the contact's inverse inertia, about
        1/17 kg here) and ``b_t`` the friction rows' velocity decay rate. Three documented pair
        attributes (MJCF <pair>: solimp, solref, solreffriction) and one option:

        * ``solimp`` d = ``wheel_contact_impedance`` (0.015, constant with depth): R_n = 66 A, so
          b_t / R_n is 23-35 N s/m instead of 16 800 (at mu 0.8 and the 0.13 m/s slip of a 0.5 rad/s
          spin, 2-4 N of inflation on 50-90 N loads). MuJoCo's impedance scaling keeps the contact's
          dynamics independent of d (docs, Modeling > Solver parameters); only the resting
          penetration grows, to 1.4-1.6 mm (measured; a tyre's deflection) from 0.16 mm. Measured:
          d = 0.005 ... 0.1 give the same gains to 0.01 up to (v, w) = (1, 2); 0.2 fails at 2 rad/s.
        * ``solref`` (0.02 s, 1): MuJoCo's default normal reference, stated explicitly: the normal
          spring-damper is unchanged (natural period 20 ms, critically damped).
        * ``solreffriction``: the friction rows would otherwise inherit b = 2 / (d timeconst), 63x
          the default; timeconst 0.02 x 0.95 / d restores MuJoCo's default b_t = 105 /s, i.e. the
          default friction law (slip decays in 10 ms, Coulomb cap mu N). Lowering b_t instead turns
          friction viscous (measured with b_t = 1 /s: half the wheel speed after 2 s of straight
          driving, locked-wheel deceleration 0.14 m/s^2 for mu g = 2.9).
        * ``impratio`` = ((1 - d) / d) / ((1 - df) / df) with df = ``wheel_friction_impedance`` 0.98:
          the friction rows' R_t = R_n / impratio is that of impedance 0.98 (MuJoCo's default contact
          has 0.90 at impratio 1). MuJoCo's docs: "when contact slip is a problem, ... use elliptic
          cones, large impratio". Measured creep parked at 0.8 atan(mu): 1.6 mm/s at df 0.90,
          0.71 at 0.95, 0.27 at 0.98 (the default contact: 6.6 mm/s). It applies to every contact; the
          chassis contacts' friction just gets stiffer.

        Pairs, not geom attributes, because only pairs carry solreffriction (geom contacts use one
        solref for normal and friction rows, and a normal damping that low bounces: measured,
        the robot never settles at rest). The wheels' own dynamic collisions are switched off, so a
        wheel touches only the floor and terrain (not another robot). Cost: one pair per wheel and
        ground shape (1 940 per robot on the gravel strip).
        """
        import mujoco

        d = settings.wheel_contact_impedance
        df = settings.wheel_friction_impedance
        spec.option.impratio = ((1 - d) / d) / ((1 - df) / df)
        ratio = settings.friction_ratio
        for k, body in enumerate(wheels):
            for g, geom in enumerate(body.geoms):
                geom.name = geom.name or f"{prefix}wheel{k}_{g}"
                geom.contype = geom.conaffinity = 0
                if ratio != 1.0 and geom.type == mujoco.mjtGeom.mjGEOM_CYLINDER:
                    geom.type = mujoco.mjtGeom.mjGEOM_CAPSULE  # same size: radius, half-width (see friction_ratio)
                for ground, mu in grounds:
                    if ratio != 1.0:  # capsule frame: tangent 1 along the axle, tangent 2 rolling
                        spec.add_pair(
                            geomname1=ground.name,
                            geomname2=geom.name,
                            condim=3,
                            friction=[ratio * mu, mu, 0.0, 0.0, 0.0],
                            solref=[MUJOCO_TIMECONST, 1.0],
                            solimp=[d, d, 0.001, 0.5, 2.0],
                            solreffriction=[MUJOCO_TIMECONST * MUJOCO_DMAX / d, 1.0],
                        )
                        continue
                    # isotropic: friction[0] and [1] equal (for a cylinder on a plane the contact
                    # frame is world-fixed, measured: rows (0, 0, 1), (0, 1, 0), (-1, 0, 0) at every
                    # heading; see MujocoSettings.friction_ratio for the anisotropic pairs)
                    spec.add_pair(
                        geomname1=ground.name,
                        geomname2=geom.name,
                        condim=3,
                        friction=[mu, mu, 0.0, 0.0, 0.0],
                        solref=[MUJOCO_TIMECONST, 1.0],
                        solimp=[d, d, 0.001, 0.5, 2.0],
                        solreffriction=[MUJOCO_TIMECONST * MUJOCO_DMAX / d, 1.0],
                    )


class MujocoWorld:
    """One compiled MuJoCo world and its data (simpick.engines.base.World); its record comes from
    MuJoCo's own sensors, the accelerometer and gyro included, stepped in C by ``rollout``."""

    def __init__(self, model, wheels: int):
        import mujoco
        from mujoco import rollout  # imported here, not in the timed rollout

        self.mujoco, self.model, self.data, self.wheels = mujoco, model, mujoco.MjData(model), wheels
        self.rollout_module = rollout

    def set_wheel_targets(self, speeds: np.ndarray) -> None:
        self.data.ctrl[:] = speeds.reshape(-1)

    def step(self, n: int = 1) -> None:
        self.mujoco.mj_step(self.model, self.data, nstep=n)

    def _columns(self, sensordata: np.ndarray) -> dict[str, np.ndarray]:
        columns, start = {}, 0
        for name, width in SENSORS:
            width = self.wheels if width is None else width
            columns[name] = sensordata[..., start : start + width]
            start += width
        return columns

    def read(self) -> BaseState:
        # MuJoCo evaluates sensors at the start of a step: mj_forward evaluates them at the state
        # the last step reached (it changes no state, so the next step is the same)
        self.mujoco.mj_forward(self.model, self.data)
        c = self._columns(self.data.sensordata.copy())
        return BaseState(c["pos"], c["quat"], c["linvel"], c["angvel"], c["wheels"])

    def rollout(self, commands: np.ndarray) -> BaseStates:
        """The whole run in C (mujoco.rollout), the sensors recorded there."""
        mujoco, rollout = self.mujoco, self.rollout_module
        model, data = self.model, self.data
        state_spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
        initial = np.empty(mujoco.mj_stateSize(model, state_spec))
        mujoco.mj_getState(model, data, initial, state_spec)
        steps = commands.shape[0]
        # One extra step so that the sensors of the last real step's end state get evaluated.
        padded = np.concatenate([commands, commands[-1:]], axis=0)
        control = np.ascontiguousarray(padded.reshape(1, steps + 1, -1), dtype=np.float64)
        _, sensordata = rollout.rollout(model, data, initial[None], control)
        columns = self._columns(sensordata[0])

        # MuJoCo evaluates sensors at the start of each step: row k + 1 holds the state at
        # the end of step k, as every engine's record does, while the accelerometer's row k
        # is the acceleration *during* step k.
        def after_step(a: np.ndarray) -> np.ndarray:
            return a[1:]

        return BaseStates(
            position=after_step(columns["pos"]),
            quaternion=after_step(columns["quat"]),
            linear_velocity=after_step(columns["linvel"]),
            angular_velocity=after_step(columns["angvel"]),
            wheel_speed=after_step(columns["wheels"]),
            specific_force=columns["accel"][:-1].copy(),
            gyro=after_step(columns["gyro"]),
        )
