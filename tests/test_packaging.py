"""Packaging: the native library is built with the package (no compiler or cache at run time), the
loader refuses damaged or stale libraries before loading them, and the wheel installs only ``cof_gym``."""

from __future__ import annotations

import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from cof_gym.physics.native import build, toolchain

ROOT = Path(__file__).resolve().parents[1]


# ---------------------------------------------------------------------------- the loader's checks
def test_the_installed_library_matches_its_sources() -> None:
    assert build.native().cofgym_creep_force is not None  # (rebuilt first in a source tree if stale)
    assert build.library_problem() is None
    assert toolchain.embedded_build_id(build.LIBRARY) == toolchain.expected_build_id()


def test_truncated_empty_and_foreign_files_are_refused_before_loading(tmp_path: Path) -> None:
    data = build.LIBRARY.read_bytes()
    cases = {
        "truncated": data[: len(data) // 2],
        "empty": b"",
        "foreign": b"#!/bin/sh\necho not a library\n" * 10,
        "no build id": data.replace(toolchain.BUILD_ID_MARKER, b"X" * len(toolchain.BUILD_ID_MARKER)),
        "stale": data.replace(toolchain.embedded_build_id(build.LIBRARY).encode(), b"0" * 64),
    }
    expected = {"truncated": "truncated", "empty": "empty", "foreign": "not an ELF", "no build id": "no build id",
                "stale": "other sources"}
    for name, content in cases.items():
        path = tmp_path / f"{name.replace(' ', '_')}.so"
        path.write_bytes(content)
        problem = build.library_problem(path)
        assert problem is not None and expected[name] in problem, (name, problem)
    assert build.library_problem(tmp_path / "missing.so") == "is missing"


def test_a_changed_source_changes_the_build_id_and_a_rebuild_matches_it(tmp_path: Path) -> None:
    """What a developer tree does after an edit of the C code or layout.py: the old library no longer
    matches; the toolchain's build does, and publishes atomically (no temporary file left)."""
    src = tmp_path / "native"
    shutil.copytree(toolchain.HERE, src, ignore=shutil.ignore_patterns("*.so", ".*", "__pycache__"))
    (src / "cofgym_native.c").write_text((src / "cofgym_native.c").read_text() + "\n/* edited */\n")
    assert toolchain.expected_build_id(src) != toolchain.expected_build_id()
    target = tmp_path / "out" / toolchain.LIBRARY_NAME
    ident = toolchain.build(target, src)
    assert ident == toolchain.expected_build_id(src) == toolchain.embedded_build_id(target)
    assert toolchain.elf_problem(target) is None
    assert sorted(p.name for p in target.parent.iterdir()) == [toolchain.LIBRARY_NAME]
    readelf = shutil.which("readelf")
    if readelf:
        dyn = subprocess.run([readelf, "-d", str(target)], capture_output=True, text=True).stdout
        assert "libmujoco" in dyn and "$ORIGIN/../../../mujoco" in dyn


def test_cc_with_arguments_is_honoured_and_a_missing_cc_is_an_error(monkeypatch) -> None:
    monkeypatch.setenv("CC", "gcc -g -O1")
    if shutil.which("gcc"):
        assert toolchain.compiler() == ["gcc", "-g", "-O1"]
    monkeypatch.setenv("CC", "no-such-compiler-xyz -O2")
    with pytest.raises(toolchain.BuildError, match="no-such-compiler-xyz"):
        toolchain.compiler()


def test_no_march_native_in_a_distributable_build() -> None:
    assert not any("march" in flag or "mtune" in flag for flag in toolchain.CFLAGS + toolchain.LDFLAGS)


# ---------------------------------------------------------------------------- the wheel
# what a wheel is built from: the tracked files of the package and its build configuration
WHEEL_SOURCES = ("pyproject.toml", "setup.py", "README.md", "LICENSE", "cof_gym")


def tracked(*paths: str) -> list[str]:
    """The files git tracks under ``paths`` (relative to the repository root)."""
    proc = subprocess.run(["git", "ls-files", "-z", "--", *paths], cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 0 and proc.stdout, f"git ls-files in {ROOT}: {proc.stderr}"
    return [name for name in proc.stdout.split("\0") if name]


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """``pip wheel .`` on a copy of the tracked sources (no build isolation: the test venv has setuptools and mujoco
    already): what a clean clone builds, never a checkout's build/ leftovers, and nothing written into the tree."""
    pytest.importorskip("setuptools")
    src, out = tmp_path_factory.mktemp("source"), tmp_path_factory.mktemp("wheel")
    for name in tracked(*WHEEL_SOURCES):
        (src / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / name, src / name)
    proc = subprocess.run([sys.executable, "-m", "pip", "wheel", str(src), "--no-deps", "--no-build-isolation",
                           "-q", "-w", str(out)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    (whl,) = out.glob("cof_gym-*.whl")
    return whl


def test_the_wheel_installs_only_cof_gym_and_carries_the_library(wheel: Path) -> None:
    with zipfile.ZipFile(wheel) as z:
        names = z.namelist()
        dist_info = next(n.split("/")[0] for n in names if n.endswith(".dist-info/RECORD"))
        assert z.read(f"{dist_info}/top_level.txt").decode().split() == ["cof_gym"]
        record = z.read(f"{dist_info}/RECORD").decode().splitlines()
        tag = [line for line in z.read(f"{dist_info}/WHEEL").decode().splitlines() if line.startswith("Tag:")]
    top = {line.split(",")[0].split("/")[0] for line in record if line}
    assert top == {"cof_gym", dist_info}, top
    assert {n.split("/")[0] for n in names} == {"cof_gym", dist_info}
    assert f"cof_gym/physics/native/{toolchain.LIBRARY_NAME}" in names
    assert "cof_gym/physics/native/layout.py" in names and "cof_gym/physics/native/cofgym_native.c" in names
    assert not any(n.endswith((".pyc", ".lock", ".tmp")) for n in names)
    # every Python module of the package as tracked, and no other (a stale build/ once shipped a removed module)
    assert {n for n in names if n.endswith(".py")} == {n for n in tracked("cof_gym") if n.endswith(".py")}
    assert tag and tag[0].split()[-1].startswith("py3-none-"), tag  # the library does not use Python's ABI


def test_the_wheel_runs_without_a_compiler_or_a_writable_home(wheel: Path, tmp_path: Path) -> None:
    """The wheel's files on sys.path (mujoco and the rest from this environment), no C compiler on PATH,
    HOME unwritable: gym.make + reset + step, and nothing written into the installed package."""
    site = tmp_path / "site"
    with zipfile.ZipFile(wheel) as z:
        z.extractall(site)
    native_dir = site / "cof_gym" / "physics" / "native"
    before = sorted(p.name for p in native_dir.iterdir())
    empty_bin = tmp_path / "bin"
    empty_bin.mkdir()
    # a HOME nobody can write, not even root (tests may run as root, for whom permissions do not count)
    env = {"PATH": str(empty_bin), "HOME": "/proc/cof-gym-no-home", "PYTHONPATH": str(site), "MUJOCO_GL": "egl",
           "CC": "", "PYTHONDONTWRITEBYTECODE": "1"}
    code = (
        "import gymnasium as gym, numpy as np, cof_gym\n"
        f"assert cof_gym.__file__.startswith({str(site)!r}), cof_gym.__file__\n"
        "from cof_gym.physics.native import build\n"
        "assert build.library_problem() is None and not build._is_source_tree()\n"
        "env = gym.make(cof_gym.WAGON_ENV_ID)\n"
        "obs, info = env.reset(seed=0)\n"
        "obs, r, term, trunc, info = env.step(np.zeros(env.action_space.shape, np.float32))\n"
        "assert np.all(np.isfinite(obs)) and np.isfinite(r)\n"
        "print('ok')\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], env=env, cwd=tmp_path, capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0 and proc.stdout.strip().endswith("ok"), proc.stderr[-3000:]
    assert sorted(p.name for p in native_dir.iterdir()) == before  # nothing built, no lock file


def _pytest_command(text: str) -> str:
    """The one ``python -m pytest ...`` command of a README or script (to the end of its line)."""
    commands = [line[line.index("python -m pytest"):].strip() for line in text.splitlines()
                if "python -m pytest" in line and not line.lstrip().startswith("#")]
    assert len(commands) == 1, commands
    return commands[0]


def test_the_readme_test_command_is_what_ci_runs_and_prints_the_summary_line() -> None:
    """CI runs the README's test command to the letter; ``addopts`` must not add a second -q (``-qq``
    drops pytest's pass/fail summary line); the workers come from the pinned pytest-xdist."""
    import tomllib

    conf = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["pytest"]["ini_options"]
    assert "-q" not in str(conf.get("addopts", "")).split()
    command = _pytest_command((ROOT / "README.md").read_text())
    assert command == _pytest_command((ROOT / ".ci" / "run").read_text())
    assert command.split()[3:5] == ["-x", "-q"] and "-n" in command.split()
    pins = (ROOT / "constraints.txt").read_text().splitlines()
    assert any(line.startswith("pytest-xdist==") for line in pins)


def test_the_test_commands_auto_workers_fit_the_cores_and_the_memory(request, monkeypatch) -> None:
    from cof_gym.commands import evaluate_workers as ev

    def auto() -> int:
        return request.config.hook.pytest_xdist_auto_num_workers(config=request.config)

    monkeypatch.delenv("PYTEST_XDIST_AUTO_NUM_WORKERS", raising=False)
    monkeypatch.setattr(ev, "usable_cores", lambda: 8)
    monkeypatch.setattr(ev, "available_memory_bytes", lambda: 5 * (3 << 29) - 1)
    assert auto() == 4
    monkeypatch.setattr(ev, "available_memory_bytes", lambda: 1 << 20)
    assert auto() == 1
    monkeypatch.setattr(ev, "available_memory_bytes", lambda: None)
    assert auto() == 8
    monkeypatch.setenv("PYTEST_XDIST_AUTO_NUM_WORKERS", "5")  # xdist's own override still decides
    assert auto() == 5
