"""ODE (Open Dynamics Engine 0.16, the engine behind Gazebo Classic and Webots) via ctypes.

ODE is a C library with no maintained Python binding, so :mod:`simpick.engines._ode`
binds the few calls used here. The world is built from the same URDF and engine-neutral
terrain as every other engine:

- robot: one ODE body per moving link of the loader's rigid model (simpick.inputs.robot.RobotSpec.rigid:
  base_link and the wheels, every link hung on one by fixed joints folded in, such as the Husky's
  18 g IMU link or a chassis link under base_link). An ODE body's origin must be its centre of
  mass, so each body sits at its link's COM with the link's orientation, the full inertia tensor
  (off-diagonal terms included) about that point, and its collision shapes offset from it. The
  record is converted back to base_link (position - R c, velocity - w x R c), as the PyBullet
  adapter does (simpick.engines.ode_world).
- passive suspension (RobotSpec.suspension, RigidModel.suspension): each rocker a body on a hinge
  with the description's limits as ODE's stops and its friction as a velocity motor held at 0 with
  that torque bound; its damping and each coupling (a stiff spring-damper: ODE has no joint-space
  coupling of two hinges) are hinge torques applied before every step (simpick.engines.ode_world).
  Wheels hang on their rocker (RigidModel.wheel_parents) and their speed is read relative to it.
- wheels: hinge joints whose velocity motor (dParamVel) is bounded by dParamFMax =
  ``scenario.max_wheel_torque``: ODE solves the motor as a constraint with a force limit,
  the same servo PyBullet's VELOCITY_CONTROL is.
- terrain: boxes, spheres and a plane as static geoms (no body).
- contacts (simpick.engines.ode_contacts): ``dSpaceCollide`` calls a Python callback for each pair whose bounding boxes
  overlap; it runs ``dCollide`` straight into a preallocated ``dContact`` array whose
  surface parameters are preset per friction value, and turns each contact into a contact
  joint. Friction: the robot's surfaces carry none of their own; a contact's mu is the
  terrain's (or the ground's, ``scenario.ground_friction``) coefficient, robot-robot
  contacts get 1.0 (what PyBullet's product 1.0 x 1.0 gives). Surface mode
  ``dContactApprox1``: the friction pyramid's bound is mu x normal force (Coulomb);
  without it ODE reads ``mu`` as a fixed force limit in newtons, not a coefficient.
  Webots' and Gazebo's ODE integrations set it too. ODE has no friction cone: each contact
  gets two friction rows, each bounded by mu x normal force on its own (a pyramid), along
  fdir1 and normal x fdir1. See ``OdeSettings.friction_direction`` for how fdir1 is chosen.
- category bits keep static terrain from being paired with itself (every stone overlaps its
  gravel bed; each pair would cost a Python callback per step) and keep a robot's own
  shapes apart; robots still collide with each other.

Settings: :class:`~simpick.engines.ode_settings.OdeSettings` (config ``engines.ode``), each with what
was measured for it.

Determinism: ODE's only randomness is the constraint reordering of the quick stepper
(``dRandInt``); the seed is reset before every run, and geoms are created in a fixed
order, so the same inputs give identical arrays.
"""

from __future__ import annotations

from simpick.engines import _ode
from simpick.engines.base import FRICTION, FRICTION_RATIO, Calibratable, Scenario
from simpick.engines.ode_settings import OdeSettings
from simpick.engines.ode_world import OdeWorld
from simpick.engines.runner import Adapter

__all__ = ["OdeEngine", "OdeSettings"]


class OdeEngine(Adapter):
    name = "ode"
    settings_model = OdeSettings
    # passive suspension (ode_world): hinges with stops, friction motor, damping and coupling torques
    simulates_suspension = True
    calibratable = {
        "friction": FRICTION,
        # Force-dependent slip, (m/s)/N: a Husky wheel's friction force is about mu x 170 N (up to
        # ~130 N at mu 0.75), so 5e-3 lets it creep at up to ~0.6 m/s, beyond the runs' 0.5 m/s:
        # the range spans rigid (0) to fully compliant.
        "contact_slip": Calibratable(0.0, 5.0e-3, why="0 (rigid) to creep beyond the runs' speeds"),
        # Global constraint force mixing (the softness of every constraint, contacts included): two
        # decades either side of ODE's and Webots' default 1e-5 (the ODE manual: larger is softer).
        "cfm": Calibratable(1.0e-7, 1.0e-3, log=True, why="two decades either side of the 1e-5 default"),
        # the turning parameter: base.FRICTION_RATIO, the adapter's friction_ratio
        "friction_ratio": FRICTION_RATIO,
    }

    def version(self) -> str:
        return _ode.version()

    def build(self, scenario: Scenario) -> OdeWorld:
        return OdeWorld(_ode.load(), scenario)
