#!/usr/bin/env bash
# `make build` without pages of make chatter: cmake --build's output goes to BUILD_DIR.build.log
# and only its progress is shown (one line per tenth, or none when nothing was out of date);
# a failure prints the log's errors and its last lines.
#   scripts/build.sh BUILD_DIR JOBS
set -uo pipefail
build_dir=$1
jobs=$2
log="$build_dir.build.log"
shown=-1
cmake --build "$build_dir" -j "$jobs" 2>&1 | tee "$log" | while IFS= read -r line; do
  # "[ 42%] Building CXX object ..." (a "Built target" line alone means nothing was rebuilt)
  if [[ "$line" =~ ^\[\ *([0-9]+)%\]\ (Building|Linking|Generating|lcm-gen) ]]; then
    tenth=$((BASH_REMATCH[1] / 10))
    if [ "$tenth" -gt "$shown" ]; then
      echo "saccade: building, ${BASH_REMATCH[1]}% (details in $log)" >&2
      shown=$tenth
    fi
  fi
done
status=${PIPESTATUS[0]}
if [ "$status" -ne 0 ]; then
  grep -E "error|Error" "$log" | head -30 >&2
  tail -15 "$log" >&2
  echo "saccade: the build failed (the whole log: $log)" >&2
fi
exit "$status"
