#!/usr/bin/env bash
# The daemon's benchmark of docs/BENCHMARKS.md: saccaded against a 30 Hz VGA camera (the
# synthetic Kinect's frames served by the virtual OpenNI2 device through the real libOpenNI2),
# for SECONDS per setting; prints saccaded's run line (drops, latency percentiles) for each.
set -euo pipefail
build=${1:-build}
seconds=${SECONDS_PER_RUN:-20}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMP_WAIT_POLICY=passive

run() {  # name, scenario spec, frames in flight
  local name=$1 scenario=$2 in_flight=$3
  rm -rf "$work/frames"
  "$build/daemon/saccade" record --source "$scenario" --out "$work/frames" --format depth >/dev/null
  { grep -v '^source:' configs/demo.yaml | sed 's/summary: line/summary: off/'
    printf 'pipeline:\n  frames_in_flight: %s\n' "$in_flight"; } > "$work/bench.yaml"
  printf '%-34s frames in flight %s: ' "$name" "$in_flight"
  # timeout's SIGINT is the normal end of a run: saccaded finishes its frames and reports.
  { SACCADE_VIRTUAL_DEVICE="$work/frames" SACCADE_VIRTUAL_DEVICE_FPS=30 \
      LD_LIBRARY_PATH="$build/io/openni2/runtime" \
      timeout -s INT "$seconds" "$build/daemon/saccaded" --config "$work/bench.yaml" \
      --source openni2:// --lcm-url "udpm://239.255.76.67:7667?ttl=0" 2>&1 || true; } |
    sed -n 's/^saccaded: info: run: //p'
}

./scripts/multicast-route.sh
for in_flight in 1 2; do
  run "tracking (static, 30 frames)" "synthetic:static?frames=30" "$in_flight"
  run "moving + occlusion (demo, 120)" "synthetic:configs/demo-scenario.yaml" "$in_flight"
done
