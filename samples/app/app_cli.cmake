# The App's command line (samples/app/app.hpp), end to end on one sample: bad options, scenes,
# parameters, values and views are errors naming the valid ones (exit 2: the old viewer accepted a
# misspelled --param and ran with the default); --help lists the settings; every view renders headless
# (exit 77: no GL context, the test is skipped) and --param reaches the technique (the printed label).
# Inputs: SAMPLE (the executable), WORK (scratch directory).
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

function(expect_fail expected_text)
  execute_process(COMMAND ${SAMPLE} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 2)
    message(FATAL_ERROR "expected exit 2 for '${ARGN}', got ${rc}:\n${out}${err}")
  endif()
  string(FIND "${err}" "${expected_text}" pos)
  if(pos EQUAL -1)
    message(FATAL_ERROR "expected '${expected_text}' in the error for '${ARGN}', got:\n${err}")
  endif()
endfunction()

expect_fail("unknown option '--bogus'; valid: --scene NAME, --mesh FILE" --bogus)
expect_fail("unknown scene 'nosuch'; valid: contact, " --scene nosuch)
expect_fail("--scene wants a name" --scene)
expect_fail("unknown parameter 'nosuch'; valid: " --param nosuch=1)
expect_fail("--param wants name=value" --param novalue)
expect_fail("--frames wants a count" --frames 0)
expect_fail("--size wants WxH" --size 12)
expect_fail("unknown view 'nosuch'; valid: shaded, " --view nosuch)
expect_fail("mesh file not found" --mesh ${WORK}/missing.obj --headless ${WORK}/missing.png)

# the sample's own settings: a misspelled name or a value that is not one of them
execute_process(COMMAND ${SAMPLE} --help RESULT_VARIABLE rc OUTPUT_VARIABLE help ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT help MATCHES "--param ")
  message(FATAL_ERROR "--help: exit ${rc}, output:\n${help}${err}")
endif()
string(REGEX MATCH "\n--param ([a-z_]+)=([^ \n]+)" first "${help}")
set(name ${CMAKE_MATCH_1})
expect_fail("unknown parameter '${name}x'; valid: ${name}" --param ${name}x=1)
expect_fail("${name}" --param ${name}=not-a-value)

# every view, headless, and a setting that reaches the technique: its label is printed
string(REGEX MATCH "views: ([^\n]+)" v "${help}")
string(REPLACE ", " ";" views "${CMAKE_MATCH_1}")
string(REGEX MATCH "--param ${name}=([^| \n]+)[|]([^| \n]+)" opt "${help}")
# (quoted: an unquoted empty match unsets `value`, and if(value STREQUAL "") then compares the word
# "value": a sample whose first setting is a number got no value)
set(value "${CMAKE_MATCH_2}")
if(value STREQUAL "")
  string(REGEX MATCH "--param ${name}=<([^.]+)\\.\\." opt "${help}")
  set(value "${CMAKE_MATCH_1}")
endif()
set(i 0)
foreach(view ${views})
  execute_process(COMMAND ${SAMPLE} --headless ${WORK}/view${i}.png --scene stack --size 96x72 --frames 2
                          --view ${view} --param ${name}=${value}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 77)
    message(STATUS "no GL context: views not rendered (${err})")
    return()
  endif()
  if(NOT rc EQUAL 0 OR NOT EXISTS ${WORK}/view${i}.png)
    message(FATAL_ERROR "--view '${view}' failed (${rc}):\n${out}${err}")
  endif()
  string(FIND "${out}" "${name}=${value}" pos)
  if(pos EQUAL -1)
    message(FATAL_ERROR "--param ${name}=${value} did not reach the technique:\n${out}")
  endif()
  math(EXPR i "${i} + 1")
endforeach()
message(STATUS "app CLI ok: ${i} views, --param ${name}=${value}")
