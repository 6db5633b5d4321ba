"""Windows played under one held absolute action, for the sensor tests (test_encoder_lag, test_pulse_encoder): the
action that modulates at given frequencies, from the env's own encoding, and each window's measurement."""

from __future__ import annotations

import gymnasium as gym
import numpy as np

from cof_gym.task.interface import encode_action

FREQUENCY_HZ = 5.0  # the modulation the sensor tests hold
LOW_DC, SMALL_AMPLITUDE = -0.9, -0.6  # unit action values: a low DC torque and a small modulation
QUIET = {"noise_level": 0.0, "motor_lag_s": 0.0, "cof": 0.3, "condition": "dry"}  # no noise, no drive lag


def held_action(env: gym.Env, tones_hz: tuple[float, ...] = (FREQUENCY_HZ,), dc: float = LOW_DC,
                amplitude: float = SMALL_AMPLITUDE) -> np.ndarray:
    """The absolute action (unit values) with the DC torque ``dc``, the first tone's ``amplitude``, each tone at its
    frequency in ``tones_hz`` (Hz; the further tones at the middle of their amplitude range), estimate 0, no stop."""
    limits = env.unwrapped.task.limits

    def unit(frequency_hz: float) -> float:  # the frequency's action value, as encode_action writes it
        return float(encode_action(0.0, limits.min_amplitude_nm, frequency_hz, limits.min_cof_estimate, False,
                                   limits)[2])

    first, *further = tones_hz
    extra = [value for f in further for value in (unit(f), 0.0)]
    return np.array([dc, amplitude, unit(first), 0.0, -1.0, *extra], dtype=np.float32)


def held_windows(env_id: str, options: dict, steps: int, tones_hz: tuple[float, ...] = (FREQUENCY_HZ,),
                 dc: float = LOW_DC, amplitude: float = SMALL_AMPLITUDE, seed: int = 3, **make_kwargs) -> list[dict]:
    """``info["measurement"]`` of each of ``steps`` windows of ``env_id`` (absolute actions, ``make_kwargs``) reset
    with ``seed`` and ``options``, under :func:`held_action`."""
    env = gym.make(env_id, action_type="absolute", **make_kwargs)
    env.reset(seed=seed, options=options)
    action = held_action(env, tones_hz, dc, amplitude)
    out = [dict(env.step(action)[4]["measurement"]) for _ in range(steps)]
    env.close()
    return out
