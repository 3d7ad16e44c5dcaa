"""plumb.rehearse: a real rehearsal of the chapter's pendulum under the bridge, driven by the
example controller examples/pd_client (holds the pendulum at 0.5 rad), each test on a DDS
domain of its own (the scheme of tests/bridge/test_domain.h: a lock on
/tmp/plumb-dds-domain-<id>.lock held while this process runs)."""

import fcntl
import os
import pathlib
import signal
import threading
import time
import warnings

import mujoco
import pytest

import plumb

# what the bridge says while it runs (a PlumbWarning each call); the first test listens
pytestmark = pytest.mark.filterwarnings("ignore::plumb.PlumbWarning")

_held = []  # the domains' lock files' descriptors, open (and locked) until the process ends


@pytest.fixture
def domain() -> int:
    """A DDS domain id (10..229) no other test on this machine is using now."""
    for candidate in range(10, 230):
        fd = os.open(f"/tmp/plumb-dds-domain-{candidate}.lock",
                     os.O_CREAT | os.O_RDWR | os.O_CLOEXEC, 0o666)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(fd)
            continue
        _held.append(fd)
        return candidate
    pytest.fail("no free DDS domain id between 10 and 229 for this test")


@pytest.fixture
def pd_client() -> str:
    """examples/pd_client of this build ($PLUMB_PD_CLIENT, set by CTest when the bridge is
    built; else beside $PLUMB's build tree)."""
    path = os.environ.get("PLUMB_PD_CLIENT")
    if not path and os.environ.get("PLUMB"):
        path = str(pathlib.Path(os.environ["PLUMB"]).parent / "examples" / "pd_client" /
                   "pd_client")
    if not path or not os.path.exists(path):
        pytest.skip("examples/pd_client is not built (a build without CycloneDDS): "
                    "run through CTest with PLUMB_WITH_DDS")
    return path


@pytest.fixture
def config(tmp_path, domain) -> str:
    """The pendulum's bridge: lockstep on the test's domain, the hinge as motor 0."""
    path = tmp_path / "bridge.toml"
    path.write_text(f'family = "go"\nmode = "lockstep"\ndomain = {domain}\n'
                    'motors = ["hinge"]\n[watchdog]\ntimeout_ms = 1000\npatience_s = 1.5\n')
    return str(path)


def hold(pd_client: str) -> str:
    """The client that holds the pendulum at 0.5 rad ('{domain}': the bridge's)."""
    return f"'{pd_client}' pendulum --domain {{domain}} --seconds 30"


def test_a_client_that_holds_the_pendulum_passes(pendulum, config, pd_client, tmp_path):
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        r = plumb.rehearse(pendulum, hold(pd_client), config=config, until=1.0,
                           assertions=["qpos[hinge] > 0.4 during [0.8, 1]"],
                           report=tmp_path / "rehearsal.html")
    assert r.passed and r.ok, repr(r)
    assert isinstance(r, plumb.RehearsalResult)
    assert r.client.kind == "stopped", r.client.text
    assert r.view.commands > 100 and r.view.motors[0].name == "hinge"
    assert r.bridge.commands > 100 and abs(r.bridge.time - 1.0) < 0.01
    assert f"{r.bridge.commands} commands applied" in r.summary
    rows = {row.id: row for row in r.rows}
    asserted = [row for row in r.rows if row.section == "assert"]
    assert len(asserted) == 1 and asserted[0].status == "PASS"
    assert all(row.status != "FAIL" for row in rows.values())
    # the bridge's sentences while it ran are Python warnings, and kept on .notices
    waiting = [w for w in said if "waiting for the first command" in str(w.message)]
    assert waiting and issubclass(waiting[0].category, plumb.PlumbWarning)
    assert any("waiting for the first command" in n.text for n in r.notices)
    # the CLI's JSON, with the call's notices; the table as repr
    doc = r.to_dict()
    assert doc["passed"] is True and doc["client"]["kind"] == "stopped"
    assert any("waiting for the first command" in n["text"] for n in doc["notices"])
    assert "PASS" in repr(r)
    trace = r.trace
    assert len(trace["time"]) > 100 and "qpos[hinge]" in trace["signals"]
    page = (tmp_path / "rehearsal.html").read_text()
    assert page.startswith("<!DOCTYPE html>") and "qpos[hinge] &gt; 0.4" in page


def test_an_assertion_that_does_not_hold_fails_and_its_row_says_which(pendulum, config,
                                                                        pd_client):
    r = plumb.rehearse(pendulum, hold(pd_client), config=config, until=1.0,
                       assertions=("qpos[hinge] > 0.4 during [0.8, 1]",
                                   "qpos[hinge] > 1 during [0.8, 1]"))
    assert not r.passed
    asserted = [row for row in r.rows if row.section == "assert"]
    assert [row.status for row in asserted] == ["PASS", "FAIL"]
    assert "qpos[hinge] > 1" in asserted[1].element + asserted[1].title + asserted[1].explanation
    assert "FAIL" in repr(r)


