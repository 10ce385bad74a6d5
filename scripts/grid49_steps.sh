#!/usr/bin/env bash
# Issue 14's steps on grid49, each against the one before, in one run: `luz view --bench` under Xvfb
# with the steps turned on one at a time (every step has a switch), alternating RUNS rounds.
#   baseline   an older luz binary, when given (e.g. a build of the commit before issue 14's work)
#   vertex     lean Phong vertex stage only: --render-path forward --display-path hdr,
#              LUZ_MALLOC_TUNING=0, LP_NUM_THREADS=<cores> (lavapipe's default)
#   malloc     + glibc trim threshold raised for the CPU device
#   display    + shade, tone-map and encode in the forward pass straight into the swapchain image
#   deferred   + the deferred path (G-buffer, then one lighting pass over covered pixels)
#   threads    + 3 lavapipe rasterizer threads per core (luz's default): luz as shipped
# Usage: scripts/grid49_steps.sh [RUNS=3] [FRAMES=200] [BASELINE_BINARY]. Run on a quiet machine.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
runs="${1:-3}"
frames="${2:-200}"
baseline="${3:-}"
luz=target/release/luz
[ -x "$luz" ] || cargo build --release --quiet
export VK_ICD_FILENAMES="${VK_ICD_FILENAMES:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}"
cores=$(nproc)
scene=assets/scenes/bench/grid49.json
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
run() {  # name binary env... -- args...
  local name=$1 bin=$2
  shift 2
  local envs=()
  while [ "$1" != "--" ]; do envs+=("$1"); shift; done
  shift
  env -u LP_NUM_THREADS -u LUZ_MALLOC_TUNING "${envs[@]}" \
    xvfb-run -a -s "-screen 0 1280x720x24" "$bin" view "$scene" --bench --frames "$frames" \
    --json "$tmp/$name.json" "$@" >"$tmp/$name.log" 2>&1 || { cat "$tmp/$name.log" >&2; exit 1; }
}
steps=()
[ -n "$baseline" ] && steps+=(baseline)
steps+=(vertex malloc display deferred threads)
for i in $(seq "$runs"); do
  [ -n "$baseline" ] && run "baseline$i" "$baseline" LP_NUM_THREADS="$cores" --
  run "vertex$i" "$luz" LP_NUM_THREADS="$cores" LUZ_MALLOC_TUNING=0 -- --render-path forward --display-path hdr
  run "malloc$i" "$luz" LP_NUM_THREADS="$cores" -- --render-path forward --display-path hdr
  run "display$i" "$luz" LP_NUM_THREADS="$cores" -- --render-path forward
  run "deferred$i" "$luz" LP_NUM_THREADS="$cores" --
  run "threads$i" "$luz" --
done
python3 - "$tmp" "$runs" "${steps[@]}" <<'PY'
import json, statistics as st, sys
out, runs, steps = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
print("| step | frame p50 ms (runs) | median | p99/p50 (runs) | GPU pass medians ms (last run) | × previous step |")
print("|---|---|---|---|---|---|")
prev = None
for s in steps:
    js = [json.load(open(f"{out}/{s}{i}.json")) for i in range(1, runs + 1)]
    p50 = [j["frame_ms"]["median"] for j in js]
    tail = [j["frame_ms"]["p99"] / j["frame_ms"]["median"] for j in js]
    m = st.median(p50)
    passes = ", ".join(f"{k} {v['median']:.1f}" for k, v in js[-1].get("gpu_pass_ms", {}).items())
    ratio = f"{m / prev:.2f}" if prev else ""
    print(f"| {s} | {' / '.join(f'{x:.1f}' for x in p50)} | {m:.1f} | "
          f"{' / '.join(f'{x:.2f}' for x in tail)} | {passes} | {ratio} |")
    prev = m
PY
