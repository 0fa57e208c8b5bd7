#!/usr/bin/env bash
# The CPU peer beside Saccade's tracker (issue 36, docs/BENCHMARKS.md): ViSP's model-based
# tracker (vpMbGenericTracker, dense depth; Debian's libvisp-mbt-dev, installed here when
# missing: saccaded does not need it) on the ViSP cube's real frames, started at the truth's
# first pose, then `saccade bench-track` on the same frames from a cold start, both scored
# within 2 cm and 5 degrees against the same truth, the cube's turns onto itself as one. The
# synthetic sequences have no mesh the peer can read yet: not run.
set -euo pipefail
build=${1:-build}
data=${SACCADE_DATA:-../shared/data}
visp=$data/visp_rbt
./scripts/install-deps.sh libvisp-mbt-dev
cmake -S . -B "$build" > "$build.configure.log" 2>&1 || { cat "$build.configure.log"; exit 1; }
cmake --build "$build" --target saccade-visp-peer saccade -- -j"$(nproc)" > "$build.peer.log" 2>&1 ||
  { tail -20 "$build.peer.log"; exit 1; }
if [ ! -d "$visp/frames" ]; then
  echo "($visp not found: nothing to compare on)"
  exit 0
fi
export OMP_WAIT_POLICY=passive
truth=(--truth "$visp/truth_cube.csv" --symmetry cube --tolerance-cm 2 --tolerance-deg 5)
"$build/daemon/saccade-visp-peer" --name visp-cube --source "depth:$visp/frames?rate=0" \
  --mesh "$visp/models/cube.obj" "${truth[@]}" | grep -v '^>'
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$build/daemon/saccade" record --source "depth:$visp/frames" --out "$tmp/first" --frames 1 > /dev/null
"$build/daemon/saccade" segment --scene "$tmp/first/frame_000000.pcd" --out "$tmp/cube-cut.pcd" \
  --z-max 0.8 --pick nearest > /dev/null
"$build/daemon/saccade" bench-track --name visp-cube-cut --source "depth:$visp/frames?rate=0" \
  --model "$tmp/cube-cut.pcd" "${truth[@]}" --model-from-frame 0 --config configs/saccaded.yaml
