"""Studies beside the main flow: engines against analytic mechanics (validation), the timestep sweep, the
calibration.
"""
