// Every glsl/ snippet also compiles and links on the GL driver in use (Mesa llvmpipe here, the
// vendor's compiler on a GPU), not only in glslang: drivers disagree on corner cases.
#include <doctest/doctest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <sstream>

#include "gl_test.hpp"

namespace fs = std::filesystem;

namespace {

std::vector<std::string> header_list(const std::string& src, const std::string& key) {
    std::istringstream in(src);
    std::string line;
    while (std::getline(in, line)) {
        const auto pos = line.find_first_not_of(" \t");
        if (pos == std::string::npos) continue;
        if (line.compare(pos, 2, "//") != 0) break;
        const auto k = line.find(key + ":");
        if (k == std::string::npos) continue;
        std::vector<std::string> out;
        std::string cur;
        for (char c : line.substr(k + key.size() + 1)) {
            if (c == ',' || std::isspace(static_cast<unsigned char>(c))) {
                if (!cur.empty()) out.push_back(cur);
                cur.clear();
            } else {
                cur += c;
            }
        }
        if (!cur.empty()) out.push_back(cur);
        return out;
    }
    return {};
}

GLenum stage_enum(const std::string& s) {
    if (s == "vertex") return GL_VERTEX_SHADER;
    if (s == "fragment") return GL_FRAGMENT_SHADER;
    if (s == "geometry") return GL_GEOMETRY_SHADER;
    if (s == "compute") return GL_COMPUTE_SHADER;
    return 0;
}


}  // namespace

TEST_CASE("every snippet compiles and links on the GL driver") {
    int programs = 0;
    for (const auto& e : fs::directory_iterator(SHADOWKIT_GLSL_DIR)) {
        if (e.path().extension() != ".glsl") continue;
        const std::string stem = e.path().stem().string();
        const std::string src = skgl::read_text_file(e.path().string());
        const auto versions = header_list(src, "versions");
        const auto stages = header_list(src, "stages");
        REQUIRE_MESSAGE(!versions.empty(), stem);
        for (const auto& st : stages) {
            const GLenum type = stage_enum(st);
            REQUIRE_MESSAGE(type != 0, stem << ": stage " << st);
            const std::string driver = skgl::read_text_file(std::string(SHADOWKIT_GLSL_DIR) + "/../tests/glsl/" + stem +
                                                            "." + st + ".glsl");
            REQUIRE_MESSAGE(!driver.empty(), stem << ": driver for " << st);
            for (const auto& v : versions) {
                const std::string head = "#version " + v + " core\n";
                // a separable single-stage program: links with the driver's free inputs/outputs
                std::string log;
                const GLuint p = skgl::compile_program({{type, head + src + "\n" + driver}}, log, true);
                CHECK_MESSAGE(p != 0, stem << " (" << st << ", " << v << "): " << log);
                if (p) {
                    glDeleteProgram(p);
                    ++programs;
                }
            }
        }
    }
    MESSAGE(programs << " snippet programs linked on " << gl_test_context().renderer);
    CHECK(programs > 0);
}
