#!/usr/bin/env bash
# GPU cost of every material model: `luz bench` on assets/scenes/bench/cost_<model>.json (a plane
# filling 1280x720 under 16 lights) and the GPU forward ms per megapixel·light, as a Markdown table.
# Usage: scripts/model_costs.sh [frames]   (default 30)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
frames="${1:-30}"
luz=target/release/luz
[ -x "$luz" ] || cargo build --release --quiet
echo "| model | GPU forward median (ms) | GPU ms per megapixel·light |"
echo "|---|---|---|"
for m in lambert phong blinn_phong oren_nayar cook_torrance metal_rough principled; do
  out=$("$luz" bench "assets/scenes/bench/cost_$m.json" --frames "$frames" 2>/dev/null)
  fwd=$(echo "$out" | awk '/^GPU forward /{print $3; exit}')
  per=$(echo "$out" | awk '/per megapixel/{print $5; exit}')
  echo "| $m | $fwd | $per |"
done
