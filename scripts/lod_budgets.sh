#!/usr/bin/env bash
# Automatic LOD (issue 17) on assets/scenes/lod/bunnies_40m.json at several budgets: per budget one
# `luz bench` run with frames alternating between that budget and full detail (budget 0), so each
# ratio is measured within one run, and the mean FLIP of `luz render` at that budget against the
# full-detail render (`luz diff`). Prints a markdown table (the README's LOD table).
#
#   scripts/lod_budgets.sh [FRAMES] [BUDGETS...]   (default 3 frames; 0.1 0.2 0.3 0.5 px; LUZ=path/to/luz)
set -euo pipefail
cd "$(dirname "$0")/.."
FRAMES=${1:-3}
shift || true
BUDGETS=${*:-0.1 0.2 0.3 0.5}
LUZ=${LUZ:-${CARGO_TARGET_DIR:-target}/release/luz}
[ -x "$LUZ" ] || { echo "build first: cargo build --release ($LUZ missing)" >&2; exit 1; }
[ -f ../shared/models/stanford-bunny.obj ] || { echo "SKIPPED: ../shared/models/stanford-bunny.obj not found" >&2; exit 0; }
tmp=$(mktemp -d assets/scenes/lod/.budgets.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
scene() { # scene BUDGET OUT: bunnies_40m.json at BUDGET, one folder deeper
    python3 - "$1" "$2" <<'PY'
import json, sys
s = json.load(open("assets/scenes/lod/bunnies_40m.json"))
s["output"]["tessellation_error_px"] = float(sys.argv[1])
for o in s["objects"]:
    m = o.get("mesh", {})
    if "path" in m:
        m["path"] = "../" + m["path"]
json.dump(s, open(sys.argv[2], "w"))
PY
}
echo "# lod budgets: $(date -u +%Y-%m-%dT%H:%MZ), $("$LUZ" devices 2>/dev/null | head -1), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# command: scripts/lod_budgets.sh $FRAMES $BUDGETS ($(git rev-parse --short HEAD 2>/dev/null || echo '?'))"
scene 0 "$tmp/full.json"
"$LUZ" render "$tmp/full.json" -o "$tmp/full.png" >/dev/null
echo "| budget | triangles drawn | GPU ms | GPU ms at full detail, same run | ratio | mean FLIP against full detail |"
echo "|---|---|---|---|---|---|"
for b in $BUDGETS; do
    scene "$b" "$tmp/s.json"
    "$LUZ" bench "$tmp/s.json" --frames "$FRAMES" --warmup 1 --compare-budget 0 \
        --json "$tmp/b.json" >/dev/null
    "$LUZ" render "$tmp/s.json" -o "$tmp/s.png" >/dev/null
    flip=$("$LUZ" diff "$tmp/full.png" "$tmp/s.png" --report-only | awk '/FLIP/ {print $3; exit}')
    python3 - "$tmp/b.json" "$b" "$flip" <<'PY'
import json, sys
b = json.load(open(sys.argv[1]))
c = b["compared"]
a, f = b["gpu_total_ms"]["median"], c["gpu_total_ms"]["median"]
print(f'| {sys.argv[2]} px | {b["triangles_drawn"]:,} of {c["triangles_drawn"]:,} | {a:,.1f} | {f:,.1f} | {a / f:.3f}× | {float(sys.argv[3]):.4f} |')
PY
done
