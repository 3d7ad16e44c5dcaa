"""The peer side of bench/render_peer.sh: MuJoCo's own Python mujoco.Renderer on the loop
build/bench/render_bench runs. For each frame one mj_step (not timed), then
renderer.update_scene(data) and renderer.render() (timed: scene update, draw, readback and
the bindings' vertical flip), wall and process CPU time (all threads). 5 warm-up frames are rendered first and not timed. Prints one
JSON line like render_bench's.

Usage: render_peer.py MODEL FRAMES WIDTH HEIGHT [--no-msaa] [--dump FILE]
  --no-msaa  sets the model's offsamples to 0 before making the renderer (plumb's default);
             otherwise the model's own (4 unless it says otherwise), mujoco.Renderer's default
  --dump     writes the last frame's raw RGB bytes, top row first

Run with MUJOCO_GL=egl, inside the throw-away virtual environment bench/render_peer.sh
makes (mujoco-core 4.0.1 and PyOpenGL)."""

import json
import sys
import time

import mujoco

WARMUP_FRAMES = 5


def gl_renderer():
    """The GL_RENDERER string of the current context, or "" if PyOpenGL cannot say."""
    try:
        from OpenGL import GL  # pylint: disable=import-outside-toplevel
        return GL.glGetString(GL.GL_RENDERER).decode()
    except Exception:  # pylint: disable=broad-except
        return ""


def main():
    args = sys.argv[1:]
    if len(args) < 4:
        sys.exit(__doc__)
    path, frames, width, height = args[0], int(args[1]), int(args[2]), int(args[3])
    rest, msaa, dump = args[4:], True, None
    while rest:
        arg = rest.pop(0)
        if arg == "--no-msaa":
            msaa = False
        elif arg == "--dump" and rest:
            dump = rest.pop(0)
        else:
            sys.exit(__doc__)
    model = mujoco.MjModel.from_xml_path(path)
    if not msaa:
        model.vis.quality.offsamples = 0
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    renderer = mujoco.Renderer(model, height, width)

    pixels = None
    for _ in range(WARMUP_FRAMES):
        mujoco.mj_step(model, data)
        renderer.update_scene(data)
        pixels = renderer.render()
    seconds = cpu = 0.0
    for _ in range(frames):
        mujoco.mj_step(model, data)  # not timed
        cpu_start = time.process_time()  # the whole process, all threads
        start = time.perf_counter()
        renderer.update_scene(data)
        pixels = renderer.render()
        seconds += time.perf_counter() - start
        cpu += time.process_time() - cpu_start

    # the GL context class MUJOCO_GL chose: mujoco.egl (EGL's device platform), ...
    from mujoco.rendering.classic import gl_context  # pylint: disable=import-outside-toplevel
    backend = f"{gl_context.GLContext.__module__}, {gl_renderer()}"
    if dump:
        with open(dump, "wb") as out:
            out.write(pixels.tobytes())
    print(json.dumps({
        "model": path,
        "frames": frames,
        "width": width,
        "height": height,
        "seconds": seconds,
        "ms_per_frame": 1e3 * seconds / frames,
        "fps": frames / seconds,
        "cpu_ms_per_frame": 1e3 * cpu / frames,
        "backend": backend,
        "camera": "free (mjv_defaultFreeCamera)",
        "msaa": bool(model.vis.quality.offsamples),
        "mujoco": mujoco.mj_versionString(),
    }))
    renderer.close()


if __name__ == "__main__":
    main()
