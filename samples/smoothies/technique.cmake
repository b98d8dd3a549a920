# The technique of this folder as a library: the sample (CMakeLists.txt) and shadowkit-report link the
# same code. Included by samples/CMakeLists.txt whenever the GL harness is built (also without GLFW).
add_library(technique_smoothies STATIC ${CMAKE_CURRENT_LIST_DIR}/smoothies.cpp)
target_include_directories(technique_smoothies PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(technique_smoothies PUBLIC shadowkit_app)
shadowkit_warnings(technique_smoothies)
list(APPEND SHADOWKIT_TECHNIQUE_LIBS technique_smoothies)
