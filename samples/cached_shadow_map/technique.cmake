# The technique of this folder as a library: the sample (CMakeLists.txt) and shadowkit-report link the
# same code. Included by samples/CMakeLists.txt whenever the GL harness is built (also without GLFW).
add_library(technique_cached_shadow_map STATIC ${CMAKE_CURRENT_LIST_DIR}/cached_shadow_map.cpp)
target_include_directories(technique_cached_shadow_map PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(technique_cached_shadow_map PUBLIC shadowkit_app)
shadowkit_warnings(technique_cached_shadow_map)
list(APPEND SHADOWKIT_TECHNIQUE_LIBS technique_cached_shadow_map)
