#!/usr/bin/env python3
"""Writes assets/scenes/models/<model>.json (five spheres sweeping the model's main parameter, for
the README's images) and assets/scenes/bench/cost_<model>.json (a full-screen plane under 16 lights,
for `luz bench`'s GPU ms per megapixel·light). Rerun after changing a material's syntax."""
import json, math, pathlib

root = pathlib.Path(__file__).resolve().parent.parent
sweep = [0.05, 0.25, 0.5, 0.75, 1.0]
models = {
    "lambert": [{"model": "lambert", "albedo": [0.8 * (0.4 + 0.15 * i)] * 3} for i in range(5)],
    "phong": [{"model": "phong", "ka": 0.2, "kd": 0.7, "ks": 0.6, "shininess": s,
               "diffuse_color": [0.8, 0.25, 0.2], "specular_color": [1, 1, 1]} for s in [200, 60, 20, 8, 2]],
    "blinn_phong": [{"model": "blinn_phong", "ka": 0.2, "kd": 0.7, "ks": 0.6, "shininess": s,
                     "diffuse_color": [0.2, 0.4, 0.8], "specular_color": [1, 1, 1]} for s in [800, 240, 80, 32, 8]],
    "cook_torrance": [{"model": "cook_torrance", "color": [0.9, 0.6, 0.3], "kd": 0.5, "roughness": r, "ior": 1.5}
                      for r in sweep],
    "metal_rough": [{"model": "metal_rough", "base_color": [1.0, 0.78, 0.34], "metallic": 1.0, "roughness": r}
                    for r in sweep],
    "principled": [{"model": "principled", "base_color": [0.8, 0.15, 0.1], "roughness": r, "specular": 0.5,
                    "clearcoat": 0.5, "clearcoat_gloss": 0.9, "sheen": 0.3} for r in sweep],
    "oren_nayar": [{"model": "oren_nayar", "albedo": [0.75, 0.7, 0.65], "sigma_deg": s} for s in [0, 10, 20, 40, 80]],
}

for name, mats in models.items():
    scene = {
        "description": f"The {name} model on five spheres sweeping its main parameter (left to right); README image.",
        "camera": {"position": [0, 0.4, 9], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 11, "near": 0.1, "far": 50},
        "output": {"width": 640, "height": 160, "background": [0.02, 0.02, 0.025], "tonemap": "khronos_neutral", "msaa": 4},
        "ambient": [0.05, 0.05, 0.06],
        "lights": [
            {"type": "directional", "direction": [0.5, -0.6, -1.0], "color": [1, 0.97, 0.92], "intensity": 2.0},
            {"type": "point", "position": [-4, 3, 4], "color": [0.6, 0.7, 1.0], "intensity": 20, "falloff": "inverse_square"},
        ],
        "materials": {f"m{i}": m for i, m in enumerate(mats)},
        "objects": [{"mesh": {"type": "sphere", "radius": 0.5, "segments": 64, "rings": 32},
                     "material": f"m{i}", "position": [-2.4 + 1.2 * i, 0, 0]} for i in range(5)],
    }
    (root / "assets/scenes/models" / f"{name}.json").write_text(json.dumps(scene, indent=1) + "\n")
    lights = []
    for k in range(16):
        a = 2 * math.pi * k / 16
        if k % 2 == 0:
            lights.append({"type": "point", "position": [round(3 * math.cos(a), 4), 1.5, round(3 * math.sin(a), 4)],
                           "color": [1, 1, 1], "intensity": 1.0, "falloff": "inverse_square"})
        else:
            lights.append({"type": "directional", "direction": [round(math.cos(a), 4), -1.0, round(math.sin(a), 4)],
                           "color": [1, 1, 1], "intensity": 0.1})
    cost = {
        "description": f"Cost of the {name} model: a plane filling the 1280x720 frame under 16 lights (8 point, 8 directional). "
                       "luz bench reports GPU forward ms per megapixel·light.",
        "camera": {"position": [0, 3, 0.001], "target": [0, 0, 0], "up": [0, 0, -1], "fov_y_deg": 60, "near": 0.1, "far": 20},
        "output": {"width": 1280, "height": 720, "msaa": 1},
        "ambient": [0.02, 0.02, 0.02],
        "lights": lights,
        "materials": {"m": mats[2]},
        "objects": [{"mesh": {"type": "plane", "size": [40, 40]}, "material": "m"}],
    }
    (root / "assets/scenes/bench" / f"cost_{name}.json").write_text(json.dumps(cost, indent=1) + "\n")
print("wrote", len(models) * 2, "scenes")
