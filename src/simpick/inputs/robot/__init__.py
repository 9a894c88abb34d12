"""The robot description every engine loads, and the facts simpick reads from it.

Any wheeled ground robot described by a URDF (or a xacro file, expanded with the ``xacro``
package; its ``$(find PKG)`` includes resolved from the config's ``robot.packages``, without ROS)
can be studied. :func:`load_robot` reads the description once, at planning time and
in every job, and returns a :class:`RobotSpec`: the one interface through which the engines,
the controller, the IMU mount and the Coulomb model see the robot. Nothing else parses the URDF
for robot facts (an adapter may read the file :attr:`RobotSpec.urdf` for the shapes and
inertias its engine builds, as every engine's own URDF loader does).

What is found and how:

- **Wheels**: a ``continuous`` joint whose child link collides as a cylinder (its axis along the
  joint axis) or a sphere. A wheel hanging on the base through fixed joints only is *driven*; one
  below a continuous joint with a vertical axis (a swivel) is a *caster*, passive. The config may
  instead name the driven joints (``robot.wheels``: joint and side); every other wheel is passive.
- **Side and forward direction** from geometry: side is the sign of the wheel centre's y in the
  base frame; the joint axis, expressed in the base frame through every joint origin's rotation,
  gives ``axis_sign`` (+1 when a positive joint speed rolls the robot towards +x), so rotated or
  mirrored joint frames all drive the robot forward.
- **Base**: the URDF root link. A root without mass (a footprint) is fine: whenever the file is
  not already in the form every engine reads alike (xacro, meshes, massless links), it is rewritten
  (:func:`simpick.inputs.urdf.normalised_urdf`) with each link hung on a fixed joint fused into its parent: masses and
  inertias combined, box/cylinder/sphere collisions kept, visuals and mesh collisions dropped (with a
  note), into a file in the temporary folder named by its content hash. The Husky's file needs no
  rewrite and is loaded as it is.
- **Figures**: mass, centre of mass (whole robot, joints at zero), driven wheel radius, track
  (mean left minus mean right wheel y), wheelbase (front-most minus rear-most driven axle), the
  base's height above flat ground resting on its wheels, the IMU mount; each may be overridden in
  the config (``robot.overrides``); the overridden values feed the controller and the mechanics,
  the engines always simulate the description.

- **Passive suspension**: a ``revolute`` joint with finite limits and a lateral axis (a rocker or
  bogie pitching about y) between the base and driven wheels is a :class:`Suspension` joint: free,
  limited, with the description's ``<dynamics>`` damping and friction. Two such joints may be
  coupled (:class:`Coupling`): by URDF's ``<mimic>`` on the follower, or by the config's
  ``robot.couplings`` for a maker's description that leaves the linkage out (the Warthog's
  differential bar). Every engine enforces the coupling with its own constraint.

Refused, with one message naming the joint or link: prismatic, planar or floating joints, revolute
joints that hold no wheel, are unlimited or not lateral (steering, legs, arms), continuous joints
whose child has no collision, wheel axes
that are neither lateral nor (for a swivel) vertical, no driven wheels (tracks), a driven wheel
count other than 2, 4 or 6 or unequal sides, a description that is not XML.

The reader is split by idea: the records (:mod:`.spec`), finding the moving parts (:mod:`.parts`),
the rigid-body model (:mod:`.rigid`) and putting them together (:mod:`.load`); this package
re-exports the public names.
"""

from simpick.inputs.robot.load import OVERRIDABLE, load_from_config, load_robot
from simpick.inputs.robot.spec import SKID_REACH, Coupling, RobotSpec, Skid, Suspension, Wheel
from simpick.inputs.urdf import SNAP_TOLERANCE_DEG

__all__ = [
    "OVERRIDABLE",
    "Coupling",
    "Suspension",
    "RobotSpec",
    "SKID_REACH",
    "SNAP_TOLERANCE_DEG",
    "Skid",
    "Wheel",
    "load_from_config",
    "load_robot",
]
