#!/usr/bin/env bash
# `make test-asan`: the whole suite on the sanitized build (AddressSanitizer with LeakSanitizer,
# UndefinedBehaviorSanitizer). Any report fails the test that ran into it: ASan and UBSan stop
# the program (exit code 66 / abort), LeakSanitizer fails a program that leaked at exit. The
# programs the tests start (saccade, saccaded) inherit the options. Third-party libraries are
# not instrumented; scripts/sanitizers/lsan.supp lists what they keep until exit, by library.
set -euo pipefail
build_dir=${1:-build-asan}
root=$(cd "$(dirname "$0")/.." && pwd)
export ASAN_OPTIONS="detect_leaks=1:exitcode=66:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=0:check_initialization_order=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:exitcode=66"
export LSAN_OPTIONS="suppressions=$root/scripts/sanitizers/lsan.supp:print_suppressions=0"
export OMP_WAIT_POLICY=passive
start=$(date +%s)
status=0
(cd "$build_dir" && ctest --output-on-failure -j "${JOBS:-$(nproc)}") || status=$?
echo "saccade test-asan: the suite under ASan, LSan and UBSan took $(( $(date +%s) - start )) s" \
     "(exit $status)"
exit $status
