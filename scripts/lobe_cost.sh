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
# CLOCK=cpu measures the process's CPU time (user + system, every lavapipe thread) per frame
# instead, from two runs of FRAMES and FRAMES + 30 frames (start-up and pipeline compilation
# cancel): on a machine shared with builds, other processes inflate the GPU time's wall clock but
# not a process's own CPU time. Its ratios run about 0.1 above the GPU time's on a quiet machine
# (the frame's fixed work weighs less), so compare CPU ratios with CPU ratios only.
# LUZ_BEFORE=path/to/older/luz benches that build too in every round ("before" rows): a change's
# effect measured in one run.
#
#   scripts/lobe_cost.sh [ROUNDS] [FRAMES]   (default 3 20; LUZ=path/to/luz, RENDER_PATH=auto,
#   VARIANTS="base sheen_on ..." for a subset, base first; CLOCK=cpu; LUZ_BEFORE=path)
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
CLOCK=${CLOCK:-gpu}
# The CPU seconds (user + system) of one `luz bench` of variant $2 with binary $1 over $3 frames.
cpu_seconds() {
    /usr/bin/time -o "$tmp/t.txt" -f "%U %S" "$1" bench "$tmp/$2.json" --frames "$3" --warmup 1 \
        --render-path "$RENDER_PATH" >/dev/null 2>&1
    awk '{ print $1 + $2 }' "$tmp/t.txt"
}
# Milliseconds per frame of variant $2 with binary $1: the GPU total's median, or (CLOCK=cpu) the
# CPU time of 30 more frames over 30.
bench_with() {
    if [ "$CLOCK" = cpu ]; then
        local a b
        a=$(cpu_seconds "$1" "$2" "$FRAMES")
        b=$(cpu_seconds "$1" "$2" $((FRAMES + 30)))
        python3 -c "print('%.3f' % (($b - $a) / 30 * 1000))"
    else
        "$1" bench "$tmp/$2.json" --frames "$FRAMES" --warmup 3 --render-path "$RENDER_PATH" \
            --json "$tmp/b.json" >/dev/null
        python3 -c 'import json,sys; b = json.load(open(sys.argv[1])); print("%.3f" % b["gpu_total_ms"]["median"])' "$tmp/b.json"
    fi
}
bench() { bench_with "$LUZ" "$1"; }
if [ -n "${LUZ_BEFORE:-}" ]; then
    [ -x "$LUZ_BEFORE" ] || { echo "LUZ_BEFORE=$LUZ_BEFORE is not an executable" >&2; exit 1; }
    # Every variant again with the older build, as "<variant>@before".
    before=()
    for v in "${variants[@]}"; do before+=("$v@before"); done
fi

echo "# lobe cost: $(date -u +%Y-%m-%dT%H:%MZ), $("$LUZ" devices 2>/dev/null | head -1), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# command: RENDER_PATH=$RENDER_PATH CLOCK=$CLOCK${LUZ_BEFORE:+ LUZ_BEFORE=$LUZ_BEFORE} scripts/lobe_cost.sh $ROUNDS $FRAMES ($(git rev-parse --short HEAD 2>/dev/null || echo '?'))"
declare -A times
for r in $(seq 1 "$ROUNDS"); do
    line="round $r:"
    for v in "${variants[@]}" ${before[@]+"${before[@]}"}; do
        case "$v" in
            *@before) t=$(bench_with "$LUZ_BEFORE" "${v%@before}") ;;
            *) t=$(bench "$v") ;;
        esac
        times[$v]="${times[$v]:-} $t"
        line="$line $v ${t} ms,"
    done
    echo "${line%,}"
done
python3 - "${variants[@]}" ${before[@]+"${before[@]}"} <<PY
import statistics, sys
times = {$(for v in "${variants[@]}" ${before[@]+"${before[@]}"}; do printf '"%s": [%s], ' "$v" "$(echo ${times[$v]} | tr ' ' ',')"; done)}
goal = {"on": 1.25, "off": 1.01}
what = "GPU total p50" if "$CLOCK" == "gpu" else "CPU ms per frame"
print(f"| variant | {what} per round (ms) | median (ms) | × base | goal |")
print("|---|---|---:|---:|---:|")
for v in sys.argv[1:]:
    name, _, tag = v.partition("@")
    base = statistics.median(times["base@" + tag if tag else "base"])
    m = statistics.median(times[v])
    g = "" if name == "base" else f"≤ {goal[name.rsplit('_', 1)[1]]}"
    rounds = " / ".join(f"{t:.1f}" for t in times[v])
    label = name.replace("_", " ") + (f" ({tag})" if tag else "")
    print(f"| {label} | {rounds} | {m:.2f} | {m / base:.3f} | {g} |")
PY
