"""plumb.render: pictures as numpy arrays, runs as Frames, PNG and MP4 files."""

import subprocess

import mujoco
import numpy as np
import pytest

import plumb

SMALL = {"width": 160, "height": 120, "shadow_size": 256}


def draw(*args, **kwargs):
    try:
        return plumb.render(*args, **kwargs)
    except plumb.UnavailableError as e:
        pytest.skip(str(e))


def test_a_picture_of_the_pendulum(pendulum):
    image = draw(pendulum, set={"qpos[hinge]": 0.7}, **SMALL)
    assert image.shape == (120, 160, 3) and image.dtype == np.uint8
    # a real picture: many colours, not one flat fill
    assert image.std() > 5 and len(np.unique(image.reshape(-1, 3), axis=0)) > 20
    # the pendulum moves the picture: another angle is another image
    other = draw(pendulum, set={"qpos[hinge]": -0.7}, **SMALL)
    assert np.abs(image.astype(int) - other.astype(int)).sum() > 0


def test_state_from_mjdata_is_read_not_changed(pendulum):
    model = mujoco.MjModel.from_xml_path(pendulum)
    data = mujoco.MjData(model)
    data.qpos[0] = 0.7
    mujoco.mj_forward(model, data)
    qpos, time = data.qpos.copy(), data.time
    from_data = draw(model, state=data, **SMALL)
    from_set = draw(model, set={"qpos[hinge]": 0.7}, **SMALL)
    np.testing.assert_array_equal(from_data, from_set)
    np.testing.assert_array_equal(data.qpos, qpos)
    assert data.time == time


def test_at_runs_to_that_time(pendulum):
    start = draw(pendulum, set={"qpos[hinge]": 0.7}, **SMALL)
    later = draw(pendulum, set={"qpos[hinge]": 0.7}, at=0.5, **SMALL)
    assert np.abs(start.astype(int) - later.astype(int)).sum() > 0


def test_a_run_saved_as_png_and_mp4(pendulum, tmp_path):
    frames = draw(pendulum, set={"qpos[hinge]": 0.7}, until=1, fps=10, **SMALL)
    assert frames.array.shape == (11, 120, 160, 3)
    np.testing.assert_allclose(frames.times, np.arange(11) * 0.1, atol=1e-12)
    assert frames.fps == pytest.approx(10)
    frames.save(tmp_path / "swing.mp4")
    probe = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0",
                            "-show_entries", "stream=nb_read_frames,width,height", "-of",
                            "csv=p=0", str(tmp_path / "swing.mp4")],
                           capture_output=True, text=True)
    assert probe.returncode == 0, probe.stderr
    assert probe.stdout.strip() == "160,120,11"
    frames.save(tmp_path / "last.png")
    assert (tmp_path / "last.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    html = frames._repr_html_()
    assert html.lstrip().lower().startswith("<!doctype html>") and "flipbook" in html
    assert frames.to_dict()["frames"] == 11


def test_a_trajectory_animates(pendulum):
    t = plumb.run(pendulum, until=0.4, set={"qpos[hinge]": 0.7})
    frames = draw(pendulum, state=t, **SMALL)
    assert len(frames) == len(t) == 5
    np.testing.assert_allclose(frames.times, t.time)
    first = draw(pendulum, set={"qpos[hinge]": 0.7}, **SMALL)
    np.testing.assert_array_equal(frames[0], first)
    with pytest.raises(plumb.ArgumentError) as caught:
        draw(pendulum, state=plumb.run(pendulum, until=0.2, columns="time"), **SMALL)
    assert caught.value.argument == "state"


def test_errors_name_the_keyword(pendulum, tmp_path):
    with pytest.raises(plumb.ArgumentError) as caught:
        draw(pendulum, width=0, height=120)
    assert caught.value.argument == "width"
    with pytest.raises(plumb.ArgumentError) as caught:
        draw(pendulum, until=1, fps=0, **SMALL)
    assert caught.value.argument == "fps"
    with pytest.raises(plumb.ArgumentError) as caught:
        draw(pendulum, at=-1, **SMALL)
    assert caught.value.argument == "at"
    with pytest.raises(plumb.ValueError, match="camera"):
        draw(pendulum, camera="nowhere", **SMALL)
    with pytest.raises(plumb.ArgumentError) as caught:
        draw(pendulum, until=0.2, output=str(tmp_path / "x.gif"), **SMALL)
    assert caught.value.argument == "path"
    t = plumb.run(pendulum, until=0.2)
    with pytest.raises(plumb.ArgumentError) as caught:
        draw(pendulum, state=t, set={"qpos[hinge]": 1}, **SMALL)
    assert caught.value.argument == "set"
    with pytest.raises(plumb.ArgumentError) as caught:
        draw(pendulum, state=t, until=1, **SMALL)
    assert caught.value.argument == "until"


def test_frames_keep_a_wrapped_mjmodel_alive(pendulum):
    import gc

    model = mujoco.MjModel.from_xml_path(pendulum)
    frames = draw(model, set={"qpos[hinge]": 0.7}, until=0.2, fps=10, **SMALL)
    del model
    gc.collect()
    assert "flipbook" in frames._repr_html_()


def test_every_way_of_drawing_a_time_shows_the_state_at_that_time(pendulum):
    # a run's samples drawn again, the picture at `at` and the video's frame at that time are
    # one picture: each shows the state reached, not the step before it
    t = plumb.run(pendulum, until=0.3, every=0.1, set={"qpos[hinge]": 0.7})
    from_samples = draw(pendulum, state=t, **SMALL)
    at = draw(pendulum, set={"qpos[hinge]": 0.7}, at=0.3, **SMALL)
    film = draw(pendulum, set={"qpos[hinge]": 0.7}, until=0.3, fps=10, **SMALL)
    np.testing.assert_array_equal(from_samples[-1], at)
    np.testing.assert_array_equal(film[-1], at)
    np.testing.assert_array_equal(film.array, from_samples.array)


def test_a_time_beyond_countable_steps_is_refused_by_its_own_name(pendulum):
    # issue 46: until=1e30 raised MemoryError; at=1e17 blamed "until -1.84467e+16"
    for keyword, value in (("until", 1e30), ("at", 1e17), ("at", float("nan"))):
        with pytest.raises(plumb.ArgumentError) as caught:
            draw(pendulum, **{keyword: value}, **SMALL)
        assert caught.value.argument == keyword
        assert "-1.84467e+16" not in str(caught.value)
    # a film whose frames this machine cannot hold is refused before a frame is drawn
    with pytest.raises(plumb.ArgumentError, match="more than this machine's memory") as caught:
        draw(pendulum, until=1e12, **SMALL)
    assert caught.value.argument == "until"
