"""plumb's wheel, installed: run by scripts/test-wheel.sh with the pytest of a fresh venv that
holds only the wheel and what it requires (mujoco-core, numpy) plus pytest. Nothing here
reads plumb's build tree; $PLUMB_SOURCE is the checkout, for its models and examples."""

import importlib.metadata
import os
import pathlib
import re
import shutil
import subprocess
import sys

import pytest

SOURCE = pathlib.Path(os.environ["PLUMB_SOURCE"])
PENDULUM = str(SOURCE / "models" / "pendulum.xml")


def run(*args, cwd=None, env=None):
    return subprocess.run(args, capture_output=True, text=True, cwd=cwd, env=env, timeout=600)


def test_the_api_verifies_the_pendulum_with_mujocos_model():
    import mujoco
    import plumb

    result = plumb.verify(mujoco.MjModel.from_xml_path(PENDULUM), set={"qpos[hinge]": 0.7})
    assert result.ok
    assert len(result.rows) == 15
    assert {row.status for row in result.rows} == {"PASS"}
    assert "plumb verify" in repr(result)
    assert "<html" in result._repr_html_().lower()


def test_plumb_and_mujoco_share_the_mujoco_core_wheels_library():
    import mujoco
    import plumb

    wheel_library = pathlib.Path(mujoco.__file__).parent / "libmujoco.so.4.0.1"
    assert pathlib.Path(plumb.mujoco_library()).resolve() == wheel_library.resolve()
    with open("/proc/self/maps") as maps:
        loaded = {line.split()[-1] for line in maps if "libmujoco" in line}
    assert loaded == {str(wheel_library.resolve())}
    model = mujoco.MjModel.from_xml_path(PENDULUM)
    assert plumb.load(model).address == model._address


def test_trajectories_and_stores_work_from_the_wheel(tmp_path):
    import plumb

    t = plumb.run(PENDULUM, until=0.5, every=0.1, columns=["qpos[hinge]"], set={"qpos[hinge]": 0.7})
    assert t["qpos[hinge]"][1:] == pytest.approx([0.65403, 0.52386, 0.32596, 0.08646, -0.16156],
                                                 abs=5e-6)
    batch = plumb.rollout(PENDULUM, count=4, randomize="dof_damping[hinge]=U(0,0.1)",
                          until=0.2, db=tmp_path / "runs.db")
    assert len(batch) == 4


def test_the_command_is_on_path_and_runs_the_bundled_program(tmp_path):
    plumb = shutil.which("plumb")
    assert plumb and pathlib.Path(plumb).parent == pathlib.Path(sys.executable).parent
    version = run("plumb", "--version")
    assert version.returncode == 0, version.stderr
    import mujoco

    # the program loads the mujoco-core wheel's library and plugins, not a cache's
    mujoco_dir = str(pathlib.Path(mujoco.__file__).parent.resolve())
    assert f"MuJoCo loaded:           4.0.1 from {mujoco_dir}/libmujoco.so.4.0.1" in version.stdout
    assert f"plugin libraries:        {mujoco_dir}/plugin" in version.stdout
    verify = run("plumb", "verify", PENDULUM, "--set", "qpos[hinge]=0.7", "--report",
                 str(tmp_path / "report.html"))
    assert verify.returncode == 0, verify.stderr
    assert "15 passed, 0 warned, 0 failed" in verify.stdout
    assert (tmp_path / "report.html").stat().st_size > 100_000  # Chart.js inlined
    assert run("plumb", "verify", str(tmp_path / "missing.xml")).returncode == 2
    # a model with MuJoCo's PID actuator plugin compiles: the plugins of mujoco/plugin load
    servo = run("plumb", "run", str(SOURCE / "tests" / "models" / "pid_servo.xml"), "--set",
                "ctrl[servo]=0.5", "--until", "2", "--every", "2", "--columns", "qpos[j]")
    assert servo.returncode == 0, servo.stderr
    assert abs(float(servo.stdout.split()[-1]) - 0.5) < 0.1


def test_the_program_links_no_mpi_and_no_gl_and_renders_with_the_systems(tmp_path):
    package = pathlib.Path(importlib.util.find_spec("plumb").origin).parent
    for binary in (package / "bin" / "plumb", *package.glob("_plumb*.so")):
        needed = run("readelf", "-d", str(binary)).stdout
        names = re.findall(r"\(NEEDED\)\s+Shared library: \[(.+?)\]", needed)
        assert names and not [n for n in names if re.match(r"lib(mpi|open-|GL|EGL|OSMesa)", n)]
    picture = run("plumb", "render", PENDULUM, "-o", str(tmp_path / "p.png"))
    assert picture.returncode == 0, picture.stderr
    assert (tmp_path / "p.png").read_bytes()[:4] == b"\x89PNG"


