#!/usr/bin/env bash
# Soak test of plumb bridge: realtime mode for SECONDS (default 600) with faults injected
# (command latency 2 ms + 1 ms jitter, 5 % of commands and of states dropped, noise on q, a
# 1 s controller pause every 100 s that trips the watchdog), driven by examples/pd_client
# holding the pendulum at 0.5 rad. Samples the bridge's RSS every 10 s (and the simulated
# time, when the flight log is already on disk), then counts the flight log's rows against
# the bridge's own summary and the wall time against the simulated time. Prints a report.
# Usage: bench/bridge_soak.sh [SECONDS] [BUILD]   (BUILD default build: plumb, pd_client)
set -euo pipefail
seconds="${1:-600}"
build="${2:-build}"
root="$(cd "$(dirname "$0")/.." && pwd)"
plumb="$build/plumb" client="$build/examples/pd_client/pd_client"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
domain=$(( 100 + RANDOM % 100 ))
{
  echo "family = \"go\""
  echo "mode = \"realtime\""
  echo "domain = $domain"
  echo "motors = [\"hinge\"]"
  echo "until = $seconds"
  echo "seed = 7"
  echo "log = \"$work/soak.csv\""
  echo "[watchdog]"
  echo "timeout_ms = 200"
  echo "[[faults]]"; echo "kind = \"latency\""; echo "direction = \"command\""
  echo "fixed_ms = 2"; echo "jitter_ms = 1"
  echo "[[faults]]"; echo "kind = \"drop\""; echo "direction = \"command\""; echo "probability = 0.05"
  echo "[[faults]]"; echo "kind = \"drop\""; echo "direction = \"state\""; echo "probability = 0.05"
  echo "[[faults]]"; echo "kind = \"noise\""; echo "signal = \"q\""; echo "sigma = 0.001"
  for ((t = 50; t < seconds; t += 100)); do
    echo "[[faults]]"; echo "kind = \"controller_pause\""; echo "start = $t"; echo "stop = $((t + 1))"
  done
} >"$work/soak.toml"
"$plumb" bridge "$root/models/pendulum.xml" --config "$work/soak.toml" \
  --set 'qpos[hinge]=0.7' >"$work/bridge.out" 2>"$work/bridge.err" &
bridge=$!
"$client" pendulum --domain "$domain" --target 0.5 --seconds "$seconds" >"$work/client.out" 2>&1 &
client_pid=$!
start=$(date +%s.%N)
echo "| wall s | simulated s | RSS kB |"
echo "|---|---|---|"
while kill -0 "$bridge" 2>/dev/null; do
  sleep 10
  rss=$(awk '/VmRSS/ {print $2}' "/proc/$bridge/status" 2>/dev/null || true)
  [[ -z "$rss" ]] && break
  sim=$( (tail -c 4096 "$work/soak.csv" 2>/dev/null || true) | awk -F, '$2 == "state" {t = $1} END {print (t == "" ? "-" : t)}')
  printf '| %.0f | %s | %s |\n' "$(echo "$(date +%s.%N) - $start" | awk '{print $1 - $3}')" "$sim" "$rss"
done
wait "$bridge" || echo "bridge exit $?"
wait "$client_pid" || echo "pd_client exit $?"
end=$(date +%s.%N)
cat "$work/bridge.out"
wall=$(awk -v a="$start" -v b="$end" 'BEGIN {print b - a}')
awk -F, -v wall="$wall" -v sec="$seconds" '
  $2 == "state" {states++} $2 == "command" {commands++} $2 == "event" {events++}
  END {printf "log rows: %d states, %d commands, %d events; %g s simulated in %.1f s wall (%.3f %%)\n",
       states, commands, events, sec, wall, 100 * (wall - sec) / sec}' "$work/soak.csv"
