"""Agents for the torque-interrogation task, all behind :class:`agents.base.Agent`."""
