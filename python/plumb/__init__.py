"""plumb: is this MuJoCo simulation credible?

Every call takes a path, a ``mujoco.MjModel`` (used in place, never copied or changed) or a
``plumb.Model`` from ``plumb.load``; keyword arguments take the command line's vocabulary::

    import mujoco, plumb
    model = mujoco.MjModel.from_xml_path("models/pendulum.xml")
    result = plumb.verify(model, set={"qpos[hinge]": 0.7})
    result.ok, len(result.rows)   # True, 14
    result.to_dict()              # what `plumb verify --format json` prints
    result                        # in a notebook: the HTML report

plumb shares one MuJoCo library with the ``mujoco`` package, so it imports ``mujoco`` first
and refuses a ``mujoco`` of another version than the one it was built against.
"""

import glob as _glob
import os as _os

import mujoco as _mujoco

from . import _build


def _mujoco_library() -> str:
    found = sorted(_glob.glob(_os.path.join(_os.path.dirname(_mujoco.__file__), "libmujoco.so*")))
    return found[0] if found else "(no libmujoco.so* beside " + _mujoco.__file__ + ")"


if _mujoco.__version__ != _build.MUJOCO_VERSION:
    raise ImportError(
        f"plumb {_build.PLUMB_VERSION} was built against MuJoCo {_build.MUJOCO_VERSION}, but the "
        f"`mujoco` package imported is {_mujoco.__version__} ({_mujoco_library()}). plumb and "
        f"mujoco must share one MuJoCo library: pip install 'mujoco-core=={_build.MUJOCO_VERSION}' "
        f"(or rebuild plumb against MuJoCo {_mujoco.__version__})."
    )

from ._plumb import *  # noqa: E402,F401,F403  (the API: load, verify, ..., the result types)
from ._plumb import __version__  # noqa: E402,F401
from . import _plumb  # noqa: E402
from ._arguments import name_wrong_arguments as _name_wrong_arguments  # noqa: E402

# a wrong type of argument is named (verify(): model expects ..., not None) instead of
# nanobind's list of every signature
for _name, _function in vars(_plumb).items():
    if type(_function).__name__ == "nb_func" and not _name.startswith("_"):
        globals()[_name] = _name_wrong_arguments(_function)
del _name, _function

# one library on both sides: the mjModel pointers of mujoco.MjModel are plumb's too
if _os.path.realpath(mujoco_library()) != _os.path.realpath(_mujoco_library()):  # noqa: F405
    raise ImportError(
        f"plumb uses the MuJoCo library {mujoco_library()} but the `mujoco` package uses "  # noqa: F405
        f"{_mujoco_library()}: two copies of MuJoCo in one process cannot share models. "
        "Import plumb from an environment whose mujoco-core wheel is the one plumb links."
    )
