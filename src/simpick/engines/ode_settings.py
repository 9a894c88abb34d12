"""The ODE adapter's settings (config ``engines.ode``), each with what was measured for it."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator

from simpick.engines.base import EngineSettings


class OdeSettings(EngineSettings):
    """config ``engines.ode``. Figures measured here, 1 kHz, one robot; steps/s are of the whole
    Python stepping loop, which on flat ground spends most of its time in the collision callback
    (4 geom pairs, 8 contacts per step)."""

    # "world" or "quick". dWorldStep solves the constraints exactly (Dantzig LCP); with one robot
    # the system is small (about 20 joint rows + 3 per contact), and it was the faster of the two:
    # flat 4 s at 0.5 m/s 35 600 against 27 700 steps/s for dWorldQuickStep with 50 iterations;
    # gravel strip 26 000 against 20 400. Both pass the conformance suite. The exact solver now and
    # then prints "LCP internal error, s <= 0" (a degenerate pivot it recovers from; 4 times in 10 s
    # on the bumps strip); the adapter counts these and logs them instead of letting them reach stderr.
    # Only "quick" (50 iterations, with friction_direction_min_slip 5 mm/s) passes every
    # validation case: sliding down a slope at 45 degrees to the robot it yaws 0.0003 rad in 3 s and
    # slides at 1.015 m/s^2 (Coulomb 1.016; dWorldStep: 0.27 rad, 0.975). Its turning gains 0.478-0.491
    # at mu 0.8 / 0.2, left and right within 0.01 of each other, the same at every start heading.
    # Cost, CPU steps/s of the bare loop, lab straight 4 s, median of 3, quick / world: grass 13 160 /
    # 12 940, bumps 13 420 / 15 700, gravel 10 220 / 12 680; flat-ground turning about 0.55x.
    # config.yaml uses "quick"; the default stays ODE's own dWorldStep.
    stepper: Literal["world", "quick"] = "world"
    # quick stepper only; ODE's default is 20, Gazebo's 50
    quick_iterations: Annotated[int, Field(ge=1)] = 50
    # error reduction parameter, a fraction of the joint error corrected per step: 0.2, ODE's default
    erp: Annotated[float, Field(ge=0, le=1)] = 0.2
    # constraint force mixing: 1e-5 is Webots' WorldInfo default and ODE's default for
    # single-precision builds; Debian's double-precision build defaults to 1e-10, which we have
    # not validated
    cfm: Annotated[float, Field(ge=0, allow_inf_nan=False)] = 1e-5
    # m, ODE's default 0. Gazebo's 0.001 lets the robot rest 1 mm deep: base_link at 0.13127 m
    # instead of 0.13228 m.
    contact_surface_layer: Annotated[float, Field(ge=0, allow_inf_nan=False)] = 0.0
    # m/s (ODE's default is unlimited: .inf; Gazebo's 100 m/s). ODE pushes penetration out at
    # ERP x depth / dt; when a wheel meets a plywood edge of the bumps strip that is a kick:
    # unlimited, the base velocity jumped by 0.90 m/s within one step and the run failed the health
    # check (limit 0.5 m/s); 0.5 m/s -> 0.36 m/s, 0.1 m/s -> 0.24 m/s (PyBullet 0.49, DART 0.41,
    # MuJoCo 0.04 on the same strip). Other engines cap this too (DART: 1 mm/s; Bullet: split impulse).
    contact_max_correcting_vel: Annotated[float, Field(gt=0)] = 0.1
    # contact points per geom pair (8 gave identical runs: ODE's cylinder colliders return at most
    # 4 here; a wheel on the ground gets 2, across its width). dCollide takes the count in the
    # low 16 bits of its flags.
    max_contacts: Annotated[int, Field(ge=1, le=0xFFFF)] = 4
    # A hash space rebuilds its table every step, for every static stone: gravel strip 7 300
    # steps/s (hash) against 25 500 (quadtree with 0.4 m cells; 10 300 with 1.6 m cells, 24 700
    # with 0.2 m), flat ground the same either way.
    space: Literal["quadtree", "hash", "simple"] = "quadtree"
    quadtree_cell: Annotated[float, Field(gt=0, allow_inf_nan=False)] = 0.4  # m, finest cell (space above)
    # "plane" leaves fdir1 to ODE, which takes dPlaneSpace of the normal: on flat ground the
    # world's x and y. A wheel sliding diagonally to them then meets friction up to sqrt(2) mu N,
    # not opposite its slip, and the skid-steered Husky hardly turns (validation cases,
    # 6 s, mu 0.8): yaw-rate gain 0.115 at (v, w) = (0, 0.5), 0.207 at (0.5, 0.5), 0.028 at
    # (0.5, 0.2); mu 0.2: 0.219 / 0.388; Coulomb 0.478. Commanded to spin, it drove forward at
    # 0.135 m/s instead (the heavier right wheels rolled, the left ones slid). Parked on a
    # 1.2 atan(mu) slope it slides (1.015 m/s^2, Coulomb 1.016) when the slope runs along x, and
    # stays put when it runs along the world diagonal. Gazebo users see the same
    # (jackal_simulator#18, husky#105; gazebo-classic#2068, where a user fixes it by computing the
    # friction direction himself between collision and physics update).
    # "slip" does that: fdir1 = the contact's sliding direction (Bullet's default "velocity
    # dependent friction direction"), so a sliding contact gets mu N against its slip. Gains then
    # 0.483 / 0.484 / 0.482 (mu 0.8), 0.487 / 0.507 (mu 0.2), within 1-6 % of 0.478; the 45-degree
    # slope slides at 0.974 m/s^2. Cost: flat ground 26 200 -> 19 600 steps/s (bare loop), gravel
    # strip about 12 900 -> 11 100. Residual artefact of "slip": the second row (across the slip)
    # still holds up to mu N, so a robot sliding down a slope with locked wheels yaws (1.24 rad in
    # 3 s at 1.2 atan(0.5); Coulomb friction has no yaw moment there) and slides 3 % slower.
    # "coulomb" (the default) also frees that row (dContactMu2, mu2 = 0) while the contact slides
    # faster than friction_direction_min_slip: a sliding contact then gets exactly Coulomb's mu N
    # against its slip and nothing across it; a slower one keeps the full pyramid (sticking).
    # Measured: the same gains (0.482-0.487), slide down the slope 1.016 m/s^2 (Coulomb 1.016)
    # with 0.014 rad of yaw. Not cured: on a slope at 45 degrees to the robot it slides at 0.975
    # (4 % slow) and yaws 0.27 rad in 3 s (0.036 rad per metre); the other three engines yaw
    # < 0.01 rad there (validation case incline_slide_diagonal). With the quick stepper it does not
    # (0.0003 rad, 1.015 m/s^2; stepper above).
    # "wheel": fdir1 along each driven wheel's rolling direction (the contact plane's line across the
    # hinge axis), both rows bounded by mu on their own: the friction pyramid turned with the wheel, what
    # an SDF <fdir1> along the wheel gives in Gazebo Classic (Clearpath's Husky and Warthog tags); other
    # contacts keep ODE's own directions. A wheel sliding sideways in a skid turn then meets mu N across
    # it whatever it slips along it: the box, up to sqrt(2) mu N.
    # "wheel_x": what Gazebo Classic does with an SDF <fdir1>1 0 0</fdir1> on a wheel's collision
    # (ODEPhysics.cc Collide: fdir1 rotated by the collision's world pose, not projected onto the contact
    # plane): fdir1 = the wheel link's own x axis, which turns with the wheel's spin, handed to ODE as it is.
    friction_direction: Literal["coulomb", "slip", "plane", "wheel", "wheel_x"] = "coulomb"
    # m/s, the stick/slip threshold of "coulomb" (below it fdir1 is dPlaneSpace's and both rows
    # hold). It must exceed the creep that ODE's constraint softness allows a sticking contact
    # (CFM x load: 0.27 mm/s measured on the 0.8 atan(mu) slope); at 1e-6 that creep counts as
    # sliding, the cross row is freed and the parked robot creeps 3.4 mm/s. 1e-3 and 3e-3 gave
    # identical validation figures with dWorldStep. The quick stepper's sticking contacts creep
    # faster: at 1e-3 the robot parked on the 0.8 atan(mu) slope crept 2.7 mm/s, at 5e-3 0.32 mm/s
    # (config.yaml: 5e-3 with "quick").
    friction_direction_min_slip: Annotated[float, Field(ge=0, allow_inf_nan=False)] = 1e-3
    # force-dependent slip of terrain contacts, (m/s)/N on both friction rows (ODE's
    # dContactSlip1/2: a contact slides at slip x friction force); Gazebo exposes it as
    # <slip1>/<slip2> and users tune it for skid-steer turning. 0: off (ODE's default).
    contact_slip: Annotated[float, Field(ge=0, allow_inf_nan=False)] = 0.0
    # Lateral / longitudinal friction ratio of the driven wheels' contacts, in each
    # wheel's frame (longitudinal = the rolling direction, normal x the hinge axis). 1: isotropic
    # (the default, today's behaviour, bit-identical). ODE's own anisotropy is mu along fdir1 and
    # mu2 across it, each row bounded on its own: a box, not Coulomb's ellipse. With
    # friction_direction "coulomb" the adapter gives a sliding wheel contact the elliptic force
    # instead (simpick.coulomb): fdir1 along (s_long, r^2 s_lat) in the wheel frame, bounded by
    # mu N |(s_long, r^2 s_lat)| / |(s_long, r s_lat)|, mu2 = 0; a sticking one gets the box (fdir1
    # along the wheel, mu along it, r mu across). Measured (quick stepper, mu 0.8, 6 s, (v, w) =
    # (0, 0.5) / (0.5, 0.5) / (0.5, -0.5), anisotropic Coulomb in brackets): r 1 0.488 / 0.484 / 0.483
    # (0.478), 0.8 0.600 / 0.598 / 0.597 (0.601), 0.63 0.694 / 0.694 / 0.696 (0.705), 0.5 0.761 /
    # 0.764 / 0.767 (0.781); the same 0.694-0.696 from start headings 112.5 and -135 degrees.
    friction_ratio: Annotated[float, Field(gt=0, le=2, allow_inf_nan=False)] = 1.0
    # Contact stiffness and damping of terrain contacts, N/m and N s/m, as Gazebo Classic's SDF <kp> / <kd>
    # set them: ODE's per-contact ERP = h kp / (h kp + kd) and CFM = 1 / (h kp + kd) (h: the step;
    # dContactSoftERP / dContactSoftCFM). None: not set, the world's erp and cfm hold (ODE's default).
    contact_kp: Annotated[float, Field(gt=0, allow_inf_nan=False)] | None = None
    contact_kd: Annotated[float, Field(ge=0, allow_inf_nan=False)] = 1.0  # N s/m, with contact_kp (SDF <kd>)
    # The same softness given directly (Webots' ContactProperties softERP / softCFM): dContactSoftERP /
    # dContactSoftCFM of terrain contacts. None: not set. Exclusive with contact_kp.
    contact_soft_erp: Annotated[float, Field(ge=0, le=1)] | None = None
    contact_soft_cfm: Annotated[float, Field(ge=0, allow_inf_nan=False)] | None = None  # (see contact_soft_erp)
    # Restitution of terrain contacts and the approach speed below which none applies (dContactBounce;
    # Webots' ContactProperties bounce 0.5, bounceVelocity 0.01 m/s). 0: off, ODE's default.
    contact_bounce: Annotated[float, Field(ge=0, le=1)] = 0.0
    contact_bounce_vel: Annotated[float, Field(ge=0, allow_inf_nan=False)] = 0.01  # m/s (see contact_bounce)
    # The robot's own friction coefficient, combined with the ground's by the minimum as Gazebo Classic
    # combines two surfaces' <mu> (ODEPhysics.cc): a contact gets min(ground, surface_mu). None: the
    # ground's coefficient alone (simpick's terrains carry the whole coefficient).
    surface_mu: Annotated[float, Field(gt=0, allow_inf_nan=False)] | None = None
    # The robot's per-body contact limits, as Gazebo Classic sets them from each link's collision surface
    # (SDF <surface><contact><ode><max_vel>, default 0.01 m/s, and <min_depth>, default 0 m; ODESurfaceParams.cc:30)
    # through its ODE fork's dBodySetMaxVel / dBodySetMinDepth (ODELink::UpdateSurface). In the fork a body's
    # min_depth replaces the world's contact_surface_layer (contact.cpp, dxJointContact::getInfo2), as
    # contact_min_depth does here, per contact in the collision callback (ode_contacts.surface_limits).
    # contact_max_vel caps the contact's push-out (ERP x depth / step) as ODE 0.16 caps it with the world's
    # contact_max_correcting_vel, position and velocity alike; the fork's quickstep caps only the velocity left
    # after the step and corrects the position with the full ERP (quickstep.cpp, dxQuickStepper), which ODE 0.16
    # cannot do: measured, 0.01 m/s here sank the Warthog 6.5 cm at rest, so the Gazebo Classic profile leaves it
    # unset. None: the world's values alone (ODE's way).
    contact_max_vel: Annotated[float, Field(gt=0, allow_inf_nan=False)] | None = None  # m/s
    contact_min_depth: Annotated[float, Field(ge=0, allow_inf_nan=False)] | None = None  # m

    @model_validator(mode="after")
    def _one_softness(self):
        if self.contact_kp is not None and (self.contact_soft_erp is not None or self.contact_soft_cfm is not None):
            raise ValueError("give the contact softness either as contact_kp/contact_kd or as contact_soft_erp/cfm")
        return self

    @model_validator(mode="after")
    def _ratio_needs_coulomb(self):
        if self.friction_ratio != 1.0 and self.friction_direction not in ("coulomb", "wheel", "wheel_x"):
            raise ValueError(
                f"friction_ratio {self.friction_ratio} needs friction_direction 'coulomb' (the ellipse) or "
                f"'wheel' (the box turned with the wheel: mu2 = ratio x mu, Gazebo's <mu2>), got "
                f"{self.friction_direction!r}"
            )
        return self
