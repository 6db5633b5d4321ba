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
from hypothesis import settings  # noqa: E402

# property tests draw the same examples on every run and machine (seeded runs reproduce; a failure found once is found
# again), with no example database carried between runs
settings.register_profile("cof_gym", derandomize=True, database=None)
settings.load_profile("cof_gym")


TEST_WORKER_MEMORY_BYTES = 3 << 29  # 1.5 GiB a worker (measured: 0.53 GB peak running the training test files)


def pytest_xdist_auto_num_workers(config):
    """``-n auto`` (the README's test command): a pytest-xdist worker per usable core, a container's CPU quota
    counting (xdist's own count sees every core of the host), and at most one per
    :data:`TEST_WORKER_MEMORY_BYTES` of the available memory. ``PYTEST_XDIST_AUTO_NUM_WORKERS`` still decides where
    it is set (None: xdist's own hook)."""
    if os.environ.get("PYTEST_XDIST_AUTO_NUM_WORKERS"):
        return None
    from cof_gym.commands.evaluate_workers import fitting_workers

    return fitting_workers(TEST_WORKER_MEMORY_BYTES)


@pytest.fixture(scope="module")
def env(request):
    """One wagon env per test module, of the module's ``ENV_ID`` (default: the v2 wagon); a module
    that needs other constructor arguments defines its own ``env`` fixture."""
    e = gym.make(getattr(request.module, "ENV_ID", cof_gym.WAGON_ENV_ID))
    yield e
    e.close()


EXPERIMENTS = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "experiments")


@pytest.fixture
def experiment_exit(monkeypatch, capsys):
    """Run ``experiments/SCRIPT.py``'s ``main()`` in-process with command-line ``args``; returns (exit code,
    the line of stderr). For the bad-input checks of the experiment scripts: an option rejected before
    any work exits through argparse, as on the command line, without a Python start-up per case (each
    script keeps one subprocess test of its real command line). Checks the one-line form of
    :class:`cof_gym.commands.args.Parser`: stderr is exactly one line, ``SCRIPT.py: error: ...`` (no usage
    block)."""
    import importlib
    import sys

    def run(script: str, args: list[str]) -> tuple[int | str | None, str]:
        monkeypatch.syspath_prepend(EXPERIMENTS)
        module = importlib.import_module(script)
        monkeypatch.setattr(sys, "argv", [os.path.join(EXPERIMENTS, f"{script}.py"), *args])
        capsys.readouterr()  # only what main() writes
        with pytest.raises(SystemExit) as exit_:
            module.main()
        err = capsys.readouterr().err
        lines = err.splitlines()
        assert len(lines) == 1 and err.endswith("\n"), f"stderr is not one line: {err!r}"
        assert lines[0].startswith(f"{script}.py: error: "), lines[0]
        return exit_.value.code, lines[0]

    return run
