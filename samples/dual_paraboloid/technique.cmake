# The technique of this folder as a library: the sample (CMakeLists.txt) and shadowkit-report link the
# same code. Included by samples/CMakeLists.txt whenever the GL harness is built (also without GLFW).
add_library(technique_dual_paraboloid STATIC ${CMAKE_CURRENT_LIST_DIR}/dual_paraboloid.cpp)
target_include_directories(technique_dual_paraboloid PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(technique_dual_paraboloid PUBLIC shadowkit_app)
shadowkit_warnings(technique_dual_paraboloid)
list(APPEND SHADOWKIT_TECHNIQUE_LIBS technique_dual_paraboloid)
