"""Shared fixtures of plumb's Python tests (run by CTest with the build's venv: label python)."""

import json
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(autouse=True)
def _outside_the_checkout(tmp_path, monkeypatch):
    """Every test runs in a folder of its own: nothing it (or MuJoCo's MUJOCO_LOG.TXT) writes
    lands in the checkout. Name the repository's files through `root` or `pendulum`."""
    monkeypatch.chdir(tmp_path)


@pytest.fixture
def root() -> pathlib.Path:
    """The checkout (tests run from it)."""
    return ROOT


@pytest.fixture
def pendulum() -> str:
    """The chapter's pendulum."""
    return str(ROOT / "models" / "pendulum.xml")


# A robot of the corpus (PLUMB_CORPUS, else plumb's cache), or the test is skipped.
def robot(relative: str) -> str:
    root = pathlib.Path(os.environ.get("PLUMB_CORPUS", pathlib.Path.home() / ".cache/plumb/robots"))
    path = root / relative
    if not path.exists():
        pytest.skip(f"robot corpus missing {relative} (make corpus)")
    return str(path)


def run_cli(*args: str, check_codes=(0, 1)) -> subprocess.CompletedProcess:
    """Runs the plumb command of this build ($PLUMB) and returns the finished process."""
    plumb = os.environ.get("PLUMB")
    if not plumb:
        pytest.skip("$PLUMB (the plumb command of this build) is not set: run through CTest")
    done = subprocess.run([plumb, *args], capture_output=True, text=True, cwd=ROOT)
    assert done.returncode in check_codes, done.stderr
    return done


@pytest.fixture
def cli_json():
    """cli_json("verify", "models/pendulum.xml", ...) -> the parsed --format json output."""

    def call(*args: str):
        return json.loads(run_cli(*args, "--format", "json").stdout)

    return call
