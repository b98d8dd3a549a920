# The technique of this folder as a library: the sample (CMakeLists.txt) and shadowkit-report link the
# same code. Included by samples/CMakeLists.txt whenever the GL harness is built (also without GLFW).
add_library(technique_shadow_volumes STATIC ${CMAKE_CURRENT_LIST_DIR}/shadow_volumes.cpp)
target_include_directories(technique_shadow_volumes PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(technique_shadow_volumes PUBLIC shadowkit_app)
shadowkit_warnings(technique_shadow_volumes)
list(APPEND SHADOWKIT_TECHNIQUE_LIBS technique_shadow_volumes)
