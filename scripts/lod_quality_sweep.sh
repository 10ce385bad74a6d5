#!/usr/bin/env bash
# Automatic LOD (issue 17): triangles drawn and mean FLIP against full detail of one LOD setting
# over a list of budgets, one CSV row per budget (docs/lab/lod_simplifier_sweep.csv's format;
# compare settings with scripts/lod_quality_compare.py). The full-detail image (budget 0) of each
# scene and size is rendered once and kept in the output folder. Renders are deterministic, so
# FLIP and triangle counts do not depend on the machine's load.
#
#   SETTING="label" [CHOSEN="own error"] scripts/lod_quality_sweep.sh SCENE WIDTH HEIGHT BUDGET...
#   (SCENE: a scene under assets/scenes/lod; OUT=folder, default out/lod-sweep; LUZ=path/to/luz)
#
# The settings other than the default were measured with docs/lab/lod_simplifier_knobs.patch
# applied (temporary LODX_* environment variables in src/scene/lod/mod.rs, e.g. LODX_NW=1 for the
# normal weight, LODX_OPTS for meshopt's option bits, LODX_K for level i's error x K^i; it also
# bypasses the LOD cache with LODX_NOCACHE, set here). Example, the default's curve:
#   SETTING=default scripts/lod_quality_sweep.sh bunnies_40m.json 1280 720 0.15 0.2 0.25 0.3
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 4 ] || { sed -n '2,16p' "$0" >&2; exit 2; }
SCENE=$1 W=$2 H=$3
shift 3
LUZ=${LUZ:-${CARGO_TARGET_DIR:-target}/release/luz}
OUT=${OUT:-out/lod-sweep}
[ -x "$LUZ" ] || { echo "build first: cargo build --release ($LUZ missing)" >&2; exit 1; }
[ -f "assets/scenes/lod/$SCENE" ] || { echo "assets/scenes/lod/$SCENE: no such scene" >&2; exit 1; }
mkdir -p "$OUT"
tmp=$(mktemp -d assets/scenes/lod/.sweep.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
export LODX_NOCACHE=1
label="${SCENE%.json} ${W}x${H}"
# The scene at budget $1, in the temp folder (one level deeper: the model's relative path gains ../).
scene_at() {
    python3 - "assets/scenes/lod/$SCENE" "$tmp/s.json" "$1" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d["output"]["tessellation_error_px"] = float(sys.argv[3])
def fix(v):
    if isinstance(v, dict): return {k: fix(x) for k, x in v.items()}
    if isinstance(v, list): return [fix(x) for x in v]
    if isinstance(v, str) and v.startswith("../"): return "../" + v
    return v
json.dump(fix(d), open(sys.argv[2], "w"))
PY
}
full="$OUT/${SCENE%.json}_${W}x${H}_full.png"
if [ ! -f "$full" ]; then
    scene_at 0
    "$LUZ" render "$tmp/s.json" --width "$W" --height "$H" -o "$full" >/dev/null
fi
[ -f "$OUT/sweep.csv" ] || echo 'scene,setting,levels chosen by,budget_px,triangles_drawn,mean_flip' >"$OUT/sweep.csv"
for b in "$@"; do
    scene_at "$b"
    img="$OUT/${SCENE%.json}_${W}x${H}_$b.png"
    tri=$("$LUZ" render "$tmp/s.json" --width "$W" --height "$H" -o "$img" |
        sed -n 's/.* \([0-9]*\) of [0-9]* triangles drawn.*/\1/p')
    flip=$("$LUZ" diff "$full" "$img" --max-flip-mean none --max-abs none --max-bad-pixels none |
        sed -n 's/^FLIP *mean \([0-9.]*\).*/\1/p')
    echo "$label,\"${SETTING:-default}\",${CHOSEN:-own error},$b,$tri,$flip" | tee -a "$OUT/sweep.csv"
done
