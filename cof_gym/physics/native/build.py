"""Compile and load the native core (C, through ctypes) against the installed MuJoCo.

The shared library is built on first use with the system C compiler (``cc``/``gcc``) against
MuJoCo's own headers and library from the ``mujoco`` wheel, and cached under
``$COF_GYM_CACHE`` (default ``~/.cache/cof_gym``) keyed by the source, the layout and the MuJoCo
version. Installing the callback (:func:`install_callback`) is idempotent and process-global.
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import shutil
import subprocess
import tempfile
import warnings
from functools import lru_cache
from pathlib import Path

import mujoco

from cof_gym.physics.native import layout

_HERE = Path(__file__).resolve().parent
_SOURCE = _HERE / "cofgym_native.c"
_MJ_DIR = Path(mujoco.__file__).resolve().parent
# built on the machine that runs it, so -march=native is safe; no fast-math: results stay IEEE
_FLAGS = ("-O3", "-march=native", "-fPIC", "-shared", "-std=c99", "-fno-fast-math", "-ffp-contract=off")


def _mujoco_library() -> Path:
    libs = sorted(_MJ_DIR.glob("libmujoco.so*")) + sorted(_MJ_DIR.glob("libmujoco*.dylib"))
    if not libs:
        raise RuntimeError(f"libmujoco not found in {_MJ_DIR}; is the mujoco wheel installed?")
    return libs[0]


def _cache_dir() -> Path:
    root = os.environ.get("COF_GYM_CACHE") or os.path.join(Path.home(), ".cache", "cof_gym")
    return Path(root)


def _compiler() -> str:
    for name in (os.environ.get("CC"), "cc", "gcc", "clang"):
        if name and shutil.which(name):
            return name
    raise RuntimeError(
        "cof_gym needs a C compiler (cc, gcc or clang) to build its native MuJoCo callback; "
        "install one (e.g. apt-get install gcc) or set CC"
    )


def library_path() -> Path:
    """Path of the compiled library, building it if the cache has none for this source."""
    header = layout.c_header()
    source = _SOURCE.read_text()
    key = hashlib.sha256((source + header + mujoco.__version__ + " ".join(_FLAGS)).encode()).hexdigest()[:16]
    target = _cache_dir() / f"cofgym_native-{key}.so"
    if target.exists():
        return target
    target.parent.mkdir(parents=True, exist_ok=True)
    mjlib = _mujoco_library()
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "cofgym_layout.h").write_text(header)
        out = Path(tmp) / target.name
        cmd = [
            _compiler(), *_FLAGS,
            f"-I{tmp}", f"-I{_MJ_DIR / 'include'}", str(_SOURCE), "-o", str(out),
            str(mjlib), f"-Wl,-rpath,{mjlib.parent}", "-lm",
        ]
        proc = subprocess.run(cmd, capture_output=True, text=True)
        if proc.returncode != 0:
            raise RuntimeError(f"building the native callback failed:\n{' '.join(cmd)}\n{proc.stderr}")
        # atomic publish: concurrent processes may build the same key
        tmp_target = target.with_suffix(f".{os.getpid()}.tmp")
        shutil.copyfile(out, tmp_target)
        os.replace(tmp_target, target)
    return target


@lru_cache(maxsize=1)
def native() -> ctypes.CDLL:
    """The loaded native library with its argument types declared."""
    lib = ctypes.CDLL(str(library_path()))
    dp = ctypes.POINTER(ctypes.c_double)
    lib.cofgym_creep_force.restype = ctypes.c_double
    lib.cofgym_creep_force.argtypes = [dp, dp, ctypes.c_double, ctypes.c_double, ctypes.c_double, dp]
    lib.cofgym_creep_curve.restype = None
    lib.cofgym_creep_curve.argtypes = [dp, dp, ctypes.c_double, ctypes.c_double, dp, ctypes.c_int, dp, dp]
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
