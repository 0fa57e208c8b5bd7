#!/usr/bin/env bash
# The daemon's benchmark of docs/BENCHMARKS.md: saccaded against a 30 Hz VGA camera (each
# sequence's frames served by the virtual OpenNI2 device through the real libOpenNI2, looped),
# for SECONDS_PER_RUN seconds each; prints saccaded's run line (drops, latency percentiles).
# Every sequence of make bench-track: the demo with configs/demo.yaml (frames in flight 1 and
# 2), the synthetic presets and the real-data sequences (when ../shared/data is there) with
# configs/saccaded.yaml, every object a sequence carries tracked at once. The virtual device
# serves depth only, so colour takes no part in these runs' confidences.
set -euo pipefail
build=${1:-build}
seconds=${SECONDS_PER_RUN:-10}
data=${SACCADE_DATA:-../shared/data}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMP_WAIT_POLICY=passive

run() {  # name, source to record, base config, frames in flight, models (comma-separated)
  local name=$1 source=$2 config=$3 in_flight=$4 models=$5
  rm -rf "$work/frames"
  "$build/daemon/saccade" record --source "$source" --out "$work/frames" --format depth >/dev/null
  # The config without its source (a line or a section) and its models: the run's are given.
  { awk '/^(source|model):/ { skip = 1; next } skip && /^([ #-]|$)/ { next } { skip = 0 } 1' "$config" |
      sed -e 's/summary: line/summary: off/' -e "s/^  frames_in_flight: [0-9]*/  frames_in_flight: $in_flight/"
    printf 'model: ["%s"]\n' "${models//,/\", \"}"
    grep -q '^pipeline:' "$config" || printf 'pipeline:\n  frames_in_flight: %s\n' "$in_flight"
  } > "$work/bench.yaml"
  printf '%-32s frames in flight %s: ' "$name" "$in_flight"
  # timeout's SIGINT is the normal end of a run: saccaded finishes its frames and reports.
  { SACCADE_VIRTUAL_DEVICE="$work/frames" SACCADE_VIRTUAL_DEVICE_FPS=30 \
      LD_LIBRARY_PATH="$build/io/sources/openni2/runtime" \
      timeout -s INT "$seconds" "$build/daemon/saccaded" --config "$work/bench.yaml" \
      --source openni2:// --lcm-url "udpm://239.255.76.67:7667?ttl=0" 2>&1 || true; } |
    sed -n 's/^saccaded: info: run: //p'
}

./scripts/multicast-route.sh
for in_flight in 1 2; do
  run "demo (moves, hides; demo.yaml)" "synthetic:configs/demo-scenario.yaml" configs/demo.yaml \
    "$in_flight" synthetic:target
done
for preset in static linear circular occluded leave-return; do
  run "synthetic-$preset" "synthetic:$preset" configs/saccaded.yaml 1 synthetic:target
done
if [ -d "$data/mosd_xcap" ]; then
  for f in configs/sequences/*.yaml; do
    models=$(./scripts/sequence-models.sh "$f" "$data")
    run "$(basename "$f" .yaml) (real)" "capture:$f?data=$data" configs/saccaded.yaml 1 "$models"
  done
else
  echo "($data/mosd_xcap not found: the real-data sequences are skipped)"
fi
