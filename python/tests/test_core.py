"""What the Python package promises beside its calls: one MuJoCo shared with the `mujoco`
package, the caller's model never changed, mujoco's own errors untouched, the GIL released."""

import os
import subprocess
import sys
import textwrap
import threading
import time

import mujoco
import numpy as np
import pytest

import plumb


def _package_folder() -> str:
    """The folder plumb was imported from, for a subprocess's PYTHONPATH."""
    return os.path.dirname(os.path.dirname(os.path.abspath(plumb.__file__)))


def test_one_mujoco_library_in_the_process():
    assert plumb.mujoco_version() == mujoco.mj_versionString() == plumb.compiled_mujoco_version()
    lib = os.path.realpath(plumb.mujoco_library())
    assert lib.startswith(os.path.realpath(os.path.dirname(mujoco.__file__)))
    maps = open("/proc/self/maps").read()
    loaded = {line.split()[-1] for line in maps.splitlines() if "libmujoco.so" in line}
    assert len({os.path.realpath(p) for p in loaded}) == 1, loaded


def test_a_wrapped_mjmodel_is_the_same_memory(pendulum):
    model = mujoco.MjModel.from_xml_path(pendulum)
    wrapped = plumb.load(model)
    assert wrapped.address == model._address
    assert wrapped.mjmodel is model
    # an edit through mujoco is seen by plumb: nothing was copied
    model.opt.timestep = 0.001
    assert wrapped.timestep == 0.001


def test_load_keeps_a_start_and_validates_it(pendulum):
    loaded = plumb.load(pendulum, set={"qpos[hinge]": 0.7})
    assert loaded.sets == ["qpos[hinge]=0.7"]  # the shortest text that reads back exactly
    # numpy numbers and arrays go over the same way
    assert plumb.load(pendulum, set={"qpos[hinge]": np.float64(0.1) * 7, "opt.gravity":
                                     np.array([0, 0, -1.62])}).sets == [
        "qpos[hinge]=0.7000000000000001", "opt.gravity=0.0,0.0,-1.62"]
    assert plumb.verify(loaded).ok
    with pytest.raises(plumb.PathError):
        plumb.load(pendulum, set={"qpos[nothing]": 1})
    with pytest.raises(plumb.ValueError, match="keyframe"):
        plumb.load(pendulum, keyframe="nowhere")
    with pytest.raises(TypeError, match="mujoco.MjModel or a path"):
        plumb.load(42)


def _mjmodel_arrays(model):
    return {
        name: np.array(getattr(model, name), copy=True)
        for name in ("body_mass", "body_inertia", "dof_damping", "qpos0", "geom_size",
                     "body_subtreemass", "dof_invweight0")
    } | {"timestep": model.opt.timestep, "integrator": model.opt.integrator}


def test_the_callers_model_is_never_changed(pendulum):
    model = mujoco.MjModel.from_xml_path(pendulum)
    before = _mjmodel_arrays(model)
    edits = {"body_mass[link]": 2.0, "dof_damping[hinge]": 0.3, "opt.timestep": 0.001,
             "opt.integrator": "RK4", "qpos[hinge]": 0.7}
    plumb.verify(model, set=edits)
    plumb.audit(model, set=edits)
    plumb.converge(model, "qpos[hinge]@0.5", set=edits, halvings=2)
    plumb.snapshot(model, set=edits)
    after = _mjmodel_arrays(model)
    for name, value in before.items():
        np.testing.assert_array_equal(after[name], value, err_msg=name)


def test_mujoco_fatal_error_still_raises_after_import_plumb(pendulum):
    # an arena too small for a step: mju_error in mj_step, which mujoco turns into FatalError
    xml = (
        '<mujoco><size memory="6K"/><worldbody><geom type="plane" size="5 5 .1"/>'
        + "".join(
            f'<body pos="0 0 {0.05 + 0.19 * i}"><freejoint/><geom type="box" size=".1 .1 .1"/></body>'
            for i in range(8)
        )
        + "</worldbody></mujoco>"
    )
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    plumb.verify(pendulum)  # plumb's handlers came and went
    with pytest.raises(mujoco.FatalError, match="mj_stackAlloc"):
        for _ in range(10):
            mujoco.mj_step(model, data)
    # plumb's own calls turn the same error into plumb.MujocoError ...
    with pytest.raises(plumb.MujocoError, match="mj_stackAlloc"):
        plumb.audit(model)
    # ... and afterwards mujoco's are mujoco's again
    mujoco.mj_resetData(model, data)
    with pytest.raises(mujoco.FatalError, match="mj_stackAlloc"):
        for _ in range(10):
            mujoco.mj_step(model, data)


def test_mujoco_errors_on_another_thread_during_a_plumb_call_stay_mujocos(pendulum):
    xml = ('<mujoco><size memory="6K"/><worldbody><geom type="plane" size="5 5 .1"/>'
           + "".join(f'<body pos="0 0 {0.05 + 0.19 * i}"><freejoint/><geom type="box" '
                     'size=".1 .1 .1"/></body>' for i in range(8))
           + "</worldbody></mujoco>")
    model = mujoco.MjModel.from_xml_string(xml)
    raised = []

    def step_until_error():
        data = mujoco.MjData(model)
        try:
            for _ in range(10):
                mujoco.mj_step(model, data)
        except mujoco.FatalError as error:
            raised.append(error)

    worker = threading.Thread(target=lambda: plumb.verify(pendulum, set={"qpos[hinge]": 0.7}))
    worker.start()
    time.sleep(0.2)  # verify is running, its handler installed
    step_until_error()
    worker.join()
    assert raised, "mujoco.FatalError was not raised while plumb ran on another thread"


