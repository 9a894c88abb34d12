"""Genesis: the robot on flat ground as a Python script that builds it with Genesis's own API as simpick's Genesis
adapter does (:class:`simpick.engines.genesis_engine.GenesisWorld`): ``gs.init`` on the CPU backend, a ``gs.Scene``
with the profile's rigid options, a ``gs.morphs.Plane`` of the ground's friction, the robot's URDF as a
``gs.morphs.URDF`` entity (its base link kept) and the wheels velocity-controlled (kv, force range); beside it the
URDF the adapter loads (:mod:`.python_script`).
"""

from __future__ import annotations

from simpick.engines.genesis_engine import (
    ENUM_OPTIONS,
    INIT_OPTIONS,
    MIN_FRICTION,
    SPAWN_CLEARANCE,
    GenesisEngine,
    GenesisSettings,
    rigid_options,
)
from simpick.engines.simulator_files.common import _num
from simpick.engines.simulator_files.python_setups import python_blocks
from simpick.engines.simulator_models.common import ModelRequest
from simpick.engines.simulator_models.python_script import (
    Code,
    assign,
    claim_lines,
    claims_block,
    over_fragment,
    script,
    standalone_urdf,
    wheels_block,
)
from simpick.engines.suspension import coupled_urdf

IMPORTS = """import genesis as gs
import numpy as np
"""

BODY = '''

def build():
    """The scene built with the robot at rest: (scene, robot, wheel dofs)."""
    scene = gs.Scene(
        sim_options=gs.options.SimOptions(dt=TIMESTEP, gravity=GRAVITY),
        rigid_options=gs.options.RigidOptions(**RIGID_OPTIONS),
        show_viewer=False,
    )
    scene.add_entity(gs.morphs.Plane(), material=gs.materials.Rigid(friction=GROUND_FRICTION))
    robot = scene.add_entity(
        gs.morphs.URDF(
            file=str(Path(__file__).resolve().with_name(URDF)),
            pos=BASE_POSITION,
            quat=BASE_QUAT_WXYZ,
            links_to_keep=[BASE_LINK],
            **URDF_OPTIONS,
        ),
        material=gs.materials.Rigid(friction=ROBOT_FRICTION),
    )
    scene.build()
    dofs = [robot.get_joint(wheel["joint"]).dofs_idx_local[0] for wheel in WHEELS]
    robot.set_dofs_kp(np.zeros(len(dofs)), dofs)
    robot.set_dofs_kv(np.full(len(dofs), WHEEL_KV), dofs)
    robot.set_dofs_force_range(np.full(len(dofs), -MAX_WHEEL_TORQUE), np.full(len(dofs), MAX_WHEEL_TORQUE), dofs)
    return scene, robot, dofs


def _array(tensor) -> np.ndarray:
    return np.asarray(tensor.cpu().numpy() if hasattr(tensor, "cpu") else tensor, dtype=float).reshape(-1)


def run(v: float, w: float, duration: float) -> np.ndarray:
    """The scene built at rest, the wheels' command (v, w) set before the first step, ``duration`` s stepped: the
    base's yaw rate about its own z axis after each step."""
    scene, robot, dofs = build()
    robot.control_dofs_velocity(np.asarray(wheel_speeds(v, w), dtype=float), dofs)
    steps = int(round(duration / TIMESTEP))
    rates = np.empty(steps)
    for k in range(steps):
        scene.step()
        rates[k] = body_z_rate(_array(robot.get_quat()), _array(robot.get_ang()))
    return rates


gs.init(backend=gs.cpu, **INIT)
'''


