"""Build step for cof_gym's native MuJoCo callback (metadata: pyproject.toml).

The callback is a plain shared library loaded with ctypes, not a CPython extension module: it is
compiled by ``cof_gym/physics/native/toolchain.py`` (the same code the loader uses to rebuild a stale
library in a source tree) against the headers and ``libmujoco`` of the ``mujoco`` build requirement.
The wheel is tagged ``py3-none-<platform>``: the library does not depend on the Python version.
"""

from __future__ import annotations

import importlib.util
import os
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent
NATIVE = ROOT / "cof_gym" / "physics" / "native"
EXT_NAME = "cof_gym.physics.native.libcofgym-native"


def _toolchain():
    spec = importlib.util.spec_from_file_location("_cofgym_toolchain", NATIVE / "toolchain.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class BuildNative(build_ext):
    """Builds the ctypes library with cof_gym's toolchain (honours CC, CFLAGS, LDFLAGS)."""

    def get_ext_filename(self, fullname: str) -> str:
        # distutils asks with the full dotted name or, from get_ext_fullpath, with its last part only
        *package, last = EXT_NAME.split(".")
        if fullname == EXT_NAME:
            return os.path.join(*package, _toolchain().LIBRARY_NAME)
        if fullname == last:
            return _toolchain().LIBRARY_NAME
        return super().get_ext_filename(fullname)

    def build_extension(self, ext: Extension) -> None:
        if ext.name != EXT_NAME:
            return super().build_extension(ext)
        toolchain = _toolchain()
        target = Path(self.get_ext_fullpath(ext.name))
        ident = toolchain.build(target, NATIVE, Path(self.build_temp), verbose=bool(self.verbose))
        print(f"built {target} (build id {ident[:12]})")

    def copy_extensions_to_source(self) -> None:
        """Editable installs: publish into the source tree atomically (the default copy truncates the
        file in place, under any process that has it loaded)."""
        toolchain = _toolchain()
        build_py = self.get_finalized_command("build_py")
        for ext in self.extensions:
            inplace_file, regular_file = self._get_inplace_equivalent(build_py, ext)
            toolchain.publish(Path(regular_file), Path(inplace_file))


cmdclass = {"build_ext": BuildNative}
try:
    from setuptools.command.bdist_wheel import bdist_wheel

    class PlatformWheel(bdist_wheel):
        def get_tag(self):
            _, _, platform = super().get_tag()
            return "py3", "none", platform

    cmdclass["bdist_wheel"] = PlatformWheel
except ImportError:  # setuptools < 70.1: the default cpXY tag is correct too, only narrower
    pass

setup(
    ext_modules=[Extension(EXT_NAME, sources=[str(p.relative_to(ROOT)) for p in sorted(NATIVE.glob("*.c"))])],
    cmdclass=cmdclass,
)
