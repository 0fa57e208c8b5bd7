#!/usr/bin/env bash
# The four clients of docs/LCM.md (issue 19) against a live saccaded over real LCM: the C++,
# Python, Java and Lua examples each print the instances of 3 frames; every line must name the
# model (its short name), the track's id and state, a centroid in front of the camera and a
# confidence in [0, 1]; a track's first state is announced once (#N: NEW -> STATE) before its
# first line; and the four languages must decode the same place (within 1 cm of their mean).
# saccaded runs with signed commands (a key from saccade keygen): each language's send_command
# example sends one signed command, all four acted on, and one signed with another key is
# refused (saccaded's status counts them). Then the Python log reader must read what
# lcm-logger wrote as saccade detections does.
#   clients_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
source_dir=$(cd "$2" && pwd)
clients=$build/io/lcm/clients
work=$(mktemp -d)
url="udpm://239.255.76.67:$((7500 + $$ % 150))?ttl=0"  # not 7667, LCM's and saccaded's default
pids=()
trap 'for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; rm -rf "$work"' EXIT
fail() { echo "clients test: $*" >&2; exit 1; }

lcm-logger --lcm-url="$url" -f "$work/run.lcmlog" >"$work/logger.out" 2>&1 &
logger=$!
pids+=("$logger")
"$build/daemon/saccade" keygen --out "$work/command.key" >/dev/null
"$build/daemon/saccade" keygen --out "$work/other.key" >/dev/null
sed "s|commands: open|commands: signed\n  command_key: \"$work/command.key\"|" \
  "$source_dir/configs/demo.yaml" >"$work/signed.yaml"
grep -q "commands: signed" "$work/signed.yaml" || fail "demo.yaml no longer says commands: open"
"$build/daemon/saccaded" --config "$work/signed.yaml" \
  --source 'synthetic:static?rate=10&loop=1' --lcm-url "$url" >"$work/d.out" 2>"$work/d.err" &
pids+=("$!")

# Each waits for messages (a deadline, not a timing): 3 frames with an instance.
run() {
  local name=$1
  shift
  timeout 120 "$@" "$url" 3 >"$work/$name.out" 2>"$work/$name.err" ||
    { cat "$work/$name.err" "$work/d.err"; fail "$name client failed"; }
}
run cpp "$clients/saccade_print_instances"
python=$(command -v /usr/bin/python3 || command -v python3)  # Debian's, as a robot has it
run python env PYTHONPATH="$clients/python" "$python" "$clients/python/print_instances.py"
run java java -cp "/usr/share/java/lcm.jar:$clients/java/saccade-lcmtypes.jar:$clients/java" \
  PrintInstances
(cd "$clients/lua" && LUA_PATH="./?.lua;./?/init.lua;;" run lua lua5.2 print_instances.lua)

state='(NONE|TRACKING|LOST|SEARCHING|RE-ACQUIRED)'
line="^synthetic:target #-?[0-9]+ $state at \\((-?[0-9.]+), (-?[0-9.]+), (-?[0-9.]+)\\) m in camera, confidence ([0-9.]+)\$"
change="^synthetic:target #[0-9]+: (NEW|$state) -> $state\$"
for name in cpp python java lua; do
  grep -E "$change" "$work/$name.out" >"$work/$name.changes" || true
  grep -Ev "$change" "$work/$name.out" >"$work/$name.lines" || true
  [ "$(grep -c . "$work/$name.lines")" -ge 3 ] || fail "$name printed $(cat "$work/$name.out")"
  grep -Ev "$line" "$work/$name.lines" && fail "$name printed a line not in the format above"
  # The first line of each track comes after its announcement, and says the announced state.
  awk '/ -> / { split($2, id, ":"); told[id[1]] = $NF; next }
       $2 != "#-1" && !($2 in told) { print "no NEW -> line before: " $0; exit 1 }
       $2 != "#-1" && told[$2] != $3 { print "state " $3 " was not announced: " $0; exit 1 }' \
    "$work/$name.out" || fail "$name: a track state not announced"
  awk -v name="$name" '{ gsub(/[(),]/, " "); z = $7; c = $NF;
    if (z < 0.3 || z > 3 || c < 0 || c > 1) { print name ": " $0; exit 1 } }' \
    "$work/$name.lines" || fail "$name: a centroid or confidence out of range"
