#!/usr/bin/env python3
"""A Lambert plane under N coloured point lights (issue 18's many-lights workload).

    scripts/gen_many_lights.py N OUT.json [--no-range] [--range-min 1.5] [--range-max 3] [--seed 1]

The lights sit on a jittered grid over a 32 m x 32 m plane, 0.2-0.8 m above it, inverse-square
falloff, each with a range drawn uniformly in [range-min, range-max] (metres). --no-range writes
the same lights (same positions, colours, intensities) without their ranges. 1280x720, no MSAA.
assets/scenes/bench/plane1024.json is `gen_many_lights.py 1024 ... ` with the defaults.
"""
import argparse
import colorsys
import json
import math
import random

p = argparse.ArgumentParser()
p.add_argument("n", type=int)
p.add_argument("out")
p.add_argument("--no-range", action="store_true")
p.add_argument("--range-min", type=float, default=1.5)
p.add_argument("--range-max", type=float, default=3.0)
p.add_argument("--seed", type=int, default=1)
a = p.parse_args()

rng = random.Random(a.seed)
size = 32.0
side = math.ceil(math.sqrt(a.n))
step = size / side
lights = []
for k in range(a.n):
    i, j = k % side, k // side
    x = -size / 2 + (i + 0.2 + 0.6 * rng.random()) * step
    z = -size / 2 + (j + 0.2 + 0.6 * rng.random()) * step
    y = 0.2 + 0.6 * rng.random()
    r, g, b = colorsys.hsv_to_rgb(rng.random(), 0.7, 1.0)
    rng_range = a.range_min + (a.range_max - a.range_min) * rng.random()
    light = {
        "type": "point",
        "position": [round(x, 4), round(y, 4), round(z, 4)],
        "color": [round(r, 4), round(g, 4), round(b, 4)],
        "intensity": 0.3,
        "falloff": "inverse_square",
    }
    if not a.no_range:
        light["range"] = round(rng_range, 4)
    lights.append(light)

scene = {
    "description": f"{a.n} point lights over a Lambert plane, "
    + ("without range" if a.no_range else f"range {a.range_min}-{a.range_max} m")
    + f" (scripts/gen_many_lights.py {a.n}, seed {a.seed}; issue 18)",
    "camera": {
        "position": [0, 14, 20],
        "target": [0, 0, -2],
        "up": [0, 1, 0],
        "fov_y_deg": 50,
        "near": 0.1,
        "far": 100,
    },
    "output": {
        "width": 1280,
        "height": 720,
        "background": [0.02, 0.02, 0.03],
        "tonemap": "khronos_neutral",
        "msaa": 1,
    },
    "ambient": [0.02, 0.02, 0.02],
    "lights": lights,
    "materials": {"floor": {"model": "lambert", "albedo": [0.8, 0.8, 0.8]}},
    "objects": [{"mesh": {"type": "plane", "size": [size, size]}, "material": "floor"}],
}
with open(a.out, "w") as f:
    json.dump(scene, f, indent=1)
    f.write("\n")
