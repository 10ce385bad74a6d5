#!/usr/bin/env bash
# grid49's windowed frame against its floor, in one run: `luz view --bench` of the scene as written
# (48x48 spheres, 4 lights), of the same geometry unlit (the `base_color` debug view: the same
# triangles and pixels into the swapchain with no lighting), and of the scene with automatic
# tessellation (assets/scenes/bench/grid49_auto.json: segments and rings left out), alternating
# RUNS times under Xvfb. Prints each run, the medians and luz's frame as a multiple of the floor.
# Usage: scripts/grid49_floor.sh [RUNS=3] [FRAMES=300]. Run on a quiet machine.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
runs="${1:-3}"
frames="${2:-300}"
luz=target/release/luz
[ -x "$luz" ] || cargo build --release --quiet
export VK_ICD_FILENAMES="${VK_ICD_FILENAMES:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
view() {  # name scene [script]
  local extra=()
  [ -n "${3:-}" ] && extra=(--script "$3")
  xvfb-run -a -s "-screen 0 1280x720x24" "$luz" view "$2" --bench --frames "$frames" \
    --json "$tmp/$1.json" "${extra[@]}" >"$tmp/$1.log" 2>&1 || { cat "$tmp/$1.log" >&2; exit 1; }
}
for i in $(seq "$runs"); do
  view "lit$i" assets/scenes/bench/grid49.json
  view "floor$i" assets/scenes/bench/grid49.json "0:debug_view=base_color"
  view "auto$i" assets/scenes/bench/grid49_auto.json
done
python3 - "$tmp" "$runs" <<'PY'
import json, statistics as st, sys
out, runs = sys.argv[1], int(sys.argv[2])
def load(n):
    j = json.load(open(f"{out}/{n}.json"))
    f = j["frame_ms"]
    passes = ", ".join(f"{k} {v['median']:.1f}" for k, v in j.get("gpu_pass_ms", {}).items())
    return f["median"], f["p99"] / f["median"], passes
print("run  variant                    frame p50 ms  p99/p50  GPU pass medians ms")
rows = {"lit": [], "floor": [], "auto": []}
names = {"lit": "as written (lit)", "floor": "unlit floor (base_color)", "auto": "automatic tessellation"}
for i in range(1, runs + 1):
    for k in rows:
        m, r, p = load(f"{k}{i}")
        rows[k].append((m, r))
        print(f"{i:3}  {names[k]:25}  {m:12.1f}  {r:7.3f}  {p}")
med = {k: st.median(m for m, _ in v) for k, v in rows.items()}
print(f"median frame: as written {med['lit']:.1f} ms, unlit floor {med['floor']:.1f} ms, "
      f"automatic tessellation {med['auto']:.1f} ms")
print(f"as written / floor: {med['lit'] / med['floor']:.2f}; automatic / floor: {med['auto'] / med['floor']:.2f}")
PY
