#!/usr/bin/env bash
# Installs everything luz needs on Debian 12 and builds the merged static shaderc archive.
# Idempotent: when all is in place it only checks and returns in about a second.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

pkgs=(mesa-vulkan-drivers vulkan-validationlayers libvulkan-dev xvfb xauth glslang-dev libshaderc-dev spirv-tools fonts-dejavu-core)
# chromium: luz's own tests load the golden report in a real browser (tests/golden_cmd.rs). Building
# and running luz elsewhere (the CI recipe in docs/golden.md) does not need it: LUZ_NO_BROWSER=1.
[ -n "${LUZ_NO_BROWSER:-}" ] || pkgs+=(chromium)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Debian's libshaderc.so leaves glslang symbols unresolved; merging the static archives links in seconds.
libdir=/usr/lib/x86_64-linux-gnu
out="$root/.deps/shaderc"
archive="$out/libshaderc_combined.a"
parts=(libshaderc_combined.a libglslang.a libMachineIndependent.a libGenericCodeGen.a libOSDependent.a
       libOGLCompiler.a libSPIRV.a libglslang-default-resource-limits.a libSPIRV-Tools-opt.a libSPIRV-Tools.a)
if [ ! -s "$archive" ]; then
  echo "setup: merging shaderc static archives into $archive"
  mkdir -p "$out"
  script="$out/merge.mri"
  {
    echo "CREATE $archive.tmp"
    for p in "${parts[@]}"; do echo "ADDLIB $libdir/$p"; done
    echo "SAVE"
    echo "END"
  } >"$script"
  ar -M <"$script"
  ranlib "$archive.tmp"
  mv "$archive.tmp" "$archive"
fi

# Mitsuba 3 (issue 37's cross-check, tests/crosscheck.rs, scripts/crosscheck.sh) from PyPI into a
# venv of its own. Only its `scalar_rgb` variant is used (`llvm_ad_rgb` aborts on some CPUs with
# "LLVM ERROR: Cannot select fmaximum"). Without network the install fails: one line, and the
# cross-check group then skips visibly.
venv="$root/.deps/mitsuba-venv"
if ! "$venv/bin/python" -c "import mitsuba" 2>/dev/null; then
  mkdir -p "$root/.deps"
  echo "setup: installing Mitsuba 3 into $venv"
  if ! { python3 -m venv "$venv" && "$venv/bin/pip" install -q --disable-pip-version-check mitsuba; } >"$root/.deps/mitsuba-install.log" 2>&1; then
    echo "setup: Mitsuba 3 not installed (see .deps/mitsuba-install.log); the cross-check tests will skip"
  fi
fi
