#!/usr/bin/env bash
# Cold against warm start of the default scene (issue 33; docs/performance.md, "Cold start").
#
# Each round runs `luz render` twice in a row: cold (an empty LUZ_CACHE_DIR and an empty Mesa
# shader cache, so that neither luz's caches nor the driver's hide any cost), then warm (the
# same two folders as the cold run left them). It prints both "time to first frame" figures of
# every round and, at the end, the medians and the median of the per-round ratios cold / warm.
#
# Usage: scripts/cold_start.sh [ROUNDS (default 5)] [extra `luz render` arguments…]
# MESA_COLD=0 keeps one Mesa shader cache for every run (warmed before the first round): the
# cold runs then miss only luz's own caches.
# The binary is target/release/luz (build it first: cargo build --release --bin luz), or $LUZ.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
rounds="${1:-5}"
shift || true
luz="${LUZ:-target/release/luz}"
[ -x "$luz" ] || { echo "cold_start.sh: $luz not found; run cargo build --release --bin luz" >&2; exit 1; }
export VK_ICD_FILENAMES="${VK_ICD_FILENAMES:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# Time to first frame (ms) of one render with these cache folders.
ttff() {
    LUZ_CACHE_DIR="$1" MESA_SHADER_CACHE_DIR="$2" XDG_CACHE_HOME="$2" \
        "$luz" render -o "$work/out.png" "${@:3}" | sed -n 's/^time to first frame: \([0-9.]*\) ms.*/\1/p'
}

date -u '+%Y-%m-%d %H:%M UTC'
echo "$("$luz" --version 2>/dev/null || echo luz), $(git rev-parse --short HEAD 2>/dev/null || echo '?'), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
mesa_cold="${MESA_COLD:-1}"
echo "cold: empty LUZ_CACHE_DIR$([ "$mesa_cold" = 1 ] && echo " and empty Mesa shader cache" || echo ", Mesa shader cache kept warm")"
mkdir -p "$work/mesa"
[ "$mesa_cold" = 1 ] || { mkdir -p "$work/warmup"; ttff "$work/warmup" "$work/mesa" "$@" >/dev/null; }
cold_all=() warm_all=() ratios=()
for i in $(seq 1 "$rounds"); do
    rm -rf "$work/luz"
    [ "$mesa_cold" = 1 ] && rm -rf "$work/mesa"
    mkdir -p "$work/luz" "$work/mesa"
    cold="$(ttff "$work/luz" "$work/mesa" "$@")"
    warm="$(ttff "$work/luz" "$work/mesa" "$@")"
    ratio="$(awk -v c="$cold" -v w="$warm" 'BEGIN { printf "%.2f", c / w }')"
    echo "round $i: cold $cold ms, warm $warm ms, cold/warm $ratio"
    cold_all+=("$cold") warm_all+=("$warm") ratios+=("$ratio")
done
median() { printf '%s\n' "$@" | sort -g | awk '{ a[NR] = $1 } END { print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2 }'; }
echo "median: cold $(median "${cold_all[@]}") ms, warm $(median "${warm_all[@]}") ms, cold/warm $(median "${ratios[@]}") (over $rounds rounds)"
