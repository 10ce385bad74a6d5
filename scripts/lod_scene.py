#!/usr/bin/env python3
"""Writes the automatic-LOD benchmark scenes of issue 17 (assets/scenes/lod/): instances of the
shared Stanford bunny (69,451 triangles, ../shared/models) on a floor, in rows from behind the
camera (out of view) to far away, so that some are near, most are far and some are culled.

    scripts/lod_scene.py                 # bunnies_40m.json: 600 instances, 41.7 M triangles
    scripts/lod_scene.py COUNT OUT.json [START_Z]  # another count, first row at START_Z (14)
    scripts/lod_scene.py --lab           # bunnies_lab.json: 36 bunnies at 320x180 for `luz lab`

Columns are 24 wide (2 units apart); rows go 4 units further each, two rows behind the camera.
"""
import json
import math
import os
import sys

TRIANGLES = 69451
COLUMNS = 24


# The coarsest budget (in 0.05 px steps) whose render stays within mean FLIP 0.01 of full detail on
# bunnies_40m (0.3 px: 0.0088, 0.35 px: 0.0101; docs/performance.md, "Placed vertices").
BUDGET_PX = 0.3
# bunnies_lab's budget, the lab's "as written" row.
LAB_BUDGET_PX = 0.2


def scene(count, size=(1280, 720), start=14.0, step=4.0, budget=BUDGET_PX):
    rows = math.ceil(count / COLUMNS)
    objects = []
    for i in range(count):
        row, col = divmod(i, COLUMNS)
        x = (col - (COLUMNS - 1) / 2) * 2.0
        z = start - step * row
        objects.append({
            "name": f"bunny_{row}_{col}",
            "mesh": {"type": "obj", "path": "../../../../shared/models/stanford-bunny.obj"},
            "material": ["clay", "jade", "brass"][(row + col) % 3],
            "position": [x, -0.33, z],
            "rotation_deg": [0, (i * 47) % 360, 0],
            "scale": [10, 10, 10],
        })
    objects.append({
        "name": "floor",
        "mesh": {"type": "plane", "size": [60, step * rows + 20]},
        "material": "floor",
        "position": [0, 0, start - step * rows / 2],
    })
    return {
        "description": (
            f"Automatic LOD benchmark (issue 17): {count} instances of the shared Stanford bunny "
            f"({count * TRIANGLES / 1e6:.1f} M triangles as written) in rows of {COLUMNS} from "
            f"z = {start:g} to {start - step * (rows - 1):g} (camera at z = 8, looking down -z), on a "
            f"floor, LOD budget {budget} px; made by scripts/lod_scene.py. Needs ../shared "
            "beside the checkout."
        ),
        "camera": {"position": [0, 2.2, 8], "target": [0, 0.6, -10], "up": [0, 1, 0],
                   "fov_y_deg": 50, "near": 0.1, "far": 200},
        "output": {"width": size[0], "height": size[1], "msaa": 1, "tonemap": "aces",
                   "background": [0.05, 0.06, 0.08], "tessellation_error_px": budget},
        "ambient": [0.04, 0.04, 0.05],
        "lights": [
            {"type": "directional", "direction": [-0.4, -1.0, -0.5], "color": [1, 0.96, 0.9],
             "intensity": 2.5},
            {"type": "directional", "direction": [0.6, -0.4, 0.3], "color": [0.5, 0.6, 0.8],
             "intensity": 0.8},
        ],
        "materials": {
            "clay": {"model": "lambert", "albedo": [0.75, 0.45, 0.35]},
            "jade": {"model": "lambert", "albedo": [0.35, 0.65, 0.45]},
            "brass": {"model": "lambert", "albedo": [0.8, 0.7, 0.3]},
            "floor": {"model": "lambert", "albedo": [0.5, 0.5, 0.5]},
        },
        "objects": objects,
    }


if __name__ == "__main__":
    here = os.path.dirname(os.path.abspath(__file__))
    lod = os.path.join(here, "..", "assets", "scenes", "lod")
    if sys.argv[1:] == ["--lab"]:
        count, out = 36, os.path.join(lod, "bunnies_lab.json")
        s = scene(count, (320, 180), start=6.0, step=20.0, budget=LAB_BUDGET_PX)
    else:
        count = int(sys.argv[1]) if len(sys.argv) > 1 else 600
        out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(lod, "bunnies_40m.json")
        s = scene(count, start=float(sys.argv[3]) if len(sys.argv) > 3 else 14.0)
    with open(out, "w") as f:
        json.dump(s, f, indent=1)
        f.write("\n")
    print(f"{out}: {count} bunnies, {count * TRIANGLES} triangles as written")