def test_another_python_thread_runs_during_a_long_call(pendulum):
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.005)

    counter = threading.Thread(target=count)
    counter.start()
    start = time.monotonic()
    plumb.verify(pendulum, set={"qpos[hinge]": 0.7})
    elapsed = time.monotonic() - start
    stop.set()
    counter.join()
    during = [t for t in ticks if start <= t <= start + elapsed]
    # the counter sleeps 5 ms a tick: with the GIL held for the whole call it would not tick
    assert elapsed > 0.2 and len(during) >= 0.5 * elapsed / 0.005 * 0.5


def test_a_mujoco_of_another_version_is_refused(tmp_path, root):
    fake = tmp_path / "mujoco"
    fake.mkdir()
    (fake / "__init__.py").write_text('__version__ = "3.11.0"\n')
    (fake / "libmujoco.so.3.11.0").write_bytes(b"")
    env = dict(os.environ, PYTHONPATH=f"{tmp_path}:{_package_folder()}")
    done = subprocess.run([sys.executable, "-c", "import plumb"], env=env, capture_output=True,
                          text=True)
    assert done.returncode != 0
    assert "ImportError" in done.stderr
    assert "3.11.0" in done.stderr and plumb.compiled_mujoco_version() in done.stderr
    assert str(fake / "libmujoco.so.3.11.0") in done.stderr


def test_ctrl_c_stops_a_long_call_with_keyboard_interrupt(root):
    # CLOCK_MONOTONIC is one clock for both processes: the child prints when it caught the
    # KeyboardInterrupt, the parent knows when it sent SIGINT
    script = textwrap.dedent(
        f"""
        import sys, time, plumb
        print("started", flush=True)
        try:
            plumb.verify({str(root / 'models' / 'pendulum.xml')!r}, set={{"qpos[hinge]": 0.7}},
                         until=400.0)
            print("finished", flush=True)
        except KeyboardInterrupt:
            print("interrupted", time.monotonic(), flush=True)
        """
    )
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True,
                            env=dict(os.environ, PYTHONPATH=_package_folder()))
    assert proc.stdout.readline().strip() == "started"
    time.sleep(1.0)  # inside verify's long run
    sent = time.monotonic()
    proc.send_signal(2)
    out, err = proc.communicate(timeout=60)
    words = out.split()
    assert words[0] == "interrupted", out + err
    latency = float(words[1]) - sent
    # the call polls every 20 ms and verify stops at its next step: well within 100 ms on an idle
    # machine; the bound leaves room for a loaded CI machine's scheduling
    assert 0 <= latency < 0.25, latency


def test_type_stubs_describe_the_api():
    import ast

    stub = os.path.join(os.path.dirname(plumb.__file__), "_plumb.pyi")
    assert os.path.exists(os.path.join(os.path.dirname(plumb.__file__), "py.typed"))
    tree = ast.parse(open(stub).read())
    functions = {node.name: node for node in tree.body if isinstance(node, ast.FunctionDef)}
    for name in ("load", "verify", "audit", "converge", "snapshot", "diff"):
        assert name in functions, name
    verify = functions["verify"]
    annotations = {a.arg: ast.unparse(a.annotation) for a in verify.args.args}
    assert annotations["model"] == "Model | mujoco.MjModel | str | os.PathLike[str]"
    assert annotations["tol"] == "float"
    assert ast.unparse(verify.returns) == "VerifyResult"
    classes = {node.name for node in tree.body if isinstance(node, ast.ClassDef)}
    assert {"Model", "CheckRow", "VerifyResult", "AuditResult", "Error"} <= classes | {"Error"}


def test_plugins_are_mujocos_loaded_once(root):
    # a model with a first-party plugin (mujoco.pid) compiles in plumb through the plugins the
    # mujoco package registered. plumb maps no plugin library of its own, even where the plumb
    # command would load one (PLUMB_MUJOCO_PLUGIN_PATH: here the cache's copies, the same files
    # as the package's)
    path = root / "tests" / "models" / "pid_servo.xml"
    other = os.path.realpath(os.path.join(os.path.dirname(plumb.mujoco_library()), "..", "bin",
                                          "mujoco_plugin"))
    cache = os.path.expanduser("~/.cache/plumb/mujoco/4.0.1/bin/mujoco_plugin")
    folder = cache if os.path.isdir(cache) else other
    script = textwrap.dedent(f"""
        import os, mujoco, plumb
        result = plumb.verify({str(path)!r}, set={{"ctrl[servo]": 0.5}})
        assert next(r for r in result.rows if r.id == "load").status == "PASS"
        maps = {{os.path.realpath(line.split()[-1]) for line in open("/proc/self/maps")
                if "plugin" in line and line.rstrip().endswith(".so")}}
        print("\\n".join(sorted(maps)))
    """)
    env = dict(os.environ, PYTHONPATH=_package_folder(), PLUMB_MUJOCO_PLUGIN_PATH=folder)
    done = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    plugins = done.stdout.split()
    assert plugins, "the mujoco package loaded no plugin library"
    package = os.path.realpath(os.path.dirname(mujoco.__file__))
    assert all(p.startswith(package) for p in plugins), plugins
    names = [os.path.basename(p) for p in plugins]
    assert len(names) == len(set(names))
