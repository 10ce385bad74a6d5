#!/usr/bin/env bash
# Runs `luz fidelity` through the REAL Khronos glTF Render Fidelity generator
# (KhronosGroup/glTF-Render-Fidelity-Generator, its `render-goldens` workflow), not through
# luz's own reading of its contract: the generator's TypeScript, built as its package.json says,
# spawns luz once per scenario and must find test/goldens/<scenario>/luz-golden.png.
# docs/fidelity.md "Run through the real generator" records a run (issue 39).
#
# Usage: scripts/fidelity_generator.sh LUZ_BINARY [GENERATOR_CHECKOUT]
#
#   LUZ_BINARY          the luz executable to test (e.g. target/release/luz); it is not built here
#   GENERATOR_CHECKOUT  an existing copy of the generator holding at least src/, package.json
#                       (package-lock.json, tsconfig*.json if it has them). Without it the script
#                       fetches only those files: git clone --depth 1 --filter=blob:none --sparse
#                       of the public repository (the repository's goldens are gigabytes).
#
# Environment: LUZ_SHARED (default: ../shared beside the repository) holds gltf/ and
# environments/ (the models and HDR of the scenarios); WORK (default: a new temporary folder,
# kept) is where the generator is installed and run; VK_ICD_FILENAMES defaults to lavapipe.
# Needs node and npm (the npm registry; no browser: Puppeteer's download is skipped).
# Not run by the test suite (it needs the network and takes minutes): run it by hand.
#
# What it does, in WORK:
#   1. copies the generator's src/, package*.json, tsconfig*.json; `npm install` (scripts off:
#      the generator's `prepare` fetches all the glTF sample assets) and `tsc` (the `build`
#      script's first half; its `rollup -c` only bundles the browser viewers);
#   2. lays the assets out as the generator's checkout does: glTF-Sample-Assets/Models/… and
#      environments/… at its root, the scenario paths relative (../../../…) like test/config.json;
#   3. writes test/config.json with only the `luz` renderer and three 256-pixel scenarios;
#   4. runs render-goldens for luz with the entry docs/fidelity.md gives (args ["fidelity"]:
#      luz resolves the scenario's paths against outputFile's folder, as the generator's Blender
#      script does) — it must write every PNG; prints the generator's output, each scenario's
#      time (luz's "wrote … in N ms") and the PNG listing.
set -euo pipefail

usage() { sed -n '8,21p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//' >&2; exit 2; }
[ $# -ge 1 ] && [ $# -le 2 ] || usage
case "$1" in -h|--help) usage ;; esac

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
luz="$(realpath "$1")"
[ -x "$luz" ] || { echo "not an executable: $1" >&2; exit 2; }
shared="$(realpath "${LUZ_SHARED:-$repo/../shared}")"
for f in gltf/CesiumMan/glTF-Binary/CesiumMan.glb gltf/color_teapot_spheres.gltf gltf/retroufo.glb \
  environments/newport_loft.hdr; do
  [ -f "$shared/$f" ] || { echo "missing $shared/$f (set LUZ_SHARED)" >&2; exit 2; }
done
command -v npm >/dev/null || { echo "npm is not installed" >&2; exit 2; }
export VK_ICD_FILENAMES="${VK_ICD_FILENAMES:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}"
export PUPPETEER_SKIP_DOWNLOAD=1 PUPPETEER_SKIP_CHROMIUM_DOWNLOAD=1
work="${WORK:-$(mktemp -d /tmp/fidelity-generator.XXXXXX)}"
mkdir -p "$work"
echo "work folder: $work"

