#!/usr/bin/env bash
# Installs what shadowkit's build, tests, samples and report need on Debian 12 (run as root,
# or with sudo available). It installs only missing packages and prints what it installs:
#   build:    cmake ninja-build g++ pkg-config
#   headers:  libglm-dev                       (the only dependency of the public headers)
#   tests:    doctest-dev glslang-dev glslang-tools
#   GL:       libepoxy-dev libegl-dev libegl-mesa0 libgl1-mesa-dri (Mesa llvmpipe, EGL surfaceless)
#   samples:  libglfw3-dev libstb-dev libimgui-dev xvfb xauth   (window, PNG, the Dear ImGui panel)
#   report:   libembree-dev libtbb-dev libassimp-dev   (ray-traced reference, mesh files)
#   bench:    libbenchmark-dev                     (Google Benchmark, samples/bench)
#   fuzzing:  clang libclang-rt-14-dev              (only with --fuzz)
set -euo pipefail
pkgs=(cmake ninja-build g++ pkg-config git
      libglm-dev doctest-dev glslang-dev glslang-tools
      libepoxy-dev libegl-dev libegl-mesa0 libgl1-mesa-dri
      libglfw3-dev libstb-dev libimgui-dev xvfb xauth
      libembree-dev libtbb-dev libassimp-dev libbenchmark-dev)
if [[ "${1:-}" == "--fuzz" ]]; then pkgs+=(clang libclang-rt-14-dev); fi
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#pkgs[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO=sudo; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
