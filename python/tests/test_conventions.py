"""Issue 49, the Python conventions: mujoco's order of width and height, cameras and keyframes
by id, a model camera named `track`, verify's start as the CLI takes it, Trajectory.time as
MjData.time (test_run.py), and a notebook's light view of a verify result."""

import re
import time
import warnings

import mujoco
import numpy as np
import pytest

import plumb

SMALL = {"width": 64, "height": 48, "shadow_size": 256}

# a free body and two cameras: the first named like plumb's tracking camera, the second unnamed
CAMERAS = """<mujoco><worldbody><light pos="0 0 3"/>
  <camera name="track" pos="0 -3 0.5" xyaxes="1 0 0 0 0.2 1"/>
  <camera pos="3 0 0.5" xyaxes="0 1 0 -0.2 0 1"/>
  <geom type="plane" size="2 2 0.1"/>
  <body pos="0.4 0 0.5"><freejoint/><geom type="box" size="0.1 0.2 0.3" rgba="1 0 0 1"/></body>
  </worldbody>
  <keyframe><key name="high" qpos="0.4 0 2 1 0 0 0"/><key qpos="0.4 0 1 1 0 0 0"/></keyframe>
</mujoco>"""


def draw(*args, **kwargs):
    try:
        return plumb.render(*args, **kwargs)
    except plumb.UnavailableError as e:
        pytest.skip(str(e))


@pytest.fixture
def cameras(tmp_path):
    path = tmp_path / "cameras.xml"
    path.write_text(CAMERAS)
    return str(path)


def test_width_and_height_are_keywords_and_positions_warn(pendulum):
    image = draw(pendulum, width=64, height=32)
    assert image.shape == (32, 64, 3)  # rows are the height, as mujoco.Renderer's
    with pytest.warns(FutureWarning, match="keyword"):
        old = draw(pendulum, None, "fixed", 64, 32)
    assert old.shape == (32, 64, 3)
    with pytest.raises(TypeError, match="width given twice"), warnings.catch_warnings():
        warnings.simplefilter("ignore", FutureWarning)
        draw(pendulum, None, "fixed", 64, width=80)


def test_a_model_camera_named_track_is_the_models(cameras):
    theirs = draw(cameras, camera="track", **SMALL)
    by_id = draw(cameras, camera=0, **SMALL)
    ours = draw(cameras, camera="plumb:track", **SMALL)
    np.testing.assert_array_equal(theirs, by_id)
    assert np.abs(theirs.astype(int) - ours.astype(int)).sum() > 0
    unnamed = draw(cameras, camera=1, **SMALL)
    assert np.abs(unnamed.astype(int) - theirs.astype(int)).sum() > 0
    with pytest.raises(plumb.ArgumentError, match="'track', #1"):
        draw(cameras, camera=2, **SMALL)


def test_keyframes_by_id(cameras):
    assert plumb.load(cameras, keyframe=0).keyframe == "#0"
    high = plumb.run(cameras, until=0, keyframe=0, columns="qpos[*][2]")
    low = plumb.run(cameras, until=0, keyframe=1, columns="qpos[*][2]")
    named = plumb.run(cameras, until=0, keyframe="high", columns="qpos[*][2]")
    assert high.array[0, -1] == named.array[0, -1] == 2 and low.array[0, -1] == 1
    with pytest.raises(plumb.Error, match="#5"):
        plumb.run(cameras, until=0, keyframe=5)


def test_verify_takes_pose_and_qpos_as_the_cli(pendulum, tmp_path, cli_json):
    result = plumb.verify(pendulum, qpos=[0.3], until=0.5)
    assert result.start == "qpos0 with qpos=0.3"
    pose = tmp_path / "pose.txt"
    pose.write_text("0.3\n")
    from_file = plumb.verify(pendulum, pose=pose, until=0.5)
    cli = cli_json("verify", "models/pendulum.xml", "--qpos", "0.3", "--until", "0.5")
    assert [r.status for r in result.rows] == [r["status"] for r in cli["checks"]]
    assert [r.measured for r in from_file.rows if r.id.startswith("energy")] == \
        [r.measured for r in result.rows if r.id.startswith("energy")]


def _pictures(page):
    return len(re.findall(r'<img alt="[^"]*" src="data:image/png', page))


def test_a_notebook_shows_a_light_view_and_the_report_is_drawn_once(pendulum, tmp_path):
    result = plumb.verify(pendulum, set={"qpos[hinge]": 0.7}, until=0.5)
    start = time.perf_counter()
    light = result._repr_html_()
    if "No pictures:" in light:
        pytest.skip("this machine cannot render")
    assert 'class="flipbook"' not in light and _pictures(light) == 1
    assert "checks" in light.lower()  # the table is there
    full = result.html()
    assert 'class="flipbook"' in full and _pictures(full) > _pictures(light)
    assert len(light) < len(full)
    first = time.perf_counter() - start
    # kept on the result: showing it again or saving it draws nothing again
    start = time.perf_counter()
    assert result._repr_html_() is not None and result.html() == full
    result.save_report(tmp_path / "report.html")
    assert time.perf_counter() - start < max(0.05, first / 5)
    assert (tmp_path / "report.html").read_text() == full
