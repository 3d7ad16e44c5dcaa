"""plumb's pytest plugin: guard a MuJoCo model in a project's tests (the twin of CMake's
plumb_add_model_test).

Installed with plumb-mujoco and loaded by pytest through the entry point ``pytest11``
(elsewhere: ``pytest -p plumb_pytest``). A test marked

    @pytest.mark.plumb_model("robot.xml", snapshot="robot.snap.json", accept="accepted.toml",
                             scenario="stand.toml", strict=True)
    def test_robot(plumb_model):
        ...

audits the model (with the accept list, the scenario, and with ``strict`` failing on WARN
too), verifies it, and compares it with its golden snapshot; any failure fails the test with
plumb's rows as the message. ``pytest --plumb-update`` rewrites the golden snapshots from the
current models instead of comparing (review the change, then commit the files). The
``plumb_check`` fixture does the same for a model given at run time (parametrized tests).
The ``plumb_rehearse`` fixture keeps a deployment rehearsal as a test ("the policy still
walks"): it runs plumb.rehearse and fails the test with the verdict's table when it does not
pass. Relative paths are taken from the test file's folder.

The plugin imports plumb (and with it mujoco) only when a test uses it, so that installing
plumb-mujoco costs other test suites nothing.
"""

from __future__ import annotations

import difflib
import os
import pathlib
from dataclasses import dataclass, field
from typing import Any, Callable

import pytest

_UPDATE = "--plumb-update"
_OPTIONS = ("snapshot", "accept", "scenario", "strict", "set", "keyframe", "tol", "verify",
            "verify_tol")
_updated = pytest.StashKey[list]()  # the config's: snapshots --plumb-update wrote
_found = pytest.StashKey["ModelChecks"]()  # a marked test's: what its checks found


@dataclass
class ModelChecks:
    """What the plumb checks of one model found: the results of plumb.audit, plumb.verify and
    plumb.diff (None when not run), the snapshot written by --plumb-update, if any, and what
    failed."""

    model: str
    audit: Any = None
    verify: Any = None
    diff: Any = None
    snapshot_written: str | None = None
    failures: list[str] = field(default_factory=list)  # plumb's tables of the failed checks
    error: str | None = None  # bad input (a missing file, an unknown argument): what to fix

    @property
    def ok(self) -> bool:
        return not self.failures and self.error is None


def _unknown_argument(kwargs: dict[str, Any]) -> str | None:
    for name in kwargs:
        if name not in _OPTIONS:
            near = difflib.get_close_matches(name, _OPTIONS, n=1)
            hint = f" (did you mean {near[0]!r}?)" if near else ""
            return f"unknown argument {name!r}{hint}; it takes the model and {', '.join(_OPTIONS)}"
    return None


def _not_a_model(model: Any) -> str | None:
    """What is wrong with a model that is not one (None, a number, bytes), else None."""
    kind = type(model)
    if isinstance(model, (str, os.PathLike)) or kind.__name__ == "MjModel" or (
            kind.__name__ == "Model" and kind.__module__.startswith("plumb")):
        return None
    return (f"the model must be a path (str or os.PathLike), a mujoco.MjModel or a plumb.Model, "
            f"not {kind.__name__} ({model!r})")


def _path(base: pathlib.Path, value: Any) -> Any:
    if isinstance(value, (str, os.PathLike)):
        return str(base / value)
    return value  # a mujoco.MjModel or plumb.Model


def _shown(value: Any) -> str:
    return os.path.relpath(value) if isinstance(value, str) else repr(value)


def check_model(model: Any, *, base: pathlib.Path, update: bool, snapshot: Any = None,
                accept: Any = None, scenario: Any = None, strict: bool = False, set: Any = None,
                keyframe: str | None = None, tol: float = 1e-6, verify: bool = True,
                verify_tol: float = 0.01) -> ModelChecks:
    """Runs the checks and returns what they found (the failures as plumb's tables)."""
    import plumb  # here, not at pytest's start: see the module's docstring

    model = _path(base, model)
    found = ModelChecks(model=_shown(model))
    found.audit = plumb.audit(model, strict=strict, accept=_path(base, accept), set=set,
                              keyframe=keyframe, scenario=_path(base, scenario))
    if not found.audit.ok:
        found.failures.append(repr(found.audit))
    if verify:
        found.verify = plumb.verify(model, set=set, tol=verify_tol)
        if not found.verify.ok:
            found.failures.append(repr(found.verify))
    if snapshot is not None:
        golden = _path(base, snapshot)
        if update:  # then compared all the same: a snapshot must reproduce its own model
            plumb.snapshot(model, set=set).save(golden)
            found.snapshot_written = golden
        if not os.path.exists(golden):
            found.failures.append(f"plumb diff: there is no golden snapshot {_shown(golden)}: "
                                  f"write it with pytest {_UPDATE}, then commit it")
        else:
            found.diff = plumb.diff(golden, model, set=set, tol=tol)
            if not found.diff.ok:
                found.failures.append(
                    f"plumb diff {_shown(golden)} {found.model} (tol {tol:g})\n"
                    f"{found.diff!r}\nIf the change is intended: pytest {_UPDATE}, review and "
                    f"commit {_shown(golden)}.")
    return found


def _check(request: pytest.FixtureRequest, where: str, model: Any,
           kwargs: dict[str, Any]) -> ModelChecks:
    """Runs the checks; failed checks and bad input are in the result, nothing is raised."""
    import plumb

    unknown = _unknown_argument(kwargs) or _not_a_model(model)
    if unknown:
        return ModelChecks(model=_shown(model), error=f"{where}: {unknown}")
    try:
        found = check_model(model, base=request.path.parent,
                            update=request.config.getoption("plumb_update"), **kwargs)
    except (plumb.Error, TypeError) as error:  # bad input: the message names the argument
        return ModelChecks(model=_shown(model), error=f"{where}: {type(error).__name__}: {error}")
    if found.snapshot_written:
        request.config.stash[_updated].append(found.snapshot_written)
    return found


