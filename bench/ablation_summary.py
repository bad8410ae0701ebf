#!/usr/bin/env python3
"""The table of bench/decision_ablation.sh: per scene and variant the mean relMSE over the seeds and the
per-sample gain over bounded volpath (volpath's mean relMSE / the variant's), with its standard error
from the seeds' spread (delta method, the two means independent).

    python3 bench/ablation_summary.py bench/results/decision-ablation/ablation.csv [more.csv ...]
"""
import csv
import math
import sys
from collections import defaultdict


def mean_se(values):
    n = len(values)
    m = sum(values) / n
    var = sum((v - m) ** 2 for v in values) / (n - 1) if n > 1 else 0.0
    return m, math.sqrt(var / n)


def main():
    rows = defaultdict(list)
    order = []
    for path in sys.argv[1:]:
        for r in csv.DictReader(open(path)):
            key = (r["scene"], r["variant"])
            if key not in rows:
                order.append(key)
            rows[key].append(float(r["relmse"]))
    print("| scene | variant | seeds | relMSE (mean) | gain vs bounded volpath (± s.e.) |")
    print("|---|---|---:|---:|---:|")
    for scene, variant in order:
        m, se = mean_se(rows[(scene, variant)])
        base = rows.get((scene, "volpath"))
        if not base:
            gain = "—"
        else:
            bm, bse = mean_se(base)
            g = bm / m
            gain = f"{g:.2f}× ± {g * math.hypot(bse / bm, se / m):.2f}"
        print(f"| {scene} | {variant} | {len(rows[(scene, variant)])} | {m:.4g} | {gain} |")


if __name__ == "__main__":
    main()
