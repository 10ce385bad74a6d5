#!/usr/bin/env bash
# The whole test suite: installs what luz needs, then runs every test on Mesa lavapipe with the
# Vulkan validation layer on (tests fail on any validation message).
# Extra arguments go to `cargo test` (e.g. a test name filter).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/setup.sh
export VK_ICD_FILENAMES="${VK_ICD_FILENAMES:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}"
export LUZ_VALIDATION=1
cargo test --release "$@"
