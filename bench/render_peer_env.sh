# Sourced by bench/render_peer.sh and bench/render_video_peer.sh (with $plumb set): a
# throw-away folder $work, removed on exit, holding a virtual environment for the peer,
# mujoco-core at plumb's MuJoCo version and PyOpenGL (mujoco.egl needs it); MUJOCO_GL=egl.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 -m venv "$work/venv"
version=$("$plumb" --version | awk '/compiled/ {print $NF; exit}')
"$work/venv/bin/pip" install --quiet "mujoco-core==$version" pyopengl
export MUJOCO_GL=egl
