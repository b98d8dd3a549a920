// shadowkit-make-mesh OUT.obj: writes a (2,3) torus knot as a closed, consistently wound triangle
// mesh (OBJ, shared vertices) for the report's `--mesh` rows: curved self-shadowing tube, long
// silhouette loops, no file to download. 256 x 16 quads = 8192 triangles.
// shadowkit-make-mesh --bowl OUT.obj: an OPEN mesh instead, a hemispherical bowl (64 segments x 8
// rings, 960 triangles, outward winding, 64 boundary edges on its rim) tilted 30 degrees about z so
// a light above sees its outside and, through the opening, its inside: rays that enter through the
// hole leave through back faces (the open-mesh case of shadow volumes and penumbra wedges).
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

struct V3 {
    double x, y, z;
};
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V3 normalize(V3 a) { return a * (1.0 / std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z)); }

// the knot's centre line, lying in the x-z plane (y up)
V3 curve(double t) {
    const double p = 2.0, q = 3.0, r = 2.0 + std::cos(q * t);
    return {r * std::cos(p * t), 1.2 * std::sin(q * t) + 1.6, r * std::sin(p * t)};
}

// the bowl: centre (0, 1.4, 0), radius 1.2, opening up before the tilt; vertex 1 is the bottom pole
int write_bowl(std::FILE* f) {
    const int segments = 64, rings = 8;
    const double R = 1.2, half_pi = 1.5707963267948966, two_pi = 6.283185307179586, tilt = 0.5235987755982988;
    std::fprintf(f, "# open hemispherical bowl, %d triangles, %d boundary edges, written by shadowkit-make-mesh\n",
                 segments * (2 * rings - 1), segments);
    auto put = [&](double x, double y, double z) {  // tilt about z, then lift
        std::fprintf(f, "v %.6f %.6f %.6f\n", x * std::cos(tilt) - y * std::sin(tilt), x * std::sin(tilt) + y * std::cos(tilt) + 1.4, z);
    };
    put(0.0, -R, 0.0);
    for (int i = 1; i <= rings; ++i) {
        const double th = half_pi * i / rings;
        for (int j = 0; j < segments; ++j) {
            const double ph = two_pi * j / segments;
            put(R * std::sin(th) * std::cos(ph), -R * std::cos(th), R * std::sin(th) * std::sin(ph));
        }
    }
    auto v = [&](int i, int j) { return 2 + (i - 1) * segments + (j % segments); };  // ring i >= 1
    for (int j = 0; j < segments; ++j) std::fprintf(f, "f 1 %d %d\n", v(1, j), v(1, j + 1));  // normals point down/out
    for (int i = 1; i < rings; ++i)
        for (int j = 0; j < segments; ++j)
            std::fprintf(f, "f %d %d %d\nf %d %d %d\n", v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j), v(i + 1, j + 1), v(i, j + 1));
    return std::fclose(f) == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    const bool bowl = argc == 3 && std::string(argv[1]) == "--bowl";
    if (argc != 2 && !bowl) {
        std::fprintf(stderr, "usage: %s [--bowl] OUT.obj\n", argv[0]);
        return 2;
    }
    if (bowl) {
        std::FILE* bf = std::fopen(argv[2], "w");
        if (!bf) {
            std::fprintf(stderr, "%s: cannot write %s\n", argv[0], argv[2]);
            return 1;
        }
        return write_bowl(bf);
    }
    const int along = 256, around = 16;
    const double tube = 0.45, two_pi = 6.283185307179586;
    std::FILE* f = std::fopen(argv[1], "w");
    if (!f) {
        std::fprintf(stderr, "%s: cannot write %s\n", argv[0], argv[1]);
        return 1;
    }
    std::fprintf(f, "# (2,3) torus knot, %d triangles, written by shadowkit-make-mesh\n", 2 * along * around);
    for (int i = 0; i < along; ++i) {
        const double t = two_pi * i / along, h = 1e-4;
        const V3 c = curve(t), tangent = normalize(curve(t + h) - curve(t - h));
        // a frame around the tangent from the (non-parallel here) curvature direction
        const V3 accel = curve(t + h) + curve(t - h) - c * 2.0;
        const V3 b = normalize(cross(tangent, accel)), n = cross(b, tangent);
        for (int j = 0; j < around; ++j) {
            const double a = two_pi * j / around;
            const V3 p = c + (n * std::cos(a) + b * std::sin(a)) * tube;
            std::fprintf(f, "v %.6f %.6f %.6f\n", p.x, p.y, p.z);
        }
    }
    // quads (i, j) (i + 1, j) (i + 1, j + 1) (i, j + 1), wrapping both ways: outward winding
    for (int i = 0; i < along; ++i)
        for (int j = 0; j < around; ++j) {
            const int a = 1 + i * around + j, b = 1 + ((i + 1) % along) * around + j;
            const int c = 1 + ((i + 1) % along) * around + (j + 1) % around, d = 1 + i * around + (j + 1) % around;
            std::fprintf(f, "f %d %d %d\nf %d %d %d\n", a, d, c, a, c, b);
        }
    return std::fclose(f) == 0 ? 0 : 1;
}
