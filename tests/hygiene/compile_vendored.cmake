# Copies one public header alone into an empty directory and compiles a translation unit that
# includes it, with only GLM on the include path: the "vendor one header" promise.
# Inputs: CXX, HEADER, STD, GLM_INCLUDE, FLAGS (;-list), WORK.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
get_filename_component(name ${HEADER} NAME)
file(COPY ${HEADER} DESTINATION ${WORK})
file(WRITE ${WORK}/main.cpp "#include \"${name}\"\n#include \"${name}\"\nint main() { return 0; }\n")
set(inc "")
foreach(d ${GLM_INCLUDE})
  # /usr/include is already a system directory; naming it again breaks #include_next in libstdc++
  if(NOT d STREQUAL "/usr/include")
    list(APPEND inc -isystem ${d})
  endif()
endforeach()
execute_process(
  COMMAND ${CXX} -std=c++${STD} ${FLAGS} -Werror ${inc} main.cpp -o vendored
  WORKING_DIRECTORY ${WORK} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${name} does not compile alone (C++${STD}):\n${out}${err}")
endif()
message(STATUS "${name}: compiles alone with only GLM, C++${STD}")
