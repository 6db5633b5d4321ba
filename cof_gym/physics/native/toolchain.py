"""Build the native library: shared by ``setup.py`` (at install time) and the loader (developer trees).

Standard library only, and no import of :mod:`cof_gym`: ``setup.py`` loads this file by path inside
pip's isolated build environment, where only the build requirements (setuptools, mujoco) exist.

The library is a plain shared object loaded with ctypes (not a CPython extension module). It is built
from every ``*.c`` file beside this module plus two generated files: ``cofgym_layout.h`` (rendered from
``layout.py``) and a build-id unit that embeds :func:`build_id` as a marker string, so that the loader
can tell, without loading it, whether a library was built from the sources and MuJoCo it sits beside.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

HERE = Path(__file__).resolve().parent
LIBRARY_NAME = "libcofgym-native.so"  # not a valid module name: never mistaken for a Python extension
HEADER_NAME = "cofgym_layout.h"
BUILD_ID_MARKER = b"COFGYM-BUILD-ID:"
# portable code (no -march=native: a wheel runs on any CPU of its platform tag); no fast-math and no
# FMA contraction: results are plain IEEE double arithmetic, identical on every x86-64 / aarch64 CPU
CFLAGS = ("-O3", "-fPIC", "-std=c99", "-fno-fast-math", "-ffp-contract=off")
LDFLAGS = ("-shared",)
# where the mujoco package lies relative to the installed library (site-packages/cof_gym/physics/native)
RPATH = "$ORIGIN/../../../mujoco"


class BuildError(RuntimeError):
    """The native library could not be built (no compiler, compiler error)."""


def load_layout(path: Path = HERE / "layout.py"):
    """``layout.py`` as a module, loaded by path (it imports nothing from cof_gym)."""
    spec = importlib.util.spec_from_file_location("_cofgym_layout_for_build", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def source_files(src_dir: Path = HERE) -> list[Path]:
    """The C sources and headers that go into the library (whatever lies beside this module)."""
    files = [*src_dir.glob("*.c"), *src_dir.glob("*.h")]
    return sorted((p for p in files if p.name != HEADER_NAME), key=lambda p: p.name)  # the header is generated


def mujoco_dir() -> Path:
    """The installed ``mujoco`` package directory (headers in ``include/``, ``libmujoco.so.*``), found
    without importing mujoco."""
    spec = importlib.util.find_spec("mujoco")
    if spec is None or not spec.submodule_search_locations:
        raise BuildError("the mujoco package is not installed (it provides the headers and libmujoco)")
    return Path(next(iter(spec.submodule_search_locations))).resolve()


def mujoco_version() -> str:
    from importlib import metadata

    for dist in ("mujoco-core", "mujoco"):  # mujoco >= 4 ships the library in mujoco-core
        try:
            return metadata.version(dist)
        except metadata.PackageNotFoundError:
            continue
    version_file = mujoco_dir() / "_version.py"
    match = re.search(r"['\"]([^'\"]+)['\"]", version_file.read_text()) if version_file.is_file() else None
    return match.group(1) if match else "unknown"


def mujoco_library(directory: Path | None = None) -> Path:
    directory = directory or mujoco_dir()
    libs = sorted(directory.glob("libmujoco.so*")) + sorted(directory.glob("libmujoco*.dylib"))
    if not libs:
        raise BuildError(f"libmujoco not found in {directory}; is the mujoco wheel installed?")
    return libs[0]


def build_id(header: str, src_dir: Path = HERE, mujoco_ver: str | None = None) -> str:
    """Hash of everything the library is made of: the C sources, the generated layout header, the
    MuJoCo version it is linked against and cof_gym's own flags (``CFLAGS``, ``LDFLAGS`` of this module; flags
    the environment adds at build time are the builder's choice and not part of the id)."""
    h = hashlib.sha256()
    for path in source_files(src_dir):
        h.update(path.name.encode() + b"\0" + path.read_bytes() + b"\0")
    h.update(header.encode() + b"\0")
    h.update((mujoco_ver or mujoco_version()).encode() + b"\0")
    h.update(" ".join(CFLAGS + LDFLAGS + (RPATH,)).encode())
    return h.hexdigest()


def expected_build_id(src_dir: Path = HERE) -> str:
    return build_id(load_layout(src_dir / "layout.py").c_header(), src_dir)


def embedded_build_id(library: Path) -> str | None:
    """The build id embedded in a library file, or None when it has none (or cannot be read)."""
    try:
        data = Path(library).read_bytes()
    except OSError:
        return None
    i = data.find(BUILD_ID_MARKER)
    if i < 0:
        return None
    value = data[i + len(BUILD_ID_MARKER): i + len(BUILD_ID_MARKER) + 64]
    return value.decode("ascii", "replace") if re.fullmatch(rb"[0-9a-f]{64}", value) else None


