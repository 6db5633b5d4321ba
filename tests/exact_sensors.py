"""Env options that switch off every noise, the motor lag and every systematic sensor error (one
definition for the tests that compare readings with exact physics; the error names are the task's own)."""

from cof_gym.task.sensors import SYSTEMATIC_ERRORS

QUIET = {"noise_level": 0.0, "motor_lag_s": 0.0, **dict.fromkeys(SYSTEMATIC_ERRORS, 0.0)}
