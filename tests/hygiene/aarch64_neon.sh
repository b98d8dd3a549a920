#!/usr/bin/env bash
# The NEON branch of silhouette.hpp's cached-plane facing (SHADOWKIT_SIL_NEON) on AArch64, which no
# x86 build compiles (issue 27 item 19):
#   1. every public header in one translation unit, cross-compiled to an object with Debian's
#      aarch64-linux-gnu-g++ (-std=c++17 -O2 -c, the project's warnings as errors), with functions
#      that call the NEON facing so it is generated, and an #error unless the NEON branch is the one
#      selected;
#   2. when qemu-aarch64 is present: the unit tests of the cached planes (tests/unit/
#      test_silhouette_planes.cpp: facing bits identical to the exact path and to a big-integer
#      reference, the filter's error bound) and of the exact facing (test_silhouette.cpp: its
#      expansion stage takes its products by FMA there, by Dekker's split on x86-64 without FMA)
#      cross-compiled and run under it.
# Without the cross compiler: skipped (exit 77), unless SHADOWKIT_REQUIRE_AARCH64 is set (.ci/run
# sets it: there it must run). Usage: aarch64_neon.sh SOURCE_DIR WORK_DIR
set -euo pipefail
src=$1
work=$2
cxx=${SHADOWKIT_AARCH64_CXX:-aarch64-linux-gnu-g++}
if ! command -v "$cxx" >/dev/null 2>&1; then
  if [[ -n "${SHADOWKIT_REQUIRE_AARCH64:-}" ]]; then
    echo "aarch64_neon: $cxx not found and SHADOWKIT_REQUIRE_AARCH64 is set (Debian: g++-aarch64-linux-gnu)" >&2
    exit 1
  fi
  echo "aarch64_neon: skipped, $cxx not found (Debian: g++-aarch64-linux-gnu; cmake/install-deps.sh installs it)"
  exit 77
fi
rm -rf "$work"
mkdir -p "$work/inc"
# GLM and doctest are header-only and the same on every architecture: only they come from the host
# (the host's /usr/include itself would bring x86 C library headers)
glm_dir=$(dirname "$(find /usr/include /usr/local/include -maxdepth 2 -type d -name glm 2>/dev/null | head -1)")
ln -s "$glm_dir/glm" "$work/inc/glm"
[[ -d /usr/include/doctest ]] && ln -s /usr/include/doctest "$work/inc/doctest"
flags=(-std=c++17 -O2 -Wall -Wextra -Wpedantic -Wconversion -Wshadow -Werror -isystem "$work/inc" -I "$src/include")
{
  for h in "$src"/include/shadowkit/*.hpp; do echo "#include <shadowkit/$(basename "$h")>"; done
  cat <<'CPP'
#if !defined(SHADOWKIT_SIL_NEON) || defined(SHADOWKIT_SIL_SSE2)
#error "the NEON branch of silhouette.hpp is not the one selected"
#endif
// generated, not only parsed: the NEON facing and its chunked entry point
std::size_t neon_facing(const shadowkit::SilhouetteAdjacency& adj, const shadowkit::SilhouettePlanes& pl,
                        const glm::vec4& light, std::uint8_t* facing, std::size_t n) {
    return shadowkit::silhouette_compute_facing_planes(adj, pl, light, facing, n).lit_faces;
}
CPP
} > "$work/neon_tu.cpp"
"$cxx" "${flags[@]}" -c "$work/neon_tu.cpp" -o "$work/neon_tu.o"
echo "aarch64_neon: every header compiles for AArch64 with the NEON branch selected ($("$cxx" -dumpfullversion))"
if ! command -v qemu-aarch64 >/dev/null 2>&1; then
  echo "aarch64_neon: qemu-aarch64 not found: the NEON tests are compiled only"
  for t in test_silhouette_planes test_silhouette; do
    "$cxx" "${flags[@]}" -c "$src/tests/unit/$t.cpp" -o "$work/$t.o"
  done
  exit 0
fi
for t in test_silhouette_planes test_silhouette; do
  "$cxx" "${flags[@]}" -static "$src/tests/doctest_main.cpp" "$src/tests/unit/$t.cpp" -o "$work/$t" -pthread
  qemu-aarch64 "$work/$t"
  echo "aarch64_neon: $t passed on AArch64 (NEON; the exact stages' FMA products) under qemu"
done
