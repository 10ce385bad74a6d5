#!/usr/bin/env bash
# Automatic LOD (issue 17) on every shared OBJ model: 12 copies of the model (scaled to a radius
# of 1) in 3 rows 6 units apart, 640x360, two lights, Blinn-Phong. Per model and budget: the
# triangles drawn and the mean FLIP of `luz render` at that budget against the same scene at
# budget 0 (`luz diff`). With LUZ_B=path/to/other/luz, the same for that build beside it (for
# A/B comparisons of the simplifier; each build keeps its own LOD cache). Prints a markdown table.
#
#   scripts/lod_models.sh [BUDGETS...]   (default 0.5 1 2 px; LUZ=path/to/luz, LUZ_B=...)
set -euo pipefail
cd "$(dirname "$0")/.."
BUDGETS=${*:-0.5 1 2}
LUZ=${LUZ:-${CARGO_TARGET_DIR:-target}/release/luz}
[ -x "$LUZ" ] || { echo "build first: cargo build --release ($LUZ missing)" >&2; exit 1; }
models=../shared/models
[ -f "$models/spot.obj" ] || { echo "SKIPPED: $models/spot.obj not found" >&2; exit 0; }
models=$(cd "$models" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
scene() { # scene MODEL BUDGET OUT
    python3 - "$1" "$2" "$3" <<'PY'
import json, sys
model, budget, out = sys.argv[1], float(sys.argv[2]), sys.argv[3]
lo, hi = [1e30] * 3, [-1e30] * 3
with open(model) as f:
    for line in f:
        if line.startswith("v "):
            p = [float(x) for x in line.split()[1:4]]
            lo = [min(a, b) for a, b in zip(lo, p)]
            hi = [max(a, b) for a, b in zip(hi, p)]
c = [(a + b) / 2 for a, b in zip(lo, hi)]
s = 2.0 / max(b - a for a, b in zip(lo, hi))
objects = []
for i in range(12):
    row, col = divmod(i, 4)
    objects.append({
        "name": f"m{i}", "mesh": {"type": "obj", "path": model}, "material": "m",
        "position": [(col - 1.5) * 2.5 - c[0] * s, -c[1] * s, -row * 6 - c[2] * s],
        "rotation_deg": [0, i * 37, 0], "scale": [s, s, s]})
json.dump({
    "description": "scripts/lod_models.sh: 12 copies of a shared model near and far",
    "camera": {"position": [0, 1.5, 6], "target": [0, 0, -4], "up": [0, 1, 0], "fov_y_deg": 50,
               "near": 0.1, "far": 100},
    "output": {"width": 640, "height": 360, "msaa": 1, "tonemap": "aces",
               "background": [0.05, 0.06, 0.08], "tessellation_error_px": budget},
    "ambient": [0.05, 0.05, 0.05],
    "lights": [
        {"type": "directional", "direction": [-0.4, -1, -0.5], "color": [1, 0.96, 0.9], "intensity": 2.5},
        {"type": "directional", "direction": [0.6, -0.4, 0.3], "color": [0.5, 0.6, 0.8], "intensity": 0.8}],
    "materials": {"m": {"model": "blinn_phong", "kd": 0.8, "ks": 0.3, "shininess": 40,
                        "diffuse_color": [0.7, 0.6, 0.5]}},
    "objects": objects}, open(out, "w"))
PY
}
run() { # run LUZ CACHE SCENE FULL_PNG: "triangles FLIP"
    local out tris flip
    out=$(LUZ_CACHE_DIR="$2" "$1" render "$3" -o "$tmp/a.png" 2>&1)
    tris=$(echo "$out" | grep -o "[0-9]* of [0-9]* triangles drawn" | head -1 | cut -d' ' -f1)
    flip=$("$LUZ" diff "$4" "$tmp/a.png" --report-only | awk '/FLIP/ {print $3; exit}')
    echo "$tris $flip"
}
echo "# lod models: $(date -u +%Y-%m-%dT%H:%MZ), $(git rev-parse --short HEAD 2>/dev/null || echo '?')${LUZ_B:+, B: $LUZ_B}"
echo "# command: scripts/lod_models.sh $BUDGETS"
if [ -n "${LUZ_B:-}" ]; then
    echo "| model | budget | triangles drawn | mean FLIP against full detail | B: triangles | B: mean FLIP |"
    echo "|---|---|---|---|---|---|"
else
    echo "| model | budget | triangles drawn | mean FLIP against full detail |"
    echo "|---|---|---|---|"
fi
for m in "$models"/*.obj; do
    name=$(basename "$m" .obj)
    scene "$m" 0 "$tmp/full.json"
    LUZ_CACHE_DIR="$tmp/cache_a" "$LUZ" render "$tmp/full.json" -o "$tmp/full.png" >/dev/null 2>&1
    for b in $BUDGETS; do
        scene "$m" "$b" "$tmp/s.json"
        read -r tris flip < <(run "$LUZ" "$tmp/cache_a" "$tmp/s.json" "$tmp/full.png")
        row="| $name | $b px | $tris | $flip |"
        if [ -n "${LUZ_B:-}" ]; then
            read -r tris_b flip_b < <(run "$LUZ_B" "$tmp/cache_b" "$tmp/s.json" "$tmp/full.png")
            row="$row $tris_b | $flip_b |"
        fi
        echo "$row"
    done
done
