#!/usr/bin/env bash
# Duplicate pairs in the library's sources, tests aside (issue 32's measure): every crate's src
# (crates/*/src and the binary's src) without tests.rs / *_tests.rs files and tests/ folders,
# through the `duplicates` tool (runs of 6 or more identical or same-shape lines).
# Usage: scripts/duplicates.sh [--most N]   (from any folder of the checkout)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
cd "$root"
for src in src crates/*/src; do
  [ -d "$src" ] || continue
  find "$src" -name '*.rs' ! -name 'tests.rs' ! -name '*_tests.rs' ! -path '*/tests/*' -print0 |
    while IFS= read -r -d '' f; do mkdir -p "$tmp/$(dirname "$f")"; cp "$f" "$tmp/$f"; done
done
duplicates --repo "$tmp" --seconds 120 "$@"
