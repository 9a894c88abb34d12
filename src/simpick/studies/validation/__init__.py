"""Engines against analytic mechanics: cases with known answers, run before any comparison
with the real robot (METHOD.md section 6).

Every case runs the study's own robot, timestep, wheel-torque bound and engine settings on
flat rigid ground with one Coulomb coefficient, and measures one or more *checks*: the
engine's value beside the value mechanics predicts. Pass or fail is decided later, by
:func:`~.judge.summarise` with the tolerances of the config, so editing a tolerance re-judges the
stored runs without stepping an engine again.

Case kinds (their parameters come from ``validation.cases`` in the config):

``yaw_gain``  (v, w, mu, heading) skid-steer turning from start heading ``heading`` (degrees);
    steady yaw rate / commanded w over the second half of the run against
    :mod:`simpick.coulomb`'s quasi-static solution for this robot's contact layout and loads
    (the same for w and -w: mirroring a turn mirrors the COM offset, and the gain does not
    depend on the offset's side). With ``friction_ratio`` r the engine's own
    ``friction_ratio`` setting is set to r and the analytic value is the anisotropic (elliptic)
    Coulomb gain at r; an engine without that setting skips the case, saying so. Such cases stay
    out of the invariance checks and the gains table (which compare isotropic turning).
``straight``  (v, mu, heading) forward speed against measured wheel speed x radius (rolling
    without slip), and the heading drift (none expected).
``slide``     (v, mu, heading) cruise from start heading ``heading``, then every wheel commanded
    to stop (locked by its servo): the robot slides to rest with deceleration mu g. The contacts
    slide along the wheels, so an anisotropic profile's ``friction_ratio`` does not enter: mu is the
    coefficient along the wheel.
``incline``   (mu, angle_factor, heading) parked with locked wheels on a slope of angle_factor x
    atan(mu) (gravity tilted, same mechanics as a tilted plane), downhill at ``heading`` degrees
    from the robot's back (0: along -x; 45: across the world axes and the wheels). Judged by the
    elliptic anisotropic Coulomb law with the set-up's own ``friction_ratio`` r (a calibrated
    profile's fitted one; 1, isotropic, for every other), mu along the wheels and r mu across them
    (:func:`simpick.slope.slope_slide`): inside the friction ellipse, sin a |M^-1 d| <= cos a, it
    stays (creep speed 0); outside it slides down and does not yaw, its acceleration fitted along the
    downhill direction over the same window on the engine's record and on the law's path. For r = 1
    that is a parked robot below atan(mu) and g (sin a - mu cos a) above it (1.016 m/s^2 at 1.2
    atan(0.5)); across the wheels' axes with r < 1 the robot holds less and slides faster, off the
    downhill direction towards the wheels' axis (r 0.698 at 45 degrees: holds up to 0.829 atan(mu),
    1.691 m/s^2 at 1.2 atan(0.5), 0.234 rad off downhill). The factor sets the slope, not the
    answer: a case set to hold that the profile's ellipse cannot hold is judged as a slide, and its
    checks record which (``expected`` hold or slide, ``hold_angle``, the ``friction_ratio`` where it
    is not 1), and the path's angle from downhill (``drift``, the law's ``analytic_drift``),
    not judged.
``rest``      (mu) parked on level ground: accelerometer z = g, gyro 0, no creep.

Cases for a robot on a passive suspension (rockers; skipped, saying so, on a robot without one):

``rest_pose`` (mu) parked on level ground: the mechanism balances the weight with every joint at
    zero (:func:`simpick.coulomb.contact_layout` refuses a description where it cannot), so the
    chassis rests level (pitch 0, roll 0) at the description's resting height ``base_height``.
    Pitch and roll are judged by their worst sample over the measured part (the second half), the
    height by its mean: a chassis that rocks or is still settling fails.
    Uncoupled rockers have no such pose: the chassis tips onto the joint limits (the Warthog's
    public description: 0.15 rad), which this case catches.
``articulation`` (h, mu, v) two coupled rockers twisted against each other: the robot drives at
    ``v`` onto two blocks of height ``h``, one under the leading rocker's front wheel, one under
    the other rocker's back wheel (diagonally opposite), stops on them and is held. The blocks are
    stairs of 1 cm layers 4 cm apart, so that no engine's climbing traction is what is tested. Each rocker
    then pitches by theta = -asin(dz / L) (dz its front wheel's rise over its back wheel's, L the
    axle distance), and the coupling q(follower) = m q(leader) sets the chassis' pitch to
    (theta_f - m theta_l) / (1 - m): for a differential (m = -1) the mean of the two, 0 for equal
    arms. The pivots rise by the blocks' height shared by the lever arms, which gives the chassis'
    roll and height. A rigid robot rests on three of the four wheels instead, and uncoupled rockers
    drop onto their limits: both show as pitch or roll.

Invariance checks. Flat isotropic ground has no preferred direction, and the
mirror image of a turn is a turn the other way: an engine's gain must not depend on the
start heading nor on the turn's direction. :func:`~.judge.summarise` adds, from the yaw_gain cases
themselves (no extra engine runs), per group of cases with the same (v, |w|, mu):

``turn_asymmetry``  the largest |gain(w) / analytic - gain(-w) / analytic| over the headings
    at which both directions ran;
``heading_spread``  per turn direction, max - min of gain / analytic over the headings.

:func:`~.judge.gain_table` gives each engine's gain per group with its spread (left, right, over
headings): results/validation/gains.csv, which the report and its gain figure read.

The modules, one idea each: ``measures`` (the kinds, quantities and defaults, which the config reads),
``cases`` (a case run on an engine and measured; why a case does not apply to a robot), ``suspension``
(the articulation case's geometry), ``job`` (the workflow's per-engine job), ``judge`` (checks against
the tolerances, the invariance checks, the gains table) and ``__main__`` (the command line).
"""
