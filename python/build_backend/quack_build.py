"""The PEP 517 build backend of `pip install .` and `pip wheel .` (pyproject.toml).

It needs nothing but the standard library, so pip's isolated build environment installs
nothing and the build works offline: CMake builds the module (target quack_python) for the
interpreter running pip, and this file packs it into a wheel with the type stubs
(python/stubs/quack/, installed as quack-stubs). docs/python.md, "Building and
installing", says how to use it.

config_settings (pip --config-settings KEY=VALUE):
    build-dir   the CMake build directory (default: build/pip-<interpreter tag>-<hash of the
                environment's prefix> in the tree, kept between builds so that a rebuild is
                quick)
    jobs        parallel compile jobs (default: the CPU count)
The environment variables QUACK_PIP_BUILD_DIR and QUACK_PIP_JOBS do the same.
"""

import base64
import hashlib
import io
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tarfile
import zipfile

SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
NAME = "quack"
SUMMARY = "2D collision detection and rigid bodies: shapes, queries, batches and worlds"


def _version():
    with open(os.path.join(SOURCE, "CMakeLists.txt"), encoding="utf-8") as f:
        m = re.search(r"project\(\s*quack\s+VERSION\s+([0-9.]+)", f.read())
    if not m:
        raise RuntimeError("quack_build: no project(quack VERSION ...) in CMakeLists.txt")
    return m.group(1)


def _tag():
    """The wheel's tag for this interpreter: cp311-cp311-linux_x86_64 and the like."""
    impl = "cp" if sys.implementation.name == "cpython" else sys.implementation.name[:2]
    py = f"{impl}{sys.version_info.major}{sys.version_info.minor}"
    plat = re.sub(r"[^A-Za-z0-9_]", "_", sysconfig.get_platform())
    return f"{py}-{py}-{plat}"


def _metadata():
    readme = ""
    try:
        with open(os.path.join(SOURCE, "docs", "python.md"), encoding="utf-8") as f:
            readme = f.read()
    except OSError:
        pass
    lines = [
        "Metadata-Version: 2.1",
        f"Name: {NAME}",
        f"Version: {_version()}",
        f"Summary: {SUMMARY}",
        "Requires-Python: >=3.8",
        "Requires-Dist: numpy",
        "Description-Content-Type: text/markdown",
    ]
    return "\n".join(lines) + "\n\n" + readme


def _dist_info():
    return f"{NAME}-{_version()}.dist-info"


def _setting(config_settings, key, env):
    value = (config_settings or {}).get(key)
    return value if value else os.environ.get(env)


def _run(cmd, env):
    print("quack_build:", " ".join(cmd), file=sys.stderr, flush=True)
    subprocess.run(cmd, check=True, env=env, stdout=sys.stderr)


def _build_module(config_settings):
    """Configures and builds quack_python; returns the path of the built module."""
    # One default directory per interpreter (two virtual environments of the same Python
    # differ in their packages, and CMake caches what it found for one).
    prefix = hashlib.sha256(os.path.abspath(sys.prefix).encode()).hexdigest()[:8]
    build_dir = _setting(config_settings, "build-dir", "QUACK_PIP_BUILD_DIR") or os.path.join(
        SOURCE, "build", f"pip-{sys.implementation.cache_tag}-{prefix}")
    jobs = _setting(config_settings, "jobs", "QUACK_PIP_JOBS") or str(os.cpu_count() or 1)
    # pip's isolated build environment points PYTHONPATH at a site directory that hides the
    # interpreter's own packages; CMake's check for numpy runs this interpreter and must see
    # them, so the CMake commands run without pip's overlay.
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONNOUSERSITE")}
    probe = subprocess.run([sys.executable, "-c", "import numpy"], env=env, capture_output=True)
    if probe.returncode != 0:
        raise RuntimeError(
            f"quack_build: {sys.executable} cannot import numpy, which the module's build "
            "needs: install it for this interpreter (Debian python3-numpy, and a virtual "
            "environment made with --system-site-packages to see it)")
    # -U: what CMake found for another interpreter in this directory is looked for again.
    configure = ["cmake", "-S", SOURCE, "-B", build_dir, "-U", "Python3_*", "-U", "_Python3_*",
                 "-DCMAKE_BUILD_TYPE=Release",
                 f"-DPython3_EXECUTABLE={sys.executable}", "-DQUACK_BUILD_PYTHON=ON",
                 "-DQUACK_BUILD_TESTS=OFF", "-DQUACK_BUILD_BENCHMARKS=OFF",
                 "-DQUACK_BUILD_APPS=OFF",
                 # A compiler newer than the ones the project is checked with may warn: a
                 # user's install should not fail for it.
                 "-DQUACK_WARNINGS_AS_ERRORS=OFF"]
    if not os.path.exists(os.path.join(build_dir, "CMakeCache.txt")) and shutil.which("ninja"):
        configure += ["-G", "Ninja"]
    _run(configure, env)
    _run(["cmake", "--build", build_dir, "--target", "quack_python", "-j", jobs], env)
    module = os.path.join(build_dir, "python", NAME + sysconfig.get_config_var("EXT_SUFFIX"))
    if not os.path.exists(module):
        raise RuntimeError(f"quack_build: the build left no {module}")
    return module


