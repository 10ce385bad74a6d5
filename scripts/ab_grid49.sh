#!/usr/bin/env bash
# Two luz binaries on grid49 in one run, alternating RUNS rounds: the viewer (`luz view --bench`
# under Xvfb, the peer comparison's measure) and headless `luz bench`, and the ratio after ÷
# before of the medians. For "not slower" claims between two builds (e.g. before and after the
# frame graph, issue 32). Usage: scripts/ab_grid49.sh BEFORE AFTER [RUNS=3] [FRAMES=200]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
before="${1:?usage: ab_grid49.sh BEFORE AFTER [RUNS] [FRAMES]}"
after="${2:?usage: ab_grid49.sh BEFORE AFTER [RUNS] [FRAMES]}"
runs="${3:-3}"
frames="${4:-200}"
export VK_ICD_FILENAMES="${VK_ICD_FILENAMES:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}"
scene=assets/scenes/bench/grid49.json
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
for i in $(seq "$runs"); do
  for side in before after; do
    bin=$before; [ "$side" = after ] && bin=$after
    xvfb-run -a -s "-screen 0 1280x720x24" "$bin" view "$scene" --bench --frames "$frames" \
      --json "$tmp/view-$side$i.json" >"$tmp/view-$side$i.log" 2>&1 || { cat "$tmp/view-$side$i.log" >&2; exit 1; }
    "$bin" bench "$scene" --frames "$((frames / 4))" --warmup 3 --json "$tmp/bench-$side$i.json" \
      >"$tmp/bench-$side$i.log" 2>&1 || { cat "$tmp/bench-$side$i.log" >&2; exit 1; }
  done
done
python3 - "$tmp" "$runs" <<'PY'
import json, statistics as st, sys
out, runs = sys.argv[1], int(sys.argv[2])
def med(kind, side, key):
    vals = []
    for i in range(1, runs + 1):
        j = json.load(open(f"{out}/{kind}-{side}{i}.json"))
        vals.append(key(j))
    return vals
rows = [
    ("luz view --bench: frame p50 ms", "view", lambda j: j["frame_ms"]["median"]),
    ("luz bench: GPU total p50 ms", "bench", lambda j: j["gpu_total_ms"]["median"]),
    ("luz bench: CPU frame p50 ms", "bench", lambda j: j["cpu_ms"]["median"]),
]
print("| measure | before (runs) | after (runs) | after ÷ before (medians) |")
print("|---|---|---|---|")
for name, kind, key in rows:
    try:
        b, a = med(kind, "before", key), med(kind, "after", key)
    except KeyError as e:
        print(f"| {name} | missing {e} | | |")
        continue
    f = lambda v: " / ".join(f"{x:.1f}" for x in v)
    print(f"| {name} | {f(b)} | {f(a)} | {st.median(a) / st.median(b):.3f} |")
PY
