#!/usr/bin/env bash
# `make soak MINUTES=N`: saccaded under AddressSanitizer and LeakSanitizer on a looping real
# capture (configs/sequences/object-moving.yaml: a coffee can sliding across a real mOSD
# capture, 30 Hz, needs ../shared/data) for N minutes. Samples the daemon's resident memory
# every SAMPLE_S seconds into soak-out/memory.csv, fits a line to the samples after the first
# quarter (ASan's quarantine and the caches fill first), prints the slope per hour and per
# frame processed and what it would add over a day-equivalent (2.6 M frames, a day at the
# source's 30 Hz: the daemon under ASan processes fewer a second, so the slope is taken per
# frame), then stops the daemon with SIGTERM and fails on any leak LSan reports at exit.
#
#   scripts/soak.sh [BUILD_DIR]   build-asan by default; a plain build soaks the daemon as
#                                 shipped (no leak check at exit, many more frames an hour)
#   MINUTES=N  SAMPLE_S=S         how long, and how often memory is sampled
#   SOAK_RATE=HZ                  the looping source's rate (30; 0: as fast as the daemon takes
#                                 them, every frame processed)
#   SOAK_OUT=DIR                  where the samples and the log go (soak-out)
#   SOAK_LCM_URL=URL              where it publishes (LCM's default URL)
set -euo pipefail
build_dir=${1:-build-asan}
minutes=${MINUTES:-10}
sample_s=${SAMPLE_S:-10}
data=${SACCADE_DATA:-../shared/data}
root=$(cd "$(dirname "$0")/.." && pwd)
build_dir=$(cd "$build_dir" && pwd)
cd "$root"  # the sequence's path and ../shared/data are the project root's
out=${SOAK_OUT:-$root/soak-out}
rate=${SOAK_RATE:-30}
if grep -q "^SACCADE_SANITIZE:BOOL=ON$" "$build_dir/CMakeCache.txt" 2>/dev/null; then
  under="under ASan"
else
  under="not sanitized"
fi
sequence="configs/sequences/object-moving.yaml"
if [ ! -d "$data/mosd_xcap" ]; then
  echo "saccade soak: $data/mosd_xcap not found (the soak runs on real data; see ../shared/data/README.md)" >&2
  exit 1
fi
mkdir -p "$out"
cat > "$out/soak.yaml" <<YAML
source: "capture:$sequence?loop=1&rate=$rate&data=$data"
model: "capture:$sequence?data=$data"
initial_fovea_m: [0.0, 0.0, 1.0]
service: {status_period_s: 10, summary: line}
YAML
export ASAN_OPTIONS="detect_leaks=1:exitcode=66:quarantine_size_mb=16"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:exitcode=66"
export LSAN_OPTIONS="suppressions=$root/scripts/sanitizers/lsan.supp:print_suppressions=0"
export OMP_WAIT_POLICY=passive
"$build_dir/daemon/saccaded" --config "$out/soak.yaml" --lcm-url "${SOAK_LCM_URL:-udpm://239.255.76.67:7667?ttl=0}" \
  >"$out/saccaded.log" 2>&1 &
pid=$!
trap 'kill -TERM $pid 2>/dev/null || true' EXIT
pace="at ${rate} Hz"
[ "$rate" = 0 ] && pace="as fast as it takes the frames"
echo "saccade soak: saccaded ($under, pid $pid) on $sequence looping $pace for $minutes min;" \
     "memory every $sample_s s in $out/memory.csv" >&2
echo "seconds,rss_kb" > "$out/memory.csv"
start=$(date +%s)
end=$((start + minutes * 60))
while [ "$(date +%s)" -lt "$end" ]; do
  rss=$(awk '/^VmRSS:/ {print $2}' "/proc/$pid/status" 2>/dev/null) ||
    { echo "saccade soak: saccaded ended early:" >&2; tail -20 "$out/saccaded.log" >&2; exit 1; }
  [ -n "$rss" ] && echo "$(( $(date +%s) - start )),$rss" >> "$out/memory.csv"
  sleep "$sample_s"
done
kill -TERM "$pid"
trap - EXIT
status=0
wait "$pid" || status=$?
# Frames processed: saccaded's run line at exit ("run: N frames processed in S s").
frames=$(sed -n 's/.*run: \([0-9]*\) frames processed in \([0-9.]*\) s.*/\1/p' "$out/saccaded.log" | tail -1)
awk -F, -v minutes="$minutes" -v frames="${frames:-0}" -v under="$under" '
  NR == 1 { next }
  { t[n] = $1; m[n] = $2 / 1024; n++ }
  END {
    if (n < 4) { print "saccade soak: too few samples"; exit 1 }
    first = int(n / 4)
    for (i = first; i < n; i++) { k++; st += t[i]; sm += m[i]; stt += t[i] * t[i]; stm += t[i] * m[i] }
    slope = (k * stm - st * sm) / (k * stt - st * st)          # MB per second
    printf "saccade soak: %d min, RSS %.1f MB at %d s, %.1f MB at the end (%d s); fit from %d s: %+.2f MB/hour\n", minutes, m[first], t[first], m[n-1], t[n-1], t[first], slope * 3600
    if (frames > 0) {
      fps = frames / t[n-1]
      printf "saccade soak: %d frames processed (%.1f a second, %s): %+.4f MB a thousand frames, %+.1f MB over a day-equivalent (2.6 M frames)\n", frames, fps, under, slope / fps * 1000, slope / fps * 2.6e6
    }
  }' "$out/memory.csv"
if grep -q "LeakSanitizer" "$out/saccaded.log"; then
  grep -A30 "LeakSanitizer" "$out/saccaded.log" | head -60 >&2
  echo "saccade soak: LeakSanitizer reported leaks (above, whole log in $out/saccaded.log)" >&2
  exit 1
fi
if [ "$status" -ne 0 ]; then
  tail -20 "$out/saccaded.log" >&2
  echo "saccade soak: saccaded exited $status after SIGTERM" >&2
  exit 1
fi
if [ "$under" = "under ASan" ]; then
  echo "saccade soak: no leak reported at exit, no sanitizer report" >&2
else
  echo "saccade soak: ended cleanly on SIGTERM (not sanitized: leaks are checked only under ASan)" >&2
fi
