// Silhouette maps (Sen, Cammarano & Hanrahan 2003): point cases, conservative rasterization,
// reconstruction against exact straight and curved boundaries (error in texels), the multi-edge
// failure and its fallback, occlusion, projection and stiff input.
#include <doctest/doctest.h>

#include <shadowkit/silhouette_map.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <set>
#include <vector>

namespace sk = shadowkit;

namespace {

// Exact 2D occluder in texel space: inside = shadowed. Edges are its boundary (silhouette).
struct Shape {
    std::vector<glm::vec2> poly;  // closed polygon, CCW (or a half-plane when half_plane)
    bool half_plane = false;
    glm::vec2 p0{0.f}, n{0.f};  // half-plane: shadowed where dot(x - p0, n) < 0
    bool inside(glm::vec2 x) const {
        if (half_plane) return glm::dot(x - p0, n) < 0.f;
        bool in = false;  // even-odd
        for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
            const glm::vec2 a = poly[i], b = poly[j];
            if ((a.y > x.y) != (b.y > x.y) && x.x < (b.x - a.x) * (x.y - a.y) / (b.y - a.y) + a.x) in = !in;
        }
        return in;
    }
    double distance(glm::vec2 x) const {
        if (half_plane) return std::abs(double(glm::dot(x - p0, n)));
        double d = 1e30;
        for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
            const glm::dvec2 a(poly[j]), b(poly[i]), p(x);
            const glm::dvec2 ab = b - a;
            const double t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
            d = std::min(d, glm::length(p - (a + t * ab)));
        }
        return d;
    }
};

struct Map {
    int W, H;
    std::vector<float> depth;
    std::vector<glm::vec2> pts;
    std::vector<std::uint8_t> wts;
    sk::SilmapBuildResult br;
};

// Depth map of the shape (occluder 0.2, receiver 1.0) and its silhouette map from `edges`.
Map build(const Shape& s, int W, int H, const std::vector<sk::SilmapEdge>& edges) {
    Map m{W, H, {}, {}, {}, {}};
    m.depth.resize(std::size_t(W) * std::size_t(H));
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i)
            m.depth[std::size_t(j) * std::size_t(W) + std::size_t(i)] =
                s.inside(glm::vec2(float(i) + 0.5f, float(j) + 0.5f)) ? 0.2f : 1.0f;
    m.pts.resize(m.depth.size());
    m.wts.resize(m.depth.size());
    m.br = sk::silmap_build(edges.data(), edges.size(), glm::uvec2(W, H), nullptr, 0.f, m.pts.data(), m.pts.size(),
                            m.wts.data(), m.wts.size());
    return m;
}

struct ErrorStats {
    double max_err = 0.0, mean_err = 0.0, wrong_fraction = 0.0;
    double max_err_claim = 0.0;  // over lookups the paper's claim covers: not a fallback (one curve per texel)
    double p99 = 0.0;
    std::size_t samples = 0, wrong = 0, fallbacks = 0;
};

// Samples jittered points in every cell of [lo, hi) and records the distance (texels) from each
// misclassified point to the true boundary. `silmap` false: the plain nearest-sample map.
ErrorStats measure(const Shape& s, const Map& m, bool silmap, int lo, int hi, int per_cell, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.f, 1.f);
    ErrorStats e;
    std::vector<double> errs;
    for (int j = lo; j < hi; ++j)
        for (int i = lo; i < hi; ++i)
            for (int k = 0; k < per_cell; ++k) {
                const glm::vec2 q(float(i) + u(rng), float(j) + u(rng));
                const bool truth_lit = !s.inside(q);
                bool lit, fb = false;
                if (silmap) {
                    const sk::SilmapLookup l = sk::silmap_lookup(m.pts.data(), m.wts.data(), m.depth.data(),
                                                                 glm::uvec2(m.W, m.H), q, 0.5f, 0.f);
                    lit = l.lit;
                    e.fallbacks += l.fallback ? 1 : 0;
                    fb = l.fallback;
                } else {
                    lit = sk::silmap_plain_lookup(m.depth.data(), glm::uvec2(m.W, m.H), q, 0.5f, 0.f).lit;
                }
                ++e.samples;
                if (lit != truth_lit) {
                    ++e.wrong;
                    const double d = s.distance(q);
                    errs.push_back(d);
                    e.max_err = std::max(e.max_err, d);
                    if (!fb) e.max_err_claim = std::max(e.max_err_claim, d);
                    e.mean_err += d;
                }
            }
    if (e.wrong) e.mean_err /= double(e.wrong);
    e.wrong_fraction = double(e.wrong) / double(e.samples);
    if (!errs.empty()) {
        std::sort(errs.begin(), errs.end());
        e.p99 = errs[std::min(errs.size() - 1, std::size_t(0.99 * double(errs.size())))];
    }
    return e;
}

// Polygon boundary as silhouette edges, each split into `splits` collinear pieces (vertices inside cells).
std::vector<sk::SilmapEdge> poly_edges(const std::vector<glm::vec2>& poly, int splits) {
    std::vector<sk::SilmapEdge> out;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const glm::vec2 a = poly[i], b = poly[(i + 1) % poly.size()];
        for (int k = 0; k < splits; ++k) {
            sk::SilmapEdge e;
            e.a = a + (b - a) * (float(k) / float(splits));
            e.b = a + (b - a) * (float(k + 1) / float(splits));
            out.push_back(e);
        }
    }
    return out;
}

}  // namespace

