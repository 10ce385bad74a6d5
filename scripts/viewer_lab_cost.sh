#!/bin/sh
# The cost of the viewer's A/B comparison (issue 20): the windowed frame time of one scene, of the
# same scene compared with itself in split and toggle modes (both scenes rendered every frame), and
# in the difference and FLIP modes (the map of both HDR images computed on the GPU every frame:
# the profiler's 'A/B map' scope).
# Usage: scripts/viewer_lab_cost.sh [SCENE] [WIDTHxHEIGHT] (default: the built-in scene, 900x560).
# Needs xvfb-run; set VK_ICD_FILENAMES for lavapipe. Times vary with the machine's load: compare
# the rows of one run only.
set -e
LUZ=${LUZ:-target/release/luz}
SCENE=${1:-assets/scenes/default.json}
SIZE=${2:-900x560}
W=${SIZE%x*}
H=${SIZE#*x}
run() {
    label=$1
    shift
    echo "== $label"
    xvfb-run -a -s "-screen 0 1920x1200x24" "$LUZ" view "$SCENE" --bench --frames 60 --warmup 10 \
        --width "$W" --height "$H" --ibl-quality fast "$@" 2>&1 |
        grep -E "^(frames:|A/B maps|p50|gpu|  )|frame time|B: scene|A/B map|forward|display" || true
}
run "A alone"
run "A/B split" --compare "$SCENE"
run "A/B toggle" --compare "$SCENE" --script "1:compare_mode=toggle"
run "A/B difference" --compare "$SCENE" --script "1:compare_mode=difference"
run "A/B flip" --compare "$SCENE" --script "1:compare_mode=flip"
