// doctest main for GL tests: creates the headless GL context first. When none can be had the
// executable prints the reason and exits with 77, which CTest reports as "skipped" (never passed).
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <cstdio>

#include "gl_test.hpp"

static std::unique_ptr<skgl::Context> g_context;

skgl::Context& gl_test_context() { return *g_context; }

int main(int argc, char** argv) {
    std::string why;
    g_context = skgl::create_context(why);
    if (!g_context) {
        std::printf("SKIPPED: no OpenGL 4.5 context: %s\n", why.c_str());
        return skgl::no_context_exit_code();  // 1 when SHADOWKIT_REQUIRE_GL is set (CI)
    }
    std::printf("GL renderer: %s | %s\n", g_context->renderer.c_str(), g_context->version.c_str());
    doctest::Context ctx(argc, argv);
    const int rc = ctx.run();
    g_context.reset();
    return rc;
}