def _record_line(path, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{path},sha256={digest},{len(data)}"


def _write_wheel(wheel_directory, files):
    """files: [(path in the wheel, bytes)], dist-info added here. Returns the wheel's name."""
    dist_info = _dist_info()
    tag = _tag()
    files = list(files) + [
        (f"{dist_info}/METADATA", _metadata().encode()),
        (f"{dist_info}/WHEEL", (f"Wheel-Version: 1.0\nGenerator: quack_build\n"
                                f"Root-Is-Purelib: false\nTag: {tag}\n").encode()),
        (f"{dist_info}/top_level.txt", f"{NAME}\n".encode()),
    ]
    record = "".join(_record_line(p, d) + "\n" for p, d in files)
    record += f"{dist_info}/RECORD,,\n"
    files.append((f"{dist_info}/RECORD", record.encode()))
    name = f"{NAME}-{_version()}-{tag}.whl"
    with zipfile.ZipFile(os.path.join(wheel_directory, name), "w",
                         compression=zipfile.ZIP_DEFLATED) as z:
        for path, data in files:
            info = zipfile.ZipInfo(path, date_time=(2020, 1, 1, 0, 0, 0))
            info.external_attr = (0o755 if path.endswith(".so") else 0o644) << 16
            info.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(info, data)
    return name


def _stub_files():
    """python/stubs/quack/*.pyi as the stub-only package quack-stubs (PEP 561)."""
    folder = os.path.join(SOURCE, "python", "stubs", "quack")
    files = []
    for name in sorted(os.listdir(folder)):
        if name.endswith(".pyi"):
            with open(os.path.join(folder, name), "rb") as f:
                files.append(("quack-stubs/" + name, f.read()))
    return files


# ---- PEP 517 hooks -------------------------------------------------------------------------

def get_requires_for_build_wheel(config_settings=None):
    return []


def get_requires_for_build_sdist(config_settings=None):
    return []


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    path = os.path.join(metadata_directory, _dist_info())
    os.makedirs(path, exist_ok=True)
    with open(os.path.join(path, "METADATA"), "w", encoding="utf-8") as f:
        f.write(_metadata())
    return _dist_info()


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    module = _build_module(config_settings)
    with open(module, "rb") as f:
        files = [(os.path.basename(module), f.read())]
    return _write_wheel(wheel_directory, files + _stub_files())


def build_sdist(sdist_directory, config_settings=None):
    """The files git tracks, as quack-VERSION.tar.gz (needs a git checkout)."""
    listed = subprocess.run(["git", "-C", SOURCE, "ls-files", "-z"], check=True,
                            capture_output=True).stdout.decode().split("\0")
    base = f"{NAME}-{_version()}"
    name = base + ".tar.gz"
    with tarfile.open(os.path.join(sdist_directory, name), "w:gz") as tar:
        for rel in filter(None, listed):
            path = os.path.join(SOURCE, rel)
            if os.path.isfile(path):
                tar.add(path, arcname=f"{base}/{rel}", recursive=False)
        info = tarfile.TarInfo(f"{base}/PKG-INFO")
        data = _metadata().encode()
        info.size = len(data)
        tar.addfile(info, io.BytesIO(data))
    return name
