"""Agents for the torque-interrogation task, all behind :class:`cof_gym.agents.base.Agent`."""
