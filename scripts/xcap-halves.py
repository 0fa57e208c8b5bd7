#!/usr/bin/env python3
"""Cross-validation across objects of a cross-capture run (saccade eval --cases ... --out DIR).

Usage: scripts/xcap-halves.py DIR/cases.csv

The identities are split in two halves by the same seeded shuffle as scripts/fit-confidence.py
(sorted, random.Random(1)). For every configuration and protocol it prints recall of the
feasible cases (protocol c: acquired within 10 frames) and false figures (a, b: false instances
a case; c: cases that locked onto a false instance first) on each half and on all, with 95%
Wilson intervals; then, per protocol, the configuration each half would choose (recall minus
false per case) and how it does on the other half. Plain Python: Debian ships no numpy by
default.
"""
import csv
import math
import random
import sys

ACQUIRE_FRAMES = 10


def wilson(k, n, z=1.96):
    if n == 0:
        return (0.0, 0.0)
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return (max(0.0, c - h), min(1.0, c + h))


def rate(k, n):
    lo, hi = wilson(k, n)
    pct = 100 * k / n if n else 0
    return f"{k}/{n} ({pct:.0f}%, CI {100 * lo:.0f}-{100 * hi:.0f}%)"


def figures(rows):
    feasible = [r for r in rows if r["feasible"] == "1"]
    if rows and rows[0]["protocol"] == "c":
        found = sum(1 for r in feasible if 0 < int(r["acquire_frames"] or 0) <= ACQUIRE_FRAMES)
        false = sum(1 for r in rows if int(r["acquire_false"] or 0) > 0)
    else:
        found = sum(1 for r in feasible if r["found"] == "1")
        false = sum(int(r["false_instances"]) for r in rows)
    return found, len(feasible), false, len(rows)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    rows = list(csv.DictReader(open(sys.argv[1])))
    if not rows:
        sys.exit(f"{sys.argv[1]}: no cases")
    ids = sorted({r["identity"] for r in rows})
    random.Random(1).shuffle(ids)
    half_a = set(ids[: len(ids) // 2])
    halves = {
        "A": lambda r: r["identity"] in half_a,
        "B": lambda r: r["identity"] not in half_a,
        "all": lambda r: True,
    }
    keys = []
    for r in rows:
        k = (r["configuration"], r["protocol"])
        if k not in keys:
            keys.append(k)
    print(f"halves: A = {len(half_a)} identities, B = {len(ids) - len(half_a)}")
    print("| configuration | protocol | half A | half B | all |")
    print("|---|---|---|---|---|")
    score = {}
    for config, protocol in keys:
        cells = []
        for name, inside in halves.items():
            sub = [r for r in rows if r["configuration"] == config and r["protocol"] == protocol
                   and inside(r)]
            found, feasible, false, cases = figures(sub)
            what = "locked false first" if protocol == "c" else "false/case"
            false_text = (f"{false}/{cases} {what}" if protocol == "c"
                          else f"{false / max(1, cases):.3f} {what}")
            cells.append(f"{rate(found, feasible)}, {false_text}")
            score[(config, protocol, name)] = (found / max(1, feasible) - false / max(1, cases),
                                               found, feasible)
        print(f"| {config} | {protocol} | " + " | ".join(cells) + " |")
    print()
    for protocol in sorted({p for _, p in keys}):
        configs = [c for c, p in keys if p == protocol]
        for chosen_on, other in (("A", "B"), ("B", "A")):
            best = max(configs, key=lambda c: score[(c, protocol, chosen_on)][0])
            _, f, n = score[(best, protocol, other)]
            _, fa, na = score[(best, protocol, "all")]
            print(f"protocol {protocol}: chosen on half {chosen_on}: {best}; on half {other} "
                  f"{rate(f, n)}; all {rate(fa, na)}")


if __name__ == "__main__":
    main()
