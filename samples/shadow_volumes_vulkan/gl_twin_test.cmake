# The Vulkan sample against its GL twin: for every built-in scene, sample_shadow_volumes (GL, llvmpipe)
# writes its "stencil counts" view (z-fail, reversed-Z P_inf, no scissor or depth bounds: the Vulkan
# sample's settings; 3 frames at 160 x 120, the same light turn) and the test executable renders the
# same frames on Vulkan and compares the two stencils pixel by pixel: in a volume or not, >= 99%.
# Prints SKIPPED (the test's SKIP_REGULAR_EXPRESSION) without a GL context or a Vulkan device.
# Inputs: GL_SAMPLE, VK_TEST, WORK, SCENES (;-separated).
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
set(failed "")
foreach(scene ${SCENES})
  execute_process(COMMAND ${GL_SAMPLE} --scene ${scene} --headless ${WORK}/${scene}.png --view "stencil counts" --frames 3
                          --size 160x120 --param method=zfail --param projection=reversed --param scissor=off
                          --param depth_bounds=off
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 77)
    message("SKIPPED: no GL context: ${err}")
    return()
  elseif(NOT rc EQUAL 0)
    message(FATAL_ERROR "GL sample on ${scene} failed (${rc}):\n${out}${err}")
  endif()
  execute_process(COMMAND ${VK_TEST} --gl-stencil ${WORK}/${scene}.png ${scene} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 77)
    message("SKIPPED: no Vulkan device: ${out}")
    return()
  endif()
  message("${out}")
  if(NOT rc EQUAL 0)
    list(APPEND failed ${scene})
  endif()
endforeach()
if(failed)
  message(FATAL_ERROR "the Vulkan stencil differs from the GL twin's on: ${failed}")
endif()
