#!/usr/bin/env bash
# MCAP logs (issue 40) read back by Foxglove's own readers (read_mcap.mjs: @mcap/core and
# @foxglove/rosmsg2-serialization; none of Saccade's code). saccaded runs the synthetic demo
# (120 frames) with Debian's lcm-logger listening and its own MCAP log on, rotated every 10 KB;
# then `saccade mcap` converts the lcm-logger log. Both must decode whole (0 failures), hold
# every message (the converted file one per logged message; saccaded's files every frame it
# processed), and say what the LCM messages said: stamps, frames, instances and positions
# (read from the LCM log by `saccade detections`).
#   mcap_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
source_dir=$(cd "$2" && pwd)
reader=$build/mcap-reader
[ -f "$reader/node_modules/@mcap/core/package.json" ] || { echo "no MCAP reader (npm)"; exit 77; }
work=$(mktemp -d)
url="udpm://239.255.76.67:$((7300 + $$ % 150))?ttl=0"
pids=()
trap 'for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; rm -rf "$work"' EXIT
fail() { echo "mcap test: $*" >&2; exit 1; }

lcm-logger --lcm-url="$url" -f "$work/run.lcmlog" >"$work/logger.out" 2>&1 &
logger=$!
pids+=("$logger")
{ cat "$source_dir/configs/demo.yaml"
  printf 'log:\n  mcap: "%s"\n  mcap_max_mb: 0.01\n' "$work/direct.mcap"
} >"$work/demo.yaml"
(cd "$source_dir" && "$build/daemon/saccaded" --config "$work/demo.yaml" --lcm-url "$url") \
  >"$work/d.out" 2>"$work/d.err" || { cat "$work/d.err"; fail "saccaded failed"; }
kill -INT "$logger"
wait "$logger" || true
ls "$work"/direct*.mcap.part 2>/dev/null && fail "a .part file was left"

"$build/daemon/saccade" mcap "$work/run.lcmlog" -o "$work/run.mcap" >"$work/mcap.out" ||
  fail "saccade mcap failed"
"$build/daemon/saccade" detections "$work/run.lcmlog" --out "$work/lcm.jsonl"
node "$reader/read_mcap.mjs" "$work/run.mcap" >"$work/run.json" || fail "the reader failed on run.mcap"
for f in "$work"/direct*.mcap; do
  node "$reader/read_mcap.mjs" "$f" >"$f.json" || fail "the reader failed on $f"
done

python3 - "$work" <<'PY'
import glob, json, re, sys
work = sys.argv[1]
lcm = [json.loads(l) for l in open(f"{work}/lcm.jsonl")]
def check(name, files, every_lcm_frame):
    detections, fixations, diagnostics, clouds = {}, 0, 0, 0
    for path in files:
        d = json.load(open(path))
        assert d["profile"] == "ros2", (path, d["profile"])
        assert d["failed"] == 0, f"{path}: {d['failed']} messages Foxglove's reader could not decode"
        assert d["message_count"] == len(d["messages"]), (path, d["message_count"], len(d["messages"]))
        for t, info in d["topics"].items():
            assert info["encoding"] == "cdr", (path, t, info)
        for m in d["messages"]:
            msg = m["message"]
            if m["topic"] == "/saccade/detections":
                s = msg["header"]["stamp"]
                detections[s["sec"] * 1000000 + s["nanosec"] // 1000] = msg
            elif m["topic"] == "/saccade/fixation":
                fixations += 1
            elif m["topic"] == "/saccade/foveated_cloud":
                clouds += 1
                assert msg["width"] > 100 and msg["point_step"] == 16, (path, msg["width"])
                assert [f["name"] for f in msg["fields"]] == ["x", "y", "z", "tag"], msg["fields"]
                assert 0.3 < sorted(msg["z"])[len(msg["z"]) // 2] < 5, "median depth"
            elif m["topic"] == "/diagnostics":
                diagnostics += 1
                assert msg["status"][0]["name"] == "saccaded", msg["status"]
    matched = instances = 0
    for frame in lcm:
        msg = detections.get(frame["utime"])
        if msg is None:
            continue
        matched += 1
        assert msg["header"]["frame_id"] == frame["frame"], msg["header"]
        seen = [i for i in frame["instances"] if i["track_state"] not in ("LOST", "SEARCHING")]
        assert len(msg["detections"]) == len(seen), (frame["seq"], msg, seen)
        for ros, i in zip(msg["detections"], seen):
            instances += 1
            r = ros["results"][0]
            assert r["hypothesis"]["class_id"] == "target", r["hypothesis"]
            # an instance no track took (id -1) has no id
            assert ros["id"] == (str(i["track_id"]) if i["track_id"] >= 0 else ""), (ros["id"], i)
            p = r["pose"]["pose"]["position"]
            for axis, v in zip("xyz", i["trans"]):
                assert abs(p[axis] - v) < 1e-6, (p, i["trans"])
            assert all(ros["bbox"]["size"][a] > 0.02 for a in "xyz"), ros["bbox"]
    if every_lcm_frame:
        assert matched == len(lcm) == len(detections), (name, matched, len(lcm), len(detections))
    else:
        assert matched == len(lcm), (name, matched, len(lcm))
    assert fixations == len(detections), (name, fixations, len(detections))
    assert instances >= 50 and diagnostics >= 2 and clouds >= 10, (name, instances, diagnostics, clouds)
    print(f"{name}: {len(detections)} frames, {instances} detections, {diagnostics} diagnostics, "
          f"{clouds} foveated clouds, {len(files)} file(s), every one decoded")
    return len(detections)
assert len(lcm) >= 100, f"lcm-logger caught {len(lcm)} frames"
check("saccade mcap", [f"{work}/run.json"], True)
direct = sorted(glob.glob(f"{work}/direct*.mcap.json"))
assert len(direct) >= 2, f"saccaded's log was not rotated: {direct}"
processed = int(re.search(r"run: (\d+) frames processed", open(f"{work}/d.err").read()).group(1))
frames = check("saccaded log.mcap", direct, False)
assert frames == processed, f"saccaded processed {processed} frames, its MCAP files hold {frames}"
PY
grep -q "^wrote .*: [0-9]* detections, [0-9]* fixations" "$work/mcap.out" || fail "$(cat "$work/mcap.out")"
echo "mcap test: passed"