TEST_CASE("point selection: the paper's four cases") {
    // cell (3, 4) is the square [3.5, 4.5] x [4.5, 5.5]
    const glm::ivec2 c(3, 4);
    // case 1: endpoint inside
    sk::SilmapPoint p = sk::silmap_select_point({3.7f, 4.9f}, {10.f, 10.f}, c);
    CHECK(p.kase == sk::SilmapCase::VertexInside);
    CHECK(p.local.x == doctest::Approx(0.2f));
    CHECK(p.local.y == doctest::Approx(0.4f));
    CHECK(p.weight == 1);  // one border crossing
    // both endpoints inside: a, no border crossing
    p = sk::silmap_select_point({3.6f, 4.6f}, {3.9f, 5.2f}, c);
    CHECK(p.kase == sk::SilmapCase::VertexInside);
    CHECK(p.weight == 0);
    // case 3: horizontal line through the middle crosses both diagonals -> midpoint (0.5, 0.3)... at y = 0.3
    p = sk::silmap_select_point({0.f, 4.8f}, {10.f, 4.8f}, c);
    CHECK(p.kase == sk::SilmapCase::TwoIntersections);
    CHECK(p.local.x == doctest::Approx(0.5f));
    CHECK(p.local.y == doctest::Approx(0.3f));
    CHECK(p.weight == 2);
    // case 2: a line cutting off the (1,1) corner crosses only the diagonal (0,0)-(1,1)
    p = sk::silmap_select_point({4.5f - 0.3f, 5.6f}, {4.6f, 5.5f - 0.3f}, c);  // local (0.7,1.1)-(1.1,0.7)
    CHECK(p.kase == sk::SilmapCase::OneIntersection);
    CHECK(p.local.x == doctest::Approx(0.9f));
    CHECK(p.local.y == doctest::Approx(0.9f));
    // case 4: a conservative fragment the edge misses (passes outside the corner)
    p = sk::silmap_select_point({4.4f, 5.7f}, {4.7f, 5.4f}, c);
    CHECK(p.kase == sk::SilmapCase::NoIntersection);
    CHECK(p.weight == 0);
}

TEST_CASE("conservative rasterization covers every crossed cell (brute force, 3000 random segments)") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-4.f, 36.f);
    std::vector<glm::ivec2> cells(4096);
    std::size_t missing = 0, extra_far = 0, total = 0;
    for (int it = 0; it < 3000; ++it) {
        glm::vec2 a(u(rng), u(rng)), b(u(rng), u(rng));
        if (it % 10 == 0) b.y = a.y;  // axis-aligned
        if (it % 10 == 1) b.x = a.x;
        if (it % 10 == 2) { a = glm::round(a) + 0.5f; b = glm::round(b) + 0.5f; }  // through cell corners
        const sk::SilmapRasterResult rr = sk::silmap_rasterize_edge(a, b, {32, 32}, cells.data(), cells.size());
        REQUIRE(rr.status == sk::Status::Ok);
        const std::size_t n = rr.count;
        REQUIRE(n == rr.needed);
        std::set<std::pair<int, int>> got;
        for (std::size_t k = 0; k < n; ++k) {
            got.insert({cells[k].x, cells[k].y});
            // every cell reported is within reach of the segment (its square grown by 0.01)
            const glm::vec2 lo(float(cells[k].x) + 0.49f, float(cells[k].y) + 0.49f), hi = lo + 1.02f;
            glm::dvec2 p0(a), p1(b);
            bool touches = sk::detail::silmap_clip(p0, p1, glm::dvec2(lo), glm::dvec2(hi));
            if (!touches) ++extra_far;
        }
        CHECK(got.size() == n);  // no duplicates
        // dense samples along the segment: the cell of each must be listed
        const int steps = 2000;
        for (int s = 0; s <= steps; ++s) {
            const glm::vec2 q = a + (b - a) * (float(s) / float(steps));
            const int cx = int(std::floor(q.x - 0.5f)), cy = int(std::floor(q.y - 0.5f));
            if (cx < 0 || cy < 0 || cx > 31 || cy > 31) continue;
            ++total;
            if (!got.count({cx, cy})) ++missing;
        }
    }
    CHECK(missing == 0);
    CHECK(extra_far == 0);
    CHECK(total > 100000);
}

TEST_CASE("all-default silhouette map reproduces the nearest-sample shadow map exactly (10,000 lookups)") {
    std::mt19937 rng(11);
    const int W = 16, H = 12;
    std::vector<float> depth(std::size_t(W * H));
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (auto& d : depth) d = u(rng);
    std::vector<glm::vec2> pts(depth.size());
    std::vector<std::uint8_t> wts(depth.size());
    const auto br = sk::silmap_build(nullptr, 0, {W, H}, depth.data(), 0.f, pts.data(), pts.size(), wts.data(), wts.size());
    REQUIRE(br.status == sk::Status::Ok);
    int mismatches = 0;
    for (int it = 0; it < 10000; ++it) {
        const glm::vec2 q(u(rng) * float(W), u(rng) * float(H));
        const float z = u(rng);
        const bool a = sk::silmap_lookup(pts.data(), wts.data(), depth.data(), {W, H}, q, z, 0.f).lit;
        const bool b = sk::silmap_plain_lookup(depth.data(), {W, H}, q, z, 0.f).lit;
        mismatches += a != b;
    }
    CHECK(mismatches == 0);
}

