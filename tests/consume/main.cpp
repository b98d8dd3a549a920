// A user program consuming shadowkit (used by the consume.* tests for add_subdirectory,
// find_package and vendoring a single header).
#include <shadowkit/infinite_projection.hpp>

#include <cstdio>

int main() {
    std::puts("shadowkit consumed");
    return 0;
}
