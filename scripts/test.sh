#!/usr/bin/env bash
# The whole test suite: installs what luz needs, then runs every test on Mesa lavapipe with the
# Vulkan validation layer and its synchronization validation on (tests fail on any validation
# message or hazard).
# Every test binary runs even when an earlier one fails (`--no-fail-fast`); the script exits
# non-zero when any test (or the build) failed, after one summary line over all binaries.
# Extra arguments go to `cargo test` (e.g. a test name filter).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/setup.sh
export VK_ICD_FILENAMES="${VK_ICD_FILENAMES:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}"
export LUZ_VALIDATION=1
# … with its synchronization checks: any hazard between commands fails the test that recorded it.
export LUZ_SYNC_VALIDATION=1
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
status=0
# pipefail: the pipeline fails when cargo does, not only when tee does.
cargo test --release --workspace --no-fail-fast "$@" 2>&1 | tee "$log" || status=$?
# One closing line over every test binary.
awk '/^test result:/ { for (i = 1; i <= NF; i++) { if ($i ~ /^passed;?$/) p += $(i-1); if ($i ~ /^failed;?$/) f += $(i-1); if ($i ~ /^ignored;?$/) s += $(i-1) } }
     END { printf "luz: %d passed, %d failed, %d skipped\n", p, f, s }' "$log"
[ "$status" -eq 0 ] || echo "luz: cargo test failed (exit status $status)" >&2
exit "$status"