TEST_CASE("straight boundaries: reconstruction within a small fraction of a texel (200 random lines)") {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    const int W = 48;
    ErrorStats sil_all, plain_all;
    double worst_sil = 0.0, worst_plain = 0.0;
    std::size_t fail_texels = 0;
    for (int it = 0; it < 200; ++it) {
        Shape s;
        s.half_plane = true;
        const float ang = 6.2831853f * u(rng);
        s.n = glm::vec2(std::cos(ang), std::sin(ang));
        s.p0 = glm::vec2(24.f + 4.f * (u(rng) - 0.5f), 24.f + 4.f * (u(rng) - 0.5f));
        const glm::vec2 t(-s.n.y, s.n.x);
        // the line as a chain of random-length collinear pieces (vertices land inside cells: case 1)
        std::vector<sk::SilmapEdge> edges;
        float a = -40.f;
        while (a < 40.f) {
            const float b = std::min(40.f, a + 0.3f + 4.f * u(rng));
            sk::SilmapEdge e;
            e.a = s.p0 + a * t;
            e.b = s.p0 + b * t;
            edges.push_back(e);
            a = b;
        }
        std::shuffle(edges.begin(), edges.end(), rng);
        const Map m = build(s, W, W, edges);
        fail_texels += m.br.failure_texels;
        const ErrorStats es = measure(s, m, true, 4, W - 4, 8, rng), ep = measure(s, m, false, 4, W - 4, 8, rng);
        worst_sil = std::max(worst_sil, es.max_err);
        worst_plain = std::max(worst_plain, ep.max_err);
        sil_all.samples += es.samples;
        sil_all.wrong += es.wrong;
        plain_all.samples += ep.samples;
        plain_all.wrong += ep.wrong;
    }
    const double fs = double(sil_all.wrong) / double(sil_all.samples), fp = double(plain_all.wrong) / double(plain_all.samples);
    std::printf("straight: silmap max error %.2e texel, misclassified %.2e; plain max %.3f texel, misclassified %.2e\n",
                worst_sil, fs, worst_plain, fp);
    CHECK(fail_texels == 0);         // collinear pieces only meet at vertices: never a failure texel
    CHECK(worst_sil < 1e-3);         // exact up to float rounding (paper: exact edge locations)
    CHECK(worst_plain > 0.5);        // the plain map's staircase: up to ~sqrt(2)/2 texel
    CHECK(fs < 0.01 * fp);
}

TEST_CASE("curved boundaries: error a fraction of a texel where one curve crosses a texel") {
    // circles as 512-gons: many short edges per texel (vertices inside texels, case 1)
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    const int W = 64;
    for (float radius : {3.f, 6.f, 12.f, 24.f}) {
        double worst = 0.0, worst_claim = 0.0, worst_plain = 0.0;
        std::size_t wrong = 0, samples = 0, pw = 0, fb = 0, fails = 0;
        for (int it = 0; it < 20; ++it) {
            Shape s;
            const glm::vec2 c(32.f + u(rng), 32.f + u(rng));
            const int segs = 512;
            const float phase = u(rng);
            for (int k = 0; k < segs; ++k) {
                const float a = 6.2831853f * (float(k) + phase) / float(segs);
                s.poly.push_back(c + radius * glm::vec2(std::cos(a), std::sin(a)));
            }
            const Map m = build(s, W, W, poly_edges(s.poly, 1));
            fails += m.br.failure_texels;
            const int lo = int(32.f - radius - 3.f), hi = int(32.f + radius + 4.f);
            const ErrorStats es = measure(s, m, true, lo, hi, 16, rng), ep = measure(s, m, false, lo, hi, 16, rng);
            worst = std::max(worst, es.max_err);
            worst_claim = std::max(worst_claim, es.max_err_claim);
            worst_plain = std::max(worst_plain, ep.max_err);
            wrong += es.wrong;
            samples += es.samples;
            pw += ep.wrong;
            fb += es.fallbacks;
        }
        std::printf("circle r=%4.1f texels: silmap max error %.3f texel (%.3f outside fallback texels), misclassified %.2e, "
                    "fallback lookups %.1e, failure texels %zu; plain max %.3f, misclassified %.2e\n",
                    double(radius), worst, worst_claim, double(wrong) / double(samples), double(fb) / double(samples),
                    fails, worst_plain, double(pw) / double(samples));
        // the chord error of a piecewise-linear reconstruction is h^2 / (8 r) with h ~ 1 texel
        CHECK(worst_claim < (radius <= 3.f ? 0.25 : 0.1));
        CHECK(worst <= worst_plain + 1e-6);        // fallback texels are never worse than the plain map
        CHECK(double(wrong) < 0.2 * double(pw));   // 5x fewer misclassified samples than the plain map
    }
}

TEST_CASE("curved boundary with one edge per texel (coarse polygon): within a tenth of a texel") {
    // a 24-gon of radius 12 texels: edges ~3.1 texels long, texels hold one edge or one vertex
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    double worst = 0.0, worst_claim = 0.0, worst_plain = 0.0;
    std::size_t fails = 0, wrong = 0, pw = 0;
    for (int it = 0; it < 50; ++it) {
        Shape s;
        const glm::vec2 c(32.f + u(rng), 32.f + u(rng));
        const float phase = u(rng);
        for (int k = 0; k < 24; ++k) {
            const float a = 6.2831853f * (float(k) + phase) / 24.f;
            s.poly.push_back(c + 12.f * glm::vec2(std::cos(a), std::sin(a)));
        }
        const Map m = build(s, 64, 64, poly_edges(s.poly, 1));
        fails += m.br.failure_texels;
        const ErrorStats es = measure(s, m, true, 16, 48, 16, rng), ep = measure(s, m, false, 16, 48, 16, rng);
        worst = std::max(worst, es.max_err);
        worst_claim = std::max(worst_claim, es.max_err_claim);
        worst_plain = std::max(worst_plain, ep.max_err);
        wrong += es.wrong;
        pw += ep.wrong;
    }
    std::printf("24-gon r=12: silmap max error %.3f texel (%.3f outside fallback texels), plain %.3f; misclassified "
                "samples %zu vs %zu; failure texels %zu (a vertex within a hair of a texel corner)\n",
                worst, worst_claim, worst_plain, wrong, pw, fails);
    CHECK(fails <= 10);
    CHECK(worst_claim < 0.1);
    CHECK(wrong * 50 < pw);
}

