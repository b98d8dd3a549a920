# The technique of this folder as a library: the sample (CMakeLists.txt) and shadowkit-report link the
# same code. Included by samples/CMakeLists.txt whenever the GL harness is built (also without GLFW).
add_library(technique_sampled_area_light STATIC ${CMAKE_CURRENT_LIST_DIR}/sampled_area_light.cpp)
target_include_directories(technique_sampled_area_light PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(technique_sampled_area_light PUBLIC shadowkit_app)
shadowkit_warnings(technique_sampled_area_light)
list(APPEND SHADOWKIT_TECHNIQUE_LIBS technique_sampled_area_light)
