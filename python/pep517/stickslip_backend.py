"""PEP 517 build backend for `pip install .`: configures the project with CMake, builds the
_stickslip module and packs it with the pure-Python package into a wheel.

It needs nothing from a package index (pyproject.toml: requires = []), so pip's isolated build
works offline; the C++ dependencies are the Debian packages tools/install-deps.sh installs, plus
python3-dev and python3-pybind11 (pybind11's CMake package).

Settings (pip install --config-settings KEY=VALUE, or the environment):
  build-dir / STICKSLIP_BUILD_DIR   CMake build directory, kept (default: a temporary one)
  CMAKE_ARGS                        extra CMake arguments, e.g. -DCMAKE_CXX_COMPILER_LAUNCHER=ccache
  CMAKE_BUILD_PARALLEL_LEVEL        build jobs (default: all cores)
"""

import base64
import hashlib
import os
import re
import shlex
import shutil
import subprocess
import sys
import sysconfig
import tarfile
import tempfile
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
NAME = "stickslip"


def _version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(stickslip VERSION ([0-9.]+)", text).group(1)


def _tag():
    interpreter = f"cp{sys.version_info.major}{sys.version_info.minor}"
    platform = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    return f"{interpreter}-{interpreter}-{platform}"


def _metadata():
    readme = "Seat suspension with dry friction, simulated sample by sample (C++ core)."
    return (f"Metadata-Version: 2.1\nName: {NAME}\nVersion: {_version()}\n"
            f"Summary: {readme}\nRequires-Python: >=3.7\nRequires-Dist: numpy\n")


def get_requires_for_build_wheel(config_settings=None):
    return []


def get_requires_for_build_sdist(config_settings=None):
    return []


def _setting(config_settings, key, environment):
    value = (config_settings or {}).get(key)
    return value if value else os.environ.get(environment)


def _build_module(build_dir):
    configure = ["cmake", "-S", str(ROOT), "-B", str(build_dir), "-DCMAKE_BUILD_TYPE=Release",
                 "-DSTICKSLIP_BUILD_PYTHON=ON", "-DSTICKSLIP_BUILD_TESTS=OFF",
                 "-DSTICKSLIP_BUILD_BENCH=OFF", "-DSTICKSLIP_WARNINGS_AS_ERRORS=OFF",
                 f"-DPython_EXECUTABLE={sys.executable}"]
    configure += shlex.split(os.environ.get("CMAKE_ARGS", ""))
    subprocess.run(configure, check=True)
    build = ["cmake", "--build", str(build_dir), "--target", "_stickslip"]
    if "CMAKE_BUILD_PARALLEL_LEVEL" not in os.environ:
        build += ["--parallel", str(os.cpu_count() or 1)]
    subprocess.run(build, check=True)
    return Path(build_dir) / "python" / NAME


def _record_line(name, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{name},sha256={digest},{len(data)}"


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    kept = _setting(config_settings, "build-dir", "STICKSLIP_BUILD_DIR")
    build_dir = Path(kept) if kept else Path(tempfile.mkdtemp(prefix="stickslip-build-"))
    try:
        package = _build_module(build_dir)
        files = {}
        for path in sorted(package.iterdir()):
            if path.suffix in (".py", ".so", ".pyd") and path.is_file():
                files[f"{NAME}/{path.name}"] = path.read_bytes()
        if not any(name.endswith((".so", ".pyd")) for name in files):
            raise RuntimeError(f"no compiled module in {package}")
    finally:
        if not kept:
            shutil.rmtree(build_dir, ignore_errors=True)
    dist_info = f"{NAME}-{_version()}.dist-info"
    files[f"{dist_info}/METADATA"] = _metadata().encode()
    files[f"{dist_info}/WHEEL"] = (f"Wheel-Version: 1.0\nGenerator: stickslip_backend\n"
                                   f"Root-Is-Purelib: false\nTag: {_tag()}\n").encode()
    record = [_record_line(name, data) for name, data in files.items()]
    record.append(f"{dist_info}/RECORD,,")
    files[f"{dist_info}/RECORD"] = ("\n".join(record) + "\n").encode()
    wheel_name = f"{NAME}-{_version()}-{_tag()}.whl"
    with zipfile.ZipFile(Path(wheel_directory) / wheel_name, "w", zipfile.ZIP_DEFLATED) as wheel:
        for name, data in files.items():
            wheel.writestr(name, data)
    return wheel_name


def build_sdist(sdist_directory, config_settings=None):
    """The files git tracks (else the tree without build directories)."""
    try:
        listed = subprocess.run(["git", "-C", str(ROOT), "ls-files", "-z"], check=True,
                                capture_output=True).stdout.decode().split("\0")
        paths = [p for p in listed if p and (ROOT / p).is_file()]
    except (OSError, subprocess.CalledProcessError):
        paths = [str(p.relative_to(ROOT)) for p in ROOT.rglob("*")
                 if p.is_file() and not {"build", ".git"} & set(p.relative_to(ROOT).parts)]
    base = f"{NAME}-{_version()}"
    with tarfile.open(Path(sdist_directory) / f"{base}.tar.gz", "w:gz") as sdist:
        for path in sorted(paths):
            sdist.add(ROOT / path, arcname=f"{base}/{path}")
        info = _metadata().encode()
        entry = tarfile.TarInfo(f"{base}/PKG-INFO")
        entry.size = len(info)
        import io
        sdist.addfile(entry, io.BytesIO(info))
    return f"{base}.tar.gz"
