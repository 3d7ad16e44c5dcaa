"""The `plumb` command of the plumb-mujoco wheel: runs the plumb binary inside the package.

A module of its own beside the package, so that the command does not import `plumb` (and with
it `mujoco`): the binary finds the mujoco-core wheel's libmujoco itself, through its RPATH.
"""

import importlib.util
import os
import sys


def _binary() -> str:
    spec = importlib.util.find_spec("plumb")  # finds the package without importing it
    folders = list(spec.submodule_search_locations or []) if spec else []
    for folder in folders:
        candidate = os.path.join(folder, "bin", "plumb")
        if os.access(candidate, os.X_OK):
            return candidate
    where = folders[0] if folders else "(no plumb package on sys.path)"
    sys.stderr.write(
        f"plumb: the plumb program is missing from this installation ({where}/bin/plumb): "
        "reinstall it (pip install --force-reinstall plumb-mujoco). A source checkout builds "
        "it as build/plumb (make build).\n"
    )
    sys.exit(5)  # docs/exit-codes.md: a part is missing


def main() -> None:
    binary = _binary()
    # the process becomes plumb: its exit code, signals and stdin/stdout are the program's own
    os.execv(binary, ["plumb", *sys.argv[1:]])


if __name__ == "__main__":
    main()
