"""Stepping the engines: a case driven under the watchdog and health checks, its IMU modelled, written as a trace;
CPU load.
"""
