#!/usr/bin/env bash
# Where grid49's frame time goes on this device: the benchmark scene and variants of it that remove
# one cost at a time, timed headless with `luz bench` (GPU forward, median), then the windowed frame
# with `luz view --bench` under Xvfb (3 runs). Usage: scripts/grid49_breakdown.sh [frames]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
frames="${1:-20}"
luz=target/release/luz
[ -x "$luz" ] || cargo build --release --quiet
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
python3 - "$tmp" <<'EOF'
import copy, json, sys
out = sys.argv[1]
s = json.load(open("assets/scenes/bench/grid49.json"))
def variant(name, f):
    t = copy.deepcopy(s)
    f(t)
    json.dump(t, open(f"{out}/{name}.json", "w"))
variant("grid49", lambda t: None)
variant("no_lights", lambda t: t.__setitem__("lights", []))
variant("one_light", lambda t: t.__setitem__("lights", t["lights"][:1]))
def low_poly(t):
    for o in t["objects"]:
        o["mesh"]["segments"] = 16
        o["mesh"]["rings"] = 16
variant("spheres_16x16", low_poly)
EOF
forward() {
  "$luz" bench "$1" --frames "$frames" --warmup 2 | awk '/^GPU forward +[0-9]/{print $3}'
}
echo "| variant | GPU forward median (ms) |"
echo "|---|---|"
for v in grid49 no_lights one_light spheres_16x16; do
  echo "| $v | $(forward "$tmp/$v.json") |"
done
if command -v xvfb-run >/dev/null; then
  echo
  echo "luz view --bench (windowed, presenting under Xvfb), 3 runs:"
  for i in 1 2 3; do
    xvfb-run -a -s "-screen 0 1600x1000x24" "$luz" view assets/scenes/bench/grid49.json --bench \
      --frames 110 | grep -E "frame ms|GPU "
  done
fi
