"""ODE's contacts in the adapter: the collision callback that turns each geom pair's contacts into
contact joints, with the friction direction and the anisotropic (elliptic) wheel friction of
:class:`~simpick.engines.ode_settings.OdeSettings`. ``owner`` is the :class:`~simpick.engines.ode_world.OdeWorld`
whose contact buffers (``surface_of``, ``robot_contacts``), bodies and axles the callback reads."""

from __future__ import annotations

import ctypes
import math

from simpick.engines import _ode


def near_callback(owner) -> _ode.dNearCallback:
    """The dSpaceCollide callback: contacts of one geom pair -> contact joints.

    With ``friction_direction`` "slip" or "coulomb" (the default) each contact's first friction
    direction (fdir1) is set to its sliding direction: the relative velocity of the two
    bodies at the contact point, projected onto the contact plane (Bullet's default
    "velocity dependent friction direction", btSequentialImpulseConstraintSolver). ODE's
    friction is a pyramid, two directions each bounded by mu N on its own; left to
    itself (dPlaneSpace of the normal) it aligns them with the world's x and y, so a
    wheel sliding diagonally meets up to sqrt(2) mu N, not opposite its slip, and the
    skid-steered Husky barely turns (see simpick.engines.ode_settings, friction_direction). With fdir1 along the
    slip, a sliding contact's friction is mu N straight against its slip: Coulomb's law.
    Below ``friction_direction_min_slip`` (m/s: rolling or parked) the direction is
    undefined and fdir1 is dPlaneSpace's, i.e. ODE's own choice.
    """
    lib = owner.lib
    surface_of, body_of = owner.surface_of, owner.body_of
    robot_contacts, max_contacts = owner.robot_contacts, owner.max_contacts
    stride = ctypes.sizeof(_ode.dContact)
    collide, create, attach = lib.dCollide, lib.dJointCreateContact, lib.dJointAttach
    world, group = owner.world, owner.group
    # each robot body's position, linear and angular velocity read straight from ODE's
    # memory (one dReal array over the span holding them): cheaper than dBodyGetPointVel
    state = {}
    for body in set(body_of.values()):
        a = [lib.dBodyGetPosition(body), lib.dBodyGetLinearVel(body), lib.dBodyGetAngularVel(body)]
        lo = min(a)
        view = (_ode.dReal * ((max(a) - lo) // ctypes.sizeof(_ode.dReal) + 3)).from_address(lo)
        state[body] = (view, *((x - lo) // ctypes.sizeof(_ode.dReal) for x in a))
    real = ctypes.sizeof(_ode.dReal)
    geom = _ode.dContact.geom.offset
    P = (geom + _ode.dContactGeom.pos.offset) // real  # indices into a contact's dReals
    N = (geom + _ode.dContactGeom.normal.offset) // real
    F = _ode.dContact.fdir1.offset // real
    min_slip2 = owner.min_slip**2
    coulomb = owner.coulomb
    MU = _ode.dContact.surface.offset // real + _ode.dSurfaceParameters.mu.offset // real
    MU2 = _ode.dContact.surface.offset // real + _ode.dSurfaceParameters.mu2.offset // real
    sqrt, half = math.sqrt, math.sqrt(0.5)
    ratio = owner.settings.friction_ratio
    axles = owner.axles if ratio != 1.0 else {}  # empty: the isotropic path, unchanged
    r2 = ratio * ratio

    limit = surface_limits(owner)

    if owner.wheel_directions:
        return _ode.dNearCallback(_wheel_near(owner, contact_state=(collide, create, attach, stride), limit=limit))

    if not owner.slip_directions and limit is not None:

        def near(_data, g1, g2):
            contacts = surface_of.get(g1) or surface_of.get(g2) or robot_contacts
            n = collide(g1, g2, max_contacts, contacts[0], stride)
            if n:
                b1, b2 = body_of.get(g1), body_of.get(g2)
                for i in range(n):
                    limit(contacts[2][i])
                    attach(create(world, group, contacts[1][i]), b1, b2)

        return _ode.dNearCallback(near)

    if not owner.slip_directions:

        def near(_data, g1, g2):
            # the pair's contact buffer: its surface (mode, mu) is preset, dCollide fills
            # the geometry of each dContact in place (stride = sizeof(dContact))
            contacts = surface_of.get(g1) or surface_of.get(g2) or robot_contacts
            n = collide(g1, g2, max_contacts, contacts[0], stride)
            if n:
                b1, b2 = body_of.get(g1), body_of.get(g2)
                for address in contacts[1][:n]:
                    attach(create(world, group, address), b1, b2)

        return _ode.dNearCallback(near)

    def near(_data, g1, g2):
        contacts = surface_of.get(g1) or surface_of.get(g2) or robot_contacts
        n = collide(g1, g2, max_contacts, contacts[0], stride)
        if n:
            b1, b2 = body_of.get(g1), body_of.get(g2)
            for i in range(n):
                c = contacts[2][i]
                px, py, pz, nx, ny, nz = c[P], c[P + 1], c[P + 2], c[N], c[N + 1], c[N + 2]
                vx = vy = vz = 0.0
                for body, sign in ((b1, 1.0), (b2, -1.0)):  # velocity of b1 relative to b2
                    if body:
                        b, x, v, w = state[body]
                        rx, ry, rz = px - b[x], py - b[x + 1], pz - b[x + 2]
                        wx, wy, wz = b[w], b[w + 1], b[w + 2]
                        vx += sign * (b[v] + wy * rz - wz * ry)
                        vy += sign * (b[v + 1] + wz * rx - wx * rz)
                        vz += sign * (b[v + 2] + wx * ry - wy * rx)
                d = vx * nx + vy * ny + vz * nz
                vx, vy, vz = vx - d * nx, vy - d * ny, vz - d * nz
                s2 = vx * vx + vy * vy + vz * vz
                if s2 > min_slip2:
                    k = 1.0 / sqrt(s2)
                    c[F], c[F + 1], c[F + 2] = vx * k, vy * k, vz * k
                    if coulomb:  # sliding: mu N against the slip, nothing across it
                        c[MU2] = 0.0
                elif abs(nz) > half:  # dPlaneSpace (ODE's choice when fdir1 is not given)
                    k = 1.0 / sqrt(ny * ny + nz * nz)
                    c[F], c[F + 1], c[F + 2] = 0.0, -nz * k, ny * k
                else:
                    k = 1.0 / sqrt(nx * nx + ny * ny)
                    c[F], c[F + 1], c[F + 2] = -ny * k, nx * k, 0.0
                if coulomb and s2 <= min_slip2:  # sticking: the full pyramid holds it
                    c[MU2] = c[MU]
                if axles:
                    wheel = axles.get(b1) or axles.get(b2)
                    if wheel is not None:
                        elliptic(c, wheel, contacts[3], nx, ny, nz, vx, vy, vz, s2 > min_slip2, ratio, r2, F, MU, MU2)
                    else:
                        c[MU] = contacts[3]
                        if s2 <= min_slip2:
                            c[MU2] = c[MU]
                if limit is not None:
                    limit(c)
                attach(create(world, group, contacts[1][i]), b1, b2)

    return _ode.dNearCallback(near)


def surface_limits(owner):
    """Per-body contact limits (OdeSettings.contact_max_vel / contact_min_depth) on one contact, or None when
    neither is set.

    Gazebo Classic hands each link's collision surface <max_vel> and <min_depth> to its ODE fork per body
    (ODELink::UpdateSurface: dBodySetMaxVel, dBodySetMinDepth), and the fork's contact joint takes the depth less
    the body's min_depth in place of the world's surface layer (deps/opende/src/joints/contact.cpp,
    dxJointContact::getInfo2). ODE 0.16 has only the world's layer, so the contact's depth is shifted here so
    that ODE's subtraction of the world's layer leaves depth - min_depth. ``contact_max_vel`` lowers the
    contact's ERP (dContactSoftERP) so that ERP x depth / step does not exceed it: ODE 0.16's own cap, on
    position and velocity alike (the fork's quickstep caps only the velocity: OdeSettings)."""
    s = owner.settings
    if s.contact_max_vel is None and s.contact_min_depth is None:
        return None
    real = ctypes.sizeof(_ode.dReal)
    D = (_ode.dContact.geom.offset + _ode.dContactGeom.depth.offset) // real
    E = (_ode.dContact.surface.offset + _ode.dSurfaceParameters.soft_erp.offset) // real
    shift = s.contact_surface_layer - (
        s.contact_min_depth if s.contact_min_depth is not None else s.contact_surface_layer
    )
    max_vel = s.contact_max_vel
    fps = 1.0 / owner.dt
    erp = owner.contact_erp  # the contact's ERP before the cap: its own soft ERP, or the world's

    def limit(c) -> None:
        depth = c[D] + shift  # ODE subtracts the world's layer from this: depth - min_depth remains
        c[D] = depth
        if max_vel is not None:
            pushout = depth - s.contact_surface_layer
            c[E] = erp if pushout <= 0 else min(erp, max_vel / (fps * pushout))

    return limit


def elliptic(c, wheel, mu, nx, ny, nz, vx, vy, vz, sliding, ratio, r2, F, MU, MU2) -> None:
    """A driven wheel's contact with friction ratio ``ratio`` (OdeSettings.friction_ratio):
    sliding, the elliptic Coulomb force along fdir1 alone; sticking, the box in the wheel frame."""
    R, (a0, a1, a2) = wheel
    # world hinge axis (dMatrix3: 3 rows of 4), its part in the contact plane = lateral t
    ax, ay, az = (
        R[0] * a0 + R[1] * a1 + R[2] * a2,
        R[4] * a0 + R[5] * a1 + R[6] * a2,
        R[8] * a0 + R[9] * a1 + R[10] * a2,
    )
    d = ax * nx + ay * ny + az * nz
    tx, ty, tz = ax - d * nx, ay - d * ny, az - d * nz
    k = 1.0 / math.sqrt(tx * tx + ty * ty + tz * tz)
    tx, ty, tz = tx * k, ty * k, tz * k
    lx, ly, lz = ny * tz - nz * ty, nz * tx - nx * tz, nx * ty - ny * tx  # rolling direction n x t
    if sliding:
        sl, st = vx * lx + vy * ly + vz * lz, vx * tx + vy * ty + vz * tz
        fl, ft = sl, r2 * st
        size = math.sqrt(fl * fl + ft * ft)
        c[F], c[F + 1], c[F + 2] = (fl * lx + ft * tx) / size, (fl * ly + ft * ty) / size, (fl * lz + ft * tz) / size
        c[MU] = mu * size / math.sqrt(sl * sl + r2 * st * st)
        c[MU2] = 0.0
    else:
        c[F], c[F + 1], c[F + 2] = lx, ly, lz
        c[MU], c[MU2] = mu, ratio * mu


def _wheel_near(owner, contact_state, limit=None):
    """The callback of ``friction_direction`` "wheel": a driven wheel's contacts get fdir1 along the
    wheel's rolling direction and mu2 = friction_ratio x mu across it (the pyramid turned with the
    wheel, as an SDF <fdir1> along the wheel sets it); every other contact gets dPlaneSpace's fdir1
    (ODE's own choice) and mu on both rows."""
    collide, create, attach, stride = contact_state
    surface_of, body_of = owner.surface_of, owner.body_of
    robot_contacts, max_contacts = owner.robot_contacts, owner.max_contacts
    world, group = owner.world, owner.group
    real = ctypes.sizeof(_ode.dReal)
    N = (_ode.dContact.geom.offset + _ode.dContactGeom.normal.offset) // real
    F = _ode.dContact.fdir1.offset // real
    MU = _ode.dContact.surface.offset // real + _ode.dSurfaceParameters.mu.offset // real
    MU2 = _ode.dContact.surface.offset // real + _ode.dSurfaceParameters.mu2.offset // real
    axles, ratio, half = owner.axles, owner.settings.friction_ratio, math.sqrt(0.5)
    link_x = owner.settings.friction_direction == "wheel_x"

    def near(_data, g1, g2):
        contacts = surface_of.get(g1) or surface_of.get(g2) or robot_contacts
        n = collide(g1, g2, max_contacts, contacts[0], stride)
        if n:
            b1, b2 = body_of.get(g1), body_of.get(g2)
            wheel = axles.get(b1) or axles.get(b2)
            for i in range(n):
                c = contacts[2][i]
                nx, ny, nz = c[N], c[N + 1], c[N + 2]
                if wheel is not None and link_x:  # the wheel link's x axis in the world, as given
                    R = wheel[0]
                    c[F], c[F + 1], c[F + 2] = R[0], R[4], R[8]
                    c[MU], c[MU2] = contacts[3], ratio * contacts[3]
                elif wheel is not None:
                    elliptic(c, wheel, contacts[3], nx, ny, nz, 0.0, 0.0, 0.0, False, ratio, 0.0, F, MU, MU2)
                else:
                    if abs(nz) > half:  # dPlaneSpace
                        k = 1.0 / math.sqrt(ny * ny + nz * nz)
                        c[F], c[F + 1], c[F + 2] = 0.0, -nz * k, ny * k
                    else:
                        k = 1.0 / math.sqrt(nx * nx + ny * ny)
                        c[F], c[F + 1], c[F + 2] = -ny * k, nx * k, 0.0
                    c[MU] = c[MU2] = contacts[3]
                if limit is not None:
                    limit(c)
                attach(create(world, group, contacts[1][i]), b1, b2)

    return near
