// doctest main for the Vulkan and HLSL tests: makes the Vulkan context (validation layer on) first.
// Without a Vulkan device, loader or layer the executable prints why and exits with 77 (CTest:
// skipped), or 1 where SHADOWKIT_REQUIRE_GL is set (CI). After the tests, any warning or error the
// validation layer reported fails the run, with the messages.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "vk_harness.hpp"

static skvk::Context g_context;

skvk::Context& skvk::vk_test_context() { return g_context; }

int main(int argc, char** argv) {
    bool no_device = false;
    const std::string why = skvk::create_context(g_context, true, no_device);
    if (!why.empty()) {
        const char* req = std::getenv("SHADOWKIT_REQUIRE_GL");
        const bool required = req && std::strcmp(req, "0") != 0 && *req;
        skvk::destroy_context(g_context);
        if (no_device && !required) {
            std::printf("SKIPPED: no Vulkan 1.1 device with the validation layer: %s\n", why.c_str());
            return 77;
        }
        std::printf("FAILED: no Vulkan context: %s%s\n", why.c_str(), required ? " (SHADOWKIT_REQUIRE_GL is set)" : "");
        return 1;
    }
    std::printf("Vulkan device: %s (validation layer on)\n", g_context.device_name.c_str());
    doctest::Context ctx(argc, argv);
    int rc = ctx.run();
    skvk::destroy_context(g_context);
    const std::size_t n = skvk::unexpected_message_count();
    std::printf("validation-layer warnings and errors: %zu (and %zu provoked on purpose)\n", n, skvk::message_count() - n);
    if (n != 0) {
        std::printf("%s", skvk::messages().c_str());
        rc = rc ? rc : 1;
    }
    return rc;
}
