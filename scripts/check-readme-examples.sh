#!/usr/bin/env bash
# Runs the plumb command lines that README.md shows, to catch examples the CLI no longer accepts.
#
#   scripts/check-readme-examples.sh [PLUMB] [README]
#
# PLUMB is the plumb binary (default build/plumb), README the Markdown file (default README.md,
# or a page in docs/), both relative to the repository root; a page's commands name files
# relative to the root too. A command is a line inside a fenced code block that
# starts with "plumb " or, in a block showing a session, "$ build/plumb " (the lines after it
# are its output); lines ending in a backslash continue on the next one. In such a session the
# output shown is checked too: each shown line must be a line of the command's output (stdout
# and stderr, blanks collapsed), in order, though the README may leave lines out; a shown
# line ending in "..." must begin an output line, and "..." alone skips. Outputs are compared
# only when plumb runs the MuJoCo version README names for them (an HTML comment: "outputs
# shown after ... are MuJoCo X's"); across versions the last digits differ. Synopses
# ("plumb run MODEL [--set ...]") are not run; neither are commands naming a model or scenario
# that is not here (placeholders such as robot.xml or humanoid.xml): both are listed. The other
# commands run in order, each block in a temporary directory holding a copy of the folders of
# the files they name, so the repository is never written to. Exit 0 (ok) and 1 (a check
# failed) are fine; exit 2 (bad input) means the README is wrong, and any other code (crash,
# timeout) is reported too. The script exits 1 when any command failed.

