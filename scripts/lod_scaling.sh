#!/usr/bin/env bash
# Automatic LOD (issue 17): frame time against triangles as written, with and without LOD, in one
# `luz bench` run per size (frames alternating between the scene's budget and budget 0).
# Scenes: scripts/lod_scene.py with 15, 144, 576 and 1,440 shared bunnies (1.0, 10.0, 40.0 and
# 100.0 M triangles as written; rows beyond the far plane at 100 M are culled) at the budget of
# assets/scenes/lod/bunnies_40m.json, the first row 2 units in front of the camera (z = 6: no row
# behind it, unlike bunnies_40m.json, so that the 1 M scene draws something).
#
#   scripts/lod_scaling.sh [FRAMES] [WIDTH HEIGHT]   (default 3 frames at 1280x720; LUZ=path/to/luz)
set -euo pipefail
cd "$(dirname "$0")/.."
FRAMES=${1:-3}
W=${2:-1280}
H=${3:-720}
LUZ=${LUZ:-${CARGO_TARGET_DIR:-target}/release/luz}
[ -x "$LUZ" ] || { echo "build first: cargo build --release ($LUZ missing)" >&2; exit 1; }
[ -f ../shared/models/stanford-bunny.obj ] || { echo "SKIPPED: ../shared/models/stanford-bunny.obj not found" >&2; exit 0; }
tmp=$(mktemp -d assets/scenes/lod/.scaling.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
echo "# lod scaling: $(date -u +%Y-%m-%dT%H:%MZ), $("$LUZ" devices 2>/dev/null | head -1), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# command: scripts/lod_scaling.sh $FRAMES $W $H ($(git rev-parse --short HEAD 2>/dev/null || echo '?'))"
echo "| triangles as written | bunnies | drawn with LOD | GPU ms with LOD | drawn at full detail (budget 0) | GPU ms at full detail | ratio |"
echo "|---|---|---|---|---|---|---|"
for count in 15 144 576 1440; do
    # The scene's folder depth must match assets/scenes/lod for the model's relative path.
    python3 scripts/lod_scene.py "$count" "$tmp/s.json" 6 >/dev/null
    sed -i 's#"\.\./\.\./\.\./\.\./shared#"../../../../../shared#' "$tmp/s.json"
    "$LUZ" bench "$tmp/s.json" --frames "$FRAMES" --warmup 1 --width "$W" --height "$H" \
        --compare-budget 0 --json "$tmp/b.json" >/dev/null
    python3 - "$tmp/b.json" "$count" <<'PY'
import json, sys
b = json.load(open(sys.argv[1])); n = int(sys.argv[2])
c = b["compared"]
a, f = b["gpu_total_ms"]["median"], c["gpu_total_ms"]["median"]
print(f'| {n * 69451 / 1e6:.1f} M | {n} | {b["triangles_drawn"]:,} | {a:,.1f} | {c["triangles_drawn"]:,} | {f:,.1f} | {a / f:.3f}× |')
PY
done
