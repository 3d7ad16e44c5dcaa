#!/usr/bin/env bash
# Writes each kind of report with the plumb binary and opens them all in Debian's Chromium
# (browser_check.py). Screenshots stay in OUT as test artifacts. A rehearsal's page (it needs
# DDS and a client to run) is written from a result made by hand by REHEARSAL_TEST, the
# rehearsal_output_test binary, when given.
#
# Usage: browser_test.sh PLUMB OUT [REHEARSAL_TEST]
set -euo pipefail
plumb="$1"
out="$2"
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
python="$("$root/scripts/test-venv.sh" "$(dirname "$out")/browser-venv")"
rm -rf "$out"
mkdir -p "$out"
m="$root/models/pendulum.xml"
humanoid=/usr/share/mujoco/model/humanoid/humanoid.xml
set -x
"$plumb" verify "$m" --set 'qpos[hinge]=0.7' --report "$out/verify.html" >/dev/null
# a foot made too light: findings that name a body, so thumbnails with it highlighted; audit
# exits 1 when a finding FAILs, and the report is what is tested here
"$plumb" audit "$humanoid" --set 'body_mass[left_foot]=1e-5' --report "$out/audit.html" >/dev/null || [[ $? -eq 1 ]]
"$plumb" converge "$m" --set 'qpos[hinge]=0.7' --metric 'qpos[hinge]@2' \
  --report "$out/converge.html" >/dev/null
"$plumb" sweep "$m" --set 'qpos[hinge]=0.7' --vary 'dof_damping[hinge]=0:1:6' \
  --vary 'opt.integrator=Euler,RK4' --metric 'qpos[hinge]@2' --metric energy_drift \
  --report "$out/sweep.html" >/dev/null
"$plumb" rollout "$m" --set 'qpos[hinge]=0.7' --count 200 --until 1 --seed 3 \
  --randomize 'dof_damping[hinge]=U(0,0.5)' --randomize 'body_mass[link]=*U(0.5,2)' \
  --metric 'qpos[hinge]@1' --metric energy_drift --report "$out/rollout.html" >/dev/null
# a "robot" with more damping than the model, replayed and fitted
"$plumb" run "$m" --set 'qpos[hinge]=0.7' --set 'dof_damping[hinge]=0.2' --format csv \
  --until 3 --every 0.01 -o "$out/decay.csv"
"$plumb" replay "$m" --log "$out/decay.csv" --report "$out/replay.html" >/dev/null
"$plumb" run "$m" --set 'qpos[hinge]=-0.4' --set 'dof_damping[hinge]=0.2' --format csv \
  --until 2 --every 0.01 -o "$out/held-out.csv"
"$plumb" identify "$m" --log "$out/decay.csv" --fit 'dof_damping[hinge]' \
  --validate "$out/held-out.csv" --report "$out/identify.html" >/dev/null
more=()
if [[ -n "${3:-}" ]]; then
  PLUMB_REHEARSAL_REPORT="$out/rehearse.html" "$3" \
    --gtest_filter='*ReportHasTheRowsChartsEventsAndTheClientsOutputAsText' >/dev/null
  more+=("$out/rehearse.html")
fi
set +x
PLUMB_EXPECT_THUMBNAILS=audit.html "$python" "$here/browser_check.py" "$out"/verify.html "$out"/audit.html "$out"/converge.html \
  "$out"/sweep.html "$out"/rollout.html "$out"/replay.html "$out"/identify.html "${more[@]}"