TEST_CASE("failure: two silhouette edges in one texel are detected and fall back to the plain result") {
    // a thin slab between two parallel lines 0.3 texels apart (a wire's shadow)
    const int W = 32;
    Shape s;
    const glm::vec2 a(2.f, 10.3f), b(30.f, 19.7f);
    const glm::vec2 d = glm::normalize(b - a), n(-d.y, d.x);
    s.poly = {a, b, b + 0.3f * n, a + 0.3f * n};
    std::vector<sk::SilmapEdge> edges = poly_edges(s.poly, 1);
    const Map m = build(s, W, W, edges);
    CHECK(m.br.failure_texels > 10);
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    int checked = 0, agree = 0;
    for (int it = 0; it < 20000; ++it) {
        const glm::vec2 q(1.f + 30.f * u(rng), 1.f + 30.f * u(rng));
        const glm::ivec2 cell(int(std::floor(q.x - 0.5f)), int(std::floor(q.y - 0.5f)));
        if (cell.x < 0 || cell.y < 0 || cell.x > W - 2 || cell.y > W - 2) continue;
        if (m.wts[std::size_t(cell.y * W + cell.x)] <= sk::kSilmapFailureWeight) continue;
        const sk::SilmapLookup l = sk::silmap_lookup(m.pts.data(), m.wts.data(), m.depth.data(), {W, W}, q, 0.5f, 0.f);
        CHECK(l.fallback);
        ++checked;
        agree += l.lit == sk::silmap_plain_lookup(m.depth.data(), {W, W}, q, 0.5f, 0.f).lit;
    }
    CHECK(checked > 100);
    CHECK(agree == checked);
    // T-junction: a third edge ending on another inside one texel
    std::vector<sk::SilmapEdge> t(2);
    t[0].a = {2.f, 10.f}; t[0].b = {30.f, 10.f};
    t[1].a = {10.2f, 10.f}; t[1].b = {10.2f, 25.f};
    std::vector<glm::vec2> pts(W * W);
    std::vector<std::uint8_t> wts(W * W);
    const auto br = sk::silmap_build(t.data(), 2, {W, W}, nullptr, 0.f, pts.data(), pts.size(), wts.data(), wts.size());
    CHECK(br.failure_texels >= 1);
    CHECK(wts[std::size_t(9 * W + 9)] == 3);  // crossing (2) + the other edge ending inside (1)
    // two edges meeting at a polygon vertex are not a failure
    std::vector<sk::SilmapEdge> v(2);
    v[0].a = {2.f, 2.f}; v[0].b = {10.2f, 10.3f};
    v[1].a = {10.2f, 10.3f}; v[1].b = {20.f, 4.f};
    const auto bv = sk::silmap_build(v.data(), 2, {W, W}, nullptr, 0.f, pts.data(), pts.size(), wts.data(), wts.size());
    CHECK(bv.failure_texels == 0);
    CHECK(wts[std::size_t(9 * W + 9)] == 2);
    CHECK(pts[std::size_t(9 * W + 9)].x == doctest::Approx(0.7f));
    CHECK(pts[std::size_t(9 * W + 9)].y == doctest::Approx(0.8f));
}

TEST_CASE("depth tests: occluded silhouette fragments and contact edges are discarded") {
    const int W = 16;
    std::vector<float> depth(W * W);
    for (int j = 0; j < W; ++j)
        for (int i = 0; i < W; ++i) depth[std::size_t(j * W + i)] = j <= 5 ? 0.3f : 0.9f;  // blocker below row 6
    std::vector<glm::vec2> pts(W * W);
    std::vector<std::uint8_t> wts(W * W);
    sk::SilmapEdge e;
    e.a = {1.f, 6.3f}; e.b = {15.f, 6.3f};   // the blocker's outline, between rows 5 and 6
    e.depth_a = e.depth_b = 0.95f;             // behind everything: occluded
    auto br = sk::silmap_build(&e, 1, {W, W}, depth.data(), 1e-3f, pts.data(), pts.size(), wts.data(), wts.size());
    CHECK(br.points_written == 0);
    CHECK(br.occluded > 10);
    e.depth_a = e.depth_b = 0.3f;              // on the blocker, the receiver behind: kept
    br = sk::silmap_build(&e, 1, {W, W}, depth.data(), 1e-3f, pts.data(), pts.size(), wts.data(), wts.size());
    CHECK(br.occluded == 0);
    CHECK(br.points_written > 10);
    std::fill(depth.begin(), depth.end(), 0.9f);  // contact edge: nothing behind it casts no shadow
    e.depth_a = e.depth_b = 0.9f;
    br = sk::silmap_build(&e, 1, {W, W}, depth.data(), 1e-3f, pts.data(), pts.size(), wts.data(), wts.size());
    CHECK(br.points_written == 0);
}

