"""Every engine loads any robot the same way: the diff-drive robot with its mirrored
wheel and swivel caster, and a six-wheeled robot, drive forward and turn the commanded way."""

from pathlib import Path

import numpy as np
import pytest
import yaml

from conftest import flat_terrain
from simpick.engines import ADAPTERS, get_engine
from simpick.engines.base import Scenario
from simpick.engines.kinematics import euler_rpy
from simpick.inputs.motions import constant_commands
from simpick.inputs.robot import load_robot
from simpick.studies.validation.cases import Setup, run_case
from test_robot import write_robot

ROOT = Path(__file__).resolve().parents[1]


# The wheel servos whose gains are set on the Husky's wheel (spin inertia 0.044 kg m^2), scaled to the diff-drive
# robot's 2.5e-4 kg m^2 as config/robots/diffbot.yaml scales MuJoCo's: Newton's intvelocity kp as MuJoCo's (20);
# Genesis's velocity gain by the inertia ratio, 3000 -> 17. With the Husky's gains a saturated small wheel is
# held by the drive's damping (Genesis: 2.50 of 8 rad/s, a locked-wheel slide braking at 0.05 m/s^2 for 2.30).
DIFFBOT_SERVOS = {"newton": {"wheel_servo_kp": 20.0}, "genesis": {"wheel_kv": 17.0}}


def _drive(engine, robot, v, w, track, duration=1.5, torque=5.0, settings=None):
    scenario = Scenario(
        robot=robot,
        terrain=flat_terrain(0.8),
        ground_friction=0.8,
        timestep=0.001,
        max_wheel_torque=torque,
        starts=((0.0, 0.0, 0.0),),
        settings=settings or {},
    )
    commands = constant_commands(v, w, duration, 0.001, track, robot)
    return get_engine(engine).simulate(scenario, commands), commands


