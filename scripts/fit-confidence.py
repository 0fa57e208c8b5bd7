#!/usr/bin/env python3
"""Fits the confidence of core/verification.cc (InstanceConfidence) from an eval's instances.csv.

Run the cross-capture benchmark with a configuration that keeps every verified instance
(`verify_min_confidence: 0`, e.g. `saccade-ungated` of configs/xcap-configs.yaml), then:

    scripts/fit-confidence.py eval-xcap/instances.csv saccade-ungated [--no-colour] [--texture]

It prints the logistic weights over (1, ln votes, fitness, coverage, [colour agreement],
[texture agreement, with --texture], relative fit) fitted on every case, and, to show they hold on objects they were not fitted
on, the counts at each threshold when each half of the identities (a seeded shuffle) is scored
by weights fitted on the other half. Plain Python: Debian ships no numpy by default.
"""
import csv
import math
import random
import sys


def features(row, best, colour, texture):
    f = [1.0, math.log(max(1.0, float(row["votes"]))), float(row["fitness"]),
         float(row["coverage"])]
    if colour:
        f.append(float(row["colour_agreement"]))
    if texture:  # not measured (-1): counted as no agreement
        f.append(max(0.0, float(row["texture_agreement"])))
    f.append(float(row["fitness"]) * float(row["coverage"]) / max(1e-6, best[row["case"]]))
    return f


def train(x, y, idx, l2=1e-3, iterations=3000, rate=0.5):
    w = [0.0] * len(x[0])
    for _ in range(iterations):
        g = [0.0] * len(w)
        for i in idx:
            p = 1 / (1 + math.exp(-sum(a * b for a, b in zip(w, x[i]))))
            for k in range(len(w)):
                g[k] += (p - y[i]) * x[i][k]
        for k in range(len(w)):
            w[k] -= rate * (g[k] / len(idx) + (l2 * w[k] if k else 0))
    return w


def prob(w, xi):
    return 1 / (1 + math.exp(-sum(a * b for a, b in zip(w, xi))))


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    path, config, colour = sys.argv[1], sys.argv[2], "--no-colour" not in sys.argv
    texture = colour and "--texture" in sys.argv
    rows = [r for r in csv.DictReader(open(path))
            if r["configuration"] == config and r["protocol"] == "a"]
    if not rows:
        sys.exit(f"{path}: no protocol (a) instances of configuration '{config}'")
    best = {}
    for r in rows:
        best[r["case"]] = max(best.get(r["case"], 0.0), float(r["fitness"]) * float(r["coverage"]))
    x = [features(r, best, colour, texture) for r in rows]
    y = [int(r["true"]) for r in rows]
    ids = sorted({r["identity"] for r in rows})
    random.Random(1).shuffle(ids)
    half_a = set(ids[: len(ids) // 2])
    ia = [i for i, r in enumerate(rows) if r["identity"] in half_a]
    ib = [i for i, r in enumerate(rows) if r["identity"] not in half_a]
    w = train(x, y, range(len(x)))
    wa, wb = train(x, y, ia), train(x, y, ib)
    names = (["bias", "ln votes", "fitness", "coverage"] + (["colour"] if colour else []) +
             (["texture"] if texture else []) + ["relative fit"])
    print(f"{len(rows)} instances ({sum(y)} true); weights fitted on all:")
    print("  " + ", ".join(f"{n} {v:.3f}" for n, v in zip(names, w)))
    print("threshold | held-out: true kept, false kept | fitted on all: true kept, false kept")
    for t in (0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9):
        held = [(i, prob(wb, x[i])) for i in ia] + [(i, prob(wa, x[i])) for i in ib]
        ht = sum(1 for i, p in held if p >= t and y[i])
        hf = sum(1 for i, p in held if p >= t and not y[i])
        ft = sum(1 for i in range(len(x)) if prob(w, x[i]) >= t and y[i])
        ff = sum(1 for i in range(len(x)) if prob(w, x[i]) >= t and not y[i])
        print(f"{t:.1f} | {ht}, {hf} | {ft}, {ff}")


if __name__ == "__main__":
    main()