TEST_CASE("projection into texel space: matrix, near clipping, bad indices") {
    const glm::mat4 vp = glm::ortho(-1.f, 1.f, -1.f, 1.f, 0.f, 10.f);  // looking down -z
    const glm::vec3 pos[4] = {{-1.f, -1.f, -5.f}, {1.f, 1.f, -5.f}, {0.f, 0.f, -10.f}, {0.f, 0.f, -2.5f}};
    const std::uint32_t idx[6] = {0, 1, 2, 3, 0, 7};
    sk::SilmapEdge out[3];
    // an index >= vertex_count: IndexOutOfRange, nothing written
    auto r = sk::silmap_project_edges(vp, sk::ClipDepth::NegativeOneToOne, {100, 50}, pos, 4, idx, 3, out, 3);
    CHECK(r.status == sk::Status::IndexOutOfRange);
    CHECK(r.count == 0);
    r = sk::silmap_project_edges(vp, sk::ClipDepth::NegativeOneToOne, {100, 50}, pos, 4, idx, 2, out, 3);
    CHECK(r.status == sk::Status::Ok);
    CHECK(r.count == 2);
    CHECK(out[0].a.x == doctest::Approx(0.f));
    CHECK(out[0].b.x == doctest::Approx(100.f));
    CHECK(out[0].b.y == doctest::Approx(50.f));
    CHECK(out[0].depth_a == doctest::Approx(0.5f));
    CHECK(out[1].depth_a == doctest::Approx(1.0f));
    CHECK(out[1].depth_b == doctest::Approx(0.25f));
    r = sk::silmap_project_edges(vp, sk::ClipDepth::ZeroToOne, {100, 50}, pos, 4, idx, 1, out, 3);
    CHECK(out[0].depth_a == doctest::Approx(0.f));  // ndc z of the GL ortho at -5: 0
    // perspective: an edge crossing the light plane is clipped, one behind is skipped
    const glm::mat4 pp = glm::perspective(1.5f, 1.f, 0.1f, 100.f);
    const glm::vec3 pq[4] = {{0.f, 0.f, -5.f}, {0.f, 0.f, 5.f}, {1.f, 0.f, 3.f}, {-1.f, 0.f, 4.f}};
    const std::uint32_t ei[4] = {0, 1, 2, 3};
    r = sk::silmap_project_edges(pp, sk::ClipDepth::NegativeOneToOne, {64, 64}, pq, 4, ei, 2, out, 3);
    CHECK(r.status == sk::Status::Ok);
    CHECK(r.count == 1);
    CHECK(r.culled == 1);
    CHECK(std::isfinite(out[0].b.x));
    // buffer too small reports the count
    r = sk::silmap_project_edges(vp, sk::ClipDepth::NegativeOneToOne, {100, 50}, pos, 4, idx, 2, out, 1);
    CHECK(r.status == sk::Status::BufferTooSmall);
    CHECK(r.needed == 2);
    CHECK(r.count == 1);
}

TEST_CASE("stiff input: NaN, huge and tiny coordinates, zero-length edges, grid-aligned edges, 1x1 maps") {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const int W = 64;
    std::vector<glm::vec2> pts(W * W);
    std::vector<std::uint8_t> wts(W * W);
    std::vector<float> depth(W * W, 1.f);
    std::vector<sk::SilmapEdge> e(6);
    e[0].a = {nan, 1.f}; e[0].b = {3.f, 3.f};
    e[1].a = {-1e6f, 20.3f}; e[1].b = {1e6f, 20.3f + 1e-6f};       // huge: clipped, bounded work
    e[2].a = {10.5f, 10.5f}; e[2].b = {10.5f, 10.5f};              // zero length, on a depth sample
    e[3].a = {5.5f, 2.f}; e[3].b = {5.5f, 60.f};                   // along a cell boundary (grid line)
    e[4].a = {1.5f, 1.5f}; e[4].b = {40.5f, 40.5f};                // through cell corners
    e[5].a = {-inf, 0.f}; e[5].b = {inf, 0.f};
    // a NaN or infinite edge rejects the whole build (NonFinite, nothing written); it once skipped
    // the edge and still said NonFinite after writing the map
    auto br = sk::silmap_build(e.data(), e.size(), {W, W}, depth.data(), 0.f, pts.data(), pts.size(), wts.data(), wts.size());
    CHECK(br.status == sk::Status::NonFinite);
    CHECK(br.count == 0);
    br = sk::silmap_build(e.data() + 1, 4, {W, W}, depth.data(), 0.f, pts.data(), pts.size(), wts.data(), wts.size());
    CHECK(br.status == sk::Status::Ok);
    CHECK(br.count == pts.size());
    for (std::size_t k = 0; k < pts.size(); ++k) {
        REQUIRE(std::isfinite(pts[k].x));
        REQUIRE(pts[k].x >= 0.f);
        REQUIRE(pts[k].x <= 1.f);
        REQUIRE(pts[k].y >= 0.f);
        REQUIRE(pts[k].y <= 1.f);
    }
    // the huge edge wrote a point in every column it crosses
    int row_points = 0;
    for (int i = 0; i < W; ++i) row_points += wts[std::size_t(19 * W + i)] > 0;
    CHECK(row_points >= W - 1);
    // lookups: NaN is NonFinite (it was a silent "lit" fallback), huge positions are border lookups
    CHECK(sk::silmap_lookup(pts.data(), wts.data(), depth.data(), {W, W}, {nan, 3.f}, 0.5f, 0.f).status ==
          sk::Status::NonFinite);
    const sk::SilmapLookup far = sk::silmap_lookup(pts.data(), wts.data(), depth.data(), {W, W}, {1e30f, -1e30f}, 0.5f, 0.f);
    CHECK(far.status == sk::Status::Ok);
    CHECK(far.fallback);
    CHECK(sk::silmap_lookup(pts.data(), wts.data(), depth.data(), {W, W}, {3.f, 3.f}, nan, 0.f).status ==
          sk::Status::NonFinite);
    CHECK(sk::silmap_lookup(pts.data(), wts.data(), depth.data(), {W, W}, {3.f, 3.f}, 0.5f, inf).status ==
          sk::Status::NonFinite);
    CHECK(sk::silmap_lookup(nullptr, wts.data(), depth.data(), {W, W}, {3.f, 3.f}, 0.5f, 0.f).status ==
          sk::Status::InvalidArgument);
    CHECK(sk::silmap_plain_lookup(nullptr, {W, W}, {3.f, 3.f}, 0.5f, 0.f).status == sk::Status::InvalidArgument);
    CHECK(sk::silmap_plain_lookup(depth.data(), {W, W}, {3.f, nan}, 0.5f, 0.f).status == sk::Status::NonFinite);
    // 1x1 map: no interior cell, plain result
    float d1 = 0.2f;
    glm::vec2 p1;
    std::uint8_t w1;
    CHECK(sk::silmap_build(e.data() + 2, 1, {1, 1}, &d1, 0.f, &p1, 1, &w1, 1).status == sk::Status::Ok);
    CHECK_FALSE(sk::silmap_lookup(&p1, &w1, &d1, {1, 1}, {0.5f, 0.5f}, 0.5f, 0.f).lit);
    // bad arguments
    CHECK(sk::silmap_build(e.data(), 1, {0, 4}, nullptr, 0.f, pts.data(), pts.size(), wts.data(), wts.size()).status ==
          sk::Status::InvalidArgument);
    CHECK(sk::silmap_build(e.data() + 1, 1, {W, W}, nullptr, 0.f, pts.data(), 10, wts.data(), 10).status ==
          sk::Status::BufferTooSmall);
    // tiny features: a 1e-6 texel edge still yields its vertex, near-parallel to a diagonal
    sk::SilmapPoint p = sk::silmap_select_point({3.9f, 4.9f}, {3.9f + 1e-6f, 4.9f + 1e-6f}, {3, 4});
    CHECK(p.kase == sk::SilmapCase::VertexInside);
    // degenerate sectors fall back to the nearest corner
    const bool lit[4] = {true, false, false, false};
    const sk::SilmapLookup l = sk::silmap_reconstruct({0.4f, 0.4f}, {0.5f, 0.5f}, {-0.5f, 0.5f}, {0.5f, 0.5f},
                                                      {0.5f, 0.5f}, {0.5f, 0.5f}, lit);
    CHECK(l.fallback);
    CHECK(l.lit);
}

