"""One ODE world (simpick.engines.base.World): terrain geoms, robot bodies and hinges, and the
recorded robot's state copied from ODE's memory after each step. Built from the loader's rigid
bodies (:attr:`simpick.inputs.robot.RobotSpec.rigid`): an ODE body's origin must be its centre of
mass, so each body sits at its link's COM with the link's orientation, the full inertia tensor
about that point, and its collision shapes offset from it; the record is converted back to
base_link (position - R c, velocity - w x R c), as the PyBullet adapter does."""

from __future__ import annotations

import ctypes
import logging
import math

import numpy as np

from simpick.engines import _ode
from simpick.engines.base import BaseStates, Scenario
from simpick.engines.kinematics import matrices_to_quaternions, rotation_matrices
from simpick.engines.ode_contacts import near_callback
from simpick.engines.ode_settings import OdeSettings
from simpick.errors import InputError, SimulationFailure
from simpick.inputs.urdf import Body, rpy_matrix

LOG = logging.getLogger(__name__)
SPAWN_CLEARANCE = 0.002  # m above resting height, as for the other engines
TERRAIN_BIT = 1  # category bit of static terrain; robot i gets bit i + 1
ROBOT_ROBOT_FRICTION = 1.0
memmove = ctypes.memmove
ROWS = 4096  # steps per block of the record buffer (the run's length is not known in advance)
# A coupling between suspension joints (RobotSpec.couplings): ODE has no joint-space constraint that
# links two hinges on a moving body (its transmission joint gears two bodies about their own,
# distinct axes; the Warthog's rockers turn about one axis), so each coupling is a stiff
# spring-damper on g = q(joint) - multiplier q(leader) - offset, its torque -(k g + c g') applied each
# step to the follower's hinge and, times -multiplier, to the leader's (the linkage's virtual work),
# through dJointAddHingeTorque. Explicit, so bounded by stability; measured on the Warthog at 1 kHz
# (rest 2 s, then a 2 s spin at +-0.5 m/s rims), residual g at rest / after the spin:
#   k 1e5, c 2e3: 1.96e-4 / 1.96e-4 rad     k 3e5, c 2e3: 6.5e-5 / 5.5e-5 (chosen)
#   k 1e6, c 2e3: 2.0e-5 / 2.0e-5           k 1e5, c 6.3e3: 1.96e-4 / -9.6e-4 (near unstable)
#   k 1e6, c 6.3e3: diverges (the chassis flung 990 m up)
# so the explicit damping sets the limit (c x step / inertia reaches 2 near c 6e3: the coupled mode's
# inertia is about 3 kg m^2); the chosen stiffness is a third of 1e6 (stable), the damping a third of
# 6.3e3 (near unstable), a damping ratio of about 1 on that inertia.
COUPLING_STIFFNESS = 3.0e5  # N m/rad
COUPLING_DAMPING = 2.0e3  # N m s/rad