def elf_problem(library: Path) -> str | None:
    """Why a file is not a complete ELF shared object (truncated, empty, foreign), or None. Checked
    before ``dlopen``: mapping a truncated library kills the process with SIGBUS."""
    import struct

    try:
        size = library.stat().st_size
        with open(library, "rb") as fh:
            head = fh.read(64)
    except OSError as e:
        return f"cannot be read ({e.strerror})"
    if size == 0:
        return "is empty"
    if head[:4] != b"\x7fELF" or len(head) < 64:
        return "is not an ELF shared library"
    if head[4] == 2:  # 64-bit
        fmt = "<" if head[5] == 1 else ">"
        e_phoff, e_shoff = struct.unpack_from(fmt + "QQ", head, 32)
        e_phentsize, e_phnum, e_shentsize, e_shnum = struct.unpack_from(fmt + "HHHH", head, 54)
    else:
        fmt = "<" if head[5] == 1 else ">"
        e_phoff, e_shoff = struct.unpack_from(fmt + "II", head, 28)
        e_phentsize, e_phnum, e_shentsize, e_shnum = struct.unpack_from(fmt + "HHHH", head, 42)
    end = max(e_phoff + e_phentsize * e_phnum, e_shoff + e_shentsize * e_shnum)
    if end > size:
        return f"is truncated ({size} bytes, its headers reach {end})"
    return None


def compiler() -> list[str]:
    """The C compiler command: ``$CC`` (with its arguments, e.g. ``ccache gcc`` or ``gcc -g``) when set,
    else the first of cc, gcc, clang on PATH."""
    env_cc = os.environ.get("CC", "").strip()
    if env_cc:
        cmd = shlex.split(env_cc)
        if shutil.which(cmd[0]) is None:
            raise BuildError(f"CC={env_cc!r}: {cmd[0]!r} not found on PATH")
        return cmd
    for name in ("cc", "gcc", "clang"):
        if shutil.which(name):
            return [name]
    raise BuildError("building cof_gym's native MuJoCo callback needs a C compiler (cc, gcc or clang): "
                     "install one (e.g. apt-get install gcc) or set CC")


def _fsync_dir(directory: Path) -> None:
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def publish(src: Path, target: Path) -> None:
    """Copy ``src`` to ``target`` atomically: a temporary file unique to this process and thread in the
    target's directory, fsynced, then renamed over the target (a process that has the old file mapped
    keeps its inode; no reader ever sees a partial file)."""
    target = Path(target)
    tmp = target.with_name(f".{target.name}.{os.getpid()}.{threading.get_ident()}.tmp")
    try:
        with open(src, "rb") as fin, open(tmp, "wb") as fout:
            shutil.copyfileobj(fin, fout)
            fout.flush()
            os.fsync(fout.fileno())
        os.chmod(tmp, 0o755)
        os.replace(tmp, target)
    finally:
        if tmp.exists():
            tmp.unlink()
    _fsync_dir(target.parent)


def build(target: Path, src_dir: Path = HERE, build_temp: Path | None = None, verbose: bool = False) -> str:
    """Compile the library to ``target`` (published atomically); returns its build id."""
    layout = load_layout(src_dir / "layout.py")
    header = layout.c_header()
    mj_dir = mujoco_dir()
    ident = build_id(header, src_dir, mujoco_version())
    files = source_files(src_dir)
    if not any(p.suffix == ".c" for p in files):
        raise BuildError(f"no C sources in {src_dir}")
    cc = compiler()
    if build_temp is not None:
        Path(build_temp).mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=build_temp, prefix="cofgym-native-") as tmp:
        tmp = Path(tmp)
        # compiled from copies beside the generated header (a quoted #include looks beside the source first)
        sources = []
        for path in files:
            shutil.copyfile(path, tmp / path.name)
            if path.suffix == ".c":
                sources.append(tmp / path.name)
        (tmp / HEADER_NAME).write_text(header)
        id_source = tmp / "cofgym_build_id.c"
        id_source.write_text(
            "/* generated by cof_gym/physics/native/toolchain.py: the loader reads this marker */\n"
            '__attribute__((visibility("default"), used)) const char cofgym_build_id[] = '
            f'"{BUILD_ID_MARKER.decode()}{ident}";\n')
        out = tmp / LIBRARY_NAME
        cmd = [*cc, *CFLAGS, *shlex.split(os.environ.get("CFLAGS", "")), f"-I{tmp}", f"-I{mj_dir / 'include'}",
               *map(str, sources), str(id_source), "-o", str(out), *LDFLAGS,
               *shlex.split(os.environ.get("LDFLAGS", "")),
               # DT_NEEDED is libmujoco's soname: the copy the mujoco bindings already loaded is reused
               str(mujoco_library(mj_dir)), f"-Wl,-rpath,{RPATH}", "-lm"]
        if verbose:
            print(shlex.join(cmd), file=sys.stderr)
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True)
        except OSError as e:
            raise BuildError(f"running the C compiler {cc[0]!r} failed: {e}") from e
        if proc.returncode != 0:
            raise BuildError(f"building the native callback failed:\n{shlex.join(cmd)}\n{proc.stderr}")
        target.parent.mkdir(parents=True, exist_ok=True)
        publish(out, target)
    return ident


if __name__ == "__main__":  # python cof_gym/physics/native/toolchain.py: rebuild in place
    print(build(HERE / LIBRARY_NAME, verbose=True))