def write_genesis_model(request: ModelRequest) -> dict[str, str]:
    """{suffix: text}: ``py``, the script, and ``urdf``, the robot's description it loads (``<stem>.urdf``, the
    request's stem, "": ``genesis``): the ``request``'s robot on a plane of its ground friction with the Genesis
    adapter's settings and the request's step, claiming its claims."""
    stem = request.stem or "genesis"
    spec_robot = request.robot.spec(request.robot_urdf)
    typed = GenesisSettings.model_validate(dict(request.settings))
    if spec_robot.suspension or spec_robot.couplings:
        raise ValueError(f"the Genesis model of {spec_robot.name} is not written: its passive suspension is not")
    scenario = request.flat_world(spec_robot, typed.model_dump(mode="json"))
    blocks = {call: kwargs for _, call, kwargs in python_blocks("genesis", typed.model_dump(mode="json"))}
    exact = {k: Code(f"gs.{ENUM_OPTIONS[k]}.{v}") if k in ENUM_OPTIONS else v for k, v in rigid_options(typed).items()}
    rigid = over_fragment(blocks["gs.options.RigidOptions"], exact, "RigidOptions")
    urdf_options = over_fragment(
        blocks["gs.morphs.URDF"], {"default_armature": typed.default_armature}, "gs.morphs.URDF"
    )
    version = GenesisEngine().version()
    data = [
        claims_block(request.claims),
        assign("URDF", f"{stem}.urdf", "the robot's description, beside this file (the one simpick's adapter loads)"),
        assign("BASE_LINK", spec_robot.base_link, "kept as a link of its own (links_to_keep): the pose measured"),
        assign(
            "BASE_POSITION",
            (0.0, 0.0, spec_robot.base_height + SPAWN_CLEARANCE),
            f"m: the base at rest height + {_num(SPAWN_CLEARANCE)} m, heading 0",
        ),
        assign("BASE_QUAT_WXYZ", (1.0, 0.0, 0.0, 0.0)),
        assign("INIT", INIT_OPTIONS, "gs.init's keywords beside the CPU backend"),
        assign("TIMESTEP", request.timestep, "s"),
        assign("GRAVITY", tuple(scenario.gravity), "m/s^2"),
        assign("RIGID_OPTIONS", rigid, "gs.options.RigidOptions' keywords"),
        assign("URDF_OPTIONS", urdf_options, "gs.morphs.URDF's keywords beside the file and the pose"),
        assign("GROUND_FRICTION", max(request.ground_mu, MIN_FRICTION), "the plane's gs.materials.Rigid friction"),
        assign(
            "ROBOT_FRICTION",
            MIN_FRICTION,
            "the robot's: Genesis's floor (a contact takes the larger of its two materials', the ground's)",
        ),
        wheels_block(spec_robot, request.robot.track),
        assign("WHEEL_KV", typed.wheel_kv, "N m s/rad, the wheels' velocity gain (kp 0)"),
        assign("MAX_WHEEL_TORQUE", request.robot.max_wheel_torque, "N m, each wheel's force range"),
    ]
    header = [
        *request.header_lines,
        f"runs as it is, with genesis-world installed: python {stem}.py (every claim), or --v V --w W "
        f"[--duration S]; it loads {stem}.urdf from its own folder and prints, per run, the yaw-rate gain it measures "
        "(Genesis compiles its kernels on a first run)",
        f"builds, with Genesis's own API as simpick's Genesis adapter does: gs.init on the CPU backend, a gs.Scene "
        f"(step {_num(request.timestep)} s, RIGID_OPTIONS: {typed.friction_cone} cone, {typed.constraint_solver} "
        f"solver, {typed.iterations} iterations), a gs.morphs.Plane of friction "
        f"{_num(max(request.ground_mu, MIN_FRICTION))}, "
        f"{spec_robot.name}'s URDF as a gs.morphs.URDF entity (default_armature {typed.default_armature}), the "
        f"wheels velocity-controlled (kv {_num(typed.wheel_kv)} N m s/rad, force within "
        f"+-{_num(request.robot.max_wheel_torque)} N m)",
        *claim_lines(request.claims),
        f"written for genesis-world {version} (the version simpick's adapter ran)",
    ]
    doc = (
        f"{request.name or spec_robot.name}: Genesis on flat ground, as simpick's adapter builds it.\n\n"
        f"python {stem}.py runs every claim (CLAIMS) and prints the gain measured beside the one claimed;\n"
        f"python {stem}.py --v 0.5 --w 0.5 --duration 6 runs one command.\n"
    )
    return {
        "py": script(header, doc, IMPORTS, data, BODY),
        "urdf": standalone_urdf(coupled_urdf(spec_robot)),
    }
