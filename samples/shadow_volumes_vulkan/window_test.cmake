# The windowed path (GLFW surface, swapchain, present) on a virtual X display: 3 frames of a scene in a
# window, the last presented image saved (--window --out), must be byte-identical to the headless
# picture of the same scene, size and light (the PNG of the same pixels). Prints SKIPPED (the test's
# SKIP_REGULAR_EXPRESSION) when the headless run finds no Vulkan device (exit 77).
# Inputs: SAMPLE, XVFB_RUN, WORK.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
set(args --scene stack --frames 3 --size 160x120)
execute_process(COMMAND ${SAMPLE} ${args} --headless ${WORK}/headless.png RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 77)
  message("SKIPPED: no Vulkan device: ${err}")
  return()
elseif(NOT rc EQUAL 0)
  message(FATAL_ERROR "headless run failed (${rc}):\n${out}${err}")
endif()
execute_process(COMMAND ${XVFB_RUN} -a ${SAMPLE} ${args} --window --out ${WORK}/window.png
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "windowed run failed (${rc}):\n${out}${err}")
endif()
message("${out}")
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK}/headless.png ${WORK}/window.png RESULT_VARIABLE same)
if(NOT same EQUAL 0)
  message(FATAL_ERROR "the window's last image differs from the headless picture (${WORK}/window.png, ${WORK}/headless.png)")
endif()
message(STATUS "window == headless, validation layer clean")
