#!/usr/bin/env bash
# The benchmark of docs/BENCHMARKS.md: plain gold standard vs foveated on the real milk scene.
set -euo pipefail
build=${1:-build}
data=${SACCADE_DATA_DIR:-$(dirname "$0")/../../shared/data}
if [ ! -d "$data/pcl_test" ]; then
  echo "bench: real data not found at $data (set SACCADE_DATA_DIR)" >&2
  exit 1
fi
export OMP_WAIT_POLICY=passive
"$build/daemon/saccade" bench \
  --model "$data/pcl_data/correspondence_grouping/milk.pcd" \
  --scene "$data/pcl_test/milk_cartoon_all_small_clorox.pcd" \
  --truth "$data/pcl_data/correspondence_grouping/milk_pose_in_scene.txt" \
  --fovea -0.056,-0.127,0.776 --frames "${FRAMES:-10}"
# Publishing a frame of three objects: LCM alone, and LCM with the ROS 2 mirror (saccaded --ros2).
if [ -x "$build/tests/bench/saccade_publish_bench" ]; then
  echo "publishing a frame of three objects (LCM; LCM and ROS 2):"
  "$build/tests/bench/saccade_publish_bench" --benchmark_repetitions=5 \
    --benchmark_report_aggregates_only=true 2>&1 | grep -E '_(median|mean) '
fi
