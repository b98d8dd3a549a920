# The technique of this folder as a library: the sample (CMakeLists.txt) and shadowkit-report link the
# same code. It builds on the shadow_volumes sample's class (the hard shadow), as a user would compose two
# samples. Included by samples/CMakeLists.txt whenever the GL harness is built (also without GLFW).
add_library(technique_penumbra_wedges STATIC ${CMAKE_CURRENT_LIST_DIR}/penumbra_wedges.cpp)
target_include_directories(technique_penumbra_wedges PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(technique_penumbra_wedges PUBLIC technique_shadow_volumes shadowkit_app)
shadowkit_warnings(technique_penumbra_wedges)
list(APPEND SHADOWKIT_TECHNIQUE_LIBS technique_penumbra_wedges)
