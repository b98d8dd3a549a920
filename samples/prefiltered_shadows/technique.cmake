# The technique of this folder as a library: the sample (CMakeLists.txt) and shadowkit-report link the
# same code. Included by samples/CMakeLists.txt whenever the GL harness is built (also without GLFW).
add_library(technique_prefiltered_shadows STATIC ${CMAKE_CURRENT_LIST_DIR}/prefiltered_shadows.cpp)
target_include_directories(technique_prefiltered_shadows PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(technique_prefiltered_shadows PUBLIC shadowkit_app)
shadowkit_warnings(technique_prefiltered_shadows)
list(APPEND SHADOWKIT_TECHNIQUE_LIBS technique_prefiltered_shadows)
