#!/usr/bin/env bash
# Lists what a command (a test run) created or changed outside the places tests may write, and
# fails when there is anything: nothing under / or the user's home is written by a test except
# plumb's own cache (issue 46: a crosscheck built a 542 MB environment at /). .ci/run runs
# `make test` and the other legs through it.
#
# Usage: scripts/list-created-files.sh [--root DIR]... [--allow PATH]... [--checkout DIR]
#            -- COMMAND [ARG...]
#   Runs COMMAND, then lists every file and folder on the local disks (find -xdev from each
#   mount of a disk file system, or from each DIR) whose contents or inode changed after COMMAND
#   started, except below:
#   - the checkout (this script's, or DIR), checked apart: COMMAND must leave no new untracked,
#     ignored or modified path in it outside the build folders /build*/, as
#     `git status --porcelain --ignored` shows,
#   - /tmp, $TMPDIR, /proc, /sys, /dev, /run (temporary and virtual),
#   - plumb's cache, ${PLUMB_CACHE:-${XDG_CACHE_HOME:-~/.cache}/plumb},
#   - the caches third-party tools keep whenever they run, and tests run them (below),
#   - each --allow PATH.
#   What is listed fails the check when it is where a misdirected write of plumb's lands: a new
#   entry directly in a root (the issue's /warp-99f1b8621d3c), the user's home, or the system's
#   folders (/usr, /etc, /opt, /srv, /root, /bin, /sbin, /lib*, /boot); with --root, anything in
#   those roots. Elsewhere (/var/log, a sibling of the checkout) other processes on the machine
#   write while the tests run: that is printed as a note, not a failure.
#   A folder that holds an allowed path is not listed (its time changes when that path is
#   made), so a file made and removed again directly in such a folder goes unseen.
# Exit codes: COMMAND's when it failed (the listing is printed too); else 1 when something was
# listed, 0 when nothing was; 2 bad usage.
set -euo pipefail
shopt -s inherit_errexit
here="$(cd "$(dirname "$0")/.." && pwd)" && [[ -n "$here" ]] || exit 2
roots=()
allowed=()
checkout="$here"
while [[ $# -gt 0 ]]; do
  case "$1" in
    --root) roots+=("$(realpath -m -- "${2:?--root takes a folder}")"); shift 2 ;;
    --allow) allowed+=("$(realpath -m -- "${2:?--allow takes a path}")"); shift 2 ;;
    --checkout) checkout="$(realpath -m -- "${2:?--checkout takes a folder}")"; shift 2 ;;
    --) shift; break ;;
    *) echo "list-created-files.sh: usage: list-created-files.sh [--root DIR] [--allow PATH]..." \
         "-- COMMAND [ARG...]" >&2; exit 2 ;;
  esac