# 1. The generator's sources.
if [ $# -eq 2 ]; then
  src="$(realpath "$2")"
  [ -f "$src/package.json" ] && [ -d "$src/src" ] || { echo "$2: no package.json and src/" >&2; exit 2; }
  commit="$(git -C "$src" rev-parse HEAD 2>/dev/null || echo "unknown (not a git checkout)")"
else
  src="$work/checkout"
  rm -rf "$src"
  git clone --depth 1 --filter=blob:none --sparse \
    https://github.com/KhronosGroup/glTF-Render-Fidelity-Generator.git "$src"
  git -C "$src" sparse-checkout set --no-cone '/src/' '/package*.json' '/tsconfig*' '/test/config.json'
  commit="$(git -C "$src" rev-parse HEAD)"
fi
echo "generator: $src (commit $commit)"
gen="$work/gen"
rm -rf "$gen"
mkdir -p "$gen/test"
cp -r "$src/src" "$gen/src"
cp "$src"/package*.json "$gen/"
cp "$src"/tsconfig*.json "$gen/" 2>/dev/null || true
if [ ! -f "$gen/tsconfig.json" ]; then
  echo "no tsconfig.json in the generator copy: writing a minimal one (src -> lib, ES modules)"
  cat >"$gen/tsconfig.json" <<'JSON'
{
  "compilerOptions": {
    "target": "es2020", "module": "es2020", "moduleResolution": "node",
    "lib": ["es2020", "dom"], "outDir": "lib", "rootDir": "src",
    "esModuleInterop": true, "allowSyntheticDefaultImports": true,
    "skipLibCheck": true, "strict": false
  },
  "include": ["src/**/*.ts"]
}
JSON
fi
cd "$gen"
# --legacy-peer-deps: without the lock file npm 11 refuses @google/model-viewer 4.x's peer
# three@^0.183 beside the generator's three@^0.169 (ERESOLVE); render-goldens uses neither.
npm install --ignore-scripts --legacy-peer-deps --no-audit --no-fund >"$work/npm-install.log" 2>&1 ||
  { tail -20 "$work/npm-install.log" >&2; exit 1; }
npx tsc -p tsconfig.json >"$work/tsc.log" 2>&1 || echo "tsc reported type errors (see $work/tsc.log); its output is used"
[ -f lib/workflows/render-goldens.js ] || { cat "$work/tsc.log" >&2; exit 1; }

# 2. The assets where the generator's scenario paths point (../../../ from test/renderers/<name>/).
mkdir -p glTF-Sample-Assets/Models environments test/renderers/luz
ln -sfn "$shared/gltf/CesiumMan" glTF-Sample-Assets/Models/CesiumMan
ln -sfn "$shared/gltf/color_teapot_spheres.gltf" glTF-Sample-Assets/Models/color_teapot_spheres.gltf
ln -sfn "$shared/gltf/retroufo.glb" glTF-Sample-Assets/Models/retroufo.glb
ln -sfn "$shared/environments/newport_loft.hdr" environments/newport_loft.hdr

# 3. The config: the luz renderer only, three small scenarios (the format of test/config.json).
config() { # $1: the renderer's args as a JSON array
  cat <<JSON
{
  "renderers": [
    {
      "name": "luz",
      "description": "luz (Vulkan, Rust)",
      "command": {"executable": "$luz", "args": $1}
    }
  ],
  "scenarios": [
    {
      "name": "luz-CesiumMan",
      "model": "../../../glTF-Sample-Assets/Models/CesiumMan/glTF-Binary/CesiumMan.glb",
      "lighting": "../../../environments/newport_loft.hdr",
      "target": {"y": 0.75},
      "orbit": {"radius": 2},
      "dimensions": {"width": 256, "height": 256},
      "exclude": ["vray"]
    },
    {
      "name": "luz-color_teapot_spheres-skybox",
      "model": "../../../glTF-Sample-Assets/Models/color_teapot_spheres.gltf",
      "lighting": "../../../environments/newport_loft.hdr",
      "renderSkybox": true,
      "orbit": {"radius": 1.8, "theta": 20, "phi": 70},
      "dimensions": {"width": 256, "height": 256}
    },
    {
      "name": "luz-retroufo",
      "model": "../../../glTF-Sample-Assets/Models/retroufo.glb",
      "lighting": "../../../environments/newport_loft.hdr",
      "orbit": {"radius": 200, "theta": 35, "phi": 65},
      "dimensions": {"width": 256, "height": 192},
      "pt": {"numSamples": 64}
    }
  ]
}
JSON
}

# 4. The run, with the entry of docs/fidelity.md. `npm run render-goldens` already passes
# --config=./test/config.json, so the config goes there (adding `-c FILE` makes it an array).
config '["fidelity"]' >test/config.json
rm -rf test/goldens
echo
echo "== render-goldens, args [\"fidelity\"] (the renderer's working folder is $gen)"
start=$(date +%s%N)
set +e
npm run render-goldens -- -r luz 2>&1 | tee "$work/run.log"
status=${PIPESTATUS[0]}
set -e
end=$(date +%s%N)
echo
echo "render-goldens exit status $status, $(( (end - start) / 1000000 )) ms in all"
echo "per scenario (luz's own count, parse to PNG written):"
grep -E "^wrote .*luz-golden.png" "$work/run.log" | sed 's/^/  /' || true
echo "PNGs:"
fail=0
for s in luz-CesiumMan luz-color_teapot_spheres-skybox luz-retroufo; do
  f="test/goldens/$s/luz-golden.png"
  if [ -f "$f" ]; then
    printf '  %s  %s bytes  %s\n' "$gen/$f" "$(stat -c %s "$f")" "$(file -b "$f" | cut -d, -f1-3)"
  else
    echo "  MISSING $gen/$f"; fail=1
  fi
done
# renderSkybox false -> an RGBA PNG; true -> opaque RGB.
for s in luz-CesiumMan luz-retroufo; do
  file -b "test/goldens/$s/luz-golden.png" 2>/dev/null | grep -q RGBA ||
    { echo "  $s: expected an RGBA PNG (renderSkybox false)"; fail=1; }
done
[ "$status" -eq 0 ] && [ "$fail" -eq 0 ] || exit 1
echo "ok"
