#!/usr/bin/env bash
# Many lights (issue 18), every figure of docs/performance.md "Many lights" in one run:
#   1. the target: plane1024 (1,024 point lights, range 1.5-3 m, 1280x720; clustered) against the
#      same lights without range (plain loop, nothing to cull), alternating, ROUNDS rounds;
#   2. the crossover: N ranged lights (1 ... 64), plain against clustered loop, alternating;
#   3. cost per light as lights grow (16 ... 4,096 on the same plane): with ranges (clustered)
#      and without (plain);
#   4. lights256 without ranges and with ranges for irradiance thresholds 1e-2 and 1e-3
#      (scene::range_for_threshold: sqrt(1.0887 I max(colour) / t)).
# Frame cost = median GPU total of `luz bench` (all passes and the readback) plus, when clustered,
# the CPU assignment of lights to clusters (`cluster_build_ms`, measured once per scene).
#
#   5. the crossover's worst case: N lights that all reach every pixel (range 60 m, nothing to
#      cull), plain against clustered loop: what clustering costs when it saves nothing.
#
#   scripts/many_lights.sh [ROUNDS] [SECTIONS]   (default 3 "1 2 3 4 5"; LUZ=path/to/luz)
set -euo pipefail
cd "$(dirname "$0")/.."
ROUNDS=${1:-3}
SECTIONS=${2:-1 2 3 4 5}
want() { [[ " $SECTIONS " == *" $1 "* ]]; }
LUZ=${LUZ:-${CARGO_TARGET_DIR:-target}/release/luz}
[ -x "$LUZ" ] || { echo "build first: cargo build --release ($LUZ missing)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# bench SCENE FRAMES WARMUP [args...] -> prints "frame_ms gpu_ms build_ms lights_mean lights_max loop"
bench() {
    local scene=$1 frames=$2 warmup=$3
    shift 3
    "$LUZ" bench "$scene" --frames "$frames" --warmup "$warmup" --json "$tmp/b.json" "$@" >/dev/null
    python3 - "$tmp/b.json" <<'EOF'
import json, sys
b = json.load(open(sys.argv[1]))
gpu = b["gpu_total_ms"]["median"]
build = b.get("cluster_build_ms") or 0.0
print(f'{gpu + build:.3f} {gpu:.3f} {build:.3f} {b.get("cluster_lights_mean") or 0:.2f} {b.get("cluster_lights_max") or 0} {b.get("light_loop")}')
EOF
}
median() { python3 -c 'import statistics,sys; print(f"{statistics.median(map(float, sys.argv[1:])):.3f}")' "$@"; }

echo "# many lights: $(date -u +%Y-%m-%dT%H:%MZ), $("$LUZ" devices 2>/dev/null | head -1), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# command: scripts/many_lights.sh $ROUNDS ($(git rev-parse --short HEAD 2>/dev/null || echo '?'))"

if want 1; then
echo
echo "## 1. target: plane1024 with ranges (clustered) vs without ranges (plain), $ROUNDS rounds alternating"
python3 scripts/gen_many_lights.py 1024 "$tmp/norange.json" --no-range
ranged=() plain=()
for r in $(seq 1 "$ROUNDS"); do
    read -r f g b mean max < <(bench assets/scenes/bench/plane1024.json 5 1)
    ranged+=("$f")
    echo "round $r: ranges ${f} ms (GPU ${g}, assignment ${b}; lights per cluster mean ${mean} max ${max})"
    read -r f g _ _ _ < <(bench "$tmp/norange.json" 2 1)
    plain+=("$f")
    echo "round $r: no ranges ${f} ms"
done
mr=$(median "${ranged[@]}")
mp=$(median "${plain[@]}")
echo "median: ranges ${mr} ms, no ranges ${mp} ms, ratio $(python3 -c "print(f'{$mr/$mp:.4f}')") (target <= 0.05)"
fi

if want 2; then
echo
echo "## 2. crossover: N ranged lights on the plane, plain vs clustered loop (median of $ROUNDS alternating rounds)"
echo "| lights | plain ms | clustered ms | clustered / plain |"
echo "|---:|---:|---:|---:|"
for n in 1 2 4 8 16 32 64; do
    python3 scripts/gen_many_lights.py "$n" "$tmp/n$n.json"
    p=() c=()
    for r in $(seq 1 "$ROUNDS"); do
        read -r f _ < <(bench "$tmp/n$n.json" 10 2 --light-loop plain); p+=("$f")
        read -r f _ < <(bench "$tmp/n$n.json" 10 2 --light-loop clustered); c+=("$f")
    done
    mp=$(median "${p[@]}"); mc=$(median "${c[@]}")
    echo "| $n | $mp | $mc | $(python3 -c "print(f'{$mc/$mp:.3f}')") |"
done
fi

if want 3; then
echo
echo "## 3. cost per light as lights grow (same 32 m plane, ranges 1.5-3 m)"
echo "| lights | with ranges (clustered) ms | ms per light | lights per cluster mean / max | without ranges (plain) ms | ms per light | ratio |"
echo "|---:|---:|---:|---:|---:|---:|---:|"
for n in 16 64 256 1024 4096; do
    python3 scripts/gen_many_lights.py "$n" "$tmp/g$n.json"
    python3 scripts/gen_many_lights.py "$n" "$tmp/g${n}n.json" --no-range
    read -r fc _ _ mean max < <(bench "$tmp/g$n.json" 5 1 --light-loop clustered)
    if [ "$n" -ge 1024 ]; then frames=1; else frames=3; fi
    read -r fp _ < <(bench "$tmp/g${n}n.json" "$frames" 1)
    python3 -c "print(f'| $n | $fc | {$fc/$n:.4f} | $mean / $max | $fp | {$fp/$n:.4f} | {$fc/$fp:.4f} |')"
done
fi

if want 4; then
echo
echo "## 4. lights256 (256 point lights, inverse square), without and with ranges"
echo "| ranges | loop | frame ms |"
echo "|---|---|---:|"
for t in none 1e-2 1e-3; do
    python3 - assets/scenes/bench/lights256.json "$tmp/l256_$t.json" "$t" <<'EOF'
import json, math, sys
s = json.load(open(sys.argv[1]))
t = sys.argv[3]
for l in s["lights"]:
    if t != "none" and l["type"] != "directional":
        l["range"] = math.sqrt(1.0887 * l.get("intensity", 1.0) * max(l.get("color", [1, 1, 1])) / float(t))
json.dump(s, open(sys.argv[2], "w"))
EOF
    read -r f _ _ mean max loop < <(bench "$tmp/l256_$t.json" 3 1)
    [ "$loop" = clustered ] && loop="clustered (mean $mean, max $max lights per cluster)"
    echo "| ${t/none/no range}$([ "$t" != none ] && echo ' threshold') | auto: $loop | $f |"
    if [ "$t" != none ]; then
        read -r f _ < <(bench "$tmp/l256_$t.json" 3 1 --light-loop plain)
        echo "| $t threshold | forced plain | $f |"
    fi
done
fi

if want 5; then
echo
echo "## 5. worst case: N lights all reaching every pixel (range 60 m), plain vs clustered (median of $ROUNDS alternating rounds)"
echo "| lights | plain ms | clustered ms | clustered / plain |"
echo "|---:|---:|---:|---:|"
for n in 1 2 4 8 16; do
    python3 scripts/gen_many_lights.py "$n" "$tmp/w$n.json" --range-min 60 --range-max 60
    p=() c=()
    for r in $(seq 1 "$ROUNDS"); do
        read -r f _ < <(bench "$tmp/w$n.json" 10 2 --light-loop plain); p+=("$f")
        read -r f _ < <(bench "$tmp/w$n.json" 10 2 --light-loop clustered); c+=("$f")
    done
    mp=$(median "${p[@]}"); mc=$(median "${c[@]}")
    echo "| $n | $mp | $mc | $(python3 -c "print(f'{$mc/$mp:.3f}')") |"
done
fi
