#!/usr/bin/env bash
# Automatic tessellation on the benchmark grid (assets/scenes/bench/grid49.json, 49 spheres of
# 48 x 48 segments as written): the lab's error and GPU time of the scene as written and with
# automatic tessellation at every budget, then the frame time of both with `luz bench` (headless)
# and `luz view --bench` (windowed under Xvfb, 3 runs each, interleaved).
# Usage: scripts/auto_tessellation.sh [out-dir]   (default target/auto-tessellation)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
out="${1:-target/auto-tessellation}"
mkdir -p "$out"
luz=target/release/luz
[ -x "$luz" ] || cargo build --release --quiet
python3 - "$out" <<'PY'
import json, sys
s = json.load(open("assets/scenes/bench/grid49.json"))
for o in s["objects"]:
    o["mesh"].pop("segments", None)
    o["mesh"].pop("rings", None)
s["description"] = "grid49 with automatic tessellation (segments and rings left out)"
json.dump(s, open(f"{sys.argv[1]}/grid49_auto.json", "w"), indent=1)
PY
cp assets/scenes/bench/grid49.json "$out/grid49.json"
"$luz" lab "$out/grid49.json" --only auto --frames 9 --out "$out/lab"
"$luz" render "$out/grid49_auto.json" -o "$out/grid49_auto.png" --verbose | grep -E "^automatic|triangles:"
echo
echo "| scene | luz bench: GPU forward median (ms) | luz view --bench: frame median (ms) |"
echo "|---|---|---|"
declare -A bench view
for i in 1 2 3; do
  for v in grid49 grid49_auto; do
    bench[$v]+="$("$luz" bench "$out/$v.json" --frames 20 --warmup 2 | awk '/^GPU forward +[0-9]/{print $3}') "
    if command -v xvfb-run >/dev/null; then
      view[$v]+="$(xvfb-run -a -s "-screen 0 1600x1000x24" "$luz" view "$out/$v.json" --bench --frames 60 2>&1 \
        | awk '/^frame ms/{print $6}' | tr -d ,) "
    fi
  done
done
median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{a[NR]=$1} END {print (NR ? a[int((NR+1)/2)] : "n/a")}'; }
for v in grid49 grid49_auto; do
  echo "| $v | $(echo "${bench[$v]}" | median) (runs: ${bench[$v]}) | $(echo "${view[$v]:-}" | median) (runs: ${view[$v]:-}) |"
done
