#!/usr/bin/env python3
"""The lab group `area` as docs/area-lights.md shows it: one row per shape and method, the
forward pass's cost over the point light's (median over the shape's cells) and the relative L1
error against the reference at each roughness, median (worst) over the four solid-angle ×
elevation cells.

    python3 scripts/area_lab_table.py docs/lab/area_results.csv
"""
import csv
import statistics
import sys
from collections import defaultdict


def main(path):
    rows = list(csv.DictReader(open(path)))
    roughness = sorted({float(r["roughness"]) for r in rows})
    keys = []
    err = defaultdict(list)
    cost = defaultdict(list)
    for r in rows:
        label = r["method"] + (f" {r['samples']}" if r["samples"] != "0" else "")
        key = (r["shape"], label)
        if key not in keys:
            keys.append(key)
        err[key + (float(r["roughness"]),)].append(float(r["relative_l1"]))
        cost[key].append(float(r["cost_x_point"]))
    head = ["light", "method", "× point (median)"] + [f"rough {g:g}" for g in roughness]
    print("| " + " | ".join(head) + " |")
    print("|---|---|" + "---:|" * (len(head) - 2))
    for key in keys:
        cells = []
        for g in roughness:
            e = err[key + (g,)]
            cells.append(f"{100 * statistics.median(e):.1f} ({100 * max(e):.0f}) %")
        print(f"| {key[0]} | {key[1]} | {statistics.median(cost[key]):.2f} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/lab/area_results.csv")