def test_the_bridge_runs_over_the_bundled_cyclonedds(tmp_path):
    (tmp_path / "bridge.toml").write_text('motors = ["hinge"]\n')
    domain = str(100 + os.getpid() % 100)  # a DDS domain of its own
    done = run("plumb", "bridge", PENDULUM, "--config", "bridge.toml", "--mode", "realtime",
               "--until", "0.05", "--qpos", "0.7", "--log", "log.csv", "--domain", domain,
               cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert "realtime factor" in done.stdout
    header, first = (tmp_path / "log.csv").read_text().splitlines()[:2]
    assert "qpos[hinge]" in header.split(",")
    assert float(first.split(",")[header.split(",").index("qpos[hinge]")]) == 0.7


def test_the_crosscheck_adapter_is_found_inside_the_package(tmp_path):
    # no engine environment and no package index: plumb must find its adapter in the wheel
    # (plumb/share/plumb/engines) and then say that it cannot make the engine's environment
    env = dict(os.environ, PIP_NO_INDEX="1", PIP_FIND_LINKS="", PLUMB_ENGINE_VENVS=str(tmp_path))
    result = run("plumb", "crosscheck", PENDULUM, "--engine", "warp", env=env)
    assert result.returncode == 5, result.stderr
    assert "site-packages/plumb/share/plumb/engines/requirements-warp.txt" in result.stderr
    assert "plumb crosscheck --setup --engine warp" in result.stderr


def test_every_bundled_library_is_listed_with_its_licence():
    dist = importlib.metadata.distribution("plumb-mujoco")
    assert "mujoco-core==4.0.1" in dist.requires  # exactly plumb's MuJoCo
    files = [str(f) for f in dist.files]
    bundled = sorted(pathlib.Path(f).name for f in files if f.startswith("plumb_mujoco.libs/"))
    table = next(f for f in dist.files if str(f).endswith("licenses/THIRD-PARTY.md"))
    text = pathlib.Path(table.locate()).read_text()
    assert bundled and [b for b in bundled if f"`{b}`" not in text] == []
    assert not [b for b in bundled if re.match(r"lib(mujoco|mpi|open-|GL|EGL|OSMesa)", b)]
    assert "GPL-2.0-or-later" in text  # CHOLMOD's GPL modules are named
    listed = [line for line in dist.metadata.get_all("License-File") or []]
    assert "THIRD-PARTY.md" in listed and len(listed) > 5


ARM_TEST = '''
import pytest

@pytest.mark.plumb_model("arm.xml", snapshot="arm.snap.json", scenario="reach.toml",
                         accept="accepted.toml", strict=True)
def test_arm(plumb_model):
    assert plumb_model.audit.ok and plumb_model.diff.ok
'''


def test_the_pytest_plugin_guards_the_model_ci_example(tmp_path):
    project = tmp_path / "model_ci"
    shutil.copytree(SOURCE / "examples" / "model_ci", project)
    (project / "test_arm.py").write_text(ARM_TEST)

    def pytest_run(*args):
        return run(sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *args,
                   cwd=project)

    assert "--plumb-update" in pytest_run("--help").stdout  # registered by the entry point
    clean = pytest_run()
    assert clean.returncode == 0, clean.stdout

    arm = project / "arm.xml"
    arm.write_text(arm.read_text().replace('range="-1.5 1.5" damping="3"',
                                           'range="-1.5 1.5" damping="4"'))
    changed = pytest_run()
    assert changed.returncode == 1, changed.stdout
    assert "dof_damping[shoulder]: 3 → 4" in changed.stdout
    assert "pytest --plumb-update" in changed.stdout

    golden = (project / "arm.snap.json").read_text()
    updated = pytest_run("--plumb-update")
    assert updated.returncode == 0, updated.stdout
    assert "1 golden snapshot(s) rewritten" in updated.stdout
    assert (project / "arm.snap.json").read_text() != golden
    again = pytest_run()
    assert again.returncode == 0, again.stdout


@pytest.mark.skipif("PLUMB_REPAIRED_WHEEL" not in os.environ,
                    reason="run by scripts/test-wheel.sh, which names the repaired wheel")
def test_a_bundled_library_without_a_reviewed_licence_stops_the_build(tmp_path):
    # the licence table without TBB's entry: wheel-licenses.py must refuse the wheel, naming it
    table = (SOURCE / "python" / "bundled-licenses.toml").read_text()
    table = re.sub(r'\[packages\.onetbb\]\nlicense = "[^"]*"\n', "", table)
    (tmp_path / "table.toml").write_text(table)
    done = run(os.environ["PLUMB_WHEEL_TOOLS_PYTHON"], str(SOURCE / "scripts" / "wheel-licenses.py"),
               os.environ["PLUMB_REPAIRED_WHEEL"], str(tmp_path / "table.toml"),
               str(tmp_path / "out"))
    assert done.returncode == 1
    assert "libtbb" in done.stderr and "source onetbb" in done.stderr
    assert not (tmp_path / "out").exists()  # no wheel without its licences
