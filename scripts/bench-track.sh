#!/usr/bin/env bash
# The tracking benchmark of docs/BENCHMARKS.md (issue 16): `saccade bench-track` on every
# sequence, at 30 Hz on this machine (a frame the tracker has no time for is dropped). The
# synthetic Kinect's sequences are scored within 1 cm and 2 degrees; the real-data sequences
# of configs/sequences (re-rendered mOSD captures, needs ../shared/data) within 2 cm and 5
# degrees. A sequence with others is run twice, its object alone and every object at once (the
# cost of tracking several). Prints one line per sequence, then one JSON object per sequence.
set -euo pipefail
build=${1:-build}
data=${SACCADE_DATA:-../shared/data}
config=${SACCADE_BENCH_CONFIG:-configs/saccaded.yaml}
export OMP_WAIT_POLICY=passive
json=$(mktemp)
trap 'rm -f "$json"' EXIT

run() {  # name, source, model, tolerance cm, tolerance degrees, further flags
  "$build/daemon/saccade" bench-track --name "$1" --source "$2" --model "$3" \
    --tolerance-cm "$4" --tolerance-deg "$5" --config "$config" "${@:6}" |
    { read -r line; echo "$line"; cat >> "$json"; }
}

# Synthetic: the demo (moves, hides behind a screen, comes back) and the presets.
run demo "synthetic:configs/demo-scenario.yaml?rate=0" synthetic:target 1 2
for preset in static linear circular occluded leave-return; do
  run "synthetic-$preset" "synthetic:$preset?rate=0" synthetic:target 1 2
done
# Real data, re-rendered: each sequence's models are its capture's labelled object and its
# others (every object it carries the truth of), tracked at once.
if [ -d "$data/mosd_xcap" ]; then
  for f in configs/sequences/*.yaml; do
    name=$(basename "$f" .yaml)
    models=$(./scripts/sequence-models.sh "$f" "$data")
    if [ "$models" != "capture:$f?data=$data" ]; then  # the same frames, one object tracked
      run "$name-one-tracked" "capture:$f?rate=0&data=$data" "capture:$f?data=$data" 2 5
    fi
    run "$name" "capture:$f?rate=0&data=$data" "$models" 2 5
  done
else
  echo "($data/mosd_xcap not found: the real-data sequences are skipped)"
fi
# Real data recorded by others (issue 36): ViSP's hand-held RealSense sequence of a cube, its
# truth from an AprilTag board, from a cold start. The model is the cube cut from the first
# frame as a user would (saccade segment, the cluster nearest the camera), in that frame's camera
# frame; and, beside it, the model made from the dataset's mesh (docs/MODELS.md says why that
# one is not found yet). The cube looks the same turned onto any face: --symmetry cube.
visp=$data/visp_rbt
if [ -d "$visp/frames" ]; then
  tmp=$(mktemp -d)
  trap 'rm -rf "$json" "$tmp"' EXIT
  "$build/daemon/saccade" record --source "depth:$visp/frames" --out "$tmp/first" --frames 1 \
    > /dev/null
  "$build/daemon/saccade" segment --scene "$tmp/first/frame_000000.pcd" --out "$tmp/cube-cut.pcd" \
    --z-max 0.8 --pick nearest > /dev/null
  "$build/daemon/saccade" model --mesh "$visp/models/cube.obj" --out "$tmp/cube-mesh.pcd" > /dev/null
  truth=(--truth "$visp/truth_cube.csv" --symmetry cube)
  run visp-cube-cut "depth:$visp/frames?rate=0" "$tmp/cube-cut.pcd" 2 5 "${truth[@]}" \
    --model-from-frame 0
  run visp-cube-mesh "depth:$visp/frames?rate=0" "$tmp/cube-mesh.pcd" 2 5 "${truth[@]}"
else
  echo "($visp not found: the ViSP cube is skipped)"
fi
cat "$json"
