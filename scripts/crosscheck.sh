#!/usr/bin/env bash
# Independent truth (issue 37): runs the cross-check group (tests/crosscheck.rs) against Mitsuba 3
# and prints the table of docs/accuracy.md: each scene exported with `luz export --format
# mitsuba`, rendered by Mitsuba (scalar_rgb), by luz's CPU reference and by the GPU (validation
# on), relative RMSE and max over the surfaces away from silhouettes.
# The images stay in OUT (default out/crosscheck/<scene>/: mitsuba.exr, reference.exr, gpu.exr,
# mitsuba_depth.exr, the export in mitsuba/, the scene and the export's warning).
# Usage: scripts/crosscheck.sh [OUT] [extra cargo test arguments, e.g. a scene filter]
# Skips visibly (and exits 0) when Mitsuba is not importable: scripts/setup.sh installs it.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
out="${1:-out/crosscheck}"
[ $# -gt 0 ] && shift
bash scripts/setup.sh
export VK_ICD_FILENAMES="${VK_ICD_FILENAMES:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}"
export LUZ_VALIDATION=1
mkdir -p "$out"
out="$(cd "$out" && pwd)"
rm -f "$out"/*/row.md
start=$(date +%s)
set +e
LUZ_CROSSCHECK_OUT="$out" cargo test --release --test crosscheck "$@" -- --nocapture 2>&1 \
  | grep -E "^(SKIPPED|crosscheck:|test result|left out)|panicked|FAILED"
status=${PIPESTATUS[0]}
set -e
secs=$(( $(date +%s) - start ))
if ls "$out"/*/row.md >/dev/null 2>&1; then
  echo
  echo "Produced by \`scripts/crosscheck.sh\` on $(date -u +%Y-%m-%d) (${secs} s, $(git rev-parse --short HEAD 2>/dev/null || echo '?'), Mitsuba $(.deps/mitsuba-venv/bin/python -c 'import mitsuba; print(mitsuba.__version__)' 2>/dev/null || echo '?') scalar_rgb):"
  echo
  echo "| scene | reference vs Mitsuba: rel. RMSE | max | FLIP | GPU vs Mitsuba: rel. RMSE | max | FLIP | pixels compared | judged on |"
  echo "|---|---|---|---|---|---|---|---|---|"
  cat "$out"/*/row.md
fi
# cargo's status is what counts (grep's is not).
exit "$status"