TEST_CASE("rasterization of edges 1e12 to 1e30 texels long: only in-map cells (fuzz regression)") {
    // Found by fuzz_silhouette_map: the clipped end points a + t (b - a) of a 2e30-long segment lose
    // every digit (x ~ -5e11 came out, then a float-to-int overflow). The clip now clamps its result
    // to the map. Expected cells by hand for 1e12: y(x) = 2.5 + 0.2 x / 1e12 is 2.5 to 1e-11 over the
    // map, on the boundary between cell rows 1 and 2 (cells span [j + 0.5, j + 1.5]): both rows,
    // every column, 16 cells.
    std::vector<glm::ivec2> cells(64);
    const std::size_t n = sk::silmap_rasterize_edge({-1e12f, 2.3f}, {1e12f, 2.7f}, {8, 8}, cells.data(), cells.size()).count;
    REQUIRE(n == 16);
    for (std::size_t k = 0; k < n; ++k) {
        CHECK(cells[k].x == int(k / 2));
        CHECK(cells[k].y == 1 + int(k % 2));
    }
    // near-vertical at x = 4.2: column 3, every row
    const std::size_t m =
        sk::silmap_rasterize_edge({4.2f, -1e12f}, {4.2f + 1e-7f, 1e12f}, {8, 8}, cells.data(), cells.size()).count;
    REQUIRE(m == 8);
    for (std::size_t k = 0; k < m; ++k) CHECK(cells[k] == glm::ivec2(3, int(k)));
    // 1e30: double precision cannot place the crossing (t = 0.5 +- 2^-53 for the whole map), but
    // every cell returned is inside the map and there are at most W + H of them
    for (float len : {1e20f, 1e30f, 3e38f}) {
        for (const auto& ab : {std::pair<glm::vec2, glm::vec2>{{-len, 2.3f}, {len, 2.7f}},
                               std::pair<glm::vec2, glm::vec2>{{4.2f, -len}, {4.2f, len}},
                               std::pair<glm::vec2, glm::vec2>{{-len, -len}, {len, len * 0.999f}}}) {
            const sk::SilmapRasterResult rc = sk::silmap_rasterize_edge(ab.first, ab.second, {8, 8}, cells.data(), cells.size());
            CHECK(rc.status == sk::Status::Ok);
            const std::size_t c = rc.count;
            CHECK(c <= 16);
            for (std::size_t k = 0; k < std::min<std::size_t>(c, 64); ++k) {
                CHECK(cells[k].x >= 0);
                CHECK(cells[k].x < 8);
                CHECK(cells[k].y >= 0);
                CHECK(cells[k].y < 8);
            }
        }
    }
}

