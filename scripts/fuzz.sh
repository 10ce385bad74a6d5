#!/usr/bin/env bash
# Runs every fuzz target of fuzz/ (cargo-fuzz / libFuzzer, nightly) for SECONDS each, one after
# the other on one core, and appends one line per target to docs/fuzz/results.md.
#
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]     (default 600 s; all targets)
#
# Seed corpora are built at run time in target/fuzz-corpus/<target>/ from the project's own files
# (assets/scenes, tests/bad_inputs, fuzz/seeds) and from ../shared (models, environments,
# textures); what libFuzzer adds is kept there between runs (not committed). Crash, timeout and
# out-of-memory inputs go to fuzz/artifacts/<target>/; copy the minimised ones into
# tests/fuzz_regressions/<target>/ (see tests/fuzz_regressions.rs). CI does not run this.
set -euo pipefail

cd "$(dirname "$0")/.."
ROOT=$PWD
COMMAND="scripts/fuzz.sh $*"
SECONDS_PER_TARGET=${1:-600}
shift || true
TARGETS=("$@")
[ ${#TARGETS[@]} -eq 0 ] && TARGETS=(scene obj_mtl image diff gltf)
SHARED=${LUZ_SHARED:-$ROOT/../shared}
CORPUS=$ROOT/target/fuzz-corpus
RESULTS=$ROOT/docs/fuzz/results.md

if ! command -v cargo-fuzz >/dev/null 2>&1; then
    cargo install cargo-fuzz --locked
fi
if [ ! -d "$ROOT/.deps/shaderc" ]; then
    echo "fuzz.sh: .deps/shaderc is missing; run scripts/setup.sh first" >&2
    exit 1
fi

# --- seed corpora -------------------------------------------------------------------------------
SPLIT=$'\n#LUZ-SPLIT#\n'
seed() { # seed TARGET NAME  (content on stdin)
    mkdir -p "$CORPUS/$1"
    cat >"$CORPUS/$1/seed-$2"
}
ext_code() { # the image target's first byte for a file's extension
    case "${1##*.}" in
        png | PNG) echo 0 ;;
        exr | EXR) echo 1 ;;
        hdr | HDR) echo 2 ;;
        *) echo 0 ;;
    esac
}
byte() { printf "\\$(printf '%03o' "$1")"; }

build_seeds() {
    local f b
    # scene: every shipped scene, the scenes of tests/bad_inputs and tests/bad_scenes, the
    # committed seeds.
    for f in assets/scenes/*.json assets/scenes/*/*.json tests/bad_inputs/*.json \
        tests/bad_scenes/*.json fuzz/seeds/scene/*; do
        [ -f "$f" ] && seed scene "$(echo "$f" | tr / _)" <"$f"
    done
    # obj_mtl: the OBJ files (mtllib renamed to the harness's m.mtl), OBJ + MTL pairs of
    # tests/bad_inputs, the committed seeds.
    for f in tests/bad_inputs/*.obj tests/bad_scenes/*.obj "$SHARED"/models/*.obj; do
        [ -f "$f" ] || continue
        b=$(basename "$f" .obj)
        sed 's/^mtllib .*/mtllib m.mtl/' "$f" | seed obj_mtl "$b.obj"
        if [ -f "${f%.obj}.mtl" ]; then
            { sed 's/^mtllib .*/mtllib m.mtl/' "$f"; printf '%s' "$SPLIT"; cat "${f%.obj}.mtl"; } |
                seed obj_mtl "$b.obj_mtl"
        fi
    done
    for f in fuzz/seeds/obj_mtl/*; do
        [ -f "$f" ] && seed obj_mtl "$(basename "$f")" <"$f"
    done
    # image: every image file of tests/bad_inputs and ../shared, each as texture (sRGB, linear
    # with channel R, normal map without mipmaps).
    for f in tests/bad_inputs/*.png tests/bad_inputs/*.exr tests/bad_inputs/*.hdr tests/bad_scenes/*.png \
        tests/bad_scenes/*.hdr \
        "$SHARED"/textures/*/*.png "$SHARED"/environments/*.hdr fuzz/seeds/image/*; do
        [ -f "$f" ] || continue
        b=$(basename "$f")
        local c
        c=$(ext_code "$f")
        for opts in $((c)) $((c | 4 | 16)) $((c | 8 | 128)); do
            { byte "$opts"; cat "$f"; } | seed image "$opts-$b"
        done
    done
    # diff: the diff_* files and 1×1 texture, alone (compared with themselves) and in pairs.
    local imgs=(tests/bad_inputs/diff_*.png tests/bad_inputs/diff_*.exr tests/bad_inputs/tex_1x1.png)
    for f in "${imgs[@]}"; do
        [ -f "$f" ] || continue
        { byte "$(ext_code "$f")"; cat "$f"; } | seed diff "$(basename "$f")"
        for g in tests/bad_inputs/diff_8x8.png tests/bad_inputs/diff_8x8.exr; do
            [ -f "$g" ] || continue
            { byte $(($(ext_code "$f") | 2 | 4 | 16)); cat "$f"; printf '%s' "$SPLIT"; byte "$(ext_code "$g")"; cat "$g"; } |
                seed diff "$(basename "$f")-$(basename "$g")"
        done
    done
    # gltf: the bad-input corpus's glTF files, the committed seeds and ../shared's glTF files
    # (the large ones are read truncated to max_len).
    for f in tests/bad_inputs/*.gltf tests/bad_inputs/*.glb fuzz/seeds/gltf/* "$SHARED"/gltf/*.gltf \
        "$SHARED"/gltf/*.glb "$SHARED"/gltf/CesiumMan/*/*.gl*; do
        [ -f "$f" ] && seed gltf "$(basename "$f")" <"$f"
    done
}

