#!/bin/sh
# The library speaks its own API: no command-line flag ("--set", "--until", ...) in a string
# of src/. Errors name the argument (plumb::ArgumentError); the command-line tool adds the flag.
# A line ending in "// argv" (a program's arguments) or "// command" (a whole command line to
# run, e.g. `plumb crosscheck --setup`) is not a message about an argument.
# Usage: no_flags_in_library.sh SOURCE_DIR
found=$(grep -rn --include='*.cc' --include='*.h' -e '"[^"]*--[a-z]' "$1/src" |
  grep -v '^[^:]*:[0-9]*: *//' | grep -v -e '// argv$' -e '// command$')
if [ -n "$found" ]; then
  echo "command-line flags in library strings (name the argument instead: ArgumentError):"
  echo "$found"
  exit 1
fi
echo "no flag in the library's strings"
