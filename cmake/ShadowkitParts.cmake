# Which parts of shadowkit's own tree can be built with what is installed, and why not.
#   header tests (unit, glsl, hygiene, consume, docs)  GLM + doctest + glslang
#   GL harness (GL tests, samples, report)              epoxy + EGL, stb, and for now Embree + assimp + zlib
#                                                       (the GL tests compare against the report's
#                                                       Embree reference)
#   samples                                             + GLFW (window)
#   samples' panel                                      + Dear ImGui (libimgui-dev: pkg-config imgui, the
#                                                         GLFW and OpenGL 3 backends in libimgui.a); without
#                                                         it the sample windows have no panel
#   report, bench                                       + Embree, assimp; Google Benchmark
# A part whose dependencies are missing is skipped with a reason, unless SHADOWKIT_REQUIRE_ALL is ON
# (the presets set it: the README's commands install everything and must build everything).
# Sets SHADOWKIT_HAVE_<PART> and prints one line per part.
set(SHADOWKIT_PARTS_SUMMARY "")

function(_sk_part name wanted ok reason)
  if(NOT wanted)
    set(line "${name}: off (option)")
  elseif(ok)
    set(line "${name}: on")
  else()
    if(SHADOWKIT_REQUIRE_ALL)
      message(FATAL_ERROR "shadowkit: ${name} cannot be built: ${reason} (SHADOWKIT_REQUIRE_ALL is ON; run cmake/install-deps.sh)")
    endif()
    set(line "${name}: skipped, ${reason}")
  endif()
  message(STATUS "shadowkit parts - ${line}")
endfunction()

# Appends "<reason> " to the caller's _why when `found` (a variable's name) is false.
macro(_sk_need found reason)
  if(NOT ${found})
    string(APPEND _why "${reason} ")
  endif()
endmacro()

# header tests
set(SHADOWKIT_HAVE_TESTS OFF)
if(SHADOWKIT_BUILD_TESTS)
  find_package(doctest CONFIG QUIET)
  find_package(glslang CONFIG QUIET)
  find_package(Threads)
  set(_why "")
  _sk_need(doctest_FOUND "doctest not found (Debian: doctest-dev)")
  _sk_need(glslang_FOUND "glslang not found (Debian: glslang-dev glslang-tools)")
  if(_why STREQUAL "")
    set(SHADOWKIT_HAVE_TESTS ON)
  endif()
  _sk_part("header tests (unit, glsl, hygiene, consume, docs)" ON "${SHADOWKIT_HAVE_TESTS}" "${_why}")
endif()

# the GL harness
set(SHADOWKIT_HAVE_HARNESS OFF)
if(SHADOWKIT_BUILD_GL_TESTS OR SHADOWKIT_BUILD_SAMPLES OR SHADOWKIT_BUILD_REPORT)
  find_package(PkgConfig QUIET)
  if(PkgConfig_FOUND)
    pkg_check_modules(EPOXY QUIET IMPORTED_TARGET GLOBAL epoxy)
  endif()
  find_path(STB_INCLUDE_DIR stb_image_write.h PATH_SUFFIXES stb)
  find_package(embree 3 CONFIG QUIET)
  find_package(assimp CONFIG QUIET)
  find_package(ZLIB QUIET)
  find_package(Threads)
  set(_why "")
  _sk_need(EPOXY_FOUND "libepoxy not found (Debian: libepoxy-dev libegl-dev)")
  _sk_need(STB_INCLUDE_DIR "stb not found (Debian: libstb-dev)")
  _sk_need(embree_FOUND "Embree not found (Debian: libembree-dev)")
  _sk_need(assimp_FOUND "assimp not found (Debian: libassimp-dev)")
  _sk_need(ZLIB_FOUND "zlib not found (Debian: zlib1g-dev)")
  if(_why STREQUAL "")
    set(SHADOWKIT_HAVE_HARNESS ON)
  endif()
  set(SHADOWKIT_HARNESS_WHY "${_why}")
  _sk_part("GL tests (epoxy, EGL; Embree reference)" "${SHADOWKIT_BUILD_GL_TESTS}" "${SHADOWKIT_HAVE_HARNESS}" "${_why}")
  _sk_part("report (Embree, assimp, epoxy)" "${SHADOWKIT_BUILD_REPORT}" "${SHADOWKIT_HAVE_HARNESS}" "${_why}")