TEST_CASE("projection: an edge whose texel coordinates overflow float is clipped to the guard band, not dropped") {
    // Regression (issue 19): the old code turned x / w * size into float, got Inf for an edge
    // spanning +-1e38 in the light's x, skipped the edge and still returned Ok with 0 edges: the
    // silhouette crossing the whole map was lost. Now the edge is clipped to |x| <= 2^20 w: finite,
    // and it still crosses the whole map at the same y.
    const glm::mat4 vp = glm::ortho(-1.f, 1.f, -1.f, 1.f, 0.f, 10.f);
    const glm::vec3 pos[2] = {{-1e38f, 0.25f, -5.f}, {1e38f, 0.25f, -5.f}};
    const std::uint32_t idx[2] = {0, 1};
    sk::SilmapEdge out[1];
    const auto r = sk::silmap_project_edges(vp, sk::ClipDepth::NegativeOneToOne, {64, 64}, pos, 2, idx, 1, out, 1);
    REQUIRE(r.status == sk::Status::Ok);
    REQUIRE(r.count == 1);
    CHECK(std::isfinite(out[0].a.x));
    CHECK(std::isfinite(out[0].b.x));
    CHECK(out[0].a.x < 0.f);
    CHECK(out[0].b.x > 64.f);
    CHECK(out[0].a.y == doctest::Approx(40.f));  // (0.25 * 0.5 + 0.5) * 64
    CHECK(out[0].b.y == doctest::Approx(40.f));
    std::vector<glm::ivec2> cells(256);
    const auto rr = sk::silmap_rasterize_edge(out[0].a, out[0].b, {64, 64}, cells.data(), cells.size());
    CHECK(rr.status == sk::Status::Ok);
    CHECK(rr.count >= 63);  // every column of the row
    // a NaN matrix is NonFinite with nothing written (the old code skipped edge by edge)
    glm::mat4 bad = vp;
    bad[3][1] = std::numeric_limits<float>::quiet_NaN();
    CHECK(sk::silmap_project_edges(bad, sk::ClipDepth::NegativeOneToOne, {64, 64}, pos, 2, idx, 1, out, 1).status ==
          sk::Status::NonFinite);
    // a clip_depth that is no enumerator, a null buffer with a capacity
    CHECK(sk::silmap_project_edges(vp, static_cast<sk::ClipDepth>(7), {64, 64}, pos, 2, idx, 1, out, 1).status ==
          sk::Status::InvalidArgument);
    CHECK(sk::silmap_project_edges(vp, sk::ClipDepth::NegativeOneToOne, {64, 64}, pos, 2, idx, 1, nullptr, 1).status ==
          sk::Status::InvalidArgument);
    CHECK(sk::silmap_project_edges(vp, sk::ClipDepth::NegativeOneToOne, {64, 64}, nullptr, 2, idx, 1, out, 1).status ==
          sk::Status::InvalidArgument);
}

TEST_CASE("rasterization: NaN and null buffers are errors, not an empty edge") {
    // Regression (issue 19, items 4 and 6): the old function returned 0 cells for a NaN end (the
    // same answer as an edge that misses the map) and treated out == nullptr with a capacity as
    // capacity 0.
    const float nan = std::numeric_limits<float>::quiet_NaN();
    glm::ivec2 cells[8];
    CHECK(sk::silmap_rasterize_edge({nan, 1.f}, {3.f, 3.f}, {8, 8}, cells, 8).status == sk::Status::NonFinite);
    CHECK(sk::silmap_rasterize_edge({1.f, 1.f}, {3.f, 3.f}, {8, 8}, nullptr, 8).status == sk::Status::InvalidArgument);
    CHECK(sk::silmap_rasterize_edge({1.f, 1.f}, {3.f, 3.f}, {0, 8}, cells, 8).status == sk::Status::InvalidArgument);
    CHECK(sk::silmap_rasterize_edge({1.f, 1.f}, {3.f, 3.f}, {8, 8}, cells, 8, 1.f).status == sk::Status::InvalidArgument);
    CHECK(sk::silmap_rasterize_edge({1.f, 1.f}, {3.f, 3.f}, {8, 8}, cells, 8, nan).status == sk::Status::InvalidArgument);
    const auto miss = sk::silmap_rasterize_edge({-50.f, -50.f}, {-40.f, -30.f}, {8, 8}, cells, 8);
    CHECK(miss.status == sk::Status::Ok);
    CHECK(miss.needed == 0);
    // a size query (capacity 0) says how many: BufferTooSmall with needed, the diagonal (1,1)-(3,3)
    // touches cells (0,0) .. (2,2) around it: brute force over the 8 x 8 grid below
    const auto q = sk::silmap_rasterize_edge({1.f, 1.f}, {3.f, 3.f}, {8, 8}, nullptr, 0);
    CHECK(q.status == sk::Status::BufferTooSmall);
    CHECK(q.count == 0);
    std::size_t expect = 0;
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i) {
            glm::dvec2 p0(1.0, 1.0), p1(3.0, 3.0);
            if (sk::detail::silmap_clip(p0, p1, glm::dvec2(i + 0.5 - 1e-4, j + 0.5 - 1e-4), glm::dvec2(i + 1.5 + 1e-4, j + 1.5 + 1e-4)))
                ++expect;
        }
    CHECK(q.needed == expect);
    const bool lit[4] = {true, true, false, false};
    CHECK(sk::silmap_reconstruct({0.5f, 0.5f}, {0.5f, 0.5f}, {0.5f, 0.5f}, {0.5f, 0.5f}, {0.5f, 0.5f}, {0.5f, 0.5f},
                                 nullptr).status == sk::Status::InvalidArgument);
    CHECK(sk::silmap_reconstruct({nan, 0.5f}, {0.5f, 0.5f}, {0.5f, 0.5f}, {0.5f, 0.5f}, {0.5f, 0.5f}, {0.5f, 0.5f}, lit)
              .status == sk::Status::NonFinite);
}