set -u

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
plumb="${1:-$root/build/plumb}"
readme="${2:-$root/README.md}"
[[ "$plumb" = /* ]] || plumb="$root/$plumb"
[[ "$readme" = /* ]] || readme="$root/$readme"
if [[ ! -x "$plumb" ]]; then
  echo "check-readme-examples: no plumb binary at $plumb: build it first (make build)" >&2
  exit 2
fi
if [[ ! -f "$readme" ]]; then
  echo "check-readme-examples: no file $readme" >&2
  exit 2
fi
# the commands name files relative to the repository root (a page in docs/ too), as if run there
readme_dir="$(cd "$(dirname "$readme")" && pwd)"
case "$readme_dir/" in
  "$root"/*) readme_dir="$root" ;;
esac
per_command_timeout="${PLUMB_README_TIMEOUT:-300}"

# the commands, one per record: "block<TAB>line<TAB>command" (continuations joined)
extract() {
  awk '
    function flush_block(   i, prompts) {
      prompts = 0
      for (i = 1; i <= n; ++i) if (text[i] ~ /^\$ build\/plumb /) ++prompts
      for (i = 1; i <= n; ++i) {
        line = text[i]
        if (prompts > 0) {
          if (line !~ /^\$ build\/plumb /) continue
          sub(/^\$ build\//, "", line)
        } else if (line !~ /^plumb /) {
          continue
        }
        start = at[i]
        while (line ~ /\\$/ && i < n) {
          sub(/[ \t]*\\$/, "", line)
          next_line = text[++i]
          sub(/^[ \t]+/, "", next_line)
          line = line " " next_line
        }
        # in a session, the lines up to the next prompt are the output shown
        shown = ""
        while (prompts > 0 && i < n && text[i + 1] !~ /^\$ build\/plumb /) {
          shown = shown "\x1f" text[++i]
        }
        printf "%d\t%d\t%s\t%s\n", block, start, line, shown
      }
      n = 0
    }
    /^[ \t]*```/ {
      if (inside) flush_block()
      else ++block
      inside = !inside
      next
    }
    inside { text[++n] = $0; at[n] = NR }
  ' "$readme"
}

# The files a command reads that must exist: its .xml and .toml arguments, unquoted.
named_files() {
  local word
  for word in $1; do
    word="${word//\'/}"
    word="${word//\"/}"
    case "$word" in
      -*=*) word="${word#*=}" ;;
    esac
    case "$word" in
      *.xml | *.toml) echo "$word" ;;
    esac
  done
}

# the shown output is compared only where plumb runs the MuJoCo version it was made with
shown_version="$(grep -o -m1 'outputs shown after "\$ build/plumb" are MuJoCo [0-9.]*' "$readme" |
  grep -o '[0-9][0-9.]*[0-9]')"
running_version="$("$plumb" --version 2>/dev/null | head -n 1 | grep -o 'MuJoCo [0-9.]*' |
  grep -o '[0-9][0-9.]*[0-9]')"
compare_output=0
if [[ -n "$shown_version" && "$shown_version" == "$running_version" ]]; then
  compare_output=1
else
  echo "note  the outputs shown are MuJoCo ${shown_version:-?}'s, plumb runs ${running_version:-?}: not compared"
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
ran=0 failed=0 skipped=0
failures=()
current_block=""

# Whether the output in file $2 shows the lines in $1 (separated by \x1f), as the header says;
# prints the first shown line not found.
shows() {
  awk -v shown="$1" '
    function norm(s) { gsub(/[ \t]+/, " ", s); sub(/^ /, "", s); sub(/ $/, "", s); return s }
    { out[++n] = norm($0) }
    END {
      count = split(shown, want, "\x1f")
      at = 1
      for (k = 1; k <= count; ++k) {
        w = norm(want[k])
        if (w == "" || w == "...") continue
        prefix = w ~ /\.\.\.$/
        if (prefix) { sub(/ ?\.\.\.$/, "", w) }
        while (at <= n && !(prefix ? index(out[at], w) == 1 : out[at] == w)) ++at
        if (at > n) { print want[k]; exit 1 }
        ++at
      }
    }' "$2"
}

while IFS=$'\t' read -r block line command shown; do
  where="README.md:$line"
  [[ "$readme" = "$root/README.md" ]] || where="$(basename "$readme"):$line"
  # a synopsis: placeholders in capitals or options in brackets
  if [[ "$command" =~ \ [A-Z][A-Z]+( |$) || "$command" == *"[--"* ]]; then
    echo "skip  $where  synopsis: $command"
    skipped=$((skipped + 1))
    continue
  fi
  missing=""
  while read -r file; do
    [[ -z "$file" ]] && continue
    if [[ "$file" = /* ]]; then
      [[ -e "$file" ]] || missing+=" $file"
    elif [[ ! -e "$readme_dir/$file" ]]; then
      missing+=" $file"
    fi
  done < <(named_files "$command")
  if [[ -n "$missing" ]]; then
    echo "skip  $where  not here:$missing: $command"
    skipped=$((skipped + 1))
    continue
  fi
  # each block runs in a directory of its own, with copies of the folders its files are in
  if [[ "$block" != "$current_block" ]]; then
    current_block="$block"
    dir="$work/block$block"
    mkdir -p "$dir"
  fi
  while read -r file; do
    [[ -z "$file" || "$file" = /* ]] && continue
    folder="$(dirname "$file")"
    [[ -e "$dir/$folder/$(basename "$file")" ]] && continue
    (cd "$readme_dir" && cp -r --parents "$folder" "$dir/") 2>/dev/null ||
      cp "$readme_dir/$file" "$dir/"
  done < <(named_files "$command")
  log="$work/command$line.log"
  (cd "$dir" && PLUMB="$plumb" timeout "$per_command_timeout" bash -c \
    'plumb() { "$PLUMB" "$@"; }
'"$command" >"$log.out" 2>"$log")
  code=$?
  ran=$((ran + 1))
  cat "$log.out" "$log" >"$log.all"
  if [[ ($code -eq 0 || $code -eq 1) && -n "$shown" && $compare_output -eq 1 ]] &&
    ! missing_line="$(shows "$shown" "$log.all")"; then
    echo "FAIL  $where  the output shown is not what it prints: $command"
    echo "        shown:  $missing_line"
    echo "        printed (first lines):"
    sed 's/^/          /' "$log.all" | head -n 12
    failed=$((failed + 1))
    failures+=("$where")
  elif [[ $code -eq 0 || $code -eq 1 ]]; then
    echo "ok    $where  exit $code: $command"
  else
    case $code in
      2) why="bad input: the README is wrong" ;;
      124) why="timed out after ${per_command_timeout} s" ;;
      *) why="exit $code" ;;
    esac
    echo "FAIL  $where  exit $code ($why): $command"
    sed 's/^/        /' "$log" | head -n 8
    failed=$((failed + 1))
    failures+=("$where")
  fi
done < <(extract)

echo
echo "$ran run, $failed failed, $skipped skipped${failures[*]:+ (failed: ${failures[*]})}"
[[ $failed -eq 0 ]]
