# The technique of this folder as a library (the sample links it; the report's PRT section uses
# prt_scene.hpp only). Included by samples/CMakeLists.txt whenever the GL harness is built (Embree is
# part of it: the transfer's visibility).
add_library(technique_prt STATIC ${CMAKE_CURRENT_LIST_DIR}/prt.cpp)
target_include_directories(technique_prt PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(technique_prt PUBLIC shadowkit_app embree Threads::Threads)
shadowkit_warnings(technique_prt)
list(APPEND SHADOWKIT_TECHNIQUE_LIBS technique_prt)
