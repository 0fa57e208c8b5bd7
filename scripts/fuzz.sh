#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz with clang (AddressSanitizer and UBSan) and runs
# each for FUZZ_SECONDS (default 60) from its seed corpus. A crash stops with the input that
# made it (fuzz-out/<target>/crash-*): add it to tests/fuzz/corpus/<target>/ as a regression
# input once fixed. Needs Debian's clang-14 and libfuzzer-14-dev (installed when missing).
set -euo pipefail
build_dir=${1:-build}
seconds=${FUZZ_SECONDS:-60}
root=$(cd "$(dirname "$0")/.." && pwd)
out="$root/fuzz-out"
for p in clang-14 libfuzzer-14-dev; do
  if [ "$(dpkg-query -W -f='${db:Status-Status}' "$p" 2>/dev/null || true)" != installed ]; then
    echo "saccade fuzz: installing $p" >&2
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$p" >/dev/null
  fi
done
flags=(-std=c++17 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined
       -DEIGEN_HAS_CXX17_OVERALIGN=0 -I"$root" -I"$root/$build_dir/io/lcmtypes"
       -I/usr/include/pcl-1.13 -I/usr/include/eigen3)
mkdir -p "$out"
declare -A sources=(
  [pcd]="$root/tests/fuzz/pcd_check_fuzz.cc $root/io/pcd_check.cc -lpcl_io -lpcl_common"
  [command]="$root/tests/fuzz/command_fuzz.cc $root/io/bus.cc $root/io/log.cc $root/core/fixation.cc -llcm -lpcl_common -lpthread"
)
for target in pcd command; do
  echo "saccade fuzz: building $target" >&2
  # shellcheck disable=SC2086
  clang++-14 "${flags[@]}" ${sources[$target]} -o "$out/$target-fuzz"
  mkdir -p "$out/$target"
  cp -n "$root/tests/fuzz/corpus/$target/"* "$out/$target/" 2>/dev/null || true
  echo "saccade fuzz: $target for $seconds s" >&2
  (cd "$out" && "./$target-fuzz" "$target" -max_total_time="$seconds" -max_len=4096 \
     -rss_limit_mb=2048 -print_final_stats=1 2>"$target.log") ||
    { tail -30 "$out/$target.log"; echo "saccade fuzz: $target found a crash (above)" >&2; exit 1; }
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$out/$target.log" | sed "s/^/  $target: /"
done
echo "saccade fuzz: no crash" >&2