done
if [[ $# -eq 0 ]]; then
  echo "list-created-files.sh: give the COMMAND to run after --" >&2
  exit 2
fi

cache="${XDG_CACHE_HOME:-$HOME/.cache}"
allowed+=(
  "$checkout" /tmp /proc /sys /dev /run
  "${PLUMB_CACHE:-$cache/plumb}"
  # pip keeps its downloads while the tests make their virtual environments (scripts/test-venv.sh:
  # Playwright, fastcrc, Unitree's SDK; the crosscheck engines')
  "$cache/pip"
  # MuJoCo Warp compiles its kernels once into ~/.cache/warp (WARP_CACHE_PATH), as it does for
  # every user of it: crosscheck_engine_test (label engines) runs Warp
  "$cache/warp"
  # Mesa keeps the shaders it compiled (the renderer's tests, and Chromium's in the browser test)
  "$cache/mesa_shader_cache" "$cache/mesa_shader_cache_db"
  # Chromium (the browser test) starts dconf, which keeps its user database here
  "$cache/dconf"
)
if [[ -n "${TMPDIR:-}" ]]; then allowed+=("$(realpath -m -- "$TMPDIR")"); fi
watched=()  # where a listed path fails the check (above); empty: everywhere in the roots
if [[ ${#roots[@]} -eq 0 ]]; then
  watched=("$(realpath -m -- "$HOME")" /usr /etc /opt /srv /root /bin /sbin /lib /lib32 /lib64
    /libx32 /boot)
  # every mounted disk file system (not /proc, tmpfs, cgroups, network or FUSE mounts)
  while read -r target fstype; do
    case "$fstype" in
      ext2|ext3|ext4|xfs|btrfs|overlay|zfs|f2fs|jfs|reiserfs) roots+=("$target") ;;
    esac
  done < <(findmnt -rn -o TARGET,FSTYPE)
  [[ ${#roots[@]} -gt 0 ]] || roots=(/)
fi

marker="$(mktemp "${TMPDIR:-/tmp}/plumb-created-files-XXXXXX")" && [[ -n "$marker" ]] || exit 2
trap 'rm -f "$marker"' EXIT
# the checkout's state: untracked, ignored (outside the build folders) and modified paths
checkout_state() {
  git -C "$checkout" status --porcelain --ignored | grep -v '^!! build[^/]*/$' | sort || true
}
is_git=false
if git -C "$checkout" rev-parse --git-dir >/dev/null 2>&1; then is_git=true; fi
checkout_before=""
if $is_git; then checkout_before="$(checkout_state)"; fi
sleep 1  # a file system may keep whole seconds: what COMMAND writes must be newer than marker

status=0
"$@" || status=$?

prune=()
for path in "${allowed[@]}"; do prune+=(-path "$path" -o); done
unset 'prune[${#prune[@]}-1]'
found="$(for root in "${roots[@]}"; do
  find "$root" -xdev \( "${prune[@]}" \) -prune -o \
    \( -newer "$marker" -o -cnewer "$marker" \) -printf '%y %p\n' 2>/dev/null || true
done | sort -u | awk -v allowed="$(printf '%s\n' "${allowed[@]}")" '
  BEGIN { n = split(allowed, list, "\n") }
  {
    path = substr($0, 3)
    if ($1 == "d") {  # a folder that holds an allowed path changes when that path is made
      prefix = (path == "/") ? "/" : (path "/")
      for (i = 1; i <= n; i++) {
        if (list[i] == path || index(list[i], prefix) == 1) next
      }
      path = path "/"
    }
    print path
  }')"

# split what was found into what fails (watched, or directly in a root) and notes
failing="" noted=""
while IFS= read -r path; do
  [[ -n "$path" ]] || continue
  fails=false
  if [[ ${#watched[@]} -eq 0 ]]; then fails=true; fi
  for root in "${roots[@]}"; do
    rest="${path#"${root%/}"/}"
    if [[ "$rest" != "$path" && "${rest%/}" != */* ]]; then fails=true; fi
  done
  for place in "${watched[@]}"; do
    if [[ "$path" == "$place" || "$path" == "$place/"* ]]; then fails=true; fi
  done
  if $fails; then failing+="$path"$'\n'; else noted+="$path"$'\n'; fi
done <<<"$found"
found="$failing"

checkout_new=""
if $is_git; then
  checkout_new="$(comm -13 <(printf '%s\n' "$checkout_before") <(checkout_state) || true)"
fi

if [[ -n "$found" ]]; then
  echo "list-created-files.sh: written outside the checkout, the temporary folders and the" \
    "allowed caches while '$*' ran (a test must write only below its temporary folder or" \
    "plumb's cache):" >&2
  printf '%s' "$found" | sed 's/^/  /' >&2
fi
if [[ -n "$noted" ]]; then
  echo "list-created-files.sh: note: changed while '$*' ran, in places other processes of the" \
    "machine write too (not a failure):" >&2
  printf '%s' "$noted" | sed 's/^/  /' >&2
fi
if [[ -n "$checkout_new" ]]; then
  echo "list-created-files.sh: left in the checkout $checkout by '$*' (git status; a test must" \
    "write below its temporary folder or the build folder):" >&2
  printf '%s\n' "$checkout_new" | sed 's/^/  /' >&2
fi
if [[ -z "$found" && -z "$checkout_new" ]]; then
  echo "list-created-files.sh: '$*' wrote nothing outside the checkout's build folders, the" \
    "temporary folders and plumb's cache" >&2
fi
if [[ $status -ne 0 ]]; then exit "$status"; fi
if [[ -n "$found" || -n "$checkout_new" ]]; then exit 1; fi
