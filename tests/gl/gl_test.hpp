// Shared by the GL tests: the context created by gl_main.cpp before any test runs.
#pragma once
#include "gl.hpp"

skgl::Context& gl_test_context();