def test_a_client_that_exits_early_is_reported_with_its_status(pendulum, config):
    model = mujoco.MjModel.from_xml_path(pendulum)  # as every call, a wrapped MjModel too
    r = plumb.rehearse(model, "sh -c 'echo bye; exit 3'", config=config, until=5.0)
    assert not r.passed
    assert r.client.kind == "exited early"
    assert r.client.exit_code == 3 and r.client.signal == 0
    assert "bye" in r.client.last_lines
    assert any(row.id == "client.process" and row.status == "FAIL" for row in r.rows)


def test_strict_raises_when_the_rehearsal_fails(pendulum, config):
    with pytest.raises(plumb.RehearsalFailed) as raised:
        plumb.rehearse(pendulum, "exit 3", config=config, until=5.0, strict=True)
    assert isinstance(raised.value, plumb.Error)
    assert raised.value.result.client.exit_code == 3
    assert str(raised.value) == repr(raised.value.result)  # the verdict's table


def test_bad_input_names_the_argument(pendulum, config):
    with pytest.raises(plumb.ArgumentError) as raised:
        plumb.rehearse(pendulum, "exit 0", config=config, until=1.0, mode="fast")
    assert raised.value.argument == "mode"
    with pytest.raises(plumb.ArgumentError) as raised:
        plumb.rehearse(pendulum, "  ", config=config, until=1.0)
    assert raised.value.argument == "client"
    with pytest.raises(plumb.PathError):
        plumb.rehearse(pendulum, "exit 0", config=config, until=1.0,
                       assertions="qpos[elbow] > 0")
    with pytest.raises(TypeError, match="env"):
        plumb.rehearse(pendulum, "exit 0", config=config, until=1.0, env={"A": 1})
    with pytest.raises(TypeError):
        plumb.rehearse(pendulum, "exit 0", config=config)  # until is required
    with pytest.raises(plumb.Error, match="report"):  # an output onto an input, before a run
        plumb.rehearse(pendulum, "exit 0", config=config, until=1.0, report=config)


def test_the_client_gets_its_directory_environment_and_domain(pendulum, config, domain, tmp_path):
    folder = tmp_path / "client"
    folder.mkdir()
    r = plumb.rehearse(pendulum, "echo \"$PWD {domain} $PLUMB_BRIDGE_DOMAIN $POLICY\"; exit 4",
                       config=config, until=5.0, cwd=folder, env={"POLICY": "walk.onnx"},
                       output=tmp_path / "client.txt")
    assert r.client.exit_code == 4
    line = f"{folder} {domain} {domain} walk.onnx"
    assert line in r.client.last_lines
    assert line in (tmp_path / "client.txt").read_text()


def test_ctrl_c_stops_the_rehearsal_and_its_client(pendulum, config, tmp_path):
    pid_file = tmp_path / "client.pid"
    timer = threading.Timer(1.0, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    began = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        # the client never commands: lockstep waits (first_command_timeout) unless stopped
        plumb.rehearse(pendulum, f"echo $$ > '{pid_file}'; exec sleep 1000", config=config,
                       until=100.0, first_command_timeout=300)
    timer.join()
    assert time.monotonic() - began < 15
    pid = int(pid_file.read_text())
    with pytest.raises(ProcessLookupError):  # the client was stopped with the rehearsal
        for _ in range(100):
            os.kill(pid, 0)
            time.sleep(0.05)


PLUGIN_TESTS = '''
import pytest

CLIENT = {client!r}


def test_still_holds(plumb_rehearse):
    r = plumb_rehearse("pendulum.xml", CLIENT, config="bridge.toml", until=1.0,
                       assertions=["qpos[hinge] > 0.4 during [0.8, 1]"])
    assert r.passed


def test_falls(plumb_rehearse):
    plumb_rehearse("pendulum.xml", CLIENT, config="bridge.toml", until=1.0,
                   assertions=["qpos[hinge] > 1 during [0.8, 1]"])


def test_dies(plumb_rehearse):
    plumb_rehearse("pendulum.xml", "exit 3", config="bridge.toml", until=5.0)


def test_misspelt(plumb_rehearse):
    plumb_rehearse("pendulum.xml", "exit 0", config="bridge.toml", until=1.0, mode="fast")
'''


def test_the_pytest_plugin_fails_a_test_with_the_verdicts_table(pendulum, config, pd_client,
                                                               tmp_path):
    import subprocess
    import sys

    project = tmp_path / "project"
    project.mkdir()
    (project / "pendulum.xml").write_text(pathlib.Path(pendulum).read_text())
    (project / "bridge.toml").write_text(pathlib.Path(config).read_text())
    (project / "test_walks.py").write_text(PLUGIN_TESTS.format(client=hold(pd_client)))
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "plumb_pytest",
         "-rA"], capture_output=True, text=True, cwd=project, timeout=600)
    out = done.stdout
    assert done.returncode == 1, out
    assert "PASSED test_walks.py::test_still_holds" in out
    assert "3 failed, 1 passed" in out
    assert "plumb: the rehearsal of pendulum.xml with 'exit 3' failed" in out
    assert "exited early" in out  # the verdict's table says how the client ended
    assert "qpos[hinge] > 1" in out
    assert "test_misspelt: plumb_rehearse: ArgumentError: mode" in out
    assert "Traceback" not in out