def _fail_unless_ok(found: ModelChecks) -> None:
    if found.error is not None:
        pytest.fail(found.error, pytrace=False)
    if found.failures:
        pytest.fail(f"plumb: {found.model} failed {len(found.failures)} check(s)\n\n"
                    + "\n\n".join(found.failures), pytrace=False)


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("plumb", "plumb: MuJoCo model checks")
    group.addoption(_UPDATE, action="store_true", dest="plumb_update",
                    help="rewrite the golden snapshots of plumb_model/plumb_check tests from "
                    "the current models instead of comparing with them (review, then commit)")


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line(
        "markers", "plumb_model(model, *, snapshot=None, accept=None, scenario=None, "
        "strict=False, set=None, keyframe=None, tol=1e-6, verify=True, verify_tol=0.01): audit "
        "and verify MODEL, and compare it with the golden SNAPSHOT; fail with plumb's rows")
    config.stash[_updated] = []


@pytest.fixture
def plumb_model(request: pytest.FixtureRequest) -> ModelChecks:
    """What the checks of the test's @pytest.mark.plumb_model found. They run before the test,
    which fails with plumb's rows (a failure of the test, not an error of its set-up) if any
    check fails; otherwise the test receives them."""
    marker = request.node.get_closest_marker("plumb_model")
    where = f"{request.node.nodeid}: plumb_model"
    if marker is None:
        pytest.fail(f"{where}: the fixture needs @pytest.mark.plumb_model(model, ...) on the "
                    "test", pytrace=False)
    if len(marker.args) != 1:
        found = ModelChecks(model="", error=f"{where}: the marker takes one model (a path or a "
                            f"mujoco.MjModel), not {len(marker.args)}")
    else:
        found = _check(request, where, marker.args[0], dict(marker.kwargs))
    request.node.stash[_found] = found
    return found


@pytest.fixture(autouse=True)
def _plumb_model_marker(request: pytest.FixtureRequest) -> None:
    # a marked test runs the checks even when it does not ask for the plumb_model fixture
    if request.node.get_closest_marker("plumb_model") is not None:
        request.getfixturevalue("plumb_model")


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_call(item: pytest.Item) -> None:
    # before the test's body: the marker's failed checks are the test's failure
    found = item.stash.get(_found, None)
    if found is not None:
        _fail_unless_ok(found)


@pytest.fixture
def plumb_check(request: pytest.FixtureRequest) -> Callable[..., ModelChecks]:
    """plumb_check(model, snapshot=..., accept=..., ...): the marker's checks for a model given
    at run time; fails the test with plumb's rows, else returns what they found."""

    def check(model: Any, **kwargs: Any) -> ModelChecks:
        found = _check(request, f"{request.node.nodeid}: plumb_check", model, kwargs)
        _fail_unless_ok(found)
        return found

    return check


# plumb_rehearse's keywords that name files, taken from the test file's folder
_REHEARSE_PATHS = ("config", "gamepad", "output", "log", "report", "cwd")


def rehearse(model: Any, client: str, *, base: pathlib.Path, where: str, **kwargs: Any) -> Any:
    """Runs plumb.rehearse with relative paths (the model's, config, cwd, ...) taken from
    `base`, the client run there unless cwd says otherwise. Fails the test with the verdict's
    table when the rehearsal does not pass, or naming the argument for bad input; otherwise
    returns the plumb.RehearsalResult."""
    import plumb

    if "strict" in kwargs:
        pytest.fail(f"{where}: strict is plumb.rehearse's; plumb_rehearse always fails the test "
                    "when the rehearsal does not pass", pytrace=False)
    problem = _not_a_model(model)
    if problem:
        pytest.fail(f"{where}: {problem}", pytrace=False)
    kwargs.setdefault("cwd", ".")
    for name in _REHEARSE_PATHS:
        if kwargs.get(name) is not None:
            kwargs[name] = _path(base, kwargs[name])
    model = _path(base, model)
    try:
        result = plumb.rehearse(model, client, **kwargs)
    except (plumb.Error, TypeError) as error:  # bad input: the message names the argument
        pytest.fail(f"{where}: {type(error).__name__}: {error}", pytrace=False)
    if not result.passed:
        pytest.fail(f"plumb: the rehearsal of {_shown(model)} with {client!r} failed\n\n"
                    f"{result!r}", pytrace=False)
    return result


@pytest.fixture
def plumb_rehearse(request: pytest.FixtureRequest) -> Callable[..., Any]:
    """plumb_rehearse(model, client, until=..., assertions=[...], config=..., ...): a
    deployment rehearsal (plumb.rehearse's keywords) that fails the test with the verdict's
    table when it does not pass; else returns the plumb.RehearsalResult. Relative paths, and
    the client's working directory, are the test file's folder."""

    def run(model: Any, client: str, **kwargs: Any) -> Any:
        return rehearse(model, client, base=request.path.parent,
                        where=f"{request.node.nodeid}: plumb_rehearse", **kwargs)

    return run


def pytest_terminal_summary(terminalreporter: Any, config: pytest.Config) -> None:
    written = config.stash.get(_updated, [])
    if written:
        terminalreporter.write_sep("=", f"plumb: {len(written)} golden snapshot(s) rewritten")
        for path in written:
            terminalreporter.write_line(f"  {_shown(path)}  (review the change, then commit it)")
