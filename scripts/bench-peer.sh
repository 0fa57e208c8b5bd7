#!/usr/bin/env bash
# The CPU peer beside Saccade's tracker (issue 36, docs/BENCHMARKS.md): ViSP's model-based
# tracker (vpMbGenericTracker, dense depth; Debian's libvisp-mbt-dev, installed here when
# missing: saccaded does not need it) on the ViSP cube's real frames, started at the truth's
# first pose, then `saccade bench-track` on the same frames from a cold start (with a model cut
# from the first frame, and with the peer's own mesh), all scored within 2 cm and 5 degrees
# against the same truth, the cube's turns onto itself as one. Then
# the synthetic Kinect's sequences: the peer with the target's mesh (`saccade model
# --synthetic target`) from the truth's first pose, Saccade from a cold start, both within 1 cm
# and 2 degrees of the generator's truth.
set -euo pipefail
build=${1:-build}
data=${SACCADE_DATA:-../shared/data}
visp=$data/visp_rbt
./scripts/install-deps.sh libvisp-mbt-dev
cmake -S . -B "$build" > "$build.configure.log" 2>&1 || { cat "$build.configure.log"; exit 1; }
cmake --build "$build" --target saccade-visp-peer saccade -- -j"$(nproc)" > "$build.peer.log" 2>&1 ||
  { tail -20 "$build.peer.log"; exit 1; }
export OMP_WAIT_POLICY=passive
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# The synthetic sequences. The generator's truth (saccade record's truth.csv: translation and
# quaternion w x y z) as the frame,T00..T33 table both trackers are scored against.
"$build/daemon/saccade" model --synthetic target --out "$tmp/target.ply" > /dev/null
synthetic() {  # name, source
  rm -rf "$tmp/rec"
  "$build/daemon/saccade" record --source "$2" --out "$tmp/rec" --format depth > /dev/null
  awk -F, 'NR == 1 { print "frame,T00,T01,T02,T03,T10,T11,T12,T13,T20,T21,T22,T23,T30,T31,T32,T33" }
    NR > 1 { w = $6; x = $7; y = $8; z = $9
      printf "%d,%.7f,%.7f,%.7f,%.7f,%.7f,%.7f,%.7f,%.7f,%.7f,%.7f,%.7f,%.7f,0,0,0,1\n", $1,
        1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y), $3,
        2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x), $4,
        2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y), $5 }' \
    "$tmp/rec/truth.csv" > "$tmp/truth.csv"
  local scored=(--truth "$tmp/truth.csv" --tolerance-cm 1 --tolerance-deg 2)
  "$build/daemon/saccade-visp-peer" --name "$1" --source "$2" --mesh "$tmp/target.ply" \
    "${scored[@]}" | grep -v '^>'
  "$build/daemon/saccade" bench-track --name "$1" --source "$2" --model synthetic:target \
    "${scored[@]}" --config configs/saccaded.yaml
}
synthetic demo "synthetic:configs/demo-scenario.yaml?rate=0"
# Not leave-return: once its target has left the view the peer spends minutes on each frame
# with nothing of it (more than ten minutes for the sequence, by hand).
for preset in static linear circular occluded; do
  synthetic "synthetic-$preset" "synthetic:$preset?rate=0"
done

if [ ! -d "$visp/frames" ]; then
  echo "($visp not found: the real cube is skipped)"
  exit 0
fi
truth=(--truth "$visp/truth_cube.csv" --symmetry cube --tolerance-cm 2 --tolerance-deg 5)
"$build/daemon/saccade-visp-peer" --name visp-cube --source "depth:$visp/frames?rate=0" \
  --mesh "$visp/models/cube.obj" "${truth[@]}" | grep -v '^>'
"$build/daemon/saccade" record --source "depth:$visp/frames" --out "$tmp/first" --frames 1 > /dev/null
"$build/daemon/saccade" segment --scene "$tmp/first/frame_000000.pcd" --out "$tmp/cube-cut.pcd" \
  --z-max 0.8 --pick nearest > /dev/null
"$build/daemon/saccade" bench-track --name visp-cube-cut --source "depth:$visp/frames?rate=0" \
  --model "$tmp/cube-cut.pcd" "${truth[@]}" --model-from-frame 0 --config configs/saccaded.yaml
# The same mesh as the peer's: Saccade's model of it (saccade model --mesh), from a cold start.
"$build/daemon/saccade" model --mesh "$visp/models/cube.obj" --out "$tmp/cube-mesh.pcd" > /dev/null
"$build/daemon/saccade" bench-track --name visp-cube-mesh --source "depth:$visp/frames?rate=0" \
  --model "$tmp/cube-mesh.pcd" "${truth[@]}" --config configs/saccaded.yaml