done
# The same place in every language: each client's mean centroid within 1 cm of the others'.
awk '{ gsub(/[(),]/, " "); n[FILENAME]++; x[FILENAME] += $5; y[FILENAME] += $6; z[FILENAME] += $7 }
     END { for (f in n) { mx[f] = x[f] / n[f]; my[f] = y[f] / n[f]; mz[f] = z[f] / n[f] }
           for (a in n) for (b in n) {
             d = sqrt((mx[a]-mx[b])^2 + (my[a]-my[b])^2 + (mz[a]-mz[b])^2)
             if (d > 0.01) { print a " and " b " differ by " d " m"; exit 1 } } }' \
  "$work"/cpp.lines "$work"/python.lines "$work"/java.lines "$work"/lua.lines ||
  fail "the languages decode different places"

# Signed commands from each language: four acted on; the one signed with another key refused.
send() {
  local name=$1
  shift
  timeout 60 "$@" >"$work/$name.send.out" 2>"$work/$name.send.err" ||
    { cat "$work/$name.send.err"; fail "$name send_command failed"; }
}
send cpp "$clients/saccade_send_command" "$url" "$work/command.key" pause
send python env PYTHONPATH="$clients/python" "$python" "$clients/python/send_command.py" \
  "$url" "$work/command.key" resume
send java java -cp "/usr/share/java/lcm.jar:$clients/java/saccade-lcmtypes.jar:$clients/java" \
  SendCommand "$url" "$work/command.key" fovea 0.1 0.1 1.0
(cd "$clients/lua" && LUA_PATH="./?.lua;./?/init.lua;;" send lua lua5.2 send_command.lua \
  "$url" "$work/command.key" reset)
send other env PYTHONPATH="$clients/python" "$python" "$clients/python/send_command.py" \
  "$url" "$work/other.key" pause
# saccaded's status says what it did with them (a deadline, not a timing).
PYTHONPATH="$clients/python" timeout 60 "$python" - "$url" <<'PY' ||
import sys
from saccade import status_t
from saccade_lcm import Receiver
for channel, data in Receiver(sys.argv[1]).messages({"SACCADE_STATUS"}):
    s = status_t.decode(data)
    if s.commands_accepted == 4 and s.commands_rejected == 1 and not s.paused:
        break
PY
  { cat "$work/d.err"; fail "saccaded did not count 4 signed commands accepted, 1 rejected"; }
grep -q "command rejected on SACCADE_COMMAND: a wrong signature" "$work/d.err" ||
  fail "the command signed with another key was not refused as such"

# The Python log reader against lcm-logger's file: as many instances as saccade detections.
kill -INT "$logger"
wait "$logger" || true
"$build/daemon/saccade" detections "$work/run.lcmlog" --out "$work/detections.csv" ||
  fail "saccade detections"
rows=$(($(wc -l <"$work/detections.csv") - 1))
instances=$(PYTHONPATH="$clients/python" "$python" - "$work/run.lcmlog" <<'PY'
import sys
from saccade import detections_t
from saccade_lcm import read_log
print(sum(detections_t.decode(data).num_instances
          for channel, data, _ in read_log(sys.argv[1]) if channel == "SACCADE_DETECTIONS"))
PY
)
[ "$rows" -gt 0 ] && [ "$instances" = "$rows" ] ||
  fail "Python read $instances instances from the log, saccade detections $rows"
echo "clients test: C++, Python, Java and Lua printed the same instances and sent signed" \
  "commands (4 accepted, 1 of another key refused); the log held $rows"