class OdeWorld:
    """One ODE world with terrain and robots; owns every ODE object it creates."""

    def __init__(self, lib, scenario: Scenario):
        self.lib = lib
        self.settings = OdeSettings.of(scenario.settings, "ode")
        self.world = self.space = self.group = None
        self._keep = []  # ctypes objects whose memory ODE or the callback refers to
        try:
            self._build(scenario)
        except BaseException:
            self.close()
            raise
        self.dt = scenario.timestep
        self.callback = near_callback(self)
        self.ok = 1
        self._record_layout()
        _ode.messages.clear()

    def _build(self, scenario: Scenario) -> None:
        """Terrain geoms, then per robot its bodies, hinges and motors."""
        lib, s = self.lib, self.settings
        if len(scenario.starts) > 62:
            raise InputError("starts", "the ODE adapter supports at most 62 robots (one category bit each)")
        lib.dAllocateODEDataForThread(_ode.dAllocateMaskAll)
        lib.dRandSetSeed(0)
        self.world = lib.dWorldCreate()
        lib.dWorldSetGravity(self.world, *scenario.gravity)
        lib.dWorldSetERP(self.world, s.erp)
        lib.dWorldSetCFM(self.world, s.cfm)
        lib.dWorldSetContactSurfaceLayer(self.world, s.contact_surface_layer)
        lib.dWorldSetContactMaxCorrectingVel(self.world, s.contact_max_correcting_vel)
        lib.dWorldSetAutoDisableFlag(self.world, 0)
        lib.dWorldSetQuickStepNumIterations(self.world, s.quick_iterations)
        self.step_fn = lib.dWorldStep if s.stepper == "world" else lib.dWorldQuickStep

        if s.space == "hash":
            self.space = lib.dHashSpaceCreate(None)
        elif s.space == "quadtree":
            # Sized to the terrain and the starts plus a margin the robots may drive into;
            # depth chosen so that the finest cells are about quadtree_cell wide (0.4 m
            # measured fastest on the gravel strip: 25 500 steps/s against 10 300 with
            # 1.6 m cells and 7 300 for a hash space, whose table is rebuilt every step).
            terrain = scenario.terrain
            xs = [b[0] for b in terrain.boxes] + [p[0] for p in terrain.spheres] + [st[0] for st in scenario.starts]
            ys = [b[1] for b in terrain.boxes] + [p[1] for p in terrain.spheres] + [st[1] for st in scenario.starts]
            margin = 10.0
            centre = _ode.dVector3((min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2, 0.0)
            extent = _ode.dVector3(max(xs) - min(xs) + 2 * margin, max(ys) - min(ys) + 2 * margin, 2 * margin)
            cell = s.quadtree_cell
            depth = 1 + max(0, math.ceil(math.log2(max(extent[0], extent[1]) / cell)))
            self.space = lib.dQuadTreeSpaceCreate(None, centre, extent, min(depth, 9))
        else:  # "simple"
            self.space = lib.dSimpleSpaceCreate(None)
        self.group = lib.dJointGroupCreate(0)

        n_robots = len(scenario.starts)
        robot_bits = ((1 << (n_robots + 1)) - 1) & ~TERRAIN_BIT
        self.surface_of: dict[int, tuple] = {}  # static geom -> contact buffer with its friction
        self.body_of: dict[int, int] = {}  # robot geom -> its body
        self.max_contacts = s.max_contacts
        buffers: dict[float, tuple] = {}

        self.slip_directions = s.friction_direction in ("slip", "coulomb")
        self.coulomb = s.friction_direction == "coulomb"
        self.wheel_directions = s.friction_direction in ("wheel", "wheel_x")
        self.min_slip = s.friction_direction_min_slip
        slip = s.contact_slip
        soft = s.contact_kp is not None or s.contact_soft_erp is not None or s.contact_soft_cfm is not None
        mode = (
            _ode.dContactApprox1
            | (_ode.dContactFDir1 if self.slip_directions or self.wheel_directions else 0)
            | (_ode.dContactMu2 if self.coulomb or self.wheel_directions else 0)
            | (_ode.dContactSlip1 | _ode.dContactSlip2 if slip > 0 else 0)
            | (_ode.dContactSoftERP | _ode.dContactSoftCFM if soft else 0)
            | (_ode.dContactSoftERP if s.contact_max_vel is not None else 0)  # the per-body cap (ode_contacts)
            | (_ode.dContactBounce if s.contact_bounce > 0 else 0)
        )
        if s.contact_kp is not None:  # SDF <kp>/<kd> as Gazebo Classic turns them into ERP and CFM
            hk = scenario.timestep * s.contact_kp
            soft_erp, soft_cfm = hk / (hk + s.contact_kd), 1.0 / (hk + s.contact_kd)
        else:  # given directly; an unset one is the world's
            soft_erp = s.erp if s.contact_soft_erp is None else s.contact_soft_erp
            soft_cfm = s.cfm if s.contact_soft_cfm is None else s.contact_soft_cfm
        self.contact_erp = soft_erp  # a contact's ERP before a per-body max_vel caps it (ode_contacts)

        def contacts_for(mu: float) -> tuple:
            if mu not in buffers:
                array = (_ode.dContact * self.max_contacts)()
                for c in array:
                    c.surface.mode = mode
                    c.surface.mu = c.surface.mu2 = mu  # both rows bounded by mu unless sliding ("coulomb")
                    c.surface.slip1 = c.surface.slip2 = slip
                    if soft or s.contact_max_vel is not None:
                        c.surface.soft_erp, c.surface.soft_cfm = soft_erp, soft_cfm
                    c.surface.bounce, c.surface.bounce_vel = s.contact_bounce, s.contact_bounce_vel
                self._keep.append(array)
                base = ctypes.addressof(array)
                size = ctypes.sizeof(_ode.dContact)
                # each contact also as a flat array of dReals, for the callback to read its
                # position and normal and write its fdir1 without building ctypes structs
                n_reals = size // ctypes.sizeof(_ode.dReal)
                views = tuple((_ode.dReal * n_reals).from_address(base + i * size) for i in range(self.max_contacts))
                self._keep.append(views)
                buffers[mu] = (
                    base + _ode.dContact.geom.offset,
                    tuple(base + i * size for i in range(self.max_contacts)),
                    views,
                    mu,
                )
            return buffers[mu]

        def static(geom: int, mu: float) -> None:
            lib.dGeomSetCategoryBits(geom, TERRAIN_BIT)
            lib.dGeomSetCollideBits(geom, robot_bits)
            self.surface_of[geom] = contacts_for(float(mu if s.surface_mu is None else min(mu, s.surface_mu)))

        static(lib.dCreatePlane(self.space, 0.0, 0.0, 1.0, 0.0), scenario.ground_friction)
        terrain = scenario.terrain
        for x, y, z, yaw, sx, sy, sz in terrain.boxes:
            geom = lib.dCreateBox(self.space, sx, sy, sz)
            lib.dGeomSetPosition(geom, x, y, z)
            lib.dGeomSetQuaternion(geom, _ode.dQuaternion(math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)))
            static(geom, terrain.friction)
        for x, y, z, r in terrain.spheres:
            geom = lib.dCreateSphere(self.space, r)
            lib.dGeomSetPosition(geom, x, y, z)
            static(geom, terrain.friction)
        self.robot_contacts = contacts_for(ROBOT_ROBOT_FRICTION)

        model = scenario.robot.rigid  # the loader's bodies: fixed-joint chains folded
        self.model = model
        self.robots = []  # per robot: (chassis body, [hinge joints], [wheel bodies])
        self.rockers = []  # per robot: ([suspension link bodies], [their hinges]), in RobotSpec.suspension order
        self.axles: dict[int, tuple] = {}  # driven wheel body -> (its rotation matrix, hinge axis in body frame)
        self.recorded = scenario.recorded_robot
        torque = float(scenario.max_wheel_torque)
        for i, (x, y, yaw) in enumerate(scenario.starts):
            own = 1 << (i + 1)
            yaw_rot = rpy_matrix((0.0, 0.0, yaw))
            base_pos = np.array([x, y, scenario.robot.base_height + SPAWN_CLEARANCE])

            def make_body(part: Body, link_pos: np.ndarray, link_rot: np.ndarray, own: int = own) -> int:
                body = lib.dBodyCreate(self.world)
                mass = _ode.dMass()
                I = part.inertia
                lib.dMassSetParameters(
                    ctypes.byref(mass), part.mass, 0.0, 0.0, 0.0, I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]
                )
                if not lib.dMassCheck(ctypes.byref(mass)):
                    raise InputError(str(scenario.robot.urdf), "a link's inertia is not positive definite")
                lib.dBodySetMass(body, ctypes.byref(mass))
                px, py, pz = link_pos + link_rot @ part.com
                lib.dBodySetPosition(body, px, py, pz)
                lib.dBodySetQuaternion(body, _ode.dQuaternion(*matrices_to_quaternions(link_rot[None])[0]))
                for kind, dims, pos, rot in part.shapes:
                    if kind == "box":
                        geom = lib.dCreateBox(self.space, *dims)
                    elif kind == "cylinder":  # ODE's cylinder axis is local z, like URDF's
                        geom = lib.dCreateCylinder(self.space, *dims)
                    else:
                        geom = lib.dCreateSphere(self.space, *dims)
                    lib.dGeomSetBody(geom, body)
                    ox, oy, oz = pos - part.com
                    lib.dGeomSetOffsetPosition(geom, ox, oy, oz)
                    lib.dGeomSetOffsetQuaternion(geom, _ode.dQuaternion(*matrices_to_quaternions(rot[None])[0]))
                    lib.dGeomSetCategoryBits(geom, own)
                    lib.dGeomSetCollideBits(geom, TERRAIN_BIT | (robot_bits & ~own))
                    self.body_of[geom] = body
                return body

            def hinge_between(child, parent, anchor, axis):
                hinge = lib.dJointCreateHinge(self.world, None)
                # body1 = child, body2 = parent: ODE's hinge rate is (w1 - w2) . axis, so this
                # order makes it the URDF joint velocity (child relative to parent).
                lib.dJointAttach(hinge, child, parent)
                lib.dJointSetHingeAnchor(hinge, *anchor)
                lib.dJointSetHingeAxis(hinge, *axis)
                return hinge

            chassis = make_body(model.chassis, base_pos, yaw_rot)
            # passive suspension links (rockers), parents before children: hinges with the description's
            # limits as ODE's joint stops and its friction as ODE's joint-friction idiom, a velocity motor
            # held at 0 with the friction torque as its bound (as Gazebo's ODE joints do); damping and
            # couplings are torques applied each step (step)
            rockers, rocker_hinges = [], []
            for xyz, rot, axis, part, parent, sus in model.suspension:
                parent_pos, parent_rot, parent_body = (base_pos, yaw_rot, chassis) if parent < 0 else rockers[parent]
                link_pos, link_rot = parent_pos + parent_rot @ xyz, parent_rot @ rot
                body = make_body(part, link_pos, link_rot)
                hinge = hinge_between(body, parent_body, link_pos, link_rot @ axis)
                lib.dJointSetHingeParam(hinge, _ode.dParamLoStop, sus.lower)
                lib.dJointSetHingeParam(hinge, _ode.dParamHiStop, sus.upper)
                lib.dJointSetHingeParam(hinge, _ode.dParamVel, 0.0)
                lib.dJointSetHingeParam(hinge, _ode.dParamFMax, sus.friction)
                rockers.append((link_pos, link_rot, body))
                rocker_hinges.append(hinge)
            hinges, wheel_bodies = [], []
            for k, (xyz, rot, axis, part) in enumerate(model.wheels):
                on = model.wheel_parents[k] if model.wheel_parents else -1
                parent_pos, parent_rot, parent_body = (base_pos, yaw_rot, chassis) if on < 0 else rockers[on]
                link_pos, link_rot = parent_pos + parent_rot @ xyz, parent_rot @ rot
                wheel = make_body(part, link_pos, link_rot)
                hinge = hinge_between(wheel, parent_body, link_pos, link_rot @ axis)
                lib.dJointSetHingeParam(hinge, _ode.dParamVel, 0.0)
                lib.dJointSetHingeParam(hinge, _ode.dParamFMax, torque)
                hinges.append(hinge)
                wheel_bodies.append(wheel)
            # casters and swivels: free hinges (no motor), each on its parent link
            frames = []
            for xyz, rot, axis, part, parent in model.passive:
                parent_pos, parent_rot, parent_body = (base_pos, yaw_rot, chassis) if parent < 0 else frames[parent]
                link_pos, link_rot = parent_pos + parent_rot @ xyz, parent_rot @ rot
                body = make_body(part, link_pos, link_rot)
                hinge_between(body, parent_body, link_pos, link_rot @ axis)
                frames.append((link_pos, link_rot, body))
            for (_xyz, _rot, axis, _part), wheel in zip(model.wheels, wheel_bodies):
                # the hinge axis in the wheel body's frame (the body keeps its link's orientation)
                self.axles[wheel] = (
                    (_ode.dReal * 12).from_address(lib.dBodyGetRotation(wheel)),
                    tuple(float(a) for a in axis),
                )
            self.robots.append((chassis, hinges, wheel_bodies))
            self.rockers.append(([body for _, _, body in rockers], rocker_hinges))
        self.all_hinges = [h for _, hs, _ in self.robots for h in hs]
        # per-step suspension torques: (hinges, damping per hinge, couplings as (follower index, leader
        # index, multiplier, offset)) per robot; None without suspension (the stepping loop is then unchanged)
        robot = scenario.robot
        names = [sus.joint for sus in robot.suspension]
        couplings = [(names.index(c.joint), names.index(c.leader), c.multiplier, c.offset) for c in robot.couplings]
        damping = [sus.damping for sus in robot.suspension]
        self.suspension = (
            [(hs, damping, couplings) for _, hs in self.rockers] if robot.suspension and model.suspension else None
        )

    def close(self) -> None:
        lib = self.lib
        if self.group:
            lib.dJointGroupDestroy(self.group)
        if self.space:
            lib.dSpaceDestroy(self.space)  # destroys its geoms too (cleanup mode is on by default)
        if self.world:
            lib.dWorldDestroy(self.world)  # and the bodies and joints
        self.world = self.space = self.group = None

    def set_wheel_targets(self, speeds: np.ndarray) -> None:
        set_param, vel = self.lib.dJointSetHingeParam, _ode.dParamVel
        for hinge, w in zip(self.all_hinges, speeds.ravel().tolist()):
            set_param(hinge, vel, w)

    def step(self, n: int = 1) -> None:
        # the calls and their arguments in one tuple: a step costs ~35 us, so attribute lookups count
        space_collide, space, callback, step, world, dt, empty, group = self.stepping
        ok = self.ok
        if self.suspension is not None:
            self._step_suspended(n)
            return
        for _ in range(n):
            space_collide(space, None, callback)
            ok &= step(world, dt)
            empty(group)
        self.ok = ok

    def _step_suspended(self, n: int) -> None:
        """``step`` with the suspension's damping (-damping x joint speed) and coupling torques
        (COUPLING_STIFFNESS) applied before each step; ODE clears applied torques after a step."""
        space_collide, space, callback, step, world, dt, empty, group = self.stepping
        angle, rate, add = self.lib.dJointGetHingeAngle, self.lib.dJointGetHingeAngleRate, self.lib.dJointAddHingeTorque
        k, c = COUPLING_STIFFNESS, COUPLING_DAMPING
        ok = self.ok
        for _ in range(n):
            space_collide(space, None, callback)
            for hinges, damping, couplings in self.suspension:
                speeds = [rate(h) for h in hinges]
                torques = [-d * v for d, v in zip(damping, speeds)]
                for f, lead, m, offset in couplings:
                    force = -(
                        k * (angle(hinges[f]) - m * angle(hinges[lead]) - offset) + c * (speeds[f] - m * speeds[lead])
                    )
                    torques[f] += force
                    torques[lead] -= m * force
                for h, t in zip(hinges, torques):
                    add(h, t)
            ok &= step(world, dt)
            empty(group)
        self.ok = ok

    def suspension_angles(self) -> list[float]:
        """The recorded robot's suspension joint angles (rad), in RobotSpec.suspension order."""
        return [self.lib.dJointGetHingeAngle(h) for h in self.rockers[self.recorded][1]]

    def _record_layout(self) -> None:
        """The recorded robot's state is copied each step straight from ODE's body memory: one
        memmove of the span holding a body's position, quaternion and velocities (addresses from
        dBodyGet*), so reading creates no Python objects for it."""
        lib = self.lib
        chassis, _, wheels = self.robots[self.recorded]
        getters = (lib.dBodyGetPosition, lib.dBodyGetQuaternion, lib.dBodyGetLinearVel, lib.dBodyGetAngularVel)
        chunks, layout, width = [], [], 0
        # the suspension links after the wheels: a wheel on a rocker turns relative to it
        for body in [chassis] + wheels + self.rockers[self.recorded][0]:
            addresses = [g(body) for g in getters]
            lo, hi = min(addresses), max(addresses) + 4 * 8
            if hi - lo <= 1024:  # one contiguous copy per body
                chunks.append((lo, hi - lo, width))
                layout.append([width + (a - lo) // 8 for a in addresses])
                width += (hi - lo) // 8
            else:  # body state not close together: copy each vector on its own
                cols = []
                for a in addresses:
                    chunks.append((a, 32, width))
                    cols.append(width)
                    width += 4
                layout.append(cols)
        self.layout, self.width = layout, width
        self.copies = tuple((src, size, off * 8) for src, size, off in chunks)
        self.blocks, self.row, self.at = [], ROWS, 0
        self.stepping = (
            lib.dSpaceCollide,
            self.space,
            self.callback,
            self.step_fn,
            self.world,
            self.dt,
            lib.dJointGroupEmpty,
            self.group,
        )

    def read(self) -> None:
        """Copies the state into the world's own record (``states`` returns it)."""
        if self.row == ROWS:
            self.blocks.append(np.zeros((ROWS, self.width)))
            self.row, self.at = 0, self.blocks[-1].ctypes.data
        at = self.at
        for src, size, off in self.copies:
            memmove(at + off, src, size)
        self.row += 1
        self.at = at + self.width * 8

    def states(self, samples: list) -> BaseStates:
        steps = len(samples)
        if _ode.messages:
            LOG.warning(
                "ODE messages during %d steps: %s",
                steps,
                "; ".join(f"{n} x ODE message {num}: {text!r}" for (num, text), n in _ode.messages.items()),
            )
        if not self.ok:
            raise SimulationFailure("ODE's stepper failed (dWorldStep/dWorldQuickStep returned 0: out of memory)")
        buffer = np.concatenate(self.blocks)[:steps] if self.blocks else np.zeros((0, self.width))

        def columns(body_index: int, which: int, n: int) -> np.ndarray:
            c = self.layout[body_index][which]
            return buffer[:, c : c + n]

        com, quat = columns(0, 0, 3), columns(0, 1, 4).copy()
        com_v, omega = columns(0, 2, 3), columns(0, 3, 3).copy()
        quat /= np.linalg.norm(quat, axis=1, keepdims=True)
        rot = rotation_matrices(quat)
        offset = rot @ self.model.chassis.com
        wheel_speed = np.empty((steps, len(self.model.wheels)))
        n_wheels = len(self.model.wheels)
        for j, (_, jrot, axis, _) in enumerate(self.model.wheels):
            on = self.model.wheel_parents[j] if self.model.wheel_parents else -1
            if on < 0:  # on the chassis
                axis_world = rot @ (jrot @ axis)
                wheel_speed[:, j] = np.einsum("ni,ni->n", columns(1 + j, 3, 3) - omega, axis_world)
                continue
            # on a suspension link: its speed relative to that link, about the axis the link carries
            parent_q = columns(1 + n_wheels + on, 1, 4)
            parent_rot = rotation_matrices(parent_q / np.linalg.norm(parent_q, axis=1, keepdims=True))
            axis_world = parent_rot @ (jrot @ axis)
            parent_omega = columns(1 + n_wheels + on, 3, 3)
            wheel_speed[:, j] = np.einsum("ni,ni->n", columns(1 + j, 3, 3) - parent_omega, axis_world)
        return BaseStates(
            position=com - offset,
            quaternion=quat,
            linear_velocity=com_v - np.cross(omega, offset),
            angular_velocity=omega,
            wheel_speed=wheel_speed,
        )
