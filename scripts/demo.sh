#!/usr/bin/env bash
# `make demo`: saccaded on the synthetic Kinect (configs/demo.yaml, its preview on) with
# `saccade view` beside it. Prints the address to open. When the scenario ends, an interactive
# run keeps the viewer up (with the last frame) until Enter or Ctrl-C; a scripted one stops it.
set -euo pipefail
build_dir=${1:-build}
port=${DEMO_PORT:-8080}
log=$(mktemp -t saccade-view.XXXXXX)
"$build_dir/daemon/saccade" view --port "$port" >"$log" 2>&1 &
viewer=$!
trap 'kill $viewer 2>/dev/null || true; wait $viewer 2>/dev/null || true; rm -f "$log"' EXIT
# Its first line says where it listens (or why it cannot: the demo runs on without it).
for _ in $(seq 100); do
  grep -q "open http" "$log" && break
  kill -0 $viewer 2>/dev/null || break
  sleep 0.1
done
if grep -q "open http" "$log"; then
  echo "saccade demo: the viewer is at $(grep -o 'http://[^ ]*' "$log" | head -1) (open it in a browser)"
else
  echo "saccade demo: no viewer: $(cat "$log") (DEMO_PORT=N picks another port)"
fi
"$build_dir/daemon/saccaded" --config configs/demo.yaml
if [ -t 0 ] && kill -0 $viewer 2>/dev/null; then
  read -r -p "saccade demo: the viewer keeps the last frame; Enter stops it. " _ || true
fi
