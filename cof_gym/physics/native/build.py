"""Load the native core (C, through ctypes) and install its MuJoCo callback.

The shared library ``libcofgym-native.so`` is compiled when the package is built (``setup.py``, a
setuptools ``build_ext`` step; :mod:`cof_gym.physics.native.toolchain` does the work) and installed
beside this module, so an installed cof_gym needs no compiler and no writable directory at run time.
It links MuJoCo's ``libmujoco`` from the ``mujoco`` wheel (by soname, with an rpath relative to the
installed ``mujoco`` package; the loader also loads the bindings' own libmujoco globally first).

Every library carries a build id (a hash of its C sources, the layout header rendered from
``layout.py`` and the MuJoCo version). The loader checks it, and that the file is a complete ELF
object, *before* loading it: a library that does not match the sources beside it is never loaded.
In a source checkout (``pip install -e .``, or a clone on ``sys.path``) a missing or stale library is
rebuilt in place (serialized by a file lock, published atomically; set ``COF_GYM_NATIVE_REBUILD=0`` to
get an error instead); an installed package raises :class:`NativeLibraryError` asking to reinstall.
Installing the callback (:func:`install_callback`) is idempotent and process-global.
"""

from __future__ import annotations

import ctypes
import os
import sys
import threading
import warnings
from functools import lru_cache
from pathlib import Path

import mujoco

from cof_gym.physics.native import toolchain

_HERE = Path(__file__).resolve().parent
LIBRARY = _HERE / toolchain.LIBRARY_NAME
_LOCK = threading.Lock()


class NativeLibraryError(RuntimeError):
    """cof_gym's native library is missing, damaged or does not match the installed sources."""


def _is_source_tree() -> bool:
    """A source checkout (setup.py and pyproject.toml at the root), not an installed package."""
    root = _HERE.parents[2]
    return (root / "setup.py").is_file() and (root / "pyproject.toml").is_file()


def library_problem(path: Path = LIBRARY) -> str | None:
    """Why ``path`` must not be loaded (missing, damaged, built from other sources), or None."""
    if not path.exists():
        return "is missing"
    problem = toolchain.elf_problem(path)
    if problem:
        return problem
    embedded = toolchain.embedded_build_id(path)
    if embedded is None:
        return "carries no build id"
    if any(p.suffix == ".c" for p in toolchain.source_files(_HERE)):  # the sources ship with the package
        expected = toolchain.expected_build_id(_HERE)
        if embedded != expected:
            return (f"was built from other sources or another MuJoCo (build id {embedded[:12]}, "
                    f"the sources here give {expected[:12]})")
    return None


def _rebuild(path: Path, reason: str) -> None:
    import fcntl

    print(f"cof_gym: native library {path.name} {reason}; rebuilding it in this source tree", file=sys.stderr)
    lock_path = path.with_name(f".{path.name}.lock")
    with open(lock_path, "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # another process may be building it: wait, then re-check
        try:
            if library_problem(path) is not None:
                toolchain.build(path)
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


def library_path() -> Path:
    """Path of a verified native library (rebuilt first in a source tree when missing or stale)."""
    with _LOCK:
        problem = library_problem(LIBRARY)
        if problem is None:
            return LIBRARY
        rebuild_allowed = os.environ.get("COF_GYM_NATIVE_REBUILD", "1") not in ("0", "false", "no")
        if _is_source_tree() and rebuild_allowed:
            try:
                _rebuild(LIBRARY, problem)
            except (toolchain.BuildError, OSError) as e:
                raise NativeLibraryError(f"cof_gym's native library {LIBRARY} {problem}, and rebuilding it "
                                         f"failed: {e}") from e
            problem = library_problem(LIBRARY)
            if problem is None:
                return LIBRARY
        hint = ("run `pip install -e .` in the source tree again" if _is_source_tree()
                else "reinstall cof_gym (pip install --force-reinstall --no-deps cof_gym)")
        raise NativeLibraryError(f"cof_gym's native library {LIBRARY} {problem}: {hint}")


def _load_libmujoco_globally() -> None:
    """The bindings' libmujoco, made global, so the native library's MuJoCo symbols resolve to the very
    copy the bindings use (wherever this package and mujoco are installed, editable or not)."""
    try:
        ctypes.CDLL(str(toolchain.mujoco_library(Path(mujoco.__file__).resolve().parent)), mode=ctypes.RTLD_GLOBAL)
    except (OSError, toolchain.BuildError):
        pass  # the rpath and the soname still resolve it


@lru_cache(maxsize=1)
def native() -> ctypes.CDLL:
    """The loaded native library with its argument types declared."""
    path = library_path()
    _load_libmujoco_globally()
    try:
        lib = ctypes.CDLL(str(path))
    except OSError as e:
        raise NativeLibraryError(f"cof_gym's native library {path} cannot be loaded ({e}); "
                                 "reinstall cof_gym (a directory mounted noexec cannot hold it)") from e
    dp = ctypes.POINTER(ctypes.c_double)
    lib.cofgym_creep_force.restype = ctypes.c_double
    lib.cofgym_creep_force.argtypes = [dp, dp, ctypes.c_double, ctypes.c_double, ctypes.c_double, dp]
    lib.cofgym_creep_curve.restype = None
    lib.cofgym_creep_curve.argtypes = [dp, dp, ctypes.c_double, ctypes.c_double, dp, ctypes.c_int, dp, dp]
    lib.cofgym_family_id.restype = ctypes.c_int
    lib.cofgym_family_id.argtypes = [ctypes.c_char_p]
    return lib


def install_callback() -> None:
    """Install the native passive callback process-wide (idempotent).

    MuJoCo's callbacks are global; the native function leaves every model whose ``userdata`` does
    not carry cof_gym's marker untouched, so other MuJoCo users in the process are unaffected as long
    as they do not install an mjcb_passive of their own (one installed before is replaced, with a
    warning).
    """
    fn = native().cofgym_passive
    current = mujoco.get_mjcb_passive()
    if current is fn:
        return
    if current is not None:
        warnings.warn("cof_gym replaces the mjcb_passive callback installed before it", RuntimeWarning, stacklevel=2)
    mujoco.set_mjcb_passive(fn)