@pytest.mark.parametrize("engine", list(ADAPTERS))
def test_diff_drive_robot_drives_forward_and_turns_left(engine):
    bot = load_robot(ROOT / "resources" / "robot" / "diffbot.urdf.xacro")
    record, commands = _drive(engine, bot, 0.4, 0.0, bot.track, settings=DIFFBOT_SERVOS.get(engine))
    assert commands[0, 0, 1] < 0  # the mirrored right wheel is commanded backwards ...
    assert record.wheel_speed.shape == (record.steps, 2)
    # ... and turns so (its measured joint speed tracks the command), rolling the robot forward
    np.testing.assert_allclose(record.wheel_speed[-1], commands[-1, 0], rtol=0.05)
    x, y = record.position[-1, :2]
    assert 0.4 < x < 0.62 and abs(y) < 0.02, (x, y)  # 1.5 s at 0.4 m/s, less the start
    assert abs(np.degrees(euler_rpy(record.quaternion)[-1, 2])) < 2
    # rolling without slip over the second half: speed = rim speed within the validation's 2 %
    # (measured 0.983-1.000; Drake's 50 mm wheel meshed at 2 cm, a 16-sided prism: 0.970)
    half = record.steps // 2
    speed = np.linalg.norm(record.linear_velocity[half:, :2], axis=1).mean()
    assert speed / bot.rim_speeds(record.wheel_speed[half:]).mean() == pytest.approx(1.0, abs=0.02)
    record, _ = _drive(engine, bot, 0.0, 1.0, bot.track, settings=DIFFBOT_SERVOS.get(engine))
    yaw = np.unwrap(euler_rpy(record.quaternion)[:, 2])
    # a left spin at 1 rad/s, with no-slip kinematics: within 20 % of 1 rad/s over the last half
    rate = (yaw[-1] - yaw[len(yaw) // 2]) / (0.001 * (len(yaw) - 1 - len(yaw) // 2))
    assert 0.8 < rate < 1.2, rate


@pytest.mark.parametrize(
    "engine",
    [
        pytest.param(
            e,
            marks=[
                pytest.mark.xfail(
                    strict=True,
                    reason="ODE brakes the diff-drive robot at 2.00 m/s^2 "
                    "for 2.30 (docs/robot.md, validation on the shipped robots)",
                )
            ],
        )
        if e == "ode"
        else e
        for e in ADAPTERS
    ],
)
def test_a_caster_rolls_free_when_the_wheels_lock(engine):
    """The diff-drive robot's locked-wheel slide (the validation case): its caster rolls and swivels
    free, so only the driven wheels' share of the weight brakes it (2.30 m/s^2 at mu 0.3, not mu g).
    PhysX gives every joint a friction coefficient of 0.05 unless told otherwise: the caster then
    dragged, 2.449 m/s^2 (+6.3 %); with no joint friction 2.373 (+3.0 %)."""
    config = yaml.safe_load((ROOT / "config" / "robots" / "diffbot.yaml").read_text())
    bot = load_robot(ROOT / config["robot"]["urdf"])
    setup = Setup(
        engine=engine,
        robot=bot,
        timestep=0.001,
        max_wheel_torque=config["robot"]["max_wheel_torque"],
        track=config["robot"]["track"],
        settings=config.get("engines", {}).get(engine) or DIFFBOT_SERVOS.get(engine) or {},
    )
    (check,) = run_case(setup, "slide_mu0.3", {"kind": "slide", "v": 0.5, "mu": 0.3})["checks"]
    assert check["analytic_value"] == pytest.approx(2.30, abs=0.01)
    assert check["engine_value"] == pytest.approx(check["analytic_value"], rel=0.05)  # the validation's tolerance


@pytest.mark.parametrize("engine", list(ADAPTERS))
def test_six_wheels_with_mirrored_joints(engine, tmp_path):
    wheels = {
        f"{pos}{side}_joint": (x, y, 0.0, "0 0 3.141592653589793" if y < 0 else "0 0 0", "0 1 0")
        for pos, x in (("f", 0.35), ("m", 0.0), ("r", -0.35))
        for side, y in (("l", 0.3), ("r", -0.3))
    }
    robot = load_robot(write_robot(tmp_path, wheels, name="six"))
    assert [w.axis_sign for w in robot.driven] == [1, -1] * 3
    record, _ = _drive(engine, robot, 0.5, 0.0, robot.track, duration=1.0, torque=20.0)
    assert record.wheel_speed.shape == (record.steps, 6)
    x, y = record.position[-1, :2]
    assert 0.3 < x < 0.55 and abs(y) < 0.02, (x, y)


@pytest.mark.parametrize("engine", list(ADAPTERS))
def test_skid_robot_rests_and_drives_forward(engine, tmp_path):
    """A TurtleBot3-like robot (joints turned by -1.57 rad, a box skid): it settles onto its skid
    and drives straight. MuJoCo's wheel servo stiffness scaled to its 28 g wheel (spin inertia
    2.1e-5 kg m^2: kp 0.5 gives sqrt(kp / I) = 155 rad/s, the Husky's 150; the default 1000 is
    7 000 rad/s, 7 per step, and the servo chatters)."""
    from test_robot import write_skid_robot

    robot = load_robot(write_skid_robot(tmp_path))
    # Newton's intvelocity servo as MuJoCo's; Genesis's velocity gain: the Husky's 3000 x 2.1e-5 / 0.044
    settings = {"mujoco": {"wheel_servo_kp": 0.5}, "newton": {"wheel_servo_kp": 0.5}, "genesis": {"wheel_kv": 1.4}}
    settings = settings.get(engine, {})
    scenario = Scenario(
        robot=robot,
        terrain=flat_terrain(0.8),
        ground_friction=0.8,
        timestep=0.001,
        max_wheel_torque=1.0,
        starts=((0.0, 0.0, 0.0),),
        settings=settings,
    )
    commands = constant_commands(0.2, 0.0, 1.5, 0.001, robot.track, robot)
    record = get_engine(engine).simulate(scenario, commands)
    x, y = record.position[-1, :2]
    _, pitch, yaw = euler_rpy(record.quaternion)[-1]
    # resting on wheels and skid: tipped back by at most the skid's 0.5 mm over 81 mm (and a sag)
    assert abs(pitch) < 0.03, pitch
    assert 0.2 < x < 0.31 and abs(y) < 0.02, (x, y)  # forward; MuJoCo and DART drift 1.1-1.3 cm sideways
    # and straight: the six engines yaw 0.013-0.050 rad (all to the right). Drake's wheel meshed at
    # a fixed 2 cm (an 11-sided 33 mm wheel) yawed 0.38 rad and ended 5 cm sideways
    assert abs(yaw) < 0.06, yaw


def _self_contacts(engine: str, scenario: Scenario, speeds: np.ndarray, seconds: float) -> set:
    """Pairs of links of one robot that touch while it drives, from the engine's own contacts."""
    adapter, pairs = get_engine(engine), set()
    if engine == "physx":
        world = adapter.build(scenario)
        world.set_wheel_targets(speeds[None])
        scene = world.scene
        for _ in range(round(seconds / scenario.timestep)):
            scene.step()
            for contact in scene.get_contacts():
                names = {body.entity.name for body in contact.bodies}
                if "terrain" not in names:
                    pairs.add(tuple(sorted(names)))
    else:  # drake
        world = adapter.build(scenario)
        world.set_wheel_targets(speeds[None])
        simulator, plant, context = world.simulator, world.plant, world.context
        for k in range(1, 31):  # the contact results every 1/30 of the run
            simulator.AdvanceTo(k * seconds / 30)
            results = plant.get_contact_results_output_port().Eval(context)
            for i in range(results.num_point_pair_contacts()):
                info = results.point_pair_contact_info(i)
                names = {plant.get_body(info.bodyA_index()).name(), plant.get_body(info.bodyB_index()).name()}
                if "world" not in names:
                    pairs.add(tuple(sorted(names)))
    return pairs


@pytest.mark.parametrize("engine", [e for e in ("physx", "drake") if e in ADAPTERS])
def test_a_robot_s_own_links_never_touch(engine):
    """As in the other engines (PyBullet and DART: no self-collision; MuJoCo and ODE: filtered by
    the adapter). PhysX and Drake filter only links joined by a joint: the diff-drive robot's
    caster wheel, the chassis's grandchild, whose top is level with the chassis's underside, was in
    contact with it in both while the robot spun (the caster swivelling under the chassis)."""
    bot = load_robot(ROOT / "resources" / "robot" / "diffbot.urdf.xacro")
    scenario = Scenario(
        robot=bot,
        terrain=flat_terrain(0.8),
        ground_friction=0.8,
        timestep=0.001,
        max_wheel_torque=5.0,
        starts=((0.0, 0.0, 0.0),),
    )
    assert _self_contacts(engine, scenario, bot.joint_speeds(-0.3, 0.3), 1.5) == set()
