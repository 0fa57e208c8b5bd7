#!/usr/bin/env bash
# The README's first run (issue 40), its lines taken from the README and run as written, from a
# folder holding the build as `build`: the client's lines must be in the format the README
# shows, the target tracked, and the position within 5 cm of the truth's centre.
#   first_run_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
source_dir=$(cd "$2" && pwd)
work=$(mktemp -d)
trap 'kill %1 2>/dev/null || true; rm -rf "$work"' EXIT
fail() { echo "first run: $*" >&2; exit 1; }
sed -n '/<!-- first-run: begin/,/<!-- first-run: end/p' "$source_dir/README.md" |
  sed -e '/^<!--/d' -e '/^```/d' >"$work/steps.sh"
[ "$(grep -c . "$work/steps.sh")" -ge 4 ] || fail "the README's first-run block is gone"
ln -s "$build" "$work/build"
(cd "$work" && timeout 300 bash -e steps.sh) >"$work/out" 2>"$work/err" ||
  { cat "$work/err" "$work/out"; fail "a step failed"; }
cat "$work/out"
grep -q '^synthetic:target #0: NEW -> ' "$work/out" || fail "no NEW announcement"
lines=$(grep -cE '^synthetic:target #0 (RE-ACQUIRED|TRACKING) at \(-?[0-9.]+, -?[0-9.]+, -?[0-9.]+\) m in camera, confidence (0|1)\.[0-9]+$' "$work/out" || true)
[ "$lines" -eq 3 ] || fail "expected 3 instance lines, got $lines"
python3 - "$work/out" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
positions = [tuple(map(float, m)) for m in re.findall(r"at \((\S+), (\S+), (\S+)\) m", text)]
truth = tuple(map(float, text.strip().splitlines()[-1].split(",")))
for p in positions:
    d = sum((a - b) ** 2 for a, b in zip(p, truth)) ** 0.5
    assert d < 0.05, f"{p} is {d * 100:.1f} cm from the truth's centre {truth}"
print(f"first run: {len(positions)} positions within 5 cm of the truth's centre")
PY
grep -q "target within 2 cm" "$work/first-run/saccaded.log" || fail "$(cat "$work/first-run/saccaded.log")"
