"""`pip wheel .` and `pip install .` (pyproject.toml, python/build_backend/quack_build.py):
in a fresh virtual environment (with the system's site packages, for numpy), offline
(--no-index: nothing may come from a package index), the wheel builds with CMake, installs,
imports from outside the source tree, carries its type stubs, and uninstalls.

Slow (a whole Release build of the library in a new build directory): ctest runs it as
python.wheel with the label `slow`."""

import glob
import os
import shutil
import subprocess
import sys
import zipfile

import pytest


def _run(cmd, **kwargs):
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, check=False, **kwargs)
    assert out.returncode == 0, f"{cmd}\n{out.stdout[-4000:]}\n{out.stderr[-4000:]}"
    return out.stdout


def test_pip_builds_installs_and_imports_the_wheel_offline(source_dir, tmp_path):
    if shutil.which("cmake") is None:
        pytest.skip("cmake is not installed")
    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)])
    python = str(venv / "bin" / "python")
    build = tmp_path / "build"
    settings = ["--config-settings", f"build-dir={build}",
                "--config-settings", f"jobs={os.cpu_count() or 1}"]

    # pip wheel .: one wheel, tagged for this interpreter, with the module, the stubs and a
    # RECORD that lists every file.
    wheels = tmp_path / "wheels"
    _run([python, "-m", "pip", "wheel", "--no-index", "--no-deps", "-w", str(wheels)] +
         settings + [source_dir])
    [wheel] = glob.glob(str(wheels / "quack-*.whl"))
    tag = f"cp{sys.version_info.major}{sys.version_info.minor}"
    assert os.path.basename(wheel).startswith(f"quack-") and f"-{tag}-{tag}-" in wheel
    with zipfile.ZipFile(wheel) as z:
        names = set(z.namelist())
        record = z.read([n for n in names if n.endswith(".dist-info/RECORD")][0]).decode()
        metadata = z.read([n for n in names if n.endswith(".dist-info/METADATA")][0]).decode()
    assert "quack-stubs/__init__.pyi" in names and "quack-stubs/d3.pyi" in names
    assert any(n.startswith("quack.cpython-") and n.endswith(".so") for n in names)
    assert {line.split(",")[0] for line in record.splitlines()} == names
    assert "Requires-Dist: numpy" in metadata

    # pip install . (the same build directory: CMake finds it built).
    _run([python, "-m", "pip", "install", "--no-index"] + settings + [source_dir])
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    check = ("import quack, numpy as np\n"
             "w = quack.World()\n"
             "g = w.create_body(type='static')\n"
             "w.create_shape(g, quack.box(half=(5, 0.5)))\n"
             "b = w.create_body(pos=(0, 3))\n"
             "w.create_shape(b, quack.circle(radius=0.5))\n"
             "for _ in range(120): w.step()\n"
             "print(quack.__file__)\n"
             "print(round(w.body_state()[1, 1], 2), quack.__version__)\n")
    lines = _run([python, "-c", check], cwd=outside).splitlines()
    assert lines[0].startswith(str(venv)), lines
    assert lines[1].startswith("1.0 ") or lines[1].startswith("0.99 "), lines
    site = _run([python, "-c", "import sysconfig; print(sysconfig.get_paths()['platlib'])"])
    assert os.path.exists(os.path.join(site.strip(), "quack-stubs", "__init__.pyi"))

    # The installed stubs type a program, when mypy is there (no MYPYPATH: found by PEP 561).
    if _run([python, "-c", "import importlib.util as u; print(u.find_spec('mypy') is not None)"]
            ).strip() == "True":
        program = outside / "typed.py"
        program.write_text("import quack\nw = quack.World()\nn: int = w.body_count\n"
                           "s: str = w.to_svg()\n")
        out = _run([python, "-m", "mypy", "--strict", "--no-incremental", "--cache-dir",
                    str(tmp_path / "mypy"), str(program)], cwd=outside)
        assert "Success" in out

    _run([python, "-m", "pip", "uninstall", "-y", "quack"])
    gone = subprocess.run([python, "-c", "import quack"], cwd=outside, capture_output=True,
                          text=True, env={"PATH": os.environ.get("PATH", "")}, check=False)
    assert gone.returncode != 0 and "No module named 'quack'" in gone.stderr
