"""Type stubs and docstrings: python/stubs/quack/ names what the built module has, and
`mypy --strict` accepts the examples and the README's Python block against it (skipped
where mypy is not installed: Debian python3-mypy, scripts/packages/python.txt); every
public name of the module has a docstring that help() shows."""

import ast
import inspect
import os
import re
import subprocess
import sys

import pytest

import quack


def _stub_path(source_dir, module="__init__"):
    return os.path.join(source_dir, "python", "stubs", "quack", module + ".pyi")


def _stub_names(source_dir, module="__init__"):
    """Top-level names of the stub, and each class's members: {name: set of members}."""
    with open(_stub_path(source_dir, module)) as f:
        tree = ast.parse(f.read())
    names = {}
    for node in tree.body:
        if isinstance(node, ast.ImportFrom) and node.module is None:  # from . import d3 as d3
            for alias in node.names:
                names[alias.asname or alias.name] = set()
            continue
        if isinstance(node, ast.ClassDef):
            members = set()
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    members.add(item.name)
                elif isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name):
                    members.add(item.target.id)
            names[node.name] = members
        elif isinstance(node, ast.FunctionDef):
            names[node.name] = set()
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names[node.target.id] = set()
    return {k: v for k, v in names.items() if not k.startswith("_") or k == "__version__"}


def _public(obj):
    return [n for n in dir(obj) if not n.startswith("_")]


@pytest.mark.parametrize("module", ["__init__", "d3"])
def test_the_stub_names_what_the_module_has(source_dir, module):
    mod = quack if module == "__init__" else getattr(quack, module)
    stub = _stub_names(source_dir, module)
    public = set(_public(mod)) | ({"__version__"} if module == "__init__" else set())
    assert set(stub) == public
    for name, members in stub.items():
        cls = getattr(mod, name)
        if not isinstance(cls, type):
            continue
        have = set(_public(cls))
        if issubclass(cls, tuple):  # namedtuples: their fields
            have = set(cls._fields)
        if name == "BatchResult":  # fields are set per query
            have |= {"kind"}
        missing = {m for m in members if not m.startswith("_")} - have
        assert not missing, (name, missing)
        extra = have - members - ({"count", "index"} if issubclass(cls, tuple) else set())
        assert not extra, (name, extra)


@pytest.mark.parametrize("module", ["__init__", "d3"])
def test_every_public_name_has_a_docstring(module):
    mod = quack if module == "__init__" else getattr(quack, module)
    undocumented = []
    for name in _public(mod):
        obj = getattr(mod, name)
        if not callable(obj) and not isinstance(obj, type):
            continue  # constants (ALL_CATEGORIES, ...) are described in the module's docstring
        doc = inspect.getdoc(obj) or ""
        # pybind11 puts the signature on the first line: a docstring is more than that.
        text = "\n".join(line for line in doc.splitlines() if not re.match(rf"^{name}\(", line))
        if len(text.strip()) < 10:
            undocumented.append(name)
        if isinstance(obj, type) and not issubclass(obj, tuple):
            for member in _public(obj):
                attr = inspect.getattr_static(obj, member)
                mdoc = getattr(attr, "__doc__", None) or ""
                mtext = "\n".join(line for line in mdoc.splitlines()
                                  if not re.match(rf"^{member}\(", line))
                if len(mtext.strip()) < 4:
                    undocumented.append(f"{name}.{member}")
    assert undocumented == []
    if module == "d3":
        assert "EPA_STATUSES" in mod.__doc__
        return
    assert quack.d3.__doc__ and "quack.d3" in quack.__doc__
    for constant in ("ALL_CATEGORIES", "BODY_STATE_COLUMNS", "GJK_STATUSES", "EPA_STATUSES"):
        assert constant in quack.__doc__
    assert "body_state" in quack.World.__doc__ or "body_state" in (quack.World.body_state.__doc__)


def _readme_block(source_dir):
    with open(os.path.join(source_dir, "README.md")) as f:
        text = f.read()
    section = text[text.index("## Using Quack from Python"):]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_mypy_strict_accepts_the_examples_and_the_readme(source_dir, tmp_path):
    pytest.importorskip("mypy", reason="mypy is not installed (Debian python3-mypy)")
    readme = tmp_path / "readme_block.py"
    readme.write_text(_readme_block(source_dir))
    examples = os.path.join(source_dir, "examples", "python")
    files = [str(readme)] + sorted(os.path.join(examples, f) for f in os.listdir(examples)
                                   if f.endswith(".py"))
    env = dict(os.environ, MYPYPATH=os.path.dirname(os.path.dirname(_stub_path(source_dir))))
    run = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental",
                          "--cache-dir", str(tmp_path / "cache"), _stub_path(source_dir),
                          _stub_path(source_dir, "d3")] + files,
                         capture_output=True, text=True, env=env, check=False)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "Success: no issues found in" in run.stdout


def test_mypy_catches_a_wrong_call(source_dir, tmp_path):
    """A control: the stub is really used (a call the stub refuses fails the check)."""
    pytest.importorskip("mypy", reason="mypy is not installed (Debian python3-mypy)")
    bad = tmp_path / "bad.py"
    bad.write_text("import quack\nw = quack.World()\nw.step(substeps='4')\n"
                   "x: str = w.body_count\n")
    env = dict(os.environ, MYPYPATH=os.path.dirname(os.path.dirname(_stub_path(source_dir))))
    run = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental",
                          "--cache-dir", str(tmp_path / "cache"), str(bad)],
                         capture_output=True, text=True, env=env, check=False)
    assert run.returncode == 1
    assert 'bad.py:3: error: Argument "substeps"' in run.stdout
    assert "bad.py:4: error: Incompatible types in assignment" in run.stdout
