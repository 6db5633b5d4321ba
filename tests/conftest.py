"""Test session setup shared by every test module."""

from __future__ import annotations

import os

# Headless rendering: without a display MuJoCo's default GLFW context cannot start. This must run
# before anything imports mujoco (cof_gym/__init__.py does the same on import).
if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
    os.environ.setdefault("MUJOCO_GL", "egl")

import gymnasium as gym  # noqa: E402  (after the rendering setup above)
import pytest  # noqa: E402

import cof_gym  # noqa: E402


@pytest.fixture(scope="module")
def env(request):
    """One wagon env per test module, of the module's ``ENV_ID`` (default: the v2 wagon); a module
    that needs other constructor arguments defines its own ``env`` fixture."""
    e = gym.make(getattr(request.module, "ENV_ID", cof_gym.WAGON_ENV_ID))
    yield e
    e.close()
