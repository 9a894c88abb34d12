"""What a validation case measures, apart from how it is run: the case kinds, their defaults, the
quantities with their units and error measures. The config's models and the summaries read these
without reaching the engines that the cases step."""

KINDS = ("yaw_gain", "straight", "slide", "incline", "rest", "rest_pose", "articulation")
# deg: a case's start heading (the downhill direction of an incline) when it names none
DEFAULT_HEADING = 0.0
# s: a parked case (incline, rest) measures after the spawn drop and the servos' lock-up settle
SETTLE_S = 1.0
# s: the least it then measures (100 samples at 1 kHz: a slope fit and a creep speed need some)
MIN_MEASURED_S = 0.1

# Quantity -> (unit, how its error is measured): "relative" |e - a| / |a|, or "absolute" |e - a|.
QUANTITIES = {
    "yaw_rate_gain": ("1", "relative"),
    "speed_over_wheel_speed": ("1", "relative"),
    "heading_drift": ("rad", "absolute"),
    "slide_yaw": ("rad", "absolute"),
    "deceleration": ("m/s^2", "relative"),
    "creep_speed": ("m/s", "absolute"),
    "slide_acceleration": ("m/s^2", "relative"),
    "accel_z": ("m/s^2", "absolute"),
    "gyro_max": ("rad/s", "absolute"),
    "creep_distance": ("m", "absolute"),
    "turn_asymmetry": ("1", "absolute"),
    "heading_spread": ("1", "absolute"),
    "chassis_pitch": ("rad", "absolute"),
    "chassis_roll": ("rad", "absolute"),
    "chassis_height": ("m", "absolute"),
}


# the quantity under which a case without checks (skipped, or hung, crashed or not run) is listed
CASE_QUANTITY = {
    "yaw_gain": "yaw_rate_gain",
    "straight": "speed_over_wheel_speed",
    "slide": "deceleration",
    "incline": "slide_acceleration",
    "rest": "accel_z",
    "rest_pose": "chassis_pitch",
    "articulation": "chassis_pitch",
}