TEST_CASE("property: finite input in the documented ranges gives Ok and finite output; NaN gives NonFinite (4,000 configurations)") {
    std::mt19937 rng(20260);
    std::uniform_real_distribution<float> u(-1.f, 1.f), u01(0.f, 1.f);
    auto scale = [&](int k) { const float s[6] = {1e-6f, 1e-3f, 1.f, 1e3f, 1e6f, 1e30f}; return s[k % 6]; };
    std::size_t ok_calls = 0, culled = 0;
    for (int it = 0; it < 4000; ++it) {
        const float sc = scale(it);
        // light: perspective (near 1e-5 .. 1, far up to infinity) or ortho, looking from a random eye
        const glm::vec3 eye(u(rng) * sc, u(rng) * sc, u(rng) * sc);
        glm::vec3 dir(u(rng), u(rng), u(rng));
        if (glm::length(dir) < 0.1f) dir = glm::vec3(0.f, 0.f, -1.f);
        dir = glm::normalize(dir);
        const glm::vec3 up = std::abs(dir.y) > 0.9f ? glm::vec3(1.f, 0.f, 0.f) : glm::vec3(0.f, 1.f, 0.f);
        const float near_z = (it % 3 == 0 ? 1e-5f : 0.1f) * sc;
        glm::mat4 proj = (it % 4 == 0) ? glm::ortho(-sc, sc, -sc, sc, 0.f, 10.f * sc)
                         : (it % 4 == 1) ? glm::infinitePerspective(1.2f, 1.f, near_z)
                                         : glm::perspective(0.3f + 2.5f * u01(rng), 0.5f + u01(rng), near_z, near_z * 1e4f);
        const glm::mat4 vp = proj * glm::lookAt(eye, eye + dir * sc, up);
        const int nv = 2 + int(u01(rng) * 10.f);
        std::vector<glm::vec3> pos(static_cast<std::size_t>(nv));
        for (auto& p : pos) p = eye + glm::vec3(u(rng), u(rng), u(rng)) * sc * (it % 5 == 0 ? 1e6f : 2.f);
        if (it % 7 == 0) pos[0] = eye;  // a vertex at the light
        std::vector<std::uint32_t> idx(2 * std::size_t(nv));
        for (auto& i : idx) i = std::uint32_t(u01(rng) * float(nv)) % std::uint32_t(nv);
        const glm::uvec2 size(1u + std::uint32_t(u01(rng) * 100.f), 1u + std::uint32_t(u01(rng) * 100.f));
        std::vector<sk::SilmapEdge> edges(static_cast<std::size_t>(nv));
        const auto pr = sk::silmap_project_edges(vp, it % 2 ? sk::ClipDepth::ZeroToOne : sk::ClipDepth::NegativeOneToOne,
                                                 size, pos.data(), pos.size(), idx.data(), std::size_t(nv), edges.data(),
                                                 edges.size());
        bool finite_matrix = true;  // glm's float perspective overflows (2 f n) for near 1e29
        for (int c = 0; c < 4; ++c) finite_matrix = finite_matrix && std::isfinite(glm::dot(vp[c], vp[c]));
        if (!finite_matrix) continue;
        REQUIRE(pr.status == sk::Status::Ok);
        REQUIRE(pr.count == pr.needed);
        REQUIRE(pr.count + pr.culled == std::size_t(nv));
        culled += pr.culled;
        for (std::size_t e = 0; e < pr.count; ++e) {
            REQUIRE(sk::detail::silmap_finite(edges[e].a));
            REQUIRE(sk::detail::silmap_finite(edges[e].b));
            REQUIRE(std::isfinite(edges[e].depth_a));
            REQUIRE(std::isfinite(edges[e].depth_b));
        }
        // the same edges built into a map and looked up
        std::vector<glm::vec2> pts(std::size_t(size.x) * size.y);
        std::vector<std::uint8_t> wts(pts.size());
        std::vector<float> depth(pts.size());
        for (auto& d : depth) d = u01(rng);
        const auto br = sk::silmap_build(edges.data(), pr.count, size, it % 2 ? depth.data() : nullptr, 1e-4f, pts.data(),
                                         pts.size(), wts.data(), wts.size());
        REQUIRE(br.status == sk::Status::Ok);
        bool in_cell = true;
        for (const auto& p : pts) in_cell = in_cell && p.x >= 0.f && p.x <= 1.f && p.y >= 0.f && p.y <= 1.f;
        REQUIRE(in_cell);
        for (int k = 0; k < 4; ++k) {
            const glm::vec2 q(u(rng) * float(size.x) * 2.f, u(rng) * float(size.y) * 2.f);
            const auto l = sk::silmap_lookup(pts.data(), wts.data(), depth.data(), size, q, u01(rng), 1e-4f);
            REQUIRE(l.status == sk::Status::Ok);
            REQUIRE(sk::silmap_plain_lookup(depth.data(), size, q, u01(rng), 0.f).status == sk::Status::Ok);
        }
        // rasterizing any finite segment (1e-6 .. 1e30 texels) is Ok, in the map, <= 2 (W + H) + 4 cells
        std::vector<glm::ivec2> cells(4 * (size.x + size.y) + 16);
        const glm::vec2 a(u(rng) * sc, u(rng) * sc), b = a + glm::vec2(u(rng), u(rng)) * sc;
        const auto rr = sk::silmap_rasterize_edge(a, b, size, cells.data(), cells.size(), 1e-4f);
        REQUIRE(rr.status == sk::Status::Ok);
        REQUIRE(rr.count <= 2 * (size.x + size.y) + 4);
        for (std::size_t c = 0; c < rr.count; ++c)
            REQUIRE((cells[c].x >= 0 && cells[c].y >= 0 && cells[c].x < int(size.x) && cells[c].y < int(size.y)));
        ++ok_calls;
        // one NaN anywhere: NonFinite
        pos[idx[0]].y = std::numeric_limits<float>::quiet_NaN();
        REQUIRE(sk::silmap_project_edges(vp, sk::ClipDepth::NegativeOneToOne, size, pos.data(), pos.size(), idx.data(),
                                         std::size_t(nv), edges.data(), edges.size())
                    .status == sk::Status::NonFinite);
        if (pr.count) {
            edges[0].depth_b = std::numeric_limits<float>::infinity();
            REQUIRE(sk::silmap_build(edges.data(), pr.count, size, nullptr, 0.f, pts.data(), pts.size(), wts.data(),
                                     wts.size())
                        .status == sk::Status::NonFinite);
        }
    }
    CHECK(ok_calls > 3000);
    CHECK(culled > 0);
}
