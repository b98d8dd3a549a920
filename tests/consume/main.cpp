// A user program consuming shadowkit (used by the consume.* tests for add_subdirectory,
// find_package and vendoring a single header): builds an infinite projection and checks the
// closed form P[2][3] = -1, P[2][2] = -1 (GL clip depth, no epsilon).
#include <shadowkit/infinite_projection.hpp>

#include <cstdio>

int main() {
    const shadowkit::ProjectionResult p = shadowkit::projection_perspective_infinite(1.0f, 1.5f, 0.1f);
    if (p.status != shadowkit::Status::Ok || p.matrix[2][3] != -1.0f || p.matrix[2][2] != -1.0f) {
        std::puts("shadowkit consumed, but the infinite projection is wrong");
        return 1;
    }
    std::puts("shadowkit consumed");
    return 0;
}
