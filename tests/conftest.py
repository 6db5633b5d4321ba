"""Test session setup shared by every test module."""

from __future__ import annotations

import os

# Headless rendering: without a display MuJoCo's default GLFW context cannot start. This must run
# before anything imports mujoco (cof_gym/__init__.py does the same on import).
if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
    os.environ.setdefault("MUJOCO_GL", "egl")
