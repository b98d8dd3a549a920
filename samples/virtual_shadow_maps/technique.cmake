# The technique of this folder as a library: the sample (CMakeLists.txt) and shadowkit-report link the
# same code. Included by samples/CMakeLists.txt whenever the GL harness is built (also without GLFW).
add_library(technique_virtual_shadow_maps STATIC ${CMAKE_CURRENT_LIST_DIR}/virtual_shadow_maps.cpp)
target_include_directories(technique_virtual_shadow_maps PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(technique_virtual_shadow_maps PUBLIC shadowkit_app)
shadowkit_warnings(technique_virtual_shadow_maps)
list(APPEND SHADOWKIT_TECHNIQUE_LIBS technique_virtual_shadow_maps)
