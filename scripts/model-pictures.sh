#!/usr/bin/env bash
# The pictures of docs/MODELS.md, one per way to make a model, all of the synthetic Kinect's
# target (data the project makes itself): a capture's cut, its mesh, and six captures around it.
#   scripts/model-pictures.sh BUILD_DIR OUT_DIR
set -euo pipefail
saccade="$1/daemon/saccade"
out=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
# The target alone on the table, 75 cm away, turned to `yaw` (radians): one frame.
capture() {
  printf 'preset: static\nname: %s\nframes: 1\nclutter: []\ntarget_motion:\n  kind: static\n  start_xz_m: [0.0, 0.75]\n  yaw_rad: %s\n' \
    "$1" "$2" > "$tmp/$1.yaml"
  "$saccade" record --source "synthetic:$tmp/$1.yaml" --out "$tmp/$1" --format pcd > /dev/null
}
captures=()
for i in 0 1 2 3 4 5; do
  capture "side$i" "$(awk -v i="$i" 'BEGIN { print 0.3 + i * 3.14159265 / 3 }')"
  captures+=("$tmp/side$i/frame_000000.pcd")
done
"$saccade" segment --scene "$tmp/side0/frame_000000.pcd" --out "$tmp/one-view.pcd" > /dev/null
"$saccade" model --show "$tmp/one-view.pcd" --render "$out/model-one-view.png"
"$saccade" model --synthetic target --out "$tmp/target.ply" > /dev/null
"$saccade" model --mesh "$tmp/target.ply" --out "$tmp/mesh.pcd" --render "$out/model-mesh.png"
"$saccade" model --captures "$(IFS=,; echo "${captures[*]}")" --out "$tmp/captures.pcd" \
  --render "$out/model-captures.png"
