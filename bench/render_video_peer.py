"""The peer of `plumb render MODEL --until T --camera fixed -o OUT.mp4`: MuJoCo's own Python
mujoco.Renderer in the loop a user would write to make the same video. Load the model, offsamples
0 (plumb's default: no MSAA), one mujoco.Renderer, the first frame at t = 0, then one frame every
round(1 / (fps * timestep)) steps up to T, each frame piped as raw RGB to the same ffmpeg command
plumb runs (H.264, yuv420p, +faststart). The free camera mujoco.Renderer draws by default is the
picture plumb's `--camera fixed` draws (bench/render_peer.sh shows the frames byte-identical).

Usage: render_video_peer.py MODEL UNTIL FPS WIDTH HEIGHT OUT.mp4 [--shadow-size N]
Run with MUJOCO_GL=egl inside bench/render_video_peer.sh's throw-away virtual environment."""

import subprocess
import sys

import mujoco


def main():
    args = sys.argv[1:]
    if len(args) < 6:
        sys.exit(__doc__)
    path, until, fps = args[0], float(args[1]), float(args[2])
    width, height, out = int(args[3]), int(args[4]), args[5]
    shadow = None
    if args[6:8] and args[6] == "--shadow-size":
        shadow = int(args[7])
    model = mujoco.MjModel.from_xml_path(path)
    model.vis.quality.offsamples = 0
    if shadow:
        model.vis.quality.shadowsize = shadow
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    dt = model.opt.timestep
    stride = max(1, round(1.0 / (fps * dt)))
    steps = round(until / dt)
    rate = 1.0 / (stride * dt)
    renderer = mujoco.Renderer(model, height, width)
    ffmpeg = subprocess.Popen(
        ["ffmpeg", "-nostdin", "-hide_banner", "-loglevel", "error", "-y", "-f", "rawvideo",
         "-pix_fmt", "rgb24", "-s", f"{width}x{height}", "-r", f"{rate:.9g}", "-i", "pipe:0",
         "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt", "yuv420p",
         "-movflags", "+faststart", "-f", "mp4", out],
        stdin=subprocess.PIPE)
    frames = 0

    def frame():
        renderer.update_scene(data)
        ffmpeg.stdin.write(renderer.render().tobytes())

    frame()
    frames += 1
    for step in range(1, steps + 1):
        mujoco.mj_step(model, data)
        if step % stride == 0:
            frame()
            frames += 1
    ffmpeg.stdin.close()
    if ffmpeg.wait() != 0:
        sys.exit("ffmpeg failed")
    print(f"peer: wrote {out}: {frames} frames at {rate:.4g} fps")


if __name__ == "__main__":
    main()
