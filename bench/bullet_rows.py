"""The Bullet rows (CoppeliaSim, MORSE) measured beside the plain PyBullet engine: what a run costs, and what the
Husky would turn at were it built as the simulators build it (rigid bodies on constraints).

    .venv/bin/python bench/bullet_rows.py cost       # CPU of a 20 s turn per profile, median of 3
    .venv/bin/python bench/bullet_rows.py maximal    # yaw-rate gain, multibody against maximal coordinates

``maximal`` loads the Husky with loadURDF(useMaximalCoordinates=True): a btRigidBody per link, a
btGeneric6DofSpring2Constraint per joint, the wheels driven by its angular motor. Only PyBullet's shared-memory
client sees such a robot's joints (its in-process DIRECT client reports none), so this runs an in-process
shared-memory server, one command a round trip; the server reports a rigid-body robot's base only, so no wheel
speed is read. PyBullet's rigid-body motor turns the wheel the other way from the multibody's for the same
target (measured: 6 s at 0.5 m/s ends 2.94 m ahead as a multibody, 2.94 m behind with maximal coordinates), so
the maximal robot gets the targets negated. Both at CoppeliaSim's 5 ms step, 100 iterations, contact ERP 0.2,
rigid contacts, mu 0.8; the gain is the mean yaw rate over the second half of 6 s, over the command.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

URDF = ROOT / "resources/robot/husky_a200.urdf"
HUSKY = "husky_a200"
TRACK = 0.555  # m, config.yaml robot.track
TORQUE = 100.0  # N m, config.yaml robot.max_wheel_torque
STEP = 0.005  # s, CoppeliaSim's dynamics step
LEFT = ("front_left_wheel_joint", "rear_left_wheel_joint")
RIGHT = ("front_right_wheel_joint", "rear_right_wheel_joint")


def cost() -> None:
    from simpick.engines import get_engine
    from simpick.engines.base import Scenario
    from simpick.engines.catalog import load_catalog
    from simpick.inputs.motions import constant_commands
    from simpick.inputs.robot import load_robot

    robot = load_robot(URDF)
    catalog = load_catalog(ROOT / "resources/simulators/simulators.yaml")
    profiles = {
        "coppeliasim shipped before (1 ms, 100 iterations, rigid)": {
            "solver_iterations": 100,
            "contact_stiffness": 0.0,
            "contact_damping": 0.0,
        },
        **{f"{s}-{v}": catalog.settings(s, v, HUSKY) for s in ("coppeliasim", "morse") for v in ("shipped", "tuned")},
        "pybullet (config.yaml's block)": {"solver_iterations": 50, "contact_stiffness": 1e6, "contact_damping": 5e3},
    }
    flat = {"schema": "simpick.inputs.terrain/1", "name": "flat", "boxes": [], "spheres": [], "friction": 0.8}
    commands = constant_commands(0.5, 0.3, 20.0, 0.001, TRACK, robot.wheel_radius, 1)
    for name, settings in profiles.items():
        scenario = Scenario(
            robot=robot,
            terrain=flat,
            ground_friction=0.8,
            timestep=0.001,
            max_wheel_torque=TORQUE,
            starts=((0.0, 0.0, 0.0),),
            settings=settings,
        )
        cpu = sorted(get_engine("pybullet").simulate(scenario, commands).cpu_time for _ in range(3))
        print(f"{name}: CPU {cpu[1]:.2f} s for 20 s simulated ({cpu[0]:.2f}-{cpu[2]:.2f})", flush=True)


def _gain(maximal: bool, v: float, w: float, heading: float, radius: float) -> float:
    import pybullet as pb

    if maximal:
        cid = pb.connect(pb.SHARED_MEMORY_SERVER, key=30000 + os.getpid() % 20000)
    else:
        cid = pb.connect(pb.DIRECT)
    try:
        pb.setGravity(0, 0, -9.81, physicsClientId=cid)
        pb.setPhysicsEngineParameter(
            fixedTimeStep=STEP, numSubSteps=0, numSolverIterations=100, contactERP=0.2, physicsClientId=cid
        )
        ground = pb.createMultiBody(0, pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=cid), physicsClientId=cid)
        pb.changeDynamics(ground, -1, lateralFriction=0.8, physicsClientId=cid)
        body = pb.loadURDF(
            str(URDF),
            [0, 0, 0.2],
            pb.getQuaternionFromEuler([0, 0, heading]),
            flags=pb.URDF_USE_INERTIA_FROM_FILE | pb.URDF_USE_IMPLICIT_CYLINDER,
            useMaximalCoordinates=maximal,
            physicsClientId=cid,
        )
        n = pb.getNumJoints(body, physicsClientId=cid)
        joints = {pb.getJointInfo(body, j, physicsClientId=cid)[1].decode(): j for j in range(n)}
        for link in range(-1, n):
            pb.changeDynamics(  # as the adapter sets every link
                body,
                link,
                lateralFriction=1.0,
                rollingFriction=0.0,
                spinningFriction=0.0,
                restitution=0.0,
                linearDamping=0.0,
                angularDamping=0.0,
                physicsClientId=cid,
            )
        sign = -1.0 if maximal else 1.0  # the rigid-body motor's opposite sense (module docstring)
        left, right = (sign * (v - w * TRACK / 2) / radius, sign * (v + w * TRACK / 2) / radius)
        pb.setJointMotorControlArray(
            body,
            [joints[j] for j in LEFT + RIGHT],
            pb.VELOCITY_CONTROL,
            targetVelocities=[left, left, right, right],
            forces=[TORQUE] * 4,
            physicsClientId=cid,
        )
        steps, rates = round(6.0 / STEP), []
        for k in range(steps):
            pb.stepSimulation(physicsClientId=cid)
            if k >= steps // 2:
                rates.append(pb.getBaseVelocity(body, physicsClientId=cid)[1][2])
        return float(np.mean(rates)) / w
    finally:
        pb.disconnect(cid)


def maximal() -> None:
    from simpick.inputs.robot import load_robot

    radius = load_robot(URDF).wheel_radius
    for v, w, heading in ((0.5, 0.5, 0.0), (0.0, 0.5, 0.0), (0.5, 0.2, 0.0), (0.5, -0.5, 0.0), (0.5, 0.5, 1.9635)):
        cells = []
        for mode in (False, True):
            start = time.perf_counter()
            gain = _gain(mode, v, w, heading, radius)
            cells.append(f"{'maximal' if mode else 'multibody'} {gain:.3f} ({time.perf_counter() - start:.1f} s wall)")
        print(f"(v, w) = ({v}, {w}), heading {heading:.3f} rad: " + "; ".join(cells), flush=True)
    print("Coulomb (rigid body, isotropic): 0.478 (simpick.coulomb, the validation's analytic value)")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("what", choices=["cost", "maximal"])
    {"cost": cost, "maximal": maximal}[parser.parse_args().what]()
