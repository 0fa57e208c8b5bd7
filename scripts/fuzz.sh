#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz with clang (AddressSanitizer and UBSan) and runs
# each for FUZZ_SECONDS (default 60) from its seed corpus. A crash stops with the input that
# made it (fuzz-out/<target>/crash-*): add it to tests/fuzz/corpus/<target>/ as a regression
# input once fixed. Needs Debian's clang-14 and libfuzzer-14-dev (installed when missing).
#
#   scripts/fuzz.sh [BUILD_DIR] [TARGET...]   build and run (all targets by default)
#   FUZZ_OUT=DIR                              where binaries, logs and grown corpora go
#   FUZZ_SECONDS=N                            each target's time
#   FUZZ_INSTALL=0                            never install clang (the short run in make test)
#   FUZZ_SEED=N                               libFuzzer's seed (the short run: 1, repeatable)
#   FUZZ_FRESH=1                              start from the seed corpus alone (the short run)
#   FUZZ_TIMEOUT=N                            seconds one input may take (default 10); libFuzzer
#                                             counts wall time, so raise it for a run at a low
#                                             priority beside other work
#
# The code under test is compiled here with coverage instrumentation; the rest of Saccade it
# needs comes from BUILD_DIR's libraries, linked as saccaded is (its link line), so a target
# can reach any loader without a second build of the project.
set -euo pipefail
build_dir=$(cd "${1:-build}" && pwd)
shift || true
seconds=${FUZZ_SECONDS:-60}
root=$(cd "$(dirname "$0")/.." && pwd)
out=${FUZZ_OUT:-$root/fuzz-out}
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(pcd command config image source)
for p in clang-14 libfuzzer-14-dev; do
  if [ "$(dpkg-query -W -f='${db:Status-Status}' "$p" 2>/dev/null || true)" != installed ]; then
    if [ "${FUZZ_INSTALL:-1}" = 0 ]; then
      echo "saccade fuzz: $p is not installed" >&2
      exit 77
    fi
    echo "saccade fuzz: installing $p" >&2
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$p" >/dev/null
  fi
done
flags_make="$build_dir/io/sources/CMakeFiles/saccade_sources.dir/flags.make"
link_txt="$build_dir/daemon/CMakeFiles/saccaded.dir/link.txt"
for f in "$flags_make" "$link_txt"; do
  [ -f "$f" ] || { echo "saccade fuzz: $f missing (build first: make build)" >&2; exit 1; }
done
# The project's definitions and include paths, and saccaded's libraries (not its objects,
# output or optimisation flags).
read -r -a defines <<<"$(sed -n 's/^CXX_DEFINES = //p' "$flags_make")"
read -r -a includes <<<"$(sed -n 's/^CXX_INCLUDES = //p' "$flags_make")"
read -r -a link <<<"$(cut -d' ' -f2- "$link_txt")"
libs=()
skip_next=0
for arg in "${link[@]}"; do
  if [ $skip_next = 1 ]; then skip_next=0; continue; fi
  case "$arg" in
    -o) skip_next=1 ;;
    *.o | -O* | -DNDEBUG | -g*) ;;
    *) libs+=("$arg") ;;
  esac
done
flags=(-std=c++17 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined
       "${defines[@]}" "${includes[@]}" -I"$build_dir/io/lcm/lcmtypes")
declare -A sources=(
  [pcd]="tests/fuzz/pcd_check_fuzz.cc io/formats/pcd_check.cc"
  [command]="tests/fuzz/command_fuzz.cc io/lcm/bus.cc io/base/log.cc io/lcm/fixation_log.cc
             io/lcm/detections_log.cc io/lcm/lcm_log.cc io/viewer/viewer.cc io/lcm/preview.cc
             attention/attention.cc core/foveation.cc daemon/attention_command.cc"
  [config]="tests/fuzz/config_fuzz.cc io/config/config.cc daemon/settings.cc io/formats/truth_file.cc
            io/formats/images.cc io/lcm/fixation_log.cc io/lcm/lcm_log.cc"
  [image]="tests/fuzz/image_fuzz.cc io/formats/images.cc"
  [source]="tests/fuzz/source_fuzz.cc io/sources/frame_source.cc"
)
# What uninstrumented libraries (OpenNI2's drivers) keep until exit is not ours to report.
export LSAN_OPTIONS="suppressions=$root/scripts/sanitizers/lsan.supp:print_suppressions=0"
launcher=$(command -v ccache || true)
mkdir -p "$out"
for target in "${targets[@]}"; do
  : > "$out/$target.build.log"
  [ -n "${sources[$target]:-}" ] || { echo "saccade fuzz: no target '$target'" >&2; exit 2; }
  echo "saccade fuzz: building $target" >&2
  # One object a source (through ccache when present, as the project's build), then linked
  # from saccaded's folder, where its link line's relative library paths hold.
  objects=()
  mkdir -p "$out/obj/$target"
  for s in ${sources[$target]}; do
    o="$out/obj/$target/$(basename "$s" .cc).o"
    $launcher clang++-14 "${flags[@]}" -c "$root/$s" -o "$o" 2>>"$out/$target.build.log" ||
      { cat "$out/$target.build.log" >&2; echo "saccade fuzz: $target did not build" >&2; exit 1; }
    objects+=("$o")
  done
  (cd "$build_dir/daemon" && clang++-14 "${flags[@]}" "${objects[@]}" "${libs[@]}" \
     -o "$out/$target-fuzz" 2>>"$out/$target.build.log") ||
    { cat "$out/$target.build.log" >&2; echo "saccade fuzz: $target did not link" >&2; exit 1; }
done
for target in "${targets[@]}"; do
  [ "${FUZZ_FRESH:-0}" = 1 ] && rm -rf "${out:?}/$target"
  mkdir -p "$out/$target"
  cp -n "$root/tests/fuzz/corpus/$target/"* "$out/$target/" 2>/dev/null || true
  echo "saccade fuzz: $target for $seconds s" >&2
  # The CPU time it had, beside the wall time it ran (a shared machine gives it less).
  (cd "$out" && TIMEFORMAT="cpu %U s user, %S s system" &&
     { time "./$target-fuzz" "$target" -max_total_time="$seconds" -max_len=4096 \
         -rss_limit_mb=2048 -timeout="${FUZZ_TIMEOUT:-10}" -seed="${FUZZ_SEED:-0}" \
         -print_final_stats=1 2>"$target.log"; } 2>"$target.cpu") ||
    { tail -30 "$out/$target.log"; echo "saccade fuzz: $target found a crash (above)" >&2; exit 1; }
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$out/$target.log" |
    sed "s/^/  $target: /"
  sed "s/^/  $target: /" "$out/$target.cpu"
done
echo "saccade fuzz: no crash in ${targets[*]}" >&2
