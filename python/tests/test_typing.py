"""Issue 49: the stubs (_plumb.pyi) type every result: mypy --strict passes on a user's script
that touches every result type (typed_user.py), where arrays typed `object` and bare lists once
failed it (`t.array.shape`). Argument types are named in errors (test_argument_types.py).
mypy comes from python/requirements-typing.txt."""

import os
import pathlib
import subprocess
import sys

import pytest

import plumb

HERE = pathlib.Path(__file__).resolve().parent


def _mypy() -> list[str]:
    """The command that runs mypy: this venv's, else the venv of python/requirements-typing.txt,
    made (once) in plumb's cache beside this one by scripts/test-venv.sh."""
    try:
        import mypy  # noqa: F401

        return [sys.executable, "-m", "mypy"]
    except ImportError:
        pass
    root = HERE.parents[1]
    venv = pathlib.Path(sys.prefix).parent / "typing-venv"
    made = subprocess.run(
        [str(root / "scripts" / "test-venv.sh"), str(venv),
         str(root / "python" / "requirements-typing.txt")],
        capture_output=True, text=True)
    assert made.returncode == 0, "the mypy venv could not be made (pip needs PyPI): " + made.stderr
    return [made.stdout.strip(), "-m", "mypy", "--python-executable", sys.executable]


def test_mypy_strict_passes_on_a_script_over_every_result_type(tmp_path):
    config = tmp_path / "mypy.ini"
    # mujoco ships no type information; everything of plumb's is checked strictly
    config.write_text("[mypy]\nstrict = True\n[mypy-mujoco.*]\nignore_missing_imports = True\n")
    package = pathlib.Path(plumb.__file__).resolve().parents[1]
    done = subprocess.run(
        [*_mypy(), "--config-file", str(config), "--no-incremental",
         "--cache-dir", str(tmp_path / "cache"), str(HERE / "typed_user.py")],
        capture_output=True, text=True, cwd=tmp_path,
        env={**os.environ, "MYPYPATH": str(package)})
    assert done.returncode == 0, done.stdout + done.stderr


def test_the_stubs_type_arrays_and_rows():
    import ast

    stub = (pathlib.Path(plumb.__file__).parent / "_plumb.pyi").read_text()
    tree = ast.parse(stub)
    returns = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            for item in node.body:
                if isinstance(item, ast.FunctionDef) and item.returns is not None:
                    returns[f"{node.name}.{item.name}"] = ast.unparse(item.returns)
    assert returns["Trajectory.array"] == "_Floats"
    assert returns["VerifyResult.rows"] == "list[CheckRow]"
    assert returns["Frames.array"] == "_Pixels"
    untyped = sorted(k for k, v in returns.items()
                     if v in ("object", "list", "dict") and not k.endswith("__"))
    assert untyped == []
