#!/usr/bin/env bash
# Cost of the metal-rough lobes (issue 34: each lobe on ≤ 1.25× the base metal-rough frame, off
# ≤ 1.01×), measured with `luz bench` in one run on grid49 (assets/scenes/bench/grid49.json: 49
# gold metal-rough spheres, 4 point lights, 1280×720). Variants, written to a temporary folder:
#   base            the scene as it is
#   clearcoat on    every sphere with "clearcoat": {clearcoatFactor 1, clearcoatRoughnessFactor 0.1}
#   clearcoat off   the same block with clearcoatFactor 0 (the lobe's code compiles out)
#   sheen on        every sphere with "sheen": {sheenColorFactor [1, 1, 1], sheenRoughnessFactor 0.5}
#   sheen off       sheenColorFactor [0, 0, 0]
#   anisotropy on   every sphere with "anisotropy": {anisotropyStrength 0.8, anisotropyRotation 0.5}
#   anisotropy off  the same block with anisotropyStrength 0
#   iridescence on  every sphere with "iridescence": {iridescenceFactor 1, thickness 400 nm}
#   iridescence off the same block with iridescenceFactor 0
#   iridescence view on  "iridescence on" with "iridescence_angle": "view" (the film once per pixel)
# Each round benches every variant once, in turn; the ratio is the median GPU total (forward and
# every other pass) of a variant over the base's, so a busy machine slows all of them alike.
#
# RENDER_PATH (default forward) is luz bench's --render-path for every variant: grid49 itself
# takes the deferred path under "auto", an anisotropic material cannot (the G-buffer keeps no
# tangent), so "auto" would compare a lobe with the path change; "forward" compares the lobes.
#
#   scripts/lobe_cost.sh [ROUNDS] [FRAMES]   (default 3 20; LUZ=path/to/luz, RENDER_PATH=auto,
#   VARIANTS="base sheen_on ..." for a subset, base first)
set -euo pipefail
cd "$(dirname "$0")/.."
ROUNDS=${1:-3}
FRAMES=${2:-20}
RENDER_PATH=${RENDER_PATH:-forward}
LUZ=${LUZ:-${CARGO_TARGET_DIR:-target}/release/luz}
[ -x "$LUZ" ] || { echo "build first: cargo build --release ($LUZ missing)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

python3 - assets/scenes/bench/grid49.json "$tmp" <<'PY'
import json, sys
src, out = sys.argv[1], sys.argv[2]
base = json.load(open(src))
variants = {
    "base": None,
    "clearcoat_on": ("clearcoat", {"clearcoatFactor": 1, "clearcoatRoughnessFactor": 0.1}),
    "clearcoat_off": ("clearcoat", {"clearcoatFactor": 0, "clearcoatRoughnessFactor": 0.1}),
    "sheen_on": ("sheen", {"sheenColorFactor": [1, 1, 1], "sheenRoughnessFactor": 0.5}),
    "sheen_off": ("sheen", {"sheenColorFactor": [0, 0, 0], "sheenRoughnessFactor": 0.5}),
    "anisotropy_on": ("anisotropy", {"anisotropyStrength": 0.8, "anisotropyRotation": 0.5}),
    "anisotropy_off": ("anisotropy", {"anisotropyStrength": 0, "anisotropyRotation": 0.5}),
    "iridescence_on": ("iridescence", {"iridescenceFactor": 1, "iridescenceThicknessMaximum": 400}),
    "iridescence_off": ("iridescence", {"iridescenceFactor": 0, "iridescenceThicknessMaximum": 400}),
    "iridescence_view_on": ("iridescence", {"iridescenceFactor": 1, "iridescenceThicknessMaximum": 400},
                            {"iridescence_angle": "view"}),
}
for name, lobe in variants.items():
    scene = json.loads(json.dumps(base))
    if lobe:
        for m in scene["materials"].values():
            if m.get("model") == "metal_rough":
                m[lobe[0]] = lobe[1]
                m.update(lobe[2] if len(lobe) > 2 else {})
    json.dump(scene, open(f"{out}/{name}.json", "w"))
PY

# VARIANTS="base sheen_on" benches a subset (base always first).
read -r -a variants <<< "${VARIANTS:-base clearcoat_on clearcoat_off sheen_on sheen_off anisotropy_on anisotropy_off iridescence_on iridescence_off iridescence_view_on}"
bench() {
    "$LUZ" bench "$tmp/$1.json" --frames "$FRAMES" --warmup 3 --render-path "$RENDER_PATH" \
        --json "$tmp/b.json" >/dev/null
    python3 -c 'import json,sys; b = json.load(open(sys.argv[1])); print("%.3f" % b["gpu_total_ms"]["median"])' "$tmp/b.json"
}

echo "# lobe cost: $(date -u +%Y-%m-%dT%H:%MZ), $("$LUZ" devices 2>/dev/null | head -1), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# command: RENDER_PATH=$RENDER_PATH scripts/lobe_cost.sh $ROUNDS $FRAMES ($(git rev-parse --short HEAD 2>/dev/null || echo '?'))"
declare -A times
for r in $(seq 1 "$ROUNDS"); do
    line="round $r:"
    for v in "${variants[@]}"; do
        t=$(bench "$v")
        times[$v]="${times[$v]:-} $t"
        line="$line $v ${t} ms,"
    done
    echo "${line%,}"
done
python3 - "${variants[@]}" <<PY
import statistics, sys
times = {$(for v in "${variants[@]}"; do printf '"%s": [%s], ' "$v" "$(echo ${times[$v]} | tr ' ' ',')"; done)}
base = statistics.median(times["base"])
goal = {"on": 1.25, "off": 1.01}
print("| variant | GPU total p50 per round (ms) | median (ms) | × base | goal |")
print("|---|---|---:|---:|---:|")
for v in sys.argv[1:]:
    m = statistics.median(times[v])
    g = "" if v == "base" else f"≤ {goal[v.rsplit('_', 1)[1]]}"
    rounds = " / ".join(f"{t:.1f}" for t in times[v])
    print(f"| {v.replace('_', ' ')} | {rounds} | {m:.2f} | {m / base:.3f} | {g} |")
PY
