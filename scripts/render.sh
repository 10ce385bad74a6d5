#!/usr/bin/env bash
# The main job: installs what luz needs, then renders the embedded default scene headless at 1280x720
# (50 frames) to out/default.png and prints time to first frame and GPU/CPU ms per pass.
# Extra arguments go to `luz render` (e.g. a scene file, -o out.exr, --validate).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/setup.sh
mkdir -p out
cargo build --release --quiet
exec target/release/luz render --frames 50 --width 1280 --height 720 -o out/default.png "$@"