endif()

# samples
set(SHADOWKIT_HAVE_SAMPLES OFF)
if(SHADOWKIT_BUILD_SAMPLES)
  find_package(glfw3 CONFIG QUIET)
  set(_why "${SHADOWKIT_HARNESS_WHY}")
  _sk_need(glfw3_FOUND "GLFW not found (Debian: libglfw3-dev)")
  if(_why STREQUAL "")
    set(SHADOWKIT_HAVE_SAMPLES ON)
  endif()
  _sk_part("samples (GLFW, epoxy)" ON "${SHADOWKIT_HAVE_SAMPLES}" "${_why}")
endif()

# the samples' panel (Dear ImGui): optional, the windows work without it
set(SHADOWKIT_HAVE_IMGUI OFF)
if(SHADOWKIT_HAVE_SAMPLES)
  pkg_check_modules(IMGUI QUIET IMPORTED_TARGET GLOBAL imgui)
  set(_why "")
  if(NOT IMGUI_FOUND)
    set(_why "Dear ImGui not found (Debian: libimgui-dev): the sample windows have no panel")
  else()
    find_file(SHADOWKIT_IMGUI_GLFW_BACKEND backends/imgui_impl_glfw.h PATHS ${IMGUI_INCLUDE_DIRS} NO_DEFAULT_PATH)
    if(NOT SHADOWKIT_IMGUI_GLFW_BACKEND)
      set(_why "Dear ImGui has no GLFW backend header (backends/imgui_impl_glfw.h): the sample windows have no panel")
    else()
      set(SHADOWKIT_HAVE_IMGUI ON)
    endif()
  endif()
  _sk_part("samples' panel (Dear ImGui)" ON "${SHADOWKIT_HAVE_IMGUI}" "${_why}")
endif()

# the Vulkan and HLSL tests (labels vulkan, hlsl): the header tests' doctest + glslang, and the Vulkan
# loader and headers; to run, a Vulkan driver (lavapipe) and the Khronos validation layer
set(SHADOWKIT_HAVE_VULKAN OFF)
if(SHADOWKIT_BUILD_VULKAN_TESTS AND SHADOWKIT_BUILD_TESTS)
  find_package(Vulkan QUIET)
  set(_why "")
  if(NOT SHADOWKIT_HAVE_TESTS)
    string(APPEND _why "the header tests' doctest and glslang are missing ")
  endif()
  _sk_need(Vulkan_FOUND "Vulkan loader and headers not found (Debian: libvulkan-dev)")
  if(Vulkan_FOUND)
    file(GLOB _sk_icds /usr/share/vulkan/icd.d/*.json /etc/vulkan/icd.d/*.json /usr/local/share/vulkan/icd.d/*.json)
    file(GLOB _sk_layer /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json
                        /etc/vulkan/explicit_layer.d/VkLayer_khronos_validation.json
                        /usr/local/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json)
    _sk_need(_sk_icds "no Vulkan driver (Debian: mesa-vulkan-drivers, lavapipe)")
    _sk_need(_sk_layer "the Khronos validation layer not found (Debian: vulkan-validationlayers)")
  endif()
  if(_why STREQUAL "")
    set(SHADOWKIT_HAVE_VULKAN ON)
  endif()
  _sk_part("Vulkan tests (Vulkan loader, lavapipe, validation layer; glslang)" ON "${SHADOWKIT_HAVE_VULKAN}" "${_why}")
endif()
