#!/usr/bin/env bash
# Shadow cost (issue 15): the built-in scene with its two lights shadowed at the default settings
# (assets/scenes/default.json: a sun with three 1024² cascades, a point light with
# six 512² faces, PCF 2×2) against the same scene without "shadow" (default_unshadowed.json),
# alternating, ROUNDS rounds, at the scenes' own size (1280×720, MSAA 4×). Frame cost = median
# GPU total of `luz bench` (every pass, the shadow passes included, and the readback). The scene is
# static, so its maps are drawn in the first frame and reused after; `--no-shadow-cache` after
# ROUNDS and FRAMES (passed to every `luz bench`) draws them every frame (what a moving scene
# costs).
#
#   scripts/shadow_cost.sh [ROUNDS] [FRAMES] [BENCH FLAGS...]   (default 3 10; LUZ=path/to/luz)
set -euo pipefail
cd "$(dirname "$0")/.."
ROUNDS=${1:-3}
FRAMES=${2:-10}
shift $(( $# < 2 ? $# : 2 ))
EXTRA=("$@")
LUZ=${LUZ:-${CARGO_TARGET_DIR:-target}/release/luz}
[ -x "$LUZ" ] || { echo "build first: cargo build --release ($LUZ missing)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# bench SCENE -> "gpu_total_ms shadows_ms"
bench() {
    "$LUZ" bench "$1" --frames "$FRAMES" --warmup 2 --json "$tmp/b.json" "${EXTRA[@]}" >/dev/null
    python3 - "$tmp/b.json" <<'PY'
import json, sys
b = json.load(open(sys.argv[1]))
shadows = b["gpu_pass_ms"].get("shadows", {}).get("median", 0.0)
drawn = b.get("shadow_frames_drawn", 0)
reused = b.get("shadow_frames_reused", 0)
print(f'{b["gpu_total_ms"]["median"]:.3f} {shadows:.3f}ms,maps-drawn-in-{drawn}-frames,reused-in-{reused}')
PY
}
median() { python3 -c 'import statistics,sys; print(f"{statistics.median(map(float, sys.argv[1:])):.3f}")' "$@"; }

echo "# shadow cost: $(date -u +%Y-%m-%dT%H:%MZ), $("$LUZ" devices 2>/dev/null | head -1), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# command: scripts/shadow_cost.sh $ROUNDS $FRAMES ($(git rev-parse --short HEAD 2>/dev/null || echo '?'))"
with=() without=()
for r in $(seq 1 "$ROUNDS"); do
    read -r u _ < <(bench assets/scenes/shadows/default_unshadowed.json)
    read -r s p < <(bench assets/scenes/default.json)
    without+=("$u")
    with+=("$s")
    echo "round $r: without shadows ${u} ms, with shadows ${s} ms (shadow passes $(echo "$p" | tr ",-" "  ")), ratio $(python3 -c "print(f'{$s/$u:.3f}')")"
done
mu=$(median "${without[@]}")
ms=$(median "${with[@]}")
echo "median: without ${mu} ms, with ${ms} ms, ratio $(python3 -c "print(f'{$ms/$mu:.3f}')") (goal <= 1.3)"
