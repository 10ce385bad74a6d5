#!/usr/bin/env python3
"""Automatic LOD (issue 17): compares simplifier settings on the triangles-drawn-against-FLIP curve.

Reads the CSV that scripts/lod_quality_sweep.sh appends to (scene, setting, levels chosen by,
budget_px, triangles_drawn, mean_flip) and prints, per scene and setting, the mean FLIP at equal
triangles relative to the reference setting: the geometric mean over 41 triangle counts evenly
spaced (in log) between LO and HI of the ratio of the two curves, each interpolated linearly in
log-log between its measured budgets. Settings whose levels are chosen by the default's errors
(same triangles drawn at every budget) are compared budget by budget instead.

    scripts/lod_quality_compare.py docs/lab/lod_simplifier_sweep.csv
"""
import collections
import csv
import math
import sys

# Triangle range compared per scene (around the 2.86 M target on bunnies_40m at 1280x720).
RANGES = {
    "bunnies_40m 1280x720": (2.0e6, 5.0e6),
    "bunnies_40m 640x360": (0.8e6, 2.5e6),
    "bunnies_lab 320x180": (5e4, 4e5),
    "bunnies_lab 1280x720": (1.5e5, 6e5),
}
REFERENCE = "default (normal weight 0.5, LockBorder+ErrorAbsolute+ErrorClamped)"
OWN = "own error"


def interp(points, t):
    points = sorted(points)
    for (t0, f0), (t1, f1) in zip(points, points[1:]):
        if t0 <= t <= t1 and t1 > t0 and f0 > 0 and f1 > 0:
            a = (math.log(t) - math.log(t0)) / (math.log(t1) - math.log(t0))
            return math.exp(math.log(f0) + a * (math.log(f1) - math.log(f0)))
    return None


def main(path):
    curves = collections.defaultdict(dict)
    for row in csv.DictReader(open(path)):
        key = (row["scene"], row["setting"], row["levels chosen by"])
        curves[key][float(row["budget_px"])] = (int(row["triangles_drawn"]), float(row["mean_flip"]))
    print("| scene | setting | levels chosen by | budgets | mean FLIP against the default at equal triangles |")
    print("|---|---|---|---|---|")
    for (scene, setting, chosen), points in sorted(curves.items()):
        ref = curves.get((scene, REFERENCE, OWN))
        if ref is None or (setting == REFERENCE and chosen == OWN):
            continue
        if chosen == OWN:
            lo, hi = RANGES[scene]
            ratios = []
            for i in range(41):
                t = lo * (hi / lo) ** (i / 40)
                a, b = interp(points.values(), t), interp(ref.values(), t)
                if a and b:
                    ratios.append(math.log(a / b))
            note = f"{len(ratios)} of 41 counts in {lo / 1e6:g}-{hi / 1e6:g} M"
        else:
            ratios = [math.log(f / ref[b][1]) for b, (t, f) in points.items() if b in ref and ref[b][0] == t]
            note = f"{len(ratios)} budgets, same triangles"
        if ratios:
            r = math.exp(sum(ratios) / len(ratios))
            print(f"| {scene} | {setting} | {chosen} | {len(points)} | **{r:.3f}×** ({note}) |")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/lab/lod_simplifier_sweep.csv")
