"""Every path, text and list argument of plumb's functions refuses the wrong Python type with a
TypeError that names the argument and the types it takes (issue 46: bytes or a list once raised
RuntimeError: std::bad_cast)."""

import pathlib

import numpy as np
import pytest

import plumb

PATH = "missing.toml"  # never read: the argument is refused before anything is opened
LOG = "missing.csv"

# the kinds of argument, each with the wrong values it is given
WRONG = {
    "path": [b"x.toml", ["x.toml"], 3],
    "strings": [b"qpos[hinge]@1", [b"qpos[hinge]@1"], 3],
    "set": [b"qpos[hinge]=0.1", [b"qpos[hinge]=0.1"], {"qpos[hinge]": b"0.1"}, 3],
    "qpos": [b"0.1", [b"0.1"], 3],
}


def _calls():
    """(label, kind, call) for every public function and each of its path/text/list arguments;
    call(name, value) makes the call with that argument."""
    model = str(pathlib.Path(__file__).resolve().parents[2] / "models" / "pendulum.xml")
    metric = "qpos[hinge]@1"

    def with_(function, *args, **base):
        return lambda name, value: function(*args, **{**base, name: value})

    cases = [
        ("load", "set", with_(plumb.load, model)),
        ("verify", "set", with_(plumb.verify, model)),
        ("converge", "set", with_(plumb.converge, model, metric)),
        ("snapshot", "set", with_(plumb.snapshot, model)),
        ("inspect", "set", with_(plumb.inspect, model)),
        ("diff", "set", lambda name, value: plumb.diff(plumb.snapshot(model), model, set=value)),
        ("run", "set", with_(plumb.run, model, until=0.01)),
        ("run", "pose", with_(plumb.run, model, until=0.01)),
        ("run", "qpos", with_(plumb.run, model, until=0.01)),
        ("run", "columns", with_(plumb.run, model, until=0.01)),
        ("replay", "set", with_(plumb.replay, model, LOG)),
        ("replay", "columns", with_(plumb.replay, model, LOG)),
        ("identify", "set", with_(plumb.identify, model, LOG, fit="dof_damping[hinge]")),
        ("identify", "columns", with_(plumb.identify, model, LOG, fit="dof_damping[hinge]")),
        ("identify", "validate", with_(plumb.identify, model, LOG, fit="dof_damping[hinge]")),
        ("identify", "fit", with_(plumb.identify, model, log=LOG)),
        ("identify", "bounds", with_(plumb.identify, model, LOG, fit="dof_damping[hinge]")),
        ("render", "set", with_(plumb.render, model)),
        ("render", "highlight", with_(plumb.render, model)),
        ("render", "output", with_(plumb.render, model)),
    ]
    for name in ("accept", "scenario", "repro", "set"):
        cases.append(("audit", name, with_(plumb.audit, model)))
    for name in ("set", "pose", "qpos", "db", "metrics", "randomize"):
        cases.append(("rollout", name, with_(plumb.rollout, model, 2, metrics=metric, until=0.01)))
    for name in ("set", "pose", "qpos", "db", "metrics", "vary"):
        cases.append(("sweep", name, with_(plumb.sweep, model, vary="dof_damping[hinge]=0:1:2",
                                           metrics=metric, until=0.01)))
    kinds = {"set": "set", "qpos": "qpos", "columns": None, "metrics": "strings", "fit": "strings",
             "bounds": "strings", "highlight": "strings", "randomize": "strings",
             "vary": "strings"}
    out = []
    for function, name, call in cases:
        kind = kinds.get(name, "path")
        if function in ("replay", "identify") and name == "columns":
            kind = "path"  # a column map file
        elif name == "columns":
            kind = "strings"  # run's columns: paths of the model
        out.append((f"{function}-{name}", name, kind, call))
    # the positional ones and the methods
    out.append(("diff-snapshot", "snapshot", "path",
                lambda name, value: plumb.diff(value, model)))
    out.append(("replay-log", "log", "path", lambda name, value: plumb.replay(model, value)))
    out.append(("identify-log", "log", "path",
                lambda name, value: plumb.identify(model, value, fit="dof_damping[hinge]")))
    out.append(("Snapshot.load", "path", "path", lambda name, value: plumb.Snapshot.load(value)))
    out.append(("Snapshot.save", "path", "path",
                lambda name, value: plumb.snapshot(model).save(value)))
    out.append(("VerifyResult.save_report", "path", "path",
                lambda name, value: plumb.verify(model, until=0.01).save_report(value)))
    return out


CASES = [(label, name, value, call)
         for label, name, kind, call in _calls()
         for value in WRONG[kind]]


@pytest.mark.parametrize("label,name,value,call", CASES,
                         ids=[f"{c[0]}-{type(c[2]).__name__}" for c in CASES])
def test_a_wrong_type_is_a_type_error_naming_the_argument(label, name, value, call):
    if name == "log" and isinstance(value, list):
        value = [b"x.csv"]  # identify takes a list of logs: a list of bytes is wrong
        if label.startswith("replay"):
            value = ["x.csv"]
    with pytest.raises(TypeError) as caught:
        call(name, value)
    message = str(caught.value)
    assert message.startswith(f"{name}: "), message
    assert "bad_cast" not in message
    if isinstance(value, bytes):
        assert "bytes" in message and "decode" in message, message


def test_a_path_with_a_nul_is_refused_by_name(pendulum):
    with pytest.raises(plumb.ArgumentError) as caught:
        plumb.run(pendulum, until=0.01, pose="pose\0.txt")
    assert caught.value.argument == "pose"


def test_the_right_types_still_work(pendulum, tmp_path):
    # a pathlib.Path, a numpy array of qpos, a tuple of strings
    t = plumb.run(pathlib.Path(pendulum), until=0.01, qpos=np.array([0.3]),
                  set=("dof_damping[hinge]=0.1",), columns=("qpos[hinge]",))
    assert t.columns == ["qpos[hinge]"]
    plumb.snapshot(pendulum).save(tmp_path / "s.json")
    assert plumb.diff(tmp_path / "s.json", pendulum).to_dict()


# issue 49: a type nanobind refuses itself (None for the model, a str for a number) gave every
# signature of the function (verify(None): 431 characters); the error names the argument
@pytest.mark.parametrize("call,message", [
    (lambda m: plumb.verify(None), "verify(): model expects Model | mujoco.MjModel | str | "
                                   "os.PathLike[str], not None"),
    (lambda m: plumb.verify(m, tol="x"), "verify(): tol expects float, not str"),
    (lambda m: plumb.run(m, until=None), "run(): until expects float, not None"),
    (lambda m: plumb.verify(m, keyframe=1.5), "verify(): keyframe expects str | int | None, "
                                              "not float"),
    (lambda m: plumb.render(m, camera=2.5), "render(): camera expects str | int, not float"),
    (lambda m: plumb.verify(), "verify(): model is missing"),
    (lambda m: plumb.verify(m, tool=1), "verify(): no argument is named 'tool'"),
])
def test_nanobinds_refusals_name_the_argument(pendulum, call, message):
    with pytest.raises(TypeError) as caught:
        call(pendulum)
    assert str(caught.value).startswith(message), str(caught.value)
    text = str(caught.value)
    assert len(text) < 200 and "incompatible function arguments" not in text


def test_set_of_a_number_names_set(pendulum):
    with pytest.raises(TypeError, match=r"^set: expected a dict"):
        plumb.verify(pendulum, set=5)