# --- run ----------------------------------------------------------------------------------------
# max_len per target: scenes and images of a few KiB reach every parser branch; the large real
# files (the 2.3 MB bunny, the 3.7 MB HDR, the 1.8 MB roughness map) are read truncated to it.
max_len() {
    case $1 in
        scene) echo 65536 ;;
        obj_mtl) echo 65536 ;;
        image) echo 32768 ;;
        diff) echo 65536 ;;
        gltf) echo 65536 ;;
    esac
}
dict() {
    case $1 in
        scene) echo fuzz/dict/scene.dict ;;
        obj_mtl) echo fuzz/dict/obj.dict ;;
        image | diff) echo fuzz/dict/image.dict ;;
        gltf) echo fuzz/dict/scene.dict ;;
    esac
}

build_seeds
# Built once, then the binaries are run directly: `cargo fuzz run` would rebuild whenever someone
# edits src/ meanwhile, and that time would count as fuzzing time.
(cd fuzz && cargo +nightly fuzz build)
BIN=$ROOT/fuzz/target/$(rustc +nightly -vV | sed -n 's/^host: //p')/release

mkdir -p docs/fuzz
if [ ! -f "$RESULTS" ]; then
    cat >"$RESULTS" <<'EOF'
# Fuzzing results

Appended by `scripts/fuzz.sh SECONDS` (cargo-fuzz / libFuzzer, one target at a time, one core,
`-rss_limit_mb=2048 -timeout=10`), on the project's 2-core machine while other work ran on it.
"crashes" counts crash, timeout and out-of-memory inputs that run found (libFuzzer stops at the
first one; they are in `fuzz/artifacts/<target>/`).

| date (UTC) | target | seconds | executions | crashes | corpus | command |
|---|---|---:|---:|---:|---:|---|
EOF
fi

status=0
for t in "${TARGETS[@]}"; do
    mkdir -p "fuzz/artifacts/$t" "$CORPUS/$t"
    log=$ROOT/target/fuzz-$t.log
    before=$(find "fuzz/artifacts/$t" -type f | wc -l)
    start=$(date +%s)
    set +e
    "$BIN/$t" "$CORPUS/$t" \
        -max_total_time="$SECONDS_PER_TARGET" -rss_limit_mb=2048 -timeout=10 \
        -max_len="$(max_len "$t")" -dict="$ROOT/$(dict "$t")" -print_final_stats=1 \
        -artifact_prefix="$ROOT/fuzz/artifacts/$t/" >"$log" 2>&1
    rc=$?
    set -e
    # libFuzzer's own count and time: "Done 179738 runs in 61 second(s)".
    execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | tail -1 | grep -o '[0-9]*$' || true)
    elapsed=$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -1)
    elapsed=${elapsed:-$(($(date +%s) - start))} # no "Done" line after a crash: wall time
    after=$(find "fuzz/artifacts/$t" -type f | wc -l)
    crashes=$((after - before))
    [ "$rc" -ne 0 ] && [ "$crashes" -eq 0 ] && crashes="? (exit $rc, see $log)"
    corpus=$(find "$CORPUS/$t" -type f | wc -l)
    echo "$t: ${elapsed}s, ${execs:-?} executions, crashes: $crashes, corpus: $corpus (log: $log)"
    echo "| $(date -u '+%Y-%m-%d %H:%M') | $t | $elapsed | ${execs:-?} | $crashes | $corpus | \`${COMMAND% }\` |" >>"$RESULTS"
    [ "$rc" -ne 0 ] && status=1
done
exit $status
